// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/material/profile_atlas.h"

#include <fmt/format.h>

#include <array>

#include "translucent/optics/medium.h"  // ParameterError
#include "translucent/material/surface_uv.h"

namespace translucent::material {

ProfileAtlas buildProfileAtlas(const geometry::TriangleMesh& mesh, const geometry::Atlas& atlas,
                               const Material& material, const ProfileOptions& options,
                               const geometry::Atlas* surface_atlas) {
  if (atlas.triangleCount() != mesh.triangleCount())
    throw ParameterError(fmt::format("profile atlas: the atlas has {} triangles, the mesh {}",
                                     atlas.triangleCount(), mesh.triangleCount()));
  const bool surface = material.kind == Material::Kind::Surface;
  if (surface && !surface_atlas)
    throw ParameterError("profile atlas: a surface-map material needs the atlas its map is over");
  const geometry::AtlasCoverage coverage = geometry::rasterizeCoverage(atlas);
  const uint32_t n = atlas.size;

  // The owned texels' surface points, in row order.
  std::vector<glm::vec3> positions, normals;
  std::vector<glm::vec2> uvs;
  std::vector<uint32_t> texel, triangle;
  for (uint32_t y = 0; y < n; ++y)
    for (uint32_t x = 0; x < n; ++x) {
      const auto sp = geometry::texelSurfacePoint(mesh, atlas, coverage, x, y);
      if (!sp) continue;
      positions.emplace_back(sp->position);
      normals.emplace_back(sp->normal);
      texel.push_back(y * n + x);
      triangle.push_back(sp->triangle);
      if (surface) uvs.emplace_back(atlasUvAt(mesh, *surface_atlas, sp->triangle, sp->position));
    }
  if (positions.empty())
    throw ParameterError("profile atlas: no texel of the atlas lies on the mesh");

  ProfileAtlas out;
  out.size = n;
  out.profiles = PointProfiles::build(material,
                                      PointProfiles::surfaceMedia(material, positions, normals, uvs),
                                      options);
  out.segments = out.profiles.segments();
  out.radius = out.profiles.radius();
  out.triangle_uvs = atlas.uvs;
  out.texel_triangle = std::move(triangle);
  out.owned = positions.size();

  const size_t m = size_t(out.segments) + 1, plane = size_t(n) * n;
  out.nodes.assign(m * plane * 4, 0.0f);
  for (size_t i = 0; i < m * plane; ++i)
    for (size_t c = 0; c < 3; ++c) out.nodes[i * 4 + c] = float(kLnFloor);
  std::vector<uint8_t> state(plane, 0);  // 0 empty, 1 owned, 2 filled
  for (size_t i = 0; i < out.owned; ++i) {
    const size_t t = texel[i];
    state[t] = 1;
    for (size_t k = 0; k < m; ++k) {
      float* v = &out.nodes[(k * plane + t) * 4];
      for (int c = 0; c < 3; ++c) v[c] = float(out.profiles.node(i, c, int(k)));
      v[3] = 1.0f;
    }
  }
  // Dilation: each ring of empty texels next to owned or filled ones takes their mean.
  for (int ring = 0; ring < kProfileAtlasDilation; ++ring) {
    std::vector<size_t> fill;
    std::vector<std::array<size_t, 4>> from;
    std::vector<int> count;
    for (uint32_t y = 0; y < n; ++y)
      for (uint32_t x = 0; x < n; ++x) {
        const size_t t = size_t(y) * n + x;
        if (state[t] != 0) continue;
        std::array<size_t, 4> nb{};
        int c = 0;
        const auto take = [&](uint32_t xx, uint32_t yy) {
          const size_t s = size_t(yy) * n + xx;
          if (state[s] != 0) nb[size_t(c++)] = s;
        };
        if (x > 0) take(x - 1, y);
        if (x + 1 < n) take(x + 1, y);
        if (y > 0) take(x, y - 1);
        if (y + 1 < n) take(x, y + 1);
        if (c == 0) continue;
        fill.push_back(t);
        from.push_back(nb);
        count.push_back(c);
      }
    if (fill.empty()) break;
    for (size_t i = 0; i < fill.size(); ++i) {
      for (size_t k = 0; k < m; ++k) {
        float* v = &out.nodes[(k * plane + fill[i]) * 4];
        for (int ch = 0; ch < 3; ++ch) {
          double sum = 0.0;
          for (int j = 0; j < count[i]; ++j)
            sum += double(out.nodes[(k * plane + from[i][size_t(j)]) * 4 + size_t(ch)]);
          v[ch] = float(sum / count[i]);
        }
        v[3] = 0.0f;
      }
    }
    for (const size_t t : fill) state[t] = 2;
  }
  return out;
}

}  // namespace translucent::material
