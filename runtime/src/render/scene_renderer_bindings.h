#pragma once
// Binding points and uniform locations shared by the SceneRenderer's C++
// and its GLSL (shaders/lit_static.*, lit_dynamic.*, svit_shading.frag,
// shadow_depth.*, svit_runtime_delta.frag). The shaders spell the same
// numbers in their layout() qualifiers; change both together.

#include <cstdint>

namespace svit::gl::render_binding {

// ---- shader storage buffers ----
inline constexpr uint32_t kPatchDeltas = 0;  ///< runtime's vec4 per patch (lux)
/// per bake element: (n, first slot) (ShadingResources)
inline constexpr uint32_t kDeltaElements = 1;
/// per slot: its sub-triangle's welded vertices, used
inline constexpr uint32_t kDeltaSlots = 2;
inline constexpr uint32_t kVertexDeltas = 3;  ///< vec4 per welded runtime vertex (lux)
inline constexpr uint32_t kLights = 4;        ///< GpuLight array
/// vec4s of the masked area lights (lit_static.frag's svitAreaIrradiance)
inline constexpr uint32_t kAreaLights = 5;

// ---- texture units ----
inline constexpr uint32_t kBaseColorUnit = 0;
inline constexpr uint32_t kEmissiveUnit = 1;
inline constexpr uint32_t kLightmapUnit = 2;
inline constexpr uint32_t kDeltaMapUnit = 8;  ///< Runtime::shadingResources().delta_textures[page]
inline constexpr uint32_t kShadowCubeUnit = 3;  ///< samplerCubeArrayShadow
inline constexpr uint32_t kShadowFaceUnit = 4;  ///< sampler2DArrayShadow
inline constexpr uint32_t kProbeUnitR = 5;      ///< SH coefficients of red (Y00, Y1-1, Y10, Y11)
inline constexpr uint32_t kProbeUnitG = 6;
inline constexpr uint32_t kProbeUnitB = 7;
inline constexpr uint32_t kShadowMaskUnit = 9;  ///< usampler2DArray: the page's shadow masks

// ---- uniform locations (layout(location = N) uniform) ----
// Shared by both lit programs (svit_shading.frag reads some of them).
inline constexpr int kClipFromWorld = 0;  ///< mat4
inline constexpr int kView = 1;           ///< int: ShadingView
inline constexpr int kExposure = 2;       ///< float
/// int: first light of the lights buffer to shade with
inline constexpr int kLightBegin = 3;
inline constexpr int kLightEnd = 4;     ///< int: one past the last
inline constexpr int kShadowTaps = 5;   ///< int
inline constexpr int kShadowTexel = 6;  ///< float: 1 / shadow map size
/// float: irradiance (lux) shown fully saturated in kPatchDelta
inline constexpr int kDeltaReference = 7;
// Material (per batch).
inline constexpr int kBaseColor = 8;         ///< vec4: factor rgb + alpha
inline constexpr int kEmissive = 9;          ///< vec3: cd/m2
inline constexpr int kBaseTexture = 10;      ///< ivec2: (has texture, uv set)
inline constexpr int kBaseTransform = 11;    ///< vec4: scale.xy, offset.xy
inline constexpr int kBaseRotation = 12;     ///< float: radians
inline constexpr int kEmissiveTexture = 13;  ///< ivec2
inline constexpr int kEmissiveTransform = 14;
inline constexpr int kEmissiveRotation = 15;
inline constexpr int kMaterialFlags = 16;  ///< ivec2: (double sided, alpha mask)
inline constexpr int kAlphaCutoff = 17;    ///< float
// Static only.
inline constexpr int kUseDeltas = 18;  ///< int: the runtime's delta buffers bound
/// int: the runtime's delta map bound (lit_static.frag)
inline constexpr int kUseDeltaMap = 19;
/// float: the batch's bake emitter scale (lit_static.frag)
inline constexpr int kEmissionScale = 24;
/// int: the masked baked lights are lights [begin, end) (lit_static.frag)
inline constexpr int kMaskedBegin = 25;
inline constexpr int kMaskedEnd = 26;
/// int: 1 where the batch draws backs no baked light reaches
/// (kUnlitBackPage): no lightmap, no masked light (lit_static.frag)
inline constexpr int kUnlitSide = 27;
// Dynamic only: probe grid.
inline constexpr int kProbeOrigin = 19;   ///< vec3: centre of probe (0,0,0)
inline constexpr int kProbeSpacing = 20;  ///< vec3
inline constexpr int kProbeDims = 21;     ///< vec3 (float)
inline constexpr int kUseProbes = 22;     ///< int
/// int: lights [0, this) are the baked ones (the runtime's patch values include them)
inline constexpr int kBakedLightEnd = 23;
// Shadow depth pass.
inline constexpr int kShadowClipFromWorld = 0;  ///< mat4 (shadow_depth.vert)

}  // namespace svit::gl::render_binding
