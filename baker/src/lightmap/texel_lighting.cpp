// Texel lighting: next-event estimation for direct light (point and spot
// lights, directional lights and the sun's disk, emissive surfaces picked by
// flux), and a one-bounce final gather against the interpolated radiosity
// solution for indirect light, with rays that escape seeing the sky.

#include "svit/baker/texel_lighting.h"
#include "util/double_math.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

#include "util/parallel_for.h"
#include "util/random.h"
#include "util/sampling.h"

namespace svit::baker {
namespace {

struct PointLight {
  glm::dvec3 position;
  glm::dvec3 intensity;  // cd per channel
  bool spot = false;
  glm::dvec3 axis{0, -1, 0};
  double cos_inner = 1, cos_outer = 0;
};

struct DirectionalLight {
  glm::dvec3 travel;       // unit, the way light goes
  glm::dvec3 illuminance;  // lux per channel on a surface facing it
  double cos_radius = 1;   // 1: a point at infinity
};

struct Emitter {
  uint32_t triangle;
  glm::dvec3 luminance;  // cd/m2
  bool double_sided;
};

double spotFactor(const PointLight& light, const glm::dvec3& to_receiver) {
  if (!light.spot) return 1.0;
  const double c = glm::dot(light.axis, to_receiver);
  const double t = std::clamp(
      (c - light.cos_outer) / std::max(1e-9, light.cos_inner - light.cos_outer), 0.0, 1.0);
  return t * t;
}

// What one ray of a texel contributes once its hit is known.
struct Contribution {
  enum class Kind : uint8_t { kShadow, kGather } kind;
  glm::dvec3 weight;  // shadow: added when unoccluded; gather: unused
  glm::dvec3 toward;  // gather: direction (for the sky)
};

// The static lights as the texel loop samples them.
struct TexelLights {
  std::vector<PointLight> points;
  std::vector<DirectionalLight> directionals;  // the sun's disk last
  std::vector<Emitter> emitters;
  std::vector<double> emitter_cdf;  // running flux sum, lm
  double emitter_total = 0;
};

bool isMasked(const MaskedLights& masked, uint32_t light) {
  return std::find(masked.lights.begin(), masked.lights.end(), light) != masked.lights.end();
}

PointLight pointLightOf(const Light& light) {
  PointLight p;
  p.position = dvec(light.position);
  p.intensity = dvec(light.color) * double(light.intensity);
  p.spot = light.type == LightType::kSpot;
  p.axis = glm::normalize(dvec(light.direction));
  p.cos_inner = std::cos(double(light.inner_cone_rad));
  p.cos_outer = std::cos(double(light.outer_cone_rad));
  return p;
}

DirectionalLight sunOf(const Sun& sun) {
  return {-glm::normalize(dvec(sun.direction_to_sun)),
          dvec(sun.color) * double(sun.illuminance_lux), std::cos(double(sun.angular_radius_rad))};
}

// The static lights the lightmap's direct light sums: all but the masked
// ones (their shadow masks hold their direct light).
void collectAnalyticLights(const Scene& scene, const MaskedLights& masked, TexelLights& lights) {
  for (uint32_t i = 0; i < scene.lights.size(); ++i) {
    const Light& light = scene.lights[i];
    if (light.dynamic || isMasked(masked, i)) continue;  // runtime lights are lit at run time
    if (light.type == LightType::kDirectional) {
      lights.directionals.push_back({glm::normalize(dvec(light.direction)),
                                     dvec(light.color) * double(light.intensity), 1.0});
    } else {
      lights.points.push_back(pointLightOf(light));
    }
  }
  if (scene.sun.enabled && scene.sun.illuminance_lux > 0 && !masked.sun)
    lights.directionals.push_back(sunOf(scene.sun));
}

// The emissive triangles the lightmap's direct light sums: all but those
// of masked area lights (their masks hold it).
void collectEmitters(const BakeGeometry& geometry, const MaskedLights& masked,
                     TexelLights& lights) {
  for (size_t t = 0; t < geometry.triangleCount(); ++t) {
    if (masked.masksInstance(geometry.instance[t])) continue;
    const glm::dvec3 l = dvec(geometry.emission[t]);
    const double flux =
        luminanceOf(l) * geometry.areas_m2[t] * (geometry.double_sided[t] ? 2.0 : 1.0);
    if (flux > 0) {
      lights.emitters.push_back({uint32_t(t), l, geometry.double_sided[t] != 0});
      lights.emitter_cdf.push_back(lights.emitter_total += flux);
    }
  }
}

glm::dvec3 skyRadiance(const Sky& sky, const glm::dvec3& toward_sky) {
  if (sky.model == SkyModel::kNone) return glm::dvec3(0.0);
  const double mu = toward_sky.y;
  if (sky.model == SkyModel::kUniform) return mu > 0 ? dvec(sky.zenith_luminance) : glm::dvec3(0.0);
  if (mu <= 0) return dvec(sky.ground_luminance);
  return dvec(sky.horizon_luminance) +
         (dvec(sky.zenith_luminance) - dvec(sky.horizon_luminance)) * mu;
}

// What the texel stages read: the scene, the lights, the settings.
struct LightingContext {
  const Scene& scene;
  const BakeGeometry& geometry;
  const RayCaster& caster;
  const RadiositySolver& solver;
  const TexelLightingSettings& settings;
  const TexelLights& lights;
};

// One texel's rays, each with its contribution; scratch reused per texel.
struct TexelRays {
  Vec3 origin{};              // offset off the surface
  glm::dvec3 o{0.0};          // origin in double
  glm::dvec3 p{0.0}, n{0.0};  // texel position and normal
  std::vector<Ray> rays;
  std::vector<Contribution> contributions;
  std::vector<RayHit> hits;
  std::vector<double> light_cdf;    // many-light sampling
  std::vector<double> emitter_cdf;  // importance of each emitter at this texel, running sum
  std::vector<glm::dvec3> light_e;

