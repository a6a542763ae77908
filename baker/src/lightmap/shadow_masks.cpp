// Shadow masks: which lights, their visibility per texel, and the packing
// of many lights into few channels (Unity's and Godot's shadowmasks assign
// channels by overlap too, but cap them at 4; here a channel only refuses a
// light whose mask overlaps one already in it, so any number may overlap).

#include "svit/baker/shadow_masks.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "util/double_math.h"

namespace svit::baker {
namespace {

// What a light could put on a level, for ordering lights beyond the cap:
// directional light first (it reaches everything), then punctual lights
// by luminous intensity x the solid angle of their cone.
double maskPriority(const Light& light) {
  const double intensity = luminanceOf(dvec(light.color)) * double(light.intensity);
  if (light.type == LightType::kDirectional) return 1e30 * (1.0 + intensity);
  const double cone = light.type == LightType::kSpot
                          ? 2.0 * kPi * (1.0 - std::cos(double(light.outer_cone_rad)))
                          : 4.0 * kPi;
  return intensity * cone;
}

// Per static instance, its emissive triangle sides (a double-sided
// triangle emits from two), in instance order; 0 for most.
std::vector<size_t> emissiveSides(const Scene& scene, const BakeGeometry& geometry) {
  std::vector<size_t> sides(scene.instances.size(), 0);
  for (size_t t = 0; t < geometry.triangleCount(); ++t) {
    if (luminanceOf(dvec(geometry.emission[t])) > 0)
      sides[geometry.instance[t]] += geometry.double_sided[t] ? 2 : 1;
  }
  return sides;
}

std::string instanceName(const Scene& scene, uint32_t instance) {
  const int node = scene.instances[instance].node;
  const std::string name =
      node >= 0 && size_t(node) < scene.nodes.size() ? scene.nodes[size_t(node)].name : "";
  return name.empty() ? "instance " + std::to_string(instance) : name;
}

// The emissive instances to mask as area lights, in instance order, each
// taking a slot per emissive side (an upper bound of its patches) out of
// `room`; the others are listed with why.
std::vector<uint32_t> chooseEmissiveInstances(const Scene& scene, const BakeGeometry& geometry,
                                              size_t& room, std::vector<UnmaskedLight>& unmasked) {
  std::vector<uint32_t> out;
  const std::vector<size_t> sides = emissiveSides(scene, geometry);
  for (uint32_t i = 0; i < sides.size(); ++i) {
    if (sides[i] == 0) continue;
    if (sides[i] > kMaxAreaLightSides) {
      unmasked.push_back({instanceName(scene, i),
                          std::to_string(sides[i]) + " emissive triangle sides (more than " +
                              std::to_string(kMaxAreaLightSides) +
                              " make a glowing surface, not a lamp): it keeps the lightmap "
                              "and the patch deltas"});
    } else if (sides[i] > room) {
      unmasked.push_back({instanceName(scene, i),
                          "more than " + std::to_string(kMaxMaskedLights) +
                              " lights to mask: it keeps the lightmap and the patch deltas"});
    } else {
      out.push_back(i);
      room -= sides[i];
    }
  }
  return out;
}

bool hasDynamicInstance(const Scene& scene) {
  return std::any_of(scene.instances.begin(), scene.instances.end(),
                     [](const Instance& i) { return i.dynamic; });
}

// One light's mask on every page, 0..255, dilated and seamed like the lightmap.
std::vector<std::vector<uint8_t>> lightMaskPages(const BakeGeometry& geometry,
                                                 const LightmapAtlas& atlas, const TexelSet& texels,
                                                 const std::vector<float>& visibility, size_t light,
                                                 size_t light_count, const PageSettings& settings) {
  std::vector<TexelIrradiance> as_light(texels.samples.size());
  for (size_t j = 0; j < as_light.size(); ++j) {
    const float v = visibility[j * light_count + light];
    as_light[j].direct = {v, v, v};
  }
  PageSettings plain = settings;
  plain.edge_aware_filter = false;  // visibility has no gather noise to smooth
  const LightmapPages pages = buildLightmapPages(geometry, atlas, texels, as_light, plain);
  std::vector<std::vector<uint8_t>> out(pages.images.size());
  for (size_t p = 0; p < pages.images.size(); ++p) {
    const std::vector<float>& rgb = pages.images[p].rgb;
    out[p].resize(rgb.size() / 3);
    for (size_t i = 0; i < out[p].size(); ++i)
      out[p][i] = uint8_t(std::lround(std::clamp(double(rgb[i * 3]), 0.0, 1.0) * 255.0));
  }
  return out;
}

uint32_t emitterOf(const std::vector<BakeEmitter>& emitters, BakeEmitter::Kind kind,
                   uint32_t index) {
  for (size_t e = 0; e < emitters.size(); ++e) {
    if (emitters[e].kind == kind && (kind == BakeEmitter::Kind::kSun || emitters[e].index == index))
      return uint32_t(e);
  }
  return UINT32_MAX;
}

// Masked light k's bake emitter (UINT32_MAX: none): the lights, the sun,
// then the areas' patches.
uint32_t maskedEmitter(const MaskedLights& masked, const std::vector<BakeEmitter>& emitters,
                       size_t k) {
  const size_t lights = masked.lights.size(), sun = masked.sun ? 1 : 0;
  if (k < lights) return emitterOf(emitters, BakeEmitter::Kind::kLight, masked.lights[k]);
  if (k < lights + sun) return emitterOf(emitters, BakeEmitter::Kind::kSun, 0);
  return emitterOf(emitters, BakeEmitter::Kind::kPatch, masked.area_patches[k - lights - sun]);
}

std::string maskedLightName(const Scene& scene, const MaskedLights& masked, size_t k) {
  const size_t lights = masked.lights.size(), sun = masked.sun ? 1 : 0;
  if (k < lights) return scene.lights[masked.lights[k]].name;
  if (k < lights + sun) return "the sun";
  return "emissive patch " + std::to_string(masked.area_patches[k - lights - sun]);
}

// Channel packing: per channel and page, the owner of each texel (0: none).
struct ChannelOwners {
  std::vector<std::vector<std::vector<uint8_t>>> owners;  // [channel][page][texel]
  std::vector<uint32_t> next_owner;                       // per channel

