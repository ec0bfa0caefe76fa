// SPDX-License-Identifier: GPL-3.0-or-later
// Per-point profiles at texture resolution on the GPU (material/profile_atlas.h): for the
// techniques whose shaders read a surface point's SubEdit profile through pointcloud/hetero.glsl's
// pcSurfaceNode (the point cloud's shading points, the splatting technique's samples and pixels).
// With PC_PROFILE_ATLAS defined that function reads layer k of a 2D array texture (texture unit
// kProfileAtlasUnit) at the point's atlas UV, interpolated from its triangle's corner UVs (SSBO
// kTriangleUvBinding); without it, the triangle's vertex profiles.
#pragma once

#include <string>
#include <vector>

#include "translucent/gpu/objects.h"
#include "translucent/material/profile_atlas.h"
#include "translucent/techniques/technique.h"

namespace translucent::techniques {

inline constexpr unsigned kProfileAtlasUnit = 12;    // hetero.glsl's PcProfileAtlas
inline constexpr unsigned kTriangleUvBinding = 17;   // hetero.glsl's PcTriangleUvs

// `profile_storage` (vertex | texture) and `profile_texels` (256).
std::vector<ParameterInfo> profileStorageParameters();

struct GpuProfileAtlas {
  gpu::Texture texture;  // GL_TEXTURE_2D_ARRAY, RGBA32F, n + 1 layers, bilinear, clamped
  gpu::Buffer triangle_uvs;
  void bind() const;  // to kProfileAtlasUnit and kTriangleUvBinding
};
// Uploads `atlas`; `what` names it in GL errors ("splatting: profile texture").
GpuProfileAtlas uploadProfileAtlas(const material::ProfileAtlas& atlas, const std::string& what);

// "<technique>: per-point profiles in a 256² texture over the surface atlas (N texels on the
// surface, n segments on [0, r_s = R])": the frame note.
std::string describeProfileAtlas(const char* technique, const material::ProfileAtlas& atlas);

}  // namespace translucent::techniques