  void shadowTo(const glm::dvec3& target, const glm::dvec3& weight) {
    Ray ray;
    ray.origin = origin;
    ray.direction = vec3(target - o);
    ray.t_near = 0.0f;
    ray.t_far = 0.9999f;  // stop short of the light's own surface
    rays.push_back(ray);
    contributions.push_back({Contribution::Kind::kShadow, weight, glm::dvec3(0.0)});
  }
  void shadowAlong(const glm::dvec3& toward, const glm::dvec3& weight) {
    Ray ray;
    ray.origin = origin;
    ray.direction = vec3(toward);
    rays.push_back(ray);
    contributions.push_back({Contribution::Kind::kShadow, weight, glm::dvec3(0.0)});
  }
};

// Unshadowed irradiance at (p, n) from a point or spot light: E = I * cos / d^2.
glm::dvec3 pointIrradiance(const PointLight& light, const glm::dvec3& p, const glm::dvec3& n) {
  const glm::dvec3 to_light = light.position - p;
  const double d2 = glm::dot(to_light, to_light);
  if (!(d2 > 0)) return glm::dvec3(0.0);
  const glm::dvec3 l = to_light / std::sqrt(d2);
  const double cos_r = glm::dot(n, l);
  if (cos_r <= 0) return glm::dvec3(0.0);
  return light.intensity * (spotFactor(light, -l) * cos_r / d2);
}

// Point and spot lights: exact, one shadow ray each, or importance-sampled
// by unshadowed irradiance when there are many.
void addPointLightRays(const LightingContext& c, Rng& rng, TexelRays& t) {
  const std::vector<PointLight>& points = c.lights.points;
  if (points.size() <= c.settings.max_point_lights) {
    for (const PointLight& light : points) {
      const glm::dvec3 e = pointIrradiance(light, t.p, t.n);
      if (luminanceOf(e) > 0) t.shadowTo(light.position, e);
    }
    return;
  }
  std::vector<double>& cdf = t.light_cdf;
  std::vector<glm::dvec3>& e = t.light_e;
  double total = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    e[i] = pointIrradiance(points[i], t.p, t.n);
    cdf[i] = (total += luminanceOf(e[i]));
  }
  if (!(total > 0)) return;
  const uint32_t k = c.settings.max_point_lights;
  for (uint32_t s = 0; s < k; ++s) {
    const double pick = (double(s) + rng.uniformDouble()) / double(k) * total;  // stratified
    const size_t i = std::min(points.size() - 1,
                              size_t(std::lower_bound(cdf.begin(), cdf.end(), pick) - cdf.begin()));
    const double probability = luminanceOf(e[i]) / total;
    if (probability > 0) t.shadowTo(points[i].position, e[i] / (probability * double(k)));
  }
}

// Directional lights and the sun's disk (uniform radiance over the cone:
// E = E_sun * (solid angle / (pi sin^2 a)) * mean(cos * visible)).
void addDirectionalLightRays(const DirectionalLight& light, uint32_t disk_samples, Rng& rng,
                             TexelRays& t) {
  const glm::dvec3 toward = -light.travel;
  if (light.cos_radius >= 1.0) {
    const double cos_r = glm::dot(t.n, toward);
    if (cos_r > 0) t.shadowAlong(toward, light.illuminance * cos_r);
    return;
  }
  const double sin2 = 1.0 - light.cos_radius * light.cos_radius;
  const double scale = 2.0 * kPi * (1.0 - light.cos_radius) / (kPi * sin2);
  for (uint32_t s = 0; s < disk_samples; ++s) {
    const double cos_theta =
        1.0 - (double(s) + rng.uniformDouble()) / double(disk_samples) * (1.0 - light.cos_radius);
    const glm::dvec3 d = directionAt(toward, cos_theta, rng.uniformDouble());
    const double cos_r = glm::dot(t.n, d);
    if (cos_r > 0) t.shadowAlong(d, light.illuminance * (scale * cos_r / double(disk_samples)));
  }
}

void addDirectionalRays(const LightingContext& c, Rng& rng, TexelRays& t) {
  for (const DirectionalLight& light : c.lights.directionals)
    addDirectionalLightRays(light, c.settings.sun_samples, rng, t);
}

// A point on an emitter triangle for the texel at `p` (normal `n`), and
// its estimate of the integral of cos_r over the triangle's solid angle
// (irradiance per unit radiance), 0 when it sees the triangle's back or
// nothing. By solid angle where the triangle looks large (beside a lamp,
// where area sampling's 1 / d^2 has unbounded variance: a texel a
// millimetre from an emitter's edge), by area where it looks small (where
// solid angles of tiny far triangles lose precision and the two agree).
struct EmitterSample {
  glm::dvec3 point{0.0};
  glm::dvec3 normal{0.0};  ///< of the side seen
  double cosine_solid_angle = 0;
};

constexpr double kSolidAngleSamplingSr = 1e-3;

EmitterSample sampleEmitter(const BakeGeometry& geometry, const Emitter& emitter,
                            const glm::dvec3& p, const glm::dvec3& n, double r1, double r2) {
  EmitterSample out;
  const glm::dvec3 c0 = dvec(geometry.corner(emitter.triangle, 0));
  const glm::dvec3 c1 = dvec(geometry.corner(emitter.triangle, 1));
  const glm::dvec3 c2 = dvec(geometry.corner(emitter.triangle, 2));
  out.normal = dvec(geometry.normals[emitter.triangle]);
  double height = glm::dot(p - c0, out.normal);  // of p above the side it sees
  if (emitter.double_sided && height < 0) {
    out.normal = -out.normal;
    height = -height;
  }
  if (!(height > 0)) return out;
  const glm::dvec3 a = glm::normalize(c0 - p), b = glm::normalize(c1 - p),
                   c = glm::normalize(c2 - p);
  const double solid_angle = sphericalTriangleArea(a, b, c);
  if (solid_angle > kSolidAngleSamplingSr) {
    const glm::dvec3 w = sphericalTriangleDirection(a, b, c, solid_angle, r1, r2);
    const double approach = -glm::dot(w, out.normal);
    if (!(approach > 0)) return out;
    out.point = p + w * (height / approach);
    out.cosine_solid_angle = std::max(0.0, glm::dot(n, w)) * solid_angle;
    return out;
  }
  const glm::dvec2 bary = uniformTriangle(r1, r2);
  out.point = c0 + bary.x * (c1 - c0) + bary.y * (c2 - c0);
  const glm::dvec3 to_emitter = out.point - p;
  const double d2 = glm::dot(to_emitter, to_emitter);
  if (!(d2 > 0)) return out;
  const glm::dvec3 l = to_emitter / std::sqrt(d2);
  const double cos_r = glm::dot(n, l), cos_e = -glm::dot(out.normal, l);
  if (cos_r <= 0 || cos_e <= 0) return out;
  out.cosine_solid_angle = cos_r * cos_e / d2 * geometry.areas_m2[emitter.triangle];
  return out;
}

// Up to this many emitter triangles, each texel weighs them by what they
// give it (texelEmitterImportance); beyond, by their flux alone.
constexpr size_t kTexelImportanceEmitters = 64;

// The running sum of each emitter's importance at texel `t`: its solid
// angle times the cosine toward its middle (at least 0.05 of it, so a
// grazing strip that lights the texel is still picked), times its
// luminance; 0 for those it cannot light (behind the texel's horizon or
// seen from their dark side). Returns the total.
double texelEmitterImportance(const LightingContext& c, uint32_t texel_triangle, const TexelRays& t,
                              std::vector<double>& cdf) {
  const BakeGeometry& geometry = c.geometry;
  double total = 0;
  for (size_t i = 0; i < c.lights.emitters.size(); ++i) {
    const Emitter& emitter = c.lights.emitters[i];
    double importance = 0;
    const glm::dvec3 corner[3] = {dvec(geometry.corner(emitter.triangle, 0)),
                                  dvec(geometry.corner(emitter.triangle, 1)),
                                  dvec(geometry.corner(emitter.triangle, 2))};
    const glm::dvec3 normal = dvec(geometry.normals[emitter.triangle]);
    const double height = glm::dot(t.p - corner[0], normal);
    const bool lit_side = emitter.double_sided ? height != 0 : height > 0;
    if (emitter.triangle != texel_triangle && lit_side) {
      glm::dvec3 to[3];
      double highest = -1;  // cosine of the corner highest above the texel's horizon
      for (int k = 0; k < 3; ++k) {
        to[k] = glm::normalize(corner[k] - t.p);
        highest = std::max(highest, glm::dot(t.n, to[k]));
      }
      if (highest > 0) {
        double solid_angle = sphericalTriangleArea(to[0], to[1], to[2]);
        const glm::dvec3 middle = (corner[0] + corner[1] + corner[2]) / 3.0 - t.p;
        const double d2 = glm::dot(middle, middle);
        if (solid_angle < kSolidAngleSamplingSr && d2 > 0)  // small: the area's form is exact
          solid_angle = geometry.areas_m2[emitter.triangle] * std::abs(glm::dot(normal, middle)) /
                        (d2 * std::sqrt(d2));
        const double cosine = d2 > 0 ? glm::dot(t.n, middle) / std::sqrt(d2) : 0.0;
        importance = luminanceOf(emitter.luminance) * solid_angle * std::max(cosine, 0.05);
      }
    }
    cdf[i] = (total += importance);
  }
  return total;
}

// Emissive surfaces, picked in proportion to their importance at the texel
// (few emitters) or their flux (many). Points form a 2-D
// stratified set over all emitters: the first coordinate is stratified
// along the flux CDF (its remainder inside the chosen emitter places the
// point), the second follows a randomly shifted rank-1 lattice (golden
// ratio). Stratification matters most where a texel takes few samples of a
// large, near lamp (16 of a 1 m lamp 3 m away): independent points leave
// several percent of noise per texel there, stratified ones under one.
void addEmitterRays(const LightingContext& c, uint32_t texel_triangle, Rng& rng, TexelRays& t) {
  const TexelLights& lights = c.lights;
  const BakeGeometry& geometry = c.geometry;
  if (lights.emitters.empty()) return;
  const bool per_texel = lights.emitters.size() <= kTexelImportanceEmitters;
  const double emitter_total = per_texel
                                   ? texelEmitterImportance(c, texel_triangle, t, t.emitter_cdf)
                                   : lights.emitter_total;
  if (!(emitter_total > 0)) return;
  const std::vector<double>& emitter_cdf = per_texel ? t.emitter_cdf : lights.emitter_cdf;
  const uint32_t count = c.settings.area_light_samples;
  const double shift = rng.uniformDouble();
  for (uint32_t s = 0; s < count; ++s) {
    const double pick = (double(s) + rng.uniformDouble()) / double(count) * emitter_total;
    const size_t i =
        std::min(lights.emitters.size() - 1,
                 size_t(std::lower_bound(emitter_cdf.begin(), emitter_cdf.end(), pick) -
                        emitter_cdf.begin()));
    const Emitter& emitter = lights.emitters[i];
    if (emitter.triangle == texel_triangle) continue;
    const double low = i > 0 ? emitter_cdf[i - 1] : 0.0;
    const double probability = (emitter_cdf[i] - low) / emitter_total;
    if (!(probability > 0)) continue;  // a pick on the edge of an emitter that gives nothing
    const double r1 = std::clamp((pick - low) / (emitter_cdf[i] - low), 0.0, 1.0 - 1e-12);
    const double r2 = std::fmod(double(s) * 0.6180339887498949 + shift, 1.0);
    const EmitterSample sample = sampleEmitter(geometry, emitter, t.p, t.n, r1, r2);
    if (!(sample.cosine_solid_angle > 0)) continue;
    const glm::dvec3 e =
        emitter.luminance * (sample.cosine_solid_angle / (probability * double(count)));
    const Vec3 target = offsetRayOrigin(vec3(sample.point), vec3(sample.normal),
                                        cornerMagnitude(geometry, emitter.triangle));
    t.shadowTo(dvec(target), e);
  }
}

// Final gather: cosine-weighted, stratified on a jittered grid.
void addGatherRays(const LightingContext& c, Rng& rng, TexelRays& t) {
  const uint32_t gather = c.settings.gather_rays;
  const uint32_t side = std::max(1u, uint32_t(std::sqrt(double(gather))));
  for (uint32_t g = 0; g < gather; ++g) {
    const double u1 =
        g < side * side ? (double(g % side) + rng.uniformDouble()) / side : rng.uniformDouble();
    const double u2 =
        g < side * side ? (double(g / side) + rng.uniformDouble()) / side : rng.uniformDouble();
    const glm::dvec3 d = cosineHemisphere(t.n, u1, u2);
    Ray ray;
    ray.origin = t.origin;
    ray.direction = vec3(d);
    t.rays.push_back(ray);
    t.contributions.push_back({Contribution::Kind::kGather, glm::dvec3(0.0), d});
  }
}

// Casts the texel's rays and sums what they found: unoccluded shadow rays
// add their weight, gather rays the sky or the radiosity they hit.
TexelIrradiance sumContributions(const LightingContext& c, TexelRays& t) {
  const BakeGeometry& geometry = c.geometry;
  t.hits.resize(t.rays.size());
  c.caster.intersect(t.rays, t.hits);
  glm::dvec3 direct(0.0), gathered(0.0);
  for (size_t r = 0; r < t.rays.size(); ++r) {
    const Contribution& contribution = t.contributions[r];
    const RayHit& h = t.hits[r];
    if (contribution.kind == Contribution::Kind::kShadow) {
      if (!h.hit()) direct += contribution.weight;
      continue;
    }
    if (!h.hit()) {
      // E = pi * mean(L) for cosine-weighted rays
      gathered += kPi * skyRadiance(c.scene.sky, contribution.toward);
      continue;
    }
    if (!h.front && !geometry.double_sided[h.triangle]) continue;  // black back face
    const Rgb e = c.solver.irradianceAt(h.triangle, h.front, h.u, h.v, InterpolationMode::kVertex,
                                        c.settings.solution);
    const Rgb& albedo = geometry.albedo[h.triangle];
    // B = rho * E; pi * B/pi
    gathered += glm::dvec3(albedo.r * e.r, albedo.g * e.g, albedo.b * e.b);
  }
  const uint32_t gather = c.settings.gather_rays;
  TexelIrradiance out;
  out.direct = rgb(direct);
  out.indirect = rgb(gather > 0 ? gathered / double(gather) : glm::dvec3(0.0));
  return out;
}

// Texel j's rays, from its own random stream: direct light, then the gather.
void buildTexelRays(const LightingContext& c, const TexelSample& sample, size_t j, TexelRays& t) {
  Rng rng(hashIds(c.settings.seed, 0x7e3e1, j));
  t.p = dvec(sample.position);
  t.n = dvec(sample.normal);
  t.origin =
      offsetRayOrigin(sample.position, sample.normal, cornerMagnitude(c.geometry, sample.triangle));
  t.o = dvec(t.origin);
  t.rays.clear();
  t.contributions.clear();
  addPointLightRays(c, rng, t);
  addDirectionalRays(c, rng, t);
  addEmitterRays(c, sample.triangle, rng, t);
  addGatherRays(c, rng, t);
}

TexelIrradiance lightTexel(const LightingContext& c, const TexelSample& sample, size_t j,
                           TexelRays& t) {
  buildTexelRays(c, sample, j, t);
  return sumContributions(c, t);
}

TexelRays makeScratch(const TexelLights& lights) {
  TexelRays scratch;
  scratch.light_cdf.resize(lights.points.size());
  if (lights.emitters.size() <= kTexelImportanceEmitters)
    scratch.emitter_cdf.resize(lights.emitters.size());
  scratch.light_e.resize(lights.points.size());
  return scratch;
}

}  // namespace

