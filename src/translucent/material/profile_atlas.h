// SPDX-License-Identifier: GPL-3.0-or-later
// Per-point profiles at texture resolution: the SubEdit profiles (point_profiles.h) of the surface
// points under the texels of an atlas of the mesh, for a texture lookup at any surface point.
//
// The multiresolution splatting paper (Eqs. 8-9) keeps a profile per surface point and stores the
// profiles in a texture over the surface; kept at the mesh's vertices instead, a material's detail
// is limited to the mesh's resolution: a pattern finer than the triangles (veins, a chessboard on
// a coarse mesh) is sampled at the vertices and interpolated across each triangle. Here every
// texel that a triangle owns (geometry::rasterizeCoverage) gets the profile of the local medium at
// its surface point (geometry::texelSurfacePoint: position, interpolated normal, and for a
// surface map the UV of the default atlas at the same point), and a surface point on triangle t at
// barycentrics b reads ln P at UV Σ b_j uv_j(t) with bilinear filtering: the ln P nodes are
// interpolated between texel centres, as Eq. 9 interpolates between radii.
//
// Texels that no triangle owns (gutters between charts, the unused rest of the atlas) take the
// mean of their owned neighbours, repeated outwards a few rings (kDilation), so that a bilinear
// lookup near a chart's border mixes only values of the surface beside it.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>

#include "translucent/geometry/atlas.h"
#include "translucent/geometry/mesh.h"
#include "translucent/material/point_profiles.h"

namespace translucent::material {

struct ProfileAtlas {
  uint32_t size = 0;     // texels per side (the atlas')
  int segments = 0;      // n: n + 1 nodes per profile (the layers of the texture)
  double radius = 0.0;   // r_s [scene units], common to every texel
  // Node k of texel (x, y), channel c, as layer k of a 2D array texture (rows y = 0 first):
  // nodes[((k · size + y) · size + x) · 4 + c], c < 3; the fourth float is 1 for an owned texel,
  // 0 for a filled one (dilated) or one left empty (ln P = kLnFloor there).
  std::vector<float> nodes;
  // Where each triangle's corners lie in the atlas: 3 per triangle (geometry::Atlas::uvs).
  std::vector<glm::vec2> triangle_uvs;
  // The profiles of the owned texels (one per owned texel, in row order) and, per owned texel, its
  // triangle: for per-triangle or per-vertex statistics such as a splat's radius.
  PointProfiles profiles;
  std::vector<uint32_t> texel_triangle;
  size_t owned = 0;  // texels with a surface point
};

inline constexpr int kProfileAtlasDilation = 4;

// Builds the profiles of `mesh` (which `atlas` parameterises) under `material` (any kind; a
// surface map is read at the default atlas `surface_atlas`, which must then be given; a
// homogeneous material gives one profile for every texel). options.radius 0: the largest 95%
// radius over the texels' media. Throws ParameterError as PointProfiles::build does.
ProfileAtlas buildProfileAtlas(const geometry::TriangleMesh& mesh, const geometry::Atlas& atlas,
                               const Material& material, const ProfileOptions& options = {},
                               const geometry::Atlas* surface_atlas = nullptr);

}  // namespace translucent::material
