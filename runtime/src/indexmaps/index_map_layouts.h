#pragma once
// CPU side of the index-map layouts (thesis 5.2.4): a point sample's map
// frame, the cube faces each layout renders, the emission lobes, the texel
// weights, and from them the share of a lobe a layout misses. The shaders
// index_map_common.comp (weights, faces) and index_map.vert (projection)
// evaluate the same formulas: change both sides together.
//
// Conventions. The map frame of a sample is a right-handed orthonormal basis
// (t1, t2, axis), t1 = the deterministic perpendicular of `axis` turned by
// `roll_rad` about it. "Cube coordinates" are the coordinates of a cube
// around the sample: for kSingle, kHemicube and kCube (and kParallel) they
// are the map frame itself (axis = +Z); for kTriple the cube is turned so its
// corner direction (1,1,1)/sqrt(3) is the axis. Face f looks along
// `forward`, its texel (i, j) sits at face coordinates
// u = (2i + 1)/res - 1 along `right`, v = (2j + 1)/res - 1 along `up`, with
// right = forward x up so that a CCW triangle stays CCW in the window (GL's
// front-facing rule); j counts rows from the bottom like texelFetch.

#include <array>
#include <cstdint>

#include <glm/glm.hpp>

#include "index_map_renderer.h"

namespace svit::gl {

/// Cube faces, in the order of a sample's layers (layer = sample * 6 + face).
enum CubeFace : int { kPosX = 0, kNegX = 1, kPosY = 2, kNegY = 3, kPosZ = 4, kNegZ = 5 };
inline constexpr int kCubeFaceCount = 6;
inline constexpr int kMapLayoutCount = 5;

/// A face's view directions in cube coordinates (unit, orthogonal).
struct FaceBasis {
  glm::dvec3 forward, up, right;
};
/// The basis of face `face` (0..5). Side faces (+-X, +-Y) have up = +Z, so
/// their upper half (v > 0) is the half toward the axis.
FaceBasis cubeFaceBasis(int face);

/// The faces `layout` renders; kParallel renders one orthographic raster in
/// the slot of kPosZ.
struct LayoutFaces {
  int count = 0;
  std::array<int, kCubeFaceCount> faces{};
};
LayoutFaces layoutFaces(MapLayout layout);
/// Bit f set when `layout` renders cube face f.
uint32_t layoutFaceMask(MapLayout layout);
/// True when `layout` renders only the upper half (rows v > 0) of `face`
/// (the hemicube's side faces).
bool isHalfFace(MapLayout layout, int face);
/// First texel row `layout` renders of `face`: resolution / 2 for half faces.
int firstRow(MapLayout layout, int face, int resolution);
/// Raster passes, in face areas (a hemicube is 1 + 4 halves = 3).
double faceArea(MapLayout layout);

/// The map frame: columns t1, t2, axis (unit, right-handed). `axis` need not
/// be unit but must be finite and non-zero.
glm::dmat3 mapFrame(const Vec3& axis, float roll_rad);
/// World directions from cube coordinates (columns = cube axes in the world).
glm::dmat3 worldFromCube(MapLayout layout, const glm::dmat3& map_frame);
/// The lobe axis in cube coordinates: +Z, or (1,1,1)/sqrt(3) for kTriple.
glm::dvec3 cubeAxis(MapLayout layout);

/// The lobe's unnormalised profile at cos(theta) from the axis, in [0, 1]:
/// cosine max(c, 0); isotropic 1; spot t^2 with t = clamp((c - cos_outer) /
/// (cos_inner - cos_outer), 0, 1) (glTF KHR_lights_punctual, as the baker's
/// spotFalloff), a hard cone at cos_outer when cos_inner <= cos_outer;
/// parallel 0 (it has no angular profile).
double lobeProfile(Lobe lobe, double cos_inner, double cos_outer, double cos_theta);
/// Analytic integral of the profile over the sphere, sr: cosine pi,
/// isotropic 4 pi, spot 2 pi ((1 - ci) + (ci - co) / 3); 0 for parallel.
double lobeIntegral(Lobe lobe, double cos_inner, double cos_outer);

/// Face coordinate of the centre of texel `i` of `resolution` per edge.
double texelCentre(int resolution, int i);
/// Solid angle (sr) of the cube-face texel centred at face coordinates
/// (u, v), midpoint rule: (2 / res)^2 / (1 + u^2 + v^2)^(3/2).
double texelSolidAngle(int resolution, double u, double v);

/// How a lobe falls on the cube texels at one resolution.
struct LobeCoverage {
  /// Sum over all 6 x res^2 texels of solid angle x profile with the axis
  /// through a face centre, and through a corner (kTriple): the discrete
  /// normalisers of the texel weights. They equal lobeIntegral() up to the
  /// midpoint rule's O(1 / res^2); dividing by the discrete sum instead makes
  /// a covering layout conserve the sample's flux exactly and makes
  /// `missed` a pure coverage measure.
  double normaliser_face_axis = 0;
  double normaliser_corner_axis = 0;
  /// Share of the lobe each layout does not render, by MapLayout, in [0, 1].
  std::array<double, kMapLayoutCount> missed{};
};
/// Sums the texel weights of every layout (O(12 res^2)); `resolution` >= 1.
LobeCoverage lobeCoverage(Lobe lobe, double cos_inner, double cos_outer, int resolution);

}  // namespace svit::gl