bool MaskedLights::masksInstance(uint32_t instance) const {
  return std::find(emissive_instances.begin(), emissive_instances.end(), instance) !=
         emissive_instances.end();
}

Expected<std::vector<TexelIrradiance>> lightTexelList(
    const Scene& scene, const BakeGeometry& geometry, const RayCaster& caster,
    const RadiositySolver& solver, const TexelSet& texels, const std::vector<uint32_t>& samples,
    const TexelLightingSettings& settings, const std::atomic<bool>* cancel,
    const std::function<bool(size_t, size_t)>& progress) {
  for (uint32_t j : samples) {
    if (j >= texels.samples.size()) {
      return Status(StatusCode::kInvalidInput, "lightmap: texel " + std::to_string(j) +
                                                   " out of range (" +
                                                   std::to_string(texels.samples.size()) + ")");
    }
  }
  TexelLights lights;
  collectAnalyticLights(scene, settings.masked, lights);
  collectEmitters(geometry, settings.masked, lights);
  solver.prepareQueries(settings.solution);
  const int threads = resolveThreads(settings.threads);
  const LightingContext context{scene, geometry, caster, solver, settings, lights};

  std::vector<TexelIrradiance> out(samples.size());
  const auto lightRange = [&](size_t begin, size_t end) {
    TexelRays scratch = makeScratch(lights);
    for (size_t k = begin; k < end; ++k)
      out[k] = lightTexel(context, texels.samples[samples[k]], samples[k], scratch);
  };
  // Blocks between which progress and cancellation are checked; the chunking
  // inside is fixed, so results do not depend on `threads`.
  const size_t block = 16384;
  for (size_t begin = 0; begin < out.size(); begin += block) {
    const size_t end = std::min(out.size(), begin + block);
    parallelFor(end - begin, 64, threads,
                [&](size_t b, size_t e) { lightRange(begin + b, begin + e); });
    if ((cancel && cancel->load()) || (progress && !progress(end, out.size()))) {
      return Status(StatusCode::kCancelled, "lightmap: cancelled");
    }
  }
  return out;
}

