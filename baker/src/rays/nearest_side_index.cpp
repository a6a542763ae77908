#include "nearest_side_index.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "util/double_math.h"

namespace svit::baker {

// Closest point to p on the triangle (Ericson, Real-Time Collision
// Detection, 5.1.5), as a squared distance.
double distance2ToTriangle(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b,
                           const glm::dvec3& c) {
  const glm::dvec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  auto d2to = [&](const glm::dvec3& q) { return glm::dot(p - q, p - q); };
  if (d1 <= 0 && d2 <= 0) return d2to(a);
  const glm::dvec3 bp = p - b;
  const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return d2to(b);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return d2to(a + ab * (d1 / (d1 - d3)));
  const glm::dvec3 cp = p - c;
  const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return d2to(c);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return d2to(a + ac * (d2 / (d2 - d6)));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return d2to(b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))));
  const double denom = 1.0 / (va + vb + vc);
  return d2to(a + ab * (vb * denom) + ac * (vc * denom));
}

namespace {

// One query's input and its best side so far (the callback's user data).
struct Query {
  const BakeGeometry* geometry;
  const std::vector<TriangleSide>* sides;
  glm::dvec3 p, n;
  bool any_side;
  double best = std::numeric_limits<double>::infinity();  // squared distance
  uint32_t best_index = std::numeric_limits<uint32_t>::max();
};

// Embree calls this for every side whose bounds lie within the query's
// radius; the radius then shrinks to the best distance found.
bool visitSide(RTCPointQueryFunctionArguments* args) {
  Query& q = *static_cast<Query*>(args->userPtr);
  const uint32_t index = args->primID;
  const TriangleSide& side = (*q.sides)[index];
  if (!q.any_side && !(glm::dot(side.normal, q.n) > 0)) return false;
  const BakeGeometry& g = *q.geometry;
  const double d2 =
      distance2ToTriangle(q.p, dvec(g.corner(side.triangle, 0)), dvec(g.corner(side.triangle, 1)),
                          dvec(g.corner(side.triangle, 2)));
  if (!(d2 < q.best || (d2 == q.best && index < q.best_index))) return false;
  q.best = d2;
  q.best_index = index;
  // Embree culls in float around the float-rounded point: the slack keeps
  // every side at the best distance (ties) in reach.
  const double slack = 1e-6 * (std::sqrt(d2) + glm::length(q.p)) + 1e-30;
  const float radius = float(std::sqrt(d2) + slack);
  if (!(radius < args->query->radius)) return false;
  args->query->radius = radius;
  return true;
}

}  // namespace

Expected<NearestSideIndex> NearestSideIndex::build(RTCDevice device, const BakeGeometry& geometry,
                                                   const std::vector<TriangleSide>& sides) {
  NearestSideIndex index;
  index.geometry_ = &geometry;
  index.sides_ = &sides;
  index.scene_.reset(rtcNewScene(device));
  if (index.scene_ && !sides.empty()) {
    RTCGeometry mesh = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    if (mesh) {
      // Three corners per side, primID = side index (both sides of a
      // triangle are two primitives).
      auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
          mesh, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), sides.size() * 3));
      auto* indices = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(
          mesh, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(uint32_t), sides.size()));
      if (vertices && indices) {
        for (size_t s = 0; s < sides.size(); ++s) {
          for (int k = 0; k < 3; ++k) {
            const Vec3& c = geometry.corner(sides[s].triangle, k);
            float* v = vertices + (s * 3 + size_t(k)) * 3;
            v[0] = c.x;
            v[1] = c.y;
            v[2] = c.z;
            indices[s * 3 + size_t(k)] = uint32_t(s * 3 + size_t(k));
          }
        }
        rtcCommitGeometry(mesh);
        rtcAttachGeometry(index.scene_.get(), mesh);
      }
      rtcReleaseGeometry(mesh);
    }
  }
  if (index.scene_) rtcCommitScene(index.scene_.get());
  const RTCError code = rtcGetDeviceError(device);
  if (code != RTC_ERROR_NONE || !index.scene_) {
    return Status(StatusCode::kInternal, "runtime sections: the nearest-side index of " +
                                             std::to_string(sides.size()) +
                                             " triangle sides failed: " + embreeErrorName(code));
  }
  return index;
}

int32_t NearestSideIndex::nearest(const glm::dvec3& p, const glm::dvec3& n, bool any_side) const {
  Query q{geometry_, sides_, p, n, any_side};
  alignas(16) RTCPointQuery query;
  query.x = float(p.x);
  query.y = float(p.y);
  query.z = float(p.z);
  query.time = 0.0f;
  query.radius = std::numeric_limits<float>::infinity();
  RTCPointQueryContext context;
  rtcInitPointQueryContext(&context);
  rtcPointQuery(scene_.get(), &query, &context, &visitSide, &q);
  return q.best_index == std::numeric_limits<uint32_t>::max() ? -1 : int32_t(q.best_index);
}

}  // namespace svit::baker
