#include "house_soak.h"

#include <epoxy/gl.h>
#include <malloc.h>

#include <chrono>
#include <cmath>
#include <deque>

#include "abuse/abuse_draws.h"
#include "abuse/box_mesh.h"

namespace svit::soak {
namespace {

constexpr float kPitch = 4.2f;  // room + wall (make_house.py)
constexpr float kRoom = 4.0f;
constexpr size_t kMaxProps = 6;        // the oldest goes when a 7th arrives
constexpr uint64_t kDoorEvery = 150;   // frames between door moves
constexpr uint64_t kLampEvery = 40;    // between baked lamp switches or dims
constexpr uint64_t kDimEvery = 13;     // between the runtime lamp's dims
constexpr uint64_t kSwitchEvery = 97;  // between its switches
constexpr size_t kFailuresKept = 8;

Mat4 yRotated(const Mat4& placed, float angle) {
  Mat4 out = placed;
  const float c = std::cos(angle), s = std::sin(angle);
  out.m = {c, 0, -s, 0, 0, 1, 0, 0, s, 0, c, 0, placed.m[12], placed.m[13], placed.m[14], 1};
  return out;
}

DynamicMesh prop(abuse::Draws& draws) {
  const float half = draws.between(0.08f, 0.25f);
  DynamicMesh mesh = test::boxMesh("soak prop", half);
  for (Vec3& p : mesh.positions) p.y += half;  // standing on the floor
  mesh.albedo = {draws.between(0.1f, 0.9f), draws.between(0.1f, 0.9f), draws.between(0.1f, 0.9f)};
  return mesh;
}

// glibc's count of the bytes malloc has handed out and not had back.
uint64_t heapBytesInUse() { return uint64_t(mallinfo2().uordblks); }

bool finiteRgb(const Rgb& c) {
  return std::isfinite(c.r) && std::isfinite(c.g) && std::isfinite(c.b);
}

// The house's moving parts, found by node name.
struct HouseParts {
  std::vector<std::pair<ObjectId, Mat4>> tables, doors;  // and where the level placed them
  std::vector<uint32_t> lamps;                           // baked light emitters
  int rooms_x = 0, rooms_z = 0;
};

HouseParts findParts(const Runtime& runtime) {
  HouseParts parts;
  const Scene& scene = runtime.scene();
  for (size_t n = 0; n < scene.nodes.size(); ++n) {
    const std::string& name = scene.nodes[n].name;
    const ObjectId id = runtime.objectForNode(int(n));
    if (id == kInvalidId) continue;
    const Mat4 placed = runtime.objectInfo(id)->world_from_object;
    if (name.rfind("table_", 0) == 0) parts.tables.push_back({id, placed});
    if (name.rfind("door_", 0) == 0) parts.doors.push_back({id, placed});
  }
  const std::vector<BakeEmitter>& emitters = runtime.bake().emitters;
  for (uint32_t e = 0; e < emitters.size(); ++e) {
    if (emitters[e].kind == BakeEmitter::Kind::kLight) parts.lamps.push_back(e);
  }
  for (const auto& [id, placed] : parts.tables) {
    parts.rooms_x = std::max(parts.rooms_x, int(placed.m[12] / kPitch) + 1);
    parts.rooms_z = std::max(parts.rooms_z, int(placed.m[14] / kPitch) + 1);
  }
  return parts;
}

class Soak {
 public:
  Soak(Runtime& runtime, uint64_t seed)
      : runtime_(runtime), draws_(seed), parts_(findParts(runtime)) {
    Light lamp;
    lamp.name = "soak lamp";
    lamp.position = {kRoom / 2, 2.5f, kRoom / 2};
    lamp.intensity = 30;
    Expected<LightId> id = runtime_.addLight(lamp);
    check(id.ok(), "addLight: " + id.status().message());
    lamp_ = id.ok() ? *id : kInvalidId;
    door_open_.assign(parts_.doors.size(), true);
  }

  void frame(uint64_t i) {
    frame_ = i;
    slideTable();
    if (i % kDoorEvery == 0) moveDoor();
    if (i % kLampEvery == 0) changeBakedLamp();
    if (i % kDimEvery == 0) dimRuntimeLamp();
    if (i % kSwitchEvery == 0) switchRuntimeLamp();
    if (i % kPropEvery == 0) cycleProps();
    walkView();
    const auto start = std::chrono::steady_clock::now();
    const FrameStats stats = runtime_.update(0);
    frame_ms_ +=
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    ++timed_frames_;
    checkFrame(stats);
  }

  SoakSample sample() {
    SoakSample s;
    s.frame = frame_;
    for (const ResourceUse& use : runtime_.resources()) {
      s.host_bytes += use.cpu_bytes;
      s.gpu_bytes += use.gpu_bytes;
      s.gl_objects += use.gl_objects;
      s.lines.push_back({use.name, use.cpu_bytes + use.gpu_bytes});
      s.host_lines.push_back({use.name, use.cpu_bytes});
      if (use.name == kObjectsLine) s.object_bytes = use.cpu_bytes;
    }
    s.heap_bytes = heapBytesInUse();
    s.emitters = uint32_t(runtime_.emitterStates().size());
    s.objects = uint32_t(runtime_.objects().size());
    s.patches = uint32_t(runtime_.patchDeltas().size());
    s.mean_frame_ms = timed_frames_ ? frame_ms_ / double(timed_frames_) : 0;
    frame_ms_ = 0;
    timed_frames_ = 0;
    return s;
  }

  SoakReport report;