std::vector<uint32_t> texelRayCounts(const Scene& scene, const BakeGeometry& geometry,
                                     const RayCaster& caster, const RadiositySolver& solver,
                                     const TexelSet& texels,
                                     const TexelLightingSettings& settings) {
  TexelLights lights;
  collectAnalyticLights(scene, settings.masked, lights);
  collectEmitters(geometry, settings.masked, lights);
  const LightingContext context{scene, geometry, caster, solver, settings, lights};
  std::vector<uint32_t> counts(texels.samples.size());
  parallelFor(counts.size(), 256, resolveThreads(settings.threads), [&](size_t begin, size_t end) {
    TexelRays scratch = makeScratch(lights);
    for (size_t j = begin; j < end; ++j) {
      buildTexelRays(context, texels.samples[j], j, scratch);
      counts[j] = uint32_t(scratch.rays.size());
    }
  });
  return counts;
}

namespace {

// A masked light as maskVisibility casts it.
struct MaskedLightRays {
  bool directional = false;
  PointLight point;
  DirectionalLight sun_or_directional;
  std::vector<uint32_t> area_elements;  ///< an area light's (triangle * 2 + side)
  std::vector<double> area_cdf;         ///< running sum of their areas
};

MaskedLightRays areaLightRays(const BakeGeometry& geometry, const std::vector<uint32_t>& elements) {
  MaskedLightRays m;
  m.area_elements = elements;
  double total = 0;
  for (uint32_t e : elements) m.area_cdf.push_back(total += geometry.areas_m2[e / 2]);
  return m;
}

// masked.lights in order, then the sun, then the areas.
std::vector<MaskedLightRays> maskedLightRays(const Scene& scene, const BakeGeometry& geometry,
                                             const MaskedLights& masked) {
  std::vector<MaskedLightRays> out;
  for (uint32_t i : masked.lights) {
    const Light& light = scene.lights[i];
    MaskedLightRays m;
    m.directional = light.type == LightType::kDirectional;
    if (m.directional) {
      m.sun_or_directional = {glm::normalize(dvec(light.direction)),
                              dvec(light.color) * double(light.intensity), 1.0};
    } else {
      m.point = pointLightOf(light);
    }
    out.push_back(m);
  }
  if (masked.sun) {
    MaskedLightRays m;
    m.directional = true;
    m.sun_or_directional = sunOf(scene.sun);
    out.push_back(m);
  }
  for (const std::vector<uint32_t>& elements : masked.area_elements)
    out.push_back(areaLightRays(geometry, elements));
  return out;
}

// An area light's shadow rays from the texel: `count` points stratified
// over its elements by area (the second coordinate on a shifted rank-1
// lattice), each weighted by its element's luminance x cosine solid angle
// estimate; elements whose emitting side the texel is behind give none.
void addAreaLightRays(const BakeGeometry& geometry, const MaskedLightRays& light, uint32_t count,
                      Rng& rng, TexelRays& t) {
  const double total = light.area_cdf.back();
  const double shift = rng.uniformDouble();
  for (uint32_t s = 0; s < count; ++s) {
    const double pick = (double(s) + rng.uniformDouble()) / double(count) * total;
    const size_t i =
        std::min(light.area_elements.size() - 1,
                 size_t(std::lower_bound(light.area_cdf.begin(), light.area_cdf.end(), pick) -
                        light.area_cdf.begin()));
    const uint32_t element = light.area_elements[i], triangle = element / 2;
    const glm::dvec3 side_normal =
        dvec(geometry.normals[triangle]) * (element % 2 == 0 ? 1.0 : -1.0);
    if (!(glm::dot(t.p - dvec(geometry.corner(triangle, 0)), side_normal) > 0)) continue;
    const double low = i > 0 ? light.area_cdf[i - 1] : 0.0;
    const double r1 = std::clamp((pick - low) / (light.area_cdf[i] - low), 0.0, 1.0 - 1e-12);
    const double r2 = std::fmod(double(s) * 0.6180339887498949 + shift, 1.0);
    // As double-sided, sampleEmitter takes the side the texel sees: this one.
    const Emitter emitter{triangle, dvec(geometry.emission[triangle]), true};
    const EmitterSample sample = sampleEmitter(geometry, emitter, t.p, t.n, r1, r2);
    if (!(sample.cosine_solid_angle > 0)) continue;
    const double weight = luminanceOf(emitter.luminance) * sample.cosine_solid_angle * total /
                          geometry.areas_m2[triangle];
    const Vec3 target = offsetRayOrigin(vec3(sample.point), vec3(sample.normal),
                                        cornerMagnitude(geometry, triangle));
    t.shadowTo(dvec(target), glm::dvec3(weight));
  }
}

// One texel's visibility of each masked light: its rays' unshadowed
// irradiance that arrives over all of it, 0 where none has any.
void texelVisibility(const BakeGeometry& geometry, const RayCaster& caster,
                     const std::vector<MaskedLightRays>& lights,
                     const TexelLightingSettings& settings, Rng& rng, TexelRays& t,
                     float* visibility) {
  t.rays.clear();
  t.contributions.clear();
  std::vector<size_t> ends;
  ends.reserve(lights.size());
  for (const MaskedLightRays& light : lights) {
    if (!light.area_elements.empty()) {
      addAreaLightRays(geometry, light, settings.area_light_samples, rng, t);
    } else if (light.directional) {
      addDirectionalLightRays(light.sun_or_directional, settings.sun_samples, rng, t);
    } else {
      const glm::dvec3 e = pointIrradiance(light.point, t.p, t.n);
      if (luminanceOf(e) > 0) t.shadowTo(light.point.position, e);
    }
    ends.push_back(t.rays.size());
  }
  t.hits.resize(t.rays.size());
  caster.intersect(t.rays, t.hits);
  size_t begin = 0;
  for (size_t k = 0; k < lights.size(); ++k) {
    double seen = 0, total = 0;
    for (size_t r = begin; r < ends[k]; ++r) {
      const double w = luminanceOf(t.contributions[r].weight);
      total += w;
      if (!t.hits[r].hit()) seen += w;
    }
    visibility[k] = total > 0 ? float(seen / total) : 0.0f;
    begin = ends[k];
  }
}

}  // namespace