  // The first channel whose texels `mask` does not overlap, or a new one.
  uint32_t place(const std::vector<std::vector<uint8_t>>& mask) {
    for (uint32_t c = 0; c < owners.size(); ++c) {
      if (next_owner[c] < 256 && !overlaps(c, mask)) return c;
    }
    owners.emplace_back(mask.size());
    for (size_t p = 0; p < mask.size(); ++p) owners.back()[p].assign(mask[p].size(), 0);
    next_owner.push_back(1);
    return uint32_t(owners.size() - 1);
  }
  bool overlaps(uint32_t c, const std::vector<std::vector<uint8_t>>& mask) const {
    for (size_t p = 0; p < mask.size(); ++p) {
      for (size_t i = 0; i < mask[p].size(); ++i)
        if (mask[p][i] != 0 && owners[c][p][i] != 0) return true;
    }
    return false;
  }
};

// Writes light `owner`'s mask into channel `channel` of the packed pages.
void packMask(const std::vector<std::vector<uint8_t>>& mask, uint32_t channel, uint32_t owner,
              BakeShadowMasks& masks) {
  const size_t layer = channel / 4, component = channel % 4;
  for (size_t p = 0; p < mask.size(); ++p) {
    const size_t texels = mask[p].size();
    for (size_t i = 0; i < texels; ++i) {
      if (mask[p][i] == 0) continue;
      masks.pages[p][(layer * texels + i) * 4 + component] = uint16_t(owner << 8 | mask[p][i]);
    }
  }
}

// Grows every page to `layers` layers (new layers hold no light).
void growLayers(const std::vector<size_t>& page_texels, uint32_t layers, BakeShadowMasks& masks) {
  for (size_t p = 0; p < page_texels.size(); ++p)
    masks.pages[p].resize(size_t(layers) * page_texels[p] * 4, 0);
}

}  // namespace

MaskChoice chooseMaskedLights(const Scene& scene, const BakeGeometry& geometry, bool enabled) {
  MaskChoice choice;
  if (!enabled) {
    choice.none_reason = "shadow masks are off (--no-shadow-masks)";
    return choice;
  }
  if (!hasDynamicInstance(scene)) {
    choice.none_reason = "the level has no dynamic objects";
    return choice;
  }
  std::vector<uint32_t> lights;
  for (uint32_t i = 0; i < scene.lights.size(); ++i) {
    const Light& l = scene.lights[i];
    if (!l.dynamic && l.intensity > 0 && luminanceOf(dvec(l.color)) > 0) lights.push_back(i);
  }
  std::stable_sort(lights.begin(), lights.end(), [&](uint32_t a, uint32_t b) {
    return maskPriority(scene.lights[a]) > maskPriority(scene.lights[b]);
  });
  const bool sun = scene.sun.enabled && scene.sun.illuminance_lux > 0;
  size_t room = kMaxMaskedLights - (sun ? 1 : 0);
  choice.masked.emissive_instances =
      chooseEmissiveInstances(scene, geometry, room, choice.unmasked);
  for (size_t k = room; k < lights.size(); ++k) {
    choice.unmasked.push_back({scene.lights[lights[k]].name,
                               "more than " + std::to_string(kMaxMaskedLights) +
                                   " lights to mask: it keeps the lightmap and the patch deltas"});
  }
  if (lights.size() > room) lights.resize(room);
  std::sort(lights.begin(), lights.end());  // scene order
  choice.masked.lights = std::move(lights);
  choice.masked.sun = sun;
  if (choice.masked.count() == 0 && choice.masked.emissive_instances.empty())
    choice.none_reason = "the level has no baked light, sun or lamp";
  return choice;
}

void addAreaLights(const BakeGeometry& geometry, const std::vector<BakePatch>& patches,
                   const std::vector<uint32_t>& patch_elements, MaskedLights& masked) {
  for (uint32_t p = 0; p < patches.size(); ++p) {
    std::vector<uint32_t> elements;
    for (uint32_t i = 0; i < patches[p].element_count; ++i) {
      const uint32_t e = patch_elements[patches[p].first_element + i];
      if (masked.masksInstance(geometry.instance[e / 2]) &&
          luminanceOf(dvec(geometry.emission[e / 2])) > 0)
        elements.push_back(e);
    }
    if (elements.empty()) continue;
    masked.area_elements.push_back(std::move(elements));
    masked.area_patches.push_back(p);
  }
}

Expected<BakeShadowMasks> buildShadowMasks(const Scene& scene, const BakeGeometry& geometry,
                                           const RayCaster& caster, const LightmapAtlas& atlas,
                                           const TexelSet& texels, const MaskedLights& masked,
                                           const std::vector<BakeEmitter>& emitters,
                                           const ShadowMaskSettings& settings,
                                           const std::atomic<bool>* cancel) {
  BakeShadowMasks masks;
  const size_t count = masked.count();
  if (count == 0) return masks;
  TexelLightingSettings lighting;
  lighting.seed = settings.seed;
  lighting.threads = settings.threads;
  lighting.sun_samples = settings.sun_samples;
  lighting.masked = masked;
  Expected<std::vector<float>> visibility =
      maskVisibility(scene, geometry, caster, texels, lighting, cancel);
  if (!visibility.ok()) return visibility.status();

  const size_t page_count = size_t(texels.page_count);
  const std::vector<size_t> page_texels(page_count,
                                        size_t(texels.page_width) * size_t(texels.page_height));
  masks.pages.resize(page_count);
  ChannelOwners channels;
  for (size_t k = 0; k < count; ++k) {
    const uint32_t emitter = maskedEmitter(masked, emitters, k);
    if (emitter == UINT32_MAX) {
      return Status(StatusCode::kInternal,
                    "shadow masks: " + maskedLightName(scene, masked, k) + " has no bake emitter");
    }
    const std::vector<std::vector<uint8_t>> mask =
        lightMaskPages(geometry, atlas, texels, *visibility, k, count, settings.pages);
    const uint32_t channel = channels.place(mask);
    const uint32_t owner = channels.next_owner[channel]++;
    for (size_t p = 0; p < page_count; ++p) {
      for (size_t i = 0; i < mask[p].size(); ++i)
        if (mask[p][i] != 0) channels.owners[channel][p][i] = uint8_t(owner);
    }
    masks.channels = std::max(masks.channels, channel + 1);
    growLayers(page_texels, masks.layers(), masks);
    packMask(mask, channel, owner, masks);
    masks.lights.push_back({emitter, channel, owner});
    if (cancel && cancel->load()) return Status(StatusCode::kCancelled, "shadow masks: cancelled");
  }
  return masks;
}

size_t maskTexelsOf(const BakeShadowMasks& masks, size_t light, size_t page) {
  const BakeMaskedLight& l = masks.lights[light];
  const std::vector<uint16_t>& values = masks.pages[page];
  const size_t texels = values.size() / (size_t(masks.layers()) * 4);
  const size_t layer = l.channel / 4, component = l.channel % 4;
  size_t n = 0;
  for (size_t i = 0; i < texels; ++i)
    if ((values[(layer * texels + i) * 4 + component] >> 8) == l.owner) ++n;
  return n;
}

}  // namespace svit::baker