 private:
  void slideTable() {
    if (parts_.tables.empty()) return;
    const auto& [id, placed] = parts_.tables[frame_ % parts_.tables.size()];
    Mat4 at = placed;
    at.m[12] += 0.5f * std::sin(float(frame_) * 0.0157f + float(id));
    check(runtime_.setObjectTransform(id, at).ok(), "setObjectTransform(table)");
  }
  void moveDoor() {
    if (parts_.doors.empty()) return;
    const size_t d = (frame_ / kDoorEvery) % parts_.doors.size();
    door_open_[d] = !door_open_[d];
    const auto& [id, open] = parts_.doors[d];
    check(runtime_.setObjectTransform(id, door_open_[d] ? open : yRotated(open, 1.5707963f)).ok(),
          "setObjectTransform(door)");
    ++report.door_moves;
  }
  void changeBakedLamp() {
    if (parts_.lamps.empty()) return;
    const uint32_t lamp = parts_.lamps[draws_.below(uint32_t(parts_.lamps.size()))];
    const float scale = draws_.chance(3) ? 0.0f : draws_.chance(2) ? 1.0f : draws_.between(0.1f, 1);
    check(runtime_.setBakedEmitterScale(lamp, scale).ok(), "setBakedEmitterScale");
    ++report.light_changes;
  }
  void dimRuntimeLamp() {
    check(runtime_.setLightDimmer(lamp_, draws_.between(0.2f, 1.5f)).ok(), "setLightDimmer");
    ++report.light_changes;
  }
  void switchRuntimeLamp() {
    lamp_on_ = !lamp_on_;
    check(runtime_.setLightEnabled(lamp_, lamp_on_).ok(), "setLightEnabled");
    ++report.light_changes;
  }
  void cycleProps() {
    const int room_x = int(draws_.below(uint32_t(std::max(1, parts_.rooms_x))));
    const int room_z = int(draws_.below(uint32_t(std::max(1, parts_.rooms_z))));
    Mat4 at;
    at.m[12] = float(room_x) * kPitch + draws_.between(0.4f, kRoom - 0.4f);
    at.m[14] = float(room_z) * kPitch + draws_.between(0.4f, kRoom - 0.4f);
    Expected<ObjectId> id =
        runtime_.addObject(prop(draws_), yRotated(at, draws_.between(0, 6.28f)));
    check(id.ok(), "addObject: " + id.status().message());
    if (id.ok()) props_.push_back(*id);
    ++report.objects_added;
    if (props_.size() <= kMaxProps) return;
    check(runtime_.removeObject(props_.front()).ok(), "removeObject");
    props_.pop_front();
    ++report.objects_removed;
  }
  // A loop through every room's centre, looking along it.
  void walkView() {
    const float cx = kPitch * float(parts_.rooms_x) / 2, cz = kPitch * float(parts_.rooms_z) / 2;
    const float radius = std::hypot(cx - kRoom / 2, cz - kRoom / 2);
    const float a = float(frame_) * 0.005f;
    RuntimeView view;
    view.position = {cx + radius * std::cos(a), 1.6f, cz + radius * std::sin(a)};
    view.look_at = {view.position.x - std::sin(a), 1.5f, view.position.z + std::cos(a)};
    check(runtime_.setView(view).ok(), "setView");
  }
  void checkFrame(const FrameStats& stats) {
    check(stats.error.empty(), "update: " + stats.error);
    const GLenum gl_error = glGetError();
    check(gl_error == GL_NO_ERROR, "GL error " + std::to_string(gl_error));
    check(std::isfinite(stats.total_ms) && std::isfinite(stats.unshot_share),
          "a statistic is not finite");
    for (const EmitterRefresh& r : stats.refreshes)
      check(std::isfinite(r.importance), "an importance is not finite");
    bool finite = true;
    for (const Rgb& d : runtime_.patchDeltas()) finite = finite && finiteRgb(d);
    check(finite, "a delta is not finite");
    report.samples_rendered += stats.samples_rendered;
  }
  void check(bool holds, const std::string& what) {
    if (holds) return;
    ++report.failure_count;
    if (report.failures.size() < kFailuresKept)
      report.failures.push_back("frame " + std::to_string(frame_) + ": " + what);
  }

  Runtime& runtime_;
  abuse::SeededDraws draws_;
  HouseParts parts_;
  std::vector<bool> door_open_;
  std::deque<ObjectId> props_;
  LightId lamp_ = kInvalidId;
  bool lamp_on_ = true;
  uint64_t frame_ = 0;
  double frame_ms_ = 0;
  uint64_t timed_frames_ = 0;
};

}  // namespace

RuntimeSettings soakSettings(int samples_per_frame) {
  RuntimeSettings settings;
  settings.target_patches = 512;
  settings.target_shooters = 64;
  settings.map_resolution = 64;
  settings.max_samples_per_emitter = 4;
  settings.max_samples_per_frame = samples_per_frame;
  settings.max_refresh_interval = 8;
  settings.view_pass_width = 96;
  settings.delta_textures = false;  // shaded per pixel, as svit-walk does
  return settings;
}

std::string grownLines(const SoakSample& before, const SoakSample& after) {
  std::string out;
  for (size_t i = 0; i < after.lines.size(); ++i) {
    const uint64_t was = i < before.lines.size() ? before.lines[i].second : 0;
    if (was == after.lines[i].second) continue;
    out += after.lines[i].first + ": " + std::to_string(was) + " -> " +
           std::to_string(after.lines[i].second) + " B\n";
  }
  return out;
}

SoakReport runHouseSoak(Runtime& runtime, uint64_t seed, uint64_t frames, uint64_t sample_every) {
  Soak soak(runtime, seed);
  for (uint64_t i = 1; i <= frames; ++i) {
    soak.frame(i);
    if (i % sample_every == 0) soak.report.samples.push_back(soak.sample());
  }
  soak.report.frames = frames;
  soak.report.final_deltas = runtime.patchDeltas();
  return std::move(soak.report);
}

}  // namespace svit::soak