Expected<std::vector<float>> maskVisibility(const Scene& scene, const BakeGeometry& geometry,
                                            const RayCaster& caster, const TexelSet& texels,
                                            const TexelLightingSettings& settings,
                                            const std::atomic<bool>* cancel) {
  for (uint32_t i : settings.masked.lights) {
    if (i >= scene.lights.size() || scene.lights[i].dynamic) {
      return Status(StatusCode::kInvalidInput,
                    "shadow masks: light " + std::to_string(i) + " is not a static light");
    }
  }
  for (const std::vector<uint32_t>& elements : settings.masked.area_elements) {
    for (uint32_t e : elements) {
      if (e / 2 >= geometry.triangleCount() || !(luminanceOf(dvec(geometry.emission[e / 2])) > 0)) {
        return Status(StatusCode::kInvalidInput, "shadow masks: area element " + std::to_string(e) +
                                                     " is not an emissive side");
      }
    }
    if (elements.empty())
      return Status(StatusCode::kInvalidInput, "shadow masks: an area light has no elements");
  }
  const std::vector<MaskedLightRays> lights = maskedLightRays(scene, geometry, settings.masked);
  const size_t count = lights.size();
  std::vector<float> out(texels.samples.size() * count, 0.0f);
  const auto visibilityRange = [&](size_t begin, size_t end) {
    TexelRays t;
    for (size_t j = begin; j < end; ++j) {
      const TexelSample& sample = texels.samples[j];
      Rng rng(hashIds(settings.seed, 0x5ad0, j));
      t.p = dvec(sample.position);
      t.n = dvec(sample.normal);
      t.origin = offsetRayOrigin(sample.position, sample.normal,
                                 cornerMagnitude(geometry, sample.triangle));
      t.o = dvec(t.origin);
      texelVisibility(geometry, caster, lights, settings, rng, t, &out[j * count]);
    }
  };
  const size_t block = 16384;  // cancellation is checked between blocks
  for (size_t begin = 0; begin < texels.samples.size(); begin += block) {
    const size_t end = std::min(texels.samples.size(), begin + block);
    parallelFor(end - begin, 64, resolveThreads(settings.threads),
                [&](size_t b, size_t e) { visibilityRange(begin + b, begin + e); });
    if (cancel && cancel->load()) return Status(StatusCode::kCancelled, "shadow masks: cancelled");
  }
  return out;
}

Expected<std::vector<TexelIrradiance>> lightTexels(
    const Scene& scene, const BakeGeometry& geometry, const RayCaster& caster,
    const RadiositySolver& solver, const TexelSet& texels, const TexelLightingSettings& settings,
    const std::atomic<bool>* cancel, const std::function<bool(size_t, size_t)>& progress) {
  std::vector<uint32_t> all(texels.samples.size());
  std::iota(all.begin(), all.end(), 0u);
  return lightTexelList(scene, geometry, caster, solver, texels, all, settings, cancel, progress);
}

}  // namespace svit::baker
