#include "light_sources.h"
#include "util/double_math.h"

#include <algorithm>
#include <cmath>

#include "util/sampling.h"

namespace svit::baker {
namespace {

glm::dvec3 normalisedColour(const glm::dvec3& c) {
  const double y = luminanceOf(c);
  return y > 0 ? c / y : glm::dvec3(1.0);
}

// Origin on the disk of radius `disk_radius` facing `towards_source`, far
// enough out that the whole enclosing sphere lies ahead of it.
glm::dvec3 diskOrigin(const LightSource& light, const glm::dvec3& towards_source, Rng& rng) {
  glm::dvec3 t, b;
  basisAround(towards_source, t, b);
  const glm::dvec2 d = concentricDisk(rng.uniformDouble(), rng.uniformDouble()) * light.disk_radius;
  return light.centre + towards_source * (2.0 * light.radius) + d.x * t + d.y * b;
}

}  // namespace

double spotFalloff(double cos_angle, double cos_inner, double cos_outer) {
  const double t =
      std::clamp((cos_angle - cos_outer) / std::max(1e-9, cos_inner - cos_outer), 0.0, 1.0);
  return t * t;
}

LightRay LightSource::sample(Rng& rng) const {
  LightRay ray;
  ray.colour = colour;
  switch (kind) {
    case LightKind::kPoint:
      ray.origin = position;
      ray.direction = uniformSphere(rng.uniformDouble(), rng.uniformDouble());
      break;
    case LightKind::kSpot: {
      // Uniform over the outer cone's solid angle, kept with probability
      // falloff: directions then follow the intensity exactly. The mean
      // acceptance is >= 1/3, so the loop is short.
      ray.origin = position;
      for (int attempt = 0; attempt < 1000; ++attempt) {
        const double cos_theta = 1.0 - rng.uniformDouble() * (1.0 - cos_outer);
        const double azimuth = rng.uniformDouble();
        if (rng.uniformDouble() < spotFalloff(cos_theta, cos_inner, cos_outer)) {
          ray.direction = directionAt(direction, cos_theta, azimuth);
          return ray;
        }
      }
      ray.direction = direction;
      break;
    }
    case LightKind::kDirectional: {
      // Within the sun's cone, cosine-weighted about the mean direction (the
      // illuminance is measured on a surface facing the sun).
      glm::dvec3 travel = direction;
      if (cos_radius < 1.0) {
        for (int attempt = 0; attempt < 1000; ++attempt) {
          const double cos_theta = 1.0 - rng.uniformDouble() * (1.0 - cos_radius);
          const double azimuth = rng.uniformDouble();
          if (rng.uniformDouble() < cos_theta) {
            travel = directionAt(direction, cos_theta, azimuth);
            break;
          }
        }
      }
      ray.direction = travel;
      ray.origin = diskOrigin(*this, -direction, rng);
      break;
    }
    case LightKind::kSky: {
      // Direction towards the sky with density proportional to its
      // luminance: upper hemisphere linear in cos(zenith angle), ground uniform.
      glm::dvec3 towards_sky;
      glm::dvec3 luminance_rgb;
      if (rng.uniformDouble() < upper_share) {
        const double a = luminanceOf(horizon), b = luminanceOf(zenith) - a;
        const double u = rng.uniformDouble();
        double mu = u;
        if (std::abs(b) > 1e-12 * std::max(a, 1e-30)) {
          // Inverse CDF of (a + b*mu) on [0, 1].
          mu = (-a + std::sqrt(std::max(0.0, a * a + 2.0 * b * u * (a + 0.5 * b)))) / b;
        }
        mu = std::clamp(mu, 0.0, 1.0);
        towards_sky = directionAt(glm::dvec3(0, 1, 0), mu, rng.uniformDouble());
        luminance_rgb = horizon + (zenith - horizon) * mu;
      } else {
        const double mu = -rng.uniformDouble();
        towards_sky = directionAt(glm::dvec3(0, 1, 0), mu, rng.uniformDouble());
        luminance_rgb = ground;
      }
      ray.colour = normalisedColour(luminance_rgb);
      ray.direction = -towards_sky;
      ray.origin = diskOrigin(*this, towards_sky, rng);
      break;
    }
  }
  return ray;
}

namespace {

// The sphere enclosing the scene, and the disk sun and sky shoot from.
struct Enclosure {
  glm::dvec3 centre{0.0};
  double radius = 0;
  double disk_area_m2 = 0;
};

Enclosure enclosureOf(const BakeGeometry& geometry) {
  Enclosure e;
  const glm::dvec3 lo = dvec(geometry.bounds.min), hi = dvec(geometry.bounds.max);
  e.centre = 0.5 * (lo + hi);
  // 1% margin so grazing rays still cover the silhouette.
  e.radius = std::max(0.5 * glm::length(hi - lo) * 1.01, 1e-6);
  e.disk_area_m2 = kPi * e.radius * e.radius;
  return e;
}

// Scenes built in code skip the loader's checks: NaN here would turn into
// rays that silently miss.
Status checkLightFinite(const Scene& scene, const Light& light) {
  const char* bad = !finite(light.position)           ? "position"
                    : !finite(light.direction)        ? "direction"
                    : !finite(light.color)            ? "colour"
                    : !std::isfinite(light.intensity) ? "intensity"
                    : !std::isfinite(light.inner_cone_rad) || !std::isfinite(light.outer_cone_rad)
                        ? "cone angle"
                        : nullptr;
  if (!bad) return Status();
  return Status(StatusCode::kInvalidInput, scene.source_path + ": light '" + light.name +
                                               "': " + bad + " is not finite (as a float)");
}

// A point, spot or directional light as a source; flux_y checked finite.
Expected<LightSource> punctualSource(const Scene& scene, const Light& light,
                                     const Enclosure& enclosure) {
  if (Status bad = checkLightFinite(scene, light); !bad.ok()) return bad;
  LightSource s;
  s.name = light.name;
  s.colour = normalisedColour(dvec(light.color));
  const glm::dvec3 intensity = dvec(light.color) * double(light.intensity);
  s.position = dvec(light.position);
  s.direction = glm::normalize(dvec(light.direction));
  s.centre = enclosure.centre;
  s.radius = enclosure.radius;
  s.disk_radius = enclosure.radius;
  switch (light.type) {
    case LightType::kPoint:
      s.kind = LightKind::kPoint;
      s.flux_rgb = intensity * (4.0 * kPi);  // isotropic candela -> lumen
      break;
    case LightType::kSpot:
      s.kind = LightKind::kSpot;
      s.cos_inner = std::cos(double(light.inner_cone_rad));
      s.cos_outer = std::cos(double(light.outer_cone_rad));
      // Integral of the falloff over the sphere: full inside the inner
      // cone, t^2 (mean 1/3 in cos) between the cones.
      s.flux_rgb =
          intensity * (2.0 * kPi * ((1.0 - s.cos_inner) + (s.cos_inner - s.cos_outer) / 3.0));
      break;
    case LightType::kDirectional:
      s.kind = LightKind::kDirectional;
      s.flux_rgb = intensity * enclosure.disk_area_m2;  // lux over the disk
      break;
  }
  s.flux_y = luminanceOf(s.flux_rgb);
  if (!std::isfinite(s.flux_y)) {
    return Status(StatusCode::kInvalidInput,
                  scene.source_path + ": light '" + light.name + "': flux is not finite");
  }
  return s;
}

Status checkSunAndSkyFinite(const Scene& scene) {
  if (scene.sun.enabled &&
      (!finite(scene.sun.direction_to_sun) || !finite(scene.sun.color) ||
       !std::isfinite(scene.sun.illuminance_lux) || !std::isfinite(scene.sun.angular_radius_rad))) {
    return Status(
        StatusCode::kInvalidInput,
        scene.source_path + ": sun: direction, colour, illuminance or radius is not finite");
  }
  if (scene.sky.model != SkyModel::kNone &&
      (!finite(scene.sky.zenith_luminance) || !finite(scene.sky.horizon_luminance) ||
       !finite(scene.sky.ground_luminance))) {
    return Status(StatusCode::kInvalidInput,
                  scene.source_path + ": sky: a luminance is not finite");
  }
  return Status();
}

LightSource sunSource(const Scene& scene, const Enclosure& enclosure) {
  LightSource s;
  s.kind = LightKind::kDirectional;
  s.name = "sun";
  s.direction = -glm::normalize(dvec(scene.sun.direction_to_sun));
  s.cos_radius = std::cos(double(scene.sun.angular_radius_rad));
  s.colour = normalisedColour(dvec(scene.sun.color));
  s.centre = enclosure.centre;
  s.radius = enclosure.radius;
  // Rays tilt by up to the angular radius over the 3R they travel.
  s.disk_radius = enclosure.radius * (1.0 + 3.0 * std::tan(double(scene.sun.angular_radius_rad)));
  s.flux_rgb = dvec(scene.sun.color) * double(scene.sun.illuminance_lux) *
               (kPi * s.disk_radius * s.disk_radius);
  s.flux_y = luminanceOf(s.flux_rgb);
  return s;
}

LightSource skySource(const Scene& scene, const Enclosure& enclosure) {
  LightSource s;
  s.kind = LightKind::kSky;
  s.name = "sky";
  s.centre = enclosure.centre;
  s.radius = enclosure.radius;
  s.disk_radius = enclosure.radius;
  s.zenith = dvec(scene.sky.zenith_luminance);
  s.horizon = scene.sky.model == SkyModel::kUniform ? s.zenith : dvec(scene.sky.horizon_luminance);
  s.ground =
      scene.sky.model == SkyModel::kUniform ? glm::dvec3(0.0) : dvec(scene.sky.ground_luminance);
  // Flux through a disk of area A from radiance L over solid angle w is
  // L*A*w: upper hemisphere 2*pi*(horizon + (zenith - horizon)/2), ground 2*pi*ground.
  const glm::dvec3 upper =
      2.0 * kPi * (s.horizon + 0.5 * (s.zenith - s.horizon)) * enclosure.disk_area_m2;
  const glm::dvec3 lower = 2.0 * kPi * s.ground * enclosure.disk_area_m2;
  s.flux_rgb = upper + lower;
  s.flux_y = luminanceOf(s.flux_rgb);
  s.upper_share = s.flux_y > 0 ? luminanceOf(upper) / s.flux_y : 1.0;
  return s;
}

}  // namespace

Expected<std::vector<LightSource>> makeLightSources(const Scene& scene,
                                                    const BakeGeometry& geometry) {
  std::vector<LightSource> sources;
  const Enclosure enclosure = enclosureOf(geometry);
  for (const Light& light : scene.lights) {
    if (light.dynamic) continue;  // runtime lights are the runtime's
    Expected<LightSource> s = punctualSource(scene, light, enclosure);
    if (!s.ok()) return s.status();
    if (s->flux_y > 0) sources.push_back(std::move(s).value());
  }
  if (Status bad = checkSunAndSkyFinite(scene); !bad.ok()) return bad;
  if (scene.sun.enabled && scene.sun.illuminance_lux > 0)
    sources.push_back(sunSource(scene, enclosure));
  if (scene.sky.model != SkyModel::kNone) {
    const LightSource sky = skySource(scene, enclosure);
    if (sky.flux_y > 0) sources.push_back(sky);
  }
  return sources;
}

bool emitsAnyLight(const Scene& scene, const BakeGeometry& geometry) {
  for (const Rgb& e : geometry.emission) {
    if (e.r > 0 || e.g > 0 || e.b > 0) return true;
  }
  const Expected<std::vector<LightSource>> sources = makeLightSources(scene, geometry);
  return !sources.ok() || !sources->empty();
}

}  // namespace svit::baker
