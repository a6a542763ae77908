// The production RayCaster: Embree 3 (third_party_notes/embree.md) over one
// triangle geometry holding every BakeGeometry triangle, primID = triangle.
// Robust scene flag (no leaks through shared edges), high build quality
// (the scene is built once and traced for minutes). Checked against the
// brute-force caster in tests/baker/ray_caster_test.cpp.

#include <embree3/rtcore.h>
#include <pmmintrin.h>
#include <xmmintrin.h>

#include <cmath>
#include <mutex>
#include <string>
#include <type_traits>

#include "embree_handles.h"
#include "ray_rules.h"
#include "scene/svit_check.h"
#include "svit/baker/ray_caster.h"

namespace svit::baker {
namespace {

/// The first message Embree's error callback reported. Embree keeps only the
/// first error code per thread until rtcGetDeviceError reads it; the callback
/// is where the explanatory text comes from. Thread-safe (Embree may call
/// the callback from its build threads).
class ErrorLog {
 public:
  static void callback(void* user, RTCError code, const char* message) {
    auto* log = static_cast<ErrorLog*>(user);
    const std::lock_guard<std::mutex> lock(log->mutex_);
    if (log->first_.empty())
      log->first_ = std::string(embreeErrorName(code)) + ": " + (message ? message : "");
  }
  std::string first() const {
    const std::lock_guard<std::mutex> lock(mutex_);
    return first_;
  }

 private:
  mutable std::mutex mutex_;
  std::string first_;
};

/// Sets MXCSR flush-to-zero and denormals-are-zero on the calling thread for
/// its lifetime and restores the caller's MXCSR after. Embree's "Performance
/// Recommendations" (doc/src/api.md, "MXCSR control and status register")
/// strongly recommend both on every thread that calls rtcIntersect*, since
/// denormal assists can slow traversal badly. MXCSR is per thread, so doing
/// it here (not once in main) covers whatever worker calls intersect(), and
/// every call traces under the same mode whatever the caller set: results do
/// not depend on which thread ran a batch (docs/style.md §5).
class FlushDenormalsScope {
 public:
  FlushDenormalsScope() : saved_(_mm_getcsr()) {
    _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
    _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
  }
  ~FlushDenormalsScope() { _mm_setcsr(saved_); }
  FlushDenormalsScope(const FlushDenormalsScope&) = delete;
  FlushDenormalsScope& operator=(const FlushDenormalsScope&) = delete;

 private:
  unsigned int saved_;
};

class EmbreeRayCaster final : public RayCaster {
 public:
  explicit EmbreeRayCaster(const BakeGeometry& geometry) : geometry_(geometry) {}

  /// Creates the device and scene; a Status naming Embree's error on failure.
  Status build() {
    device_.reset(rtcNewDevice(nullptr));
    if (!device_) {
      return Status(StatusCode::kInternal, std::string("embree: rtcNewDevice failed: ") +
                                               embreeErrorName(rtcGetDeviceError(nullptr)));
    }
    rtcSetDeviceErrorFunction(device_.get(), &ErrorLog::callback, error_log_.get());

    scene_.reset(rtcNewScene(device_.get()));
    if (scene_) {
      rtcSetSceneFlags(scene_.get(), RTC_SCENE_FLAG_ROBUST);
      rtcSetSceneBuildQuality(scene_.get(), RTC_BUILD_QUALITY_HIGH);
      const size_t triangles = geometry_.triangleCount();
      if (triangles > 0) {
        RTCGeometry mesh = rtcNewGeometry(device_.get(), RTC_GEOMETRY_TYPE_TRIANGLE);
        if (mesh) {
          // Copied, not shared: Embree wants every float3 element readable
          // with a 16-byte load, which would read past the end of
          // BakeGeometry::positions; rtcSetNewGeometryBuffer over-allocates.
          auto* vertices = static_cast<float*>(
              rtcSetNewGeometryBuffer(mesh, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                      3 * sizeof(float), triangles * 3));
          auto* indices = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(
              mesh, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(uint32_t), triangles));
          if (vertices && indices) {
            for (size_t i = 0; i < triangles * 3; ++i) {
              const Vec3& p = geometry_.positions[i];
              vertices[i * 3 + 0] = p.x;
              vertices[i * 3 + 1] = p.y;
              vertices[i * 3 + 2] = p.z;
              indices[i] = uint32_t(i);  // 3 unshared corners per triangle
            }
            rtcCommitGeometry(mesh);
            rtcAttachGeometry(scene_.get(), mesh);  // geomID 0, the only one
          }
          rtcReleaseGeometry(mesh);  // the scene holds its own reference
        }
      }
      rtcCommitScene(scene_.get());
    }
    // Errors are sticky (the first one stays until read), so one check after
    // the whole sequence catches a failure at any step.
    const RTCError code = rtcGetDeviceError(device_.get());
    if (code != RTC_ERROR_NONE || !scene_) {
      std::string message = error_log_->first();
      if (message.empty()) message = embreeErrorName(code);
      return Status(StatusCode::kInternal, "embree: building the scene of " +
                                               std::to_string(geometry_.triangleCount()) +
                                               " triangles failed: " + message);
    }
    return Status::okStatus();
  }

