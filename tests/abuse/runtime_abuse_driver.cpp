#include "runtime_abuse_driver.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>

namespace svit::abuse {
namespace {

constexpr size_t kRecentCalls = 12;  // what a finding's report shows before it
constexpr const char* kUnwritable = "/nonexistent-svit-abuse/frame";

std::string num(double v) {
  std::ostringstream out;
  out << v;
  return out.str();
}
std::string vec(const Vec3& v) { return "(" + num(v.x) + "," + num(v.y) + "," + num(v.z) + ")"; }
std::string mat(const Mat4& m) {
  std::string out = "[";
  for (size_t i = 0; i < 16; ++i) out += (i ? "," : "") + num(m.m[i]);
  return out + "]";
}
std::string light(const Light& l) {
  return std::string(l.type == LightType::kSpot    ? "spot"
                     : l.type == LightType::kPoint ? "point"
                                                   : "dir") +
         " at " + vec(l.position) + " " + num(l.intensity) + " cd cone " + num(l.inner_cone_rad) +
         "/" + num(l.outer_cone_rad);
}

// Bit-for-bit equality of two arrays (empty ones included: memcmp may not
// be handed their null data pointers).
template <typename T>
bool sameBits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

bool finiteRgb(const Rgb& c) {
  return std::isfinite(c.r) && std::isfinite(c.g) && std::isfinite(c.b);
}

// The verdict of a call with an id and a value: an unknown id is what the
// API reports first.
std::pair<Verdict, std::string> either(const Arg<uint32_t>& id, Verdict verdict,
                                       const std::string& names) {
  if (id.verdict == Verdict::kReject) return {Verdict::kReject, id.names};
  return {verdict, names};
}

LevelBox staticBox(const Runtime& runtime) {
  LevelBox box{{1e30f, 1e30f, 1e30f}, {-1e30f, -1e30f, -1e30f}};
  for (uint32_t p = 0; p < runtime.staticPatchCount(); ++p) {
    const Vec3 c = runtime.patchInfo(p)->centroid;
    box.min = {std::min(box.min.x, c.x), std::min(box.min.y, c.y), std::min(box.min.z, c.z)};
    box.max = {std::max(box.max.x, c.x), std::max(box.max.y, c.y), std::max(box.max.z, c.z)};
  }
  return box;
}

}  // namespace

Expected<Twin> makeTwin(const Scene& scene, const BakeData& bake, const std::string& bake_dir) {
  RuntimeSettings settings;
  settings.target_patches = 256;
  settings.target_shooters = 32;
  settings.map_resolution = 32;
  settings.max_samples_per_emitter = 2;
  settings.view_pass_width = 32;
  Twin twin;
  Expected<std::unique_ptr<Runtime>> runtime = Runtime::create(scene, bake, bake_dir, settings);
  if (!runtime.ok()) return runtime.status();
  twin.runtime = std::move(runtime).value();
  SceneRendererSettings frame;
  frame.width = 64;
  frame.height = 36;
  frame.shadow_map_size = 64;
  frame.shadow_taps = 4;
  Expected<std::unique_ptr<SceneRenderer>> renderer =
      SceneRenderer::create(scene, bake, bake_dir, twin.runtime.get(), frame);
  if (!renderer.ok()) return renderer.status();
  twin.renderer = std::move(renderer).value();
  return twin;
}

AbuseDriver::AbuseDriver(Twin& subject, Twin& reference, Draws& draws)
    : subject_(subject), reference_(reference), draws_(draws) {
  box_ = staticBox(*subject_.runtime);
  objects_.live = subject_.runtime->objects();
  objects_.issued = objects_.live.empty() ? 0 : objects_.live.back() + 1;
  lights_.live = subject_.runtime->lights();
  lights_.issued = lights_.live.empty() ? 0 : lights_.live.back() + 1;
  bake_emitters_ = uint32_t(subject_.runtime->bake().emitters.size());
}

void AbuseDriver::step() {
  // Weights: changes most, then the queries, an update every ~8 calls and
  // a compared frame every ~14.
  static constexpr void (AbuseDriver::*kCalls[])() = {
      &AbuseDriver::addObject,
      &AbuseDriver::addObject,
      &AbuseDriver::setTransform,
      &AbuseDriver::setTransform,
      &AbuseDriver::setTransform,
      &AbuseDriver::deform,
      &AbuseDriver::setVisible,
      &AbuseDriver::removeObject,
      &AbuseDriver::queryObject,
      &AbuseDriver::addLight,
      &AbuseDriver::setLight,
      &AbuseDriver::switchLight,
      &AbuseDriver::dimLight,
      &AbuseDriver::scaleBakedEmitter,
      &AbuseDriver::setView,
      &AbuseDriver::setSampleBudget,
      &AbuseDriver::update,
      &AbuseDriver::update,
      &AbuseDriver::update,
      &AbuseDriver::queryStatic,
      &AbuseDriver::render,
      &AbuseDriver::render,
      &AbuseDriver::scaleRenderedEmitter,
      &AbuseDriver::resize,
      &AbuseDriver::writeFrames,
      &AbuseDriver::queryResources,
  };
  constexpr uint32_t kCount = sizeof(kCalls) / sizeof(kCalls[0]);
  (this->*kCalls[draws_.below(kCount)])();
}

void AbuseDriver::settleAndCompare() {
  log("update(0) [settle]");
  const FrameStats a = subject_.runtime->update(0);
  const FrameStats b = reference_.runtime->update(0);
  checkGl("update(0)");
  compareUpdates(a, b);
  compareFrames();
}

// ---- objects ----

void AbuseDriver::addObject() {
  const Arg<DynamicMesh> mesh = drawMesh(draws_);
  const Arg<Mat4> at = drawTransform(draws_, box_);
  const auto [verdict, names] =
      mesh.verdict == Verdict::kReject ? std::pair{mesh.verdict, mesh.names}
      : at.verdict != Verdict::kAccept ? std::pair{at.verdict, at.names}
                                       : std::pair{mesh.verdict, mesh.names};
  ObjectId ids[2] = {kInvalidId, kInvalidId};
  const bool added = issue("addObject(" + std::to_string(mesh.value.indices.size() / 3) +
                               " triangles, " + mat(at.value) + ")",
                           verdict, names, [&](Twin& twin) {
                             Expected<ObjectId> id = twin.runtime->addObject(mesh.value, at.value);
                             if (!id.ok()) return id.status();
                             ids[&twin == &subject_ ? 0 : 1] = *id;
                             return Status();
                           });
  if (!added) return;
  if (ids[0] != ids[1] || ids[0] != objects_.issued) {
    finding("addObject: ids " + std::to_string(ids[0]) + " and " + std::to_string(ids[1]) +
            ", expected " + std::to_string(objects_.issued) + " (an earlier call used an id)");
  }
  objects_.live.push_back(ids[0]);
  objects_.issued = std::max(objects_.issued, ids[0] + 1);
}

void AbuseDriver::setTransform() {
  const Arg<uint32_t> id = drawId(draws_, objects_.live, objects_.gone, objects_.issued, "object");
  const Arg<Mat4> at = drawTransform(draws_, box_);
  const auto [verdict, names] = either(id, at.verdict, at.names);
  issue("setObjectTransform(" + std::to_string(id.value) + ", " + mat(at.value) + ")", verdict,
        names, [&](Twin& twin) { return twin.runtime->setObjectTransform(id.value, at.value); });
}

void AbuseDriver::deform() {
  const Arg<uint32_t> id = drawId(draws_, objects_.live, objects_.gone, objects_.issued, "object");
  Expected<ObjectInfo> info = subject_.runtime->objectInfo(id.value);
  const size_t count = info.ok() ? info->world_positions.size() : draws_.below(40);
  const Arg<std::vector<Vec3>> positions = drawPositions(draws_, count);
  const auto [verdict, names] = either(id, positions.verdict, positions.names);
  issue("deformObject(" + std::to_string(id.value) + ", " + std::to_string(positions.value.size()) +
            " positions)",
        verdict, names,
        [&](Twin& twin) { return twin.runtime->deformObject(id.value, positions.value); });
}

void AbuseDriver::setVisible() {
  const Arg<uint32_t> id = drawId(draws_, objects_.live, objects_.gone, objects_.issued, "object");
  const bool visible = draws_.chance(2);
  issue("setObjectVisible(" + std::to_string(id.value) + ", " + (visible ? "true" : "false") + ")",
        id.verdict, id.names,
        [&](Twin& twin) { return twin.runtime->setObjectVisible(id.value, visible); });
}

void AbuseDriver::removeObject() {
  const Arg<uint32_t> id = drawId(draws_, objects_.live, objects_.gone, objects_.issued, "object");
  if (!issue("removeObject(" + std::to_string(id.value) + ")", id.verdict, id.names,
             [&](Twin& twin) { return twin.runtime->removeObject(id.value); }))
    return;
  objects_.live.erase(std::find(objects_.live.begin(), objects_.live.end(), id.value));
  objects_.gone.push_back(id.value);
}

void AbuseDriver::queryObject() {
  const Arg<uint32_t> id = drawId(draws_, objects_.live, objects_.gone, objects_.issued, "object");
  const std::string call = "objectInfo(" + std::to_string(id.value) + ")";
  log(call);
  ++tally_.calls;
  Expected<ObjectInfo> info = subject_.runtime->objectInfo(id.value);
  checkRejection(call, info.status(), id.verdict, id.names);
  const uint32_t triangle = info.ok() ? draws_.below(info->patch_count + 2) : 0;
  const bool in_range = info.ok() && triangle < info->patch_count;
  ++tally_.calls;
  Expected<Rgb> irradiance = subject_.runtime->objectPatchIrradiance(id.value, triangle);
  const auto [verdict, names] =
      either(id, in_range ? Verdict::kAccept : Verdict::kReject, std::to_string(triangle));
  checkRejection(
      "objectPatchIrradiance(" + std::to_string(id.value) + ", " + std::to_string(triangle) + ")",
      irradiance.status(), verdict, names);
  if (irradiance.ok() && !finiteRgb(*irradiance)) finding(call + ": irradiance is not finite");
  checkGl(call);
}

// ---- lights ----

void AbuseDriver::addLight() {
  const Arg<Light> lamp = drawLight(draws_, box_);
  LightId ids[2] = {kInvalidId, kInvalidId};
  const bool added =
      issue("addLight(" + light(lamp.value) + ")", lamp.verdict, lamp.names, [&](Twin& twin) {
        Expected<LightId> id = twin.runtime->addLight(lamp.value);
        if (!id.ok()) return id.status();
        ids[&twin == &subject_ ? 0 : 1] = *id;
        return Status();
      });
  if (!added) return;
  if (ids[0] != ids[1] || ids[0] != lights_.issued)
    finding("addLight: ids " + std::to_string(ids[0]) + " and " + std::to_string(ids[1]) +
            ", expected " + std::to_string(lights_.issued));
  lights_.live.push_back(ids[0]);
  lights_.issued = std::max(lights_.issued, ids[0] + 1);
}

void AbuseDriver::setLight() {
  const Arg<uint32_t> id = drawId(draws_, lights_.live, lights_.gone, lights_.issued, "light");
  const Arg<Light> lamp = drawLight(draws_, box_);
  const auto [verdict, names] = either(id, lamp.verdict, lamp.names);
  issue("setLight(" + std::to_string(id.value) + ", " + light(lamp.value) + ")", verdict, names,
        [&](Twin& twin) { return twin.runtime->setLight(id.value, lamp.value); });
}

void AbuseDriver::switchLight() {
  const Arg<uint32_t> id = drawId(draws_, lights_.live, lights_.gone, lights_.issued, "light");
  const bool on = draws_.chance(2);
  issue("setLightEnabled(" + std::to_string(id.value) + ", " + (on ? "true" : "false") + ")",
        id.verdict, id.names,
        [&](Twin& twin) { return twin.runtime->setLightEnabled(id.value, on); });
}

void AbuseDriver::dimLight() {
  const Arg<uint32_t> id = drawId(draws_, lights_.live, lights_.gone, lights_.issued, "light");
  const Arg<float> dimmer = drawScale(draws_, "dimmer");
  const auto [verdict, names] = either(id, dimmer.verdict, dimmer.names);
  issue("setLightDimmer(" + std::to_string(id.value) + ", " + num(dimmer.value) + ")", verdict,
        names, [&](Twin& twin) { return twin.runtime->setLightDimmer(id.value, dimmer.value); });
}

void AbuseDriver::scaleBakedEmitter() {
  const uint32_t emitter = draws_.below(bake_emitters_ + 3);
  const Arg<uint32_t> id =
      emitter < bake_emitters_
          ? Arg<uint32_t>{emitter, Verdict::kAccept, ""}
          : Arg<uint32_t>{emitter, Verdict::kReject, "emitter " + std::to_string(emitter)};
  const Arg<float> scale = drawScale(draws_, "scale");
  const auto [verdict, names] = either(id, scale.verdict, scale.names);
  issue("setBakedEmitterScale(" + std::to_string(emitter) + ", " + num(scale.value) + ")", verdict,
        names,
        [&](Twin& twin) { return twin.runtime->setBakedEmitterScale(emitter, scale.value); });
}

// ---- per frame ----

void AbuseDriver::setView() {
  if (draws_.chance(5)) {
    log("clearView()");
    ++tally_.calls;
    subject_.runtime->clearView();
    reference_.runtime->clearView();
    return;
  }
  const Arg<RuntimeView> view = drawView(draws_, box_);
  issue("setView(" + vec(view.value.position) + " -> " + vec(view.value.look_at) + " fov " +
            num(view.value.yfov_rad) + " aspect " + num(view.value.aspect) + " near " +
            num(view.value.near_m) + ")",
        view.verdict, view.names, [&](Twin& twin) { return twin.runtime->setView(view.value); });
}

void AbuseDriver::setSampleBudget() {
  const Arg<int> budget = drawSampleBudget(draws_);
  issue("setSampleBudget(" + std::to_string(budget.value) + ")", budget.verdict, budget.names,
        [&](Twin& twin) { return twin.runtime->setSampleBudget(budget.value); });
}

void AbuseDriver::update() {
  const Arg<double> budget = drawUpdateBudget(draws_);
  const std::string call = "update(" + num(budget.value) + ")";
  log(call);
  ++tally_.calls;
  const FrameStats a = subject_.runtime->update(budget.value);
  checkGl(call);
  const Status status = a.error.empty() ? Status() : Status(StatusCode::kInvalidInput, a.error);
  checkRejection(call, status, budget.verdict, budget.names);
  if (!status.ok()) return;
  compareUpdates(a, reference_.runtime->update(budget.value));
}

void AbuseDriver::queryStatic() {
  const uint32_t patches = subject_.runtime->staticPatchCount();
  const uint32_t patch = draws_.below(patches + 3);
  const std::string call = "patchInfo(" + std::to_string(patch) + ")";
  log(call);
  tally_.calls += 3;
  Expected<PatchInfo> info = subject_.runtime->patchInfo(patch);
  checkRejection(call, info.status(), patch < patches ? Verdict::kAccept : Verdict::kReject,
                 std::to_string(patch));
  // At a patch, along its normal, the irradiance is a number; at a NaN
  // point it is NaN (documented), never a crash.
  const Vec3 point = info.ok() ? info->centroid : Vec3{NAN, 0, 0};
  const Vec3 normal = info.ok() ? info->normal : Vec3{0, 1, 0};
  const Rgb at = subject_.runtime->irradianceAt(point, normal);
  if (info.ok() && !finiteRgb(at))
    finding("irradianceAt" + vec(point) + ": not finite at a static patch");
  for (const EmitterState& e : subject_.runtime->emitterStates()) {
    if (!std::isfinite(e.importance)) finding("emitterStates: importance not finite");
  }
  checkGl(call);
}

// ---- frames ----

void AbuseDriver::render() {
  const Arg<Camera> camera = drawCamera(draws_, box_);
  const Arg<ShadingView> view = drawShadingView(draws_);
  const auto [verdict, names] = camera.verdict == Verdict::kReject
                                    ? std::pair{camera.verdict, camera.names}
                                    : std::pair{view.verdict, view.names};
  const bool drawn =
      issue("render(" + vec(camera.value.position) + " -> " + vec(camera.value.look_at) + " fov " +
                num(camera.value.yfov_rad) + " near/far " + num(camera.value.near_m) + "/" +
                num(camera.value.far_m) + ", view " + std::to_string(int(view.value)) + ")",
            verdict, names, [&](Twin& twin) {
              Expected<RenderStats> stats = twin.renderer->render(camera.value, view.value);
              return stats.ok() ? Status() : stats.status();
            });
  if (drawn) compareFrames();
}

void AbuseDriver::scaleRenderedEmitter() {
  const uint32_t emitter = draws_.below(bake_emitters_ + 3);
  const Arg<float> scale = drawScale(draws_, "scale");
  const auto [verdict, names] =
      emitter < bake_emitters_ ? std::pair{scale.verdict, scale.names}
                               : std::pair{Verdict::kReject, "emitter " + std::to_string(emitter)};
  issue("SceneRenderer::setBakedEmitterScale(" + std::to_string(emitter) + ", " + num(scale.value) +
            ")",
        verdict, names,
        [&](Twin& twin) { return twin.renderer->setBakedEmitterScale(emitter, scale.value); });
}

void AbuseDriver::resize() {
  static constexpr int kSizes[][2] = {{64, 36}, {48, 48},      {80, 45},     {0, 36},
                                      {64, -1}, {1 << 20, 36}, {64, 1 << 20}};
  const uint32_t choice = draws_.below(7);
  const int w = kSizes[choice][0], h = kSizes[choice][1];
  const bool valid = choice < 3;
  issue("resize(" + std::to_string(w) + ", " + std::to_string(h) + ")",
        valid ? Verdict::kAccept : Verdict::kReject, std::to_string(w) + "x" + std::to_string(h),
        [&](Twin& twin) { return twin.renderer->resize(w, h); });
}

void AbuseDriver::writeFrames() {
  const std::string png = std::string(kUnwritable) + ".png",
                    exr = std::string(kUnwritable) + ".exr";
  log("writePng/writeExr(" + png + ")");
  tally_.calls += 2;
  checkRejection("writePng", subject_.renderer->writePng(png), Verdict::kReject, png);
  checkRejection("writeExr", subject_.renderer->writeExr(exr), Verdict::kReject, exr);
}

void AbuseDriver::queryResources() {
  log("resources()");
  tally_.calls += 3;
  uint64_t bytes = 0;
  for (const ResourceUse& use : subject_.runtime->resources())
    bytes += use.gpu_bytes + use.cpu_bytes;
  for (const ResourceUse& use : subject_.renderer->resources()) bytes += use.gpu_bytes;
  const ShadingResources shading = subject_.runtime->shadingResources();
  if (shading.patch_delta_buffer != 0 && shading.patch_count == 0)
    finding("shadingResources: a delta buffer of no patches");
  if (bytes == 0) finding("resources(): nothing held (the lightmap pages at least)");
  checkGl("resources()");
}

// ---- checks ----

template <typename Call>
bool AbuseDriver::issue(const std::string& call, Verdict verdict, const std::string& names,
                        Call&& make) {
  log(call);
  ++tally_.calls;
  const Status got = make(subject_);
  checkGl(call);
  checkRejection(call, got, verdict, names);
  if (!got.ok()) return false;
  const Status twin = make(reference_);
  if (!twin.ok())
    finding(call + ": the reference refused what the subject took: " + twin.message());
  return true;
}

void AbuseDriver::checkRejection(const std::string& call, const Status& status, Verdict verdict,
                                 const std::string& names) {
  if (status.ok()) {
    if (verdict == Verdict::kReject) finding(call + ": accepted, but '" + names + "' is invalid");
    if (verdict == Verdict::kMayReject) ++tally_.extreme_accepted;
    return;
  }
  if (verdict == Verdict::kAccept) finding(call + ": refused a valid call: " + status.message());
  if (verdict == Verdict::kReject) ++tally_.rejected;
  if (verdict == Verdict::kMayReject) ++tally_.extreme_rejected;
  if (!names.empty() && status.message().find(names) == std::string::npos)
    finding(call + ": the error '" + status.message() + "' does not name '" + names + "'");
}

void AbuseDriver::compareUpdates(const FrameStats& a, const FrameStats& b) {
  ++tally_.updates;
  const std::string update = "update " + std::to_string(tally_.updates);
  if (!a.error.empty()) finding(update + " failed: " + a.error);
  if (a.idle != b.idle || a.emitters_refreshed != b.emitters_refreshed ||
      a.emitters_pending != b.emitters_pending || a.samples_rendered != b.samples_rendered ||
      a.triangles_drawn != b.triangles_drawn || a.bounce_rounds != b.bounce_rounds ||
      std::memcmp(&a.unshot_share, &b.unshot_share, sizeof(double)) != 0 ||
      a.refreshes.size() != b.refreshes.size()) {
    finding(update + ": the twins did different work (" + std::to_string(a.samples_rendered) +
            " and " + std::to_string(b.samples_rendered) + " samples, " +
            std::to_string(a.emitters_refreshed) + " and " + std::to_string(b.emitters_refreshed) +
            " emitters)");
  }
  if (!std::isfinite(a.unshot_share) || !std::isfinite(a.total_ms))
    finding(update + ": a statistic is not finite");
  const std::vector<Rgb>& da = subject_.runtime->patchDeltas();
  const std::vector<Rgb>& db = reference_.runtime->patchDeltas();
  if (!sameBits(da, db))
    finding(update + ": the twins' deltas differ (an earlier call changed the subject)");
  if (!std::all_of(da.begin(), da.end(), finiteRgb)) finding(update + ": a delta is not finite");
  if (subject_.runtime->objects() != reference_.runtime->objects() ||
      subject_.runtime->lights() != reference_.runtime->lights())
    finding(update + ": the twins hold different objects or lights");
}

void AbuseDriver::compareFrames() {
  ++tally_.frames;
  const std::vector<float> a = subject_.renderer->readRadiance();
  const std::vector<float> b = reference_.renderer->readRadiance();
  const std::string frame = "frame " + std::to_string(tally_.frames);
  if (!sameBits(a, b)) finding(frame + ": the twins' frames differ");
  if (!std::all_of(a.begin(), a.end(), [](float v) { return std::isfinite(v); }))
    finding(frame + ": a pixel's radiance is not finite");
}

void AbuseDriver::checkGl(const std::string& call) {
  const GLenum error = glGetError();
  if (error != GL_NO_ERROR) finding(call + ": GL error " + std::to_string(error));
}

void AbuseDriver::finding(const std::string& what) {
  std::string report = what + "\n  after:";
  for (const std::string& call : recent_) report += "\n    " + call;
  tally_.findings.push_back(report);
}

void AbuseDriver::log(const std::string& call) {
  recent_.push_back(call);
  if (recent_.size() > kRecentCalls) recent_.pop_front();
}

}  // namespace svit::abuse
