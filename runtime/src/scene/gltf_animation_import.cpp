// glTF animations -> tracks (times and values per channel), validated. The
// runtime plays them for dynamic nodes; the baker uses the rest pose.

#include <algorithm>
#include <cmath>

#include <tiny_gltf.h>

#include "accessor_reader.h"
#include "gltf_import_context.h"

namespace svit::gltf {

namespace {

Status invalid(const std::string& message) { return Status(StatusCode::kInvalidInput, message); }

// The node and path a channel animates, and its sampler's interpolation.
Status readChannelTarget(const tinygltf::AnimationChannel& channel,
                         const tinygltf::AnimationSampler& sampler, const std::string& where,
                         AnimationTrack& track) {
  track.node = channel.target_node;
  if (channel.target_path == "translation") {
    track.path = AnimationPath::kTranslation;
    track.components = 3;
  } else if (channel.target_path == "rotation") {
    track.path = AnimationPath::kRotation;
    track.components = 4;
  } else if (channel.target_path == "scale") {
    track.path = AnimationPath::kScale;
    track.components = 3;
  } else if (channel.target_path == "weights") {
    track.path = AnimationPath::kWeights;
    track.components = 1;
  } else {
    return invalid(where + ": target path '" + channel.target_path + "' is not a glTF path");
  }
  track.interpolation = sampler.interpolation == "STEP"          ? Interpolation::kStep
                        : sampler.interpolation == "CUBICSPLINE" ? Interpolation::kCubicSpline
                                                                 : Interpolation::kLinear;
  return Status();
}

Status readKeyTimes(const tinygltf::Model& model, const tinygltf::AnimationSampler& sampler,
                    const std::string& where, AnimationTrack& track) {
  if (Status s = readFloats(model, sampler.input, 1, where + " input", track.times_s); !s.ok()) {
    return s;
  }
  for (size_t k = 0; k < track.times_s.size(); ++k) {
    const bool ordered = k == 0 || track.times_s[k] > track.times_s[k - 1];
    if (!std::isfinite(track.times_s[k]) || !ordered) {
      return invalid(where + " input key " + std::to_string(k) + ": time " +
                     std::to_string(track.times_s[k]) + " is not finite and increasing");
    }
  }
  return Status();
}

// Output values: components per key (weights: as many as the output holds
// per key), three per key for cubic splines (in-tangent, value, out-tangent).
Status readKeyValues(const tinygltf::Model& model, const tinygltf::AnimationSampler& sampler,
                     const std::string& where, AnimationTrack& track) {
  const size_t keys = track.times_s.size();
  const size_t per_key = track.interpolation == Interpolation::kCubicSpline ? 3 : 1;
  const long output_count = accessorCount(model, sampler.output);
  if (track.path == AnimationPath::kWeights && keys > 0 && output_count > 0) {
    track.components = int(size_t(output_count) / (keys * per_key));
  }
  std::vector<float> values;
  const int read_components = track.path == AnimationPath::kWeights ? 1 : track.components;
  if (Status s = readFloats(model, sampler.output, read_components, where + " output", values);
      !s.ok()) {
    return s;
  }
  if (keys == 0 || values.size() != keys * per_key * size_t(std::max(track.components, 1))) {
    return invalid(where + ": " + std::to_string(values.size()) + " output values for " +
                   std::to_string(keys) + " keys of " + std::to_string(track.components) +
                   " components");
  }
  for (size_t v = 0; v < values.size(); ++v) {
    if (!std::isfinite(values[v])) {
      return invalid(where + " output value " + std::to_string(v) + " is not finite");
    }
  }
  track.values = std::move(values);
  return Status();
}

// Appends channel `c` of `source` to `animation` as a track (nothing for a
// channel without a node: glTF allows those, for extensions).
Status importChannel(ImportContext& context, const tinygltf::Animation& source, size_t c,
                     const std::string& what, Animation& animation) {
  Scene& scene = context.scene;
  const tinygltf::AnimationChannel& channel = source.channels[c];
  const std::string where = what + " channel " + std::to_string(c);
  if (channel.target_node < 0) return Status();
  if (size_t(channel.target_node) >= scene.nodes.size()) {
    return invalid(where + ": node " + std::to_string(channel.target_node) + " does not exist");
  }
  if (channel.sampler < 0 || size_t(channel.sampler) >= source.samplers.size()) {
    return invalid(where + ": sampler " + std::to_string(channel.sampler) + " does not exist");
  }
  const tinygltf::AnimationSampler& sampler = source.samplers[size_t(channel.sampler)];
  AnimationTrack track;
  if (Status s = readChannelTarget(channel, sampler, where, track); !s.ok()) return s;
  if (Status s = readKeyTimes(context.model, sampler, where, track); !s.ok()) return s;
  if (Status s = readKeyValues(context.model, sampler, where, track); !s.ok()) return s;
  animation.duration_s = std::max(animation.duration_s, track.times_s.back());
  scene.nodes[size_t(track.node)].animated = true;
  animation.tracks.push_back(std::move(track));
  return Status();
}

}  // namespace

Status importAnimations(ImportContext& context) {
  const tinygltf::Model& model = context.model;
  for (size_t a = 0; a < model.animations.size(); ++a) {
    const tinygltf::Animation& source = model.animations[a];
    Animation animation;
    animation.name = source.name.empty() ? "animation " + std::to_string(a) : source.name;
    const std::string what = context.path + ": animation '" + animation.name + "'";
    for (size_t c = 0; c < source.channels.size(); ++c) {
      if (Status s = importChannel(context, source, c, what, animation); !s.ok()) return s;
    }
    context.scene.animations.push_back(std::move(animation));
  }
  return Status();
}

}  // namespace svit::gltf