  void intersect(std::span<const Ray> rays, std::span<RayHit> hits) const override {
    SVIT_CHECK(rays.size() == hits.size(), "EmbreeRayCaster::intersect: %zu rays but %zu hits",
               rays.size(), hits.size());
    traceAll(rays, hits);
    // Outside the flush-to-zero scope, so a denormal direction component
    // decides front/back exactly as in the brute-force caster.
    for (size_t i = 0; i < rays.size(); ++i) {
      if (hits[i].hit())
        hits[i].front = arrivesOnFront(rays[i].direction, geometry_.normals[hits[i].triangle]);
    }
  }

  const char* name() const override { return "embree"; }

 private:
  /// Closest hits, `front` left unset.
  void traceAll(std::span<const Ray> rays, std::span<RayHit> hits) const {
    const FlushDenormalsScope denormals;
    // One rtcIntersect1 per ray, not packets: the baker's rays (random and
    // shooting patterns) are incoherent, which leaves packets little to share,
    // and on AVX2 Embree emulates 16-wide packets (third_party_notes/embree.md).
    // Single rays also win on determinism: a single ray's BVH traversal order
    // depends on that ray alone, so which of two exactly equidistant triangles is
    // reported cannot depend on which other rays share its packet, i.e. on how
    // the caller batched them.
    RTCIntersectContext context;  // per call: concurrent calls share nothing
    rtcInitIntersectContext(&context);
    for (size_t i = 0; i < rays.size(); ++i) {
      const Ray& ray = rays[i];
      RayHit& out = hits[i];
      out = RayHit{};
      float t_near = 0.0f, t_far = 0.0f;
      if (!usableSegment(ray, &t_near, &t_far)) continue;
      alignas(16) RTCRayHit query;  // Embree requires 16-byte alignment
      query.ray.org_x = ray.origin.x;
      query.ray.org_y = ray.origin.y;
      query.ray.org_z = ray.origin.z;
      query.ray.tnear = t_near;
      query.ray.dir_x = ray.direction.x;
      query.ray.dir_y = ray.direction.y;
      query.ray.dir_z = ray.direction.z;
      query.ray.time = 0.0f;
      query.ray.tfar = t_far;
      query.ray.mask = 0xffffffffu;  // every geometry (masks may be compiled in)
      query.ray.id = 0;
      query.ray.flags = 0;
      query.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      query.hit.primID = RTC_INVALID_GEOMETRY_ID;
      query.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
      rtcIntersect1(scene_.get(), &context, &query);
      if (query.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
      out.triangle = query.hit.primID;  // one geometry, so primID = triangle
      out.t = query.ray.tfar;           // Embree writes the hit distance here
      // Embree's (u, v): p = (1-u-v)*p0 + u*p1 + v*p2 (RTC_GEOMETRY_TYPE_TRIANGLE(3)),
      // the RayHit convention, and corners are in BakeGeometry order.
      out.u = query.hit.u;
      out.v = query.hit.v;
    }
  }

  const BakeGeometry& geometry_;
  // Declared before the handles so it outlives them: the device may report
  // errors while the scene is released.
  std::unique_ptr<ErrorLog> error_log_ = std::make_unique<ErrorLog>();
  EmbreeDevice device_;
  EmbreeScene scene_;  // released before device_ (reverse declaration order)
};

/// Input Embree would silently drop or misread (man rtcCommitScene: it
/// ignores primitives with NaN, Inf or coordinates beyond ~1.844e18).
Status validate(const BakeGeometry& geometry) {
  const size_t triangles = geometry.triangleCount();
  if (geometry.positions.size() != triangles * 3 || geometry.normals.size() != triangles) {
    return Status(StatusCode::kInvalidInput,
                  "BakeGeometry: " + std::to_string(triangles) + " triangles but " +
                      std::to_string(geometry.positions.size()) + " positions and " +
                      std::to_string(geometry.normals.size()) +
                      " normals (want 3 and 1 per triangle)");
  }
  // primID is a 32-bit value and RayHit::kNone is reserved; the index buffer
  // counts corners in 32 bits too.
  if (triangles * 3 >= size_t(RayHit::kNone)) {
    return Status(StatusCode::kUnsupported, "BakeGeometry: " + std::to_string(triangles) +
                                                " triangles exceed Embree's 32-bit index range");
  }
  // Embree's limit for a usable coordinate (man rtcCommitScene), metres.
  constexpr float kEmbreeMaxCoordinate = 1.844e18f;
  for (size_t t = 0; t < triangles; ++t) {
    for (int k = 0; k < 3; ++k) {
      const Vec3& p = geometry.corner(t, k);
      for (float c : {p.x, p.y, p.z}) {
        if (!std::isfinite(c) || std::fabs(c) > kEmbreeMaxCoordinate) {
          return Status(StatusCode::kInvalidInput, "BakeGeometry: triangle " + std::to_string(t) +
                                                       " corner " + std::to_string(k) +
                                                       ": coordinate " + std::to_string(c) +
                                                       " is not a finite value Embree accepts");
        }
      }
    }
  }
  return Status::okStatus();
}

}  // namespace

Expected<std::unique_ptr<RayCaster>> makeEmbreeCaster(const BakeGeometry& geometry) {
  if (Status status = validate(geometry); !status.ok()) return status;
  auto caster = std::make_unique<EmbreeRayCaster>(geometry);
  if (Status status = caster->build(); !status.ok()) return status;
  return std::unique_ptr<RayCaster>(std::move(caster));
}

}  // namespace svit::baker
