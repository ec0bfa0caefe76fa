// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/material/surface_uv.h"

#include <fmt/format.h>

#include <algorithm>

#include <glm/geometric.hpp>

#include "translucent/optics/medium.h"  // ParameterError

namespace translucent::material {

glm::dvec2 atlasUvAt(const geometry::TriangleMesh& mesh, const geometry::Atlas& atlas,
                     uint32_t face, const glm::dvec3& x) {
  const glm::uvec3 t = mesh.triangles[face];
  const glm::dvec3 a = mesh.positions[t[0]], e0 = mesh.positions[t[1]] - a,
                   e1 = mesh.positions[t[2]] - a, e2 = x - a;
  const double d00 = glm::dot(e0, e0), d01 = glm::dot(e0, e1), d11 = glm::dot(e1, e1);
  const double d20 = glm::dot(e2, e0), d21 = glm::dot(e2, e1), den = d00 * d11 - d01 * d01;
  const double v = den > 0.0 ? std::clamp((d11 * d20 - d01 * d21) / den, 0.0, 1.0) : 1.0 / 3.0;
  const double w = den > 0.0 ? std::clamp((d00 * d21 - d01 * d20) / den, 0.0, 1.0 - v) : 1.0 / 3.0;
  const double u = 1.0 - v - w;
  return u * glm::dvec2(atlas.uv(face, 0)) + v * glm::dvec2(atlas.uv(face, 1)) +
         w * glm::dvec2(atlas.uv(face, 2));
}

std::vector<glm::vec2> atlasUvs(const geometry::TriangleMesh& mesh, const geometry::Atlas& atlas,
                                std::span<const uint32_t> faces,
                                std::span<const glm::vec3> positions) {
  if (faces.size() != positions.size())
    throw ParameterError(fmt::format("atlas UVs: {} triangles for {} points: expected the triangle "
                                     "of every point", faces.size(), positions.size()));
  std::vector<glm::vec2> out(positions.size());
  for (size_t i = 0; i < positions.size(); ++i)
    out[i] = glm::vec2(atlasUvAt(mesh, atlas, faces[i], glm::dvec3(positions[i])));
  return out;
}

std::vector<glm::vec2> vertexAtlasUvs(const geometry::TriangleMesh& mesh,
                                      const geometry::Atlas& atlas) {
  std::vector<glm::vec2> out(mesh.vertexCount(), glm::vec2(0.0f));
  std::vector<bool> seen(mesh.vertexCount(), false);
  for (size_t f = 0; f < mesh.triangleCount(); ++f)
    for (int c = 0; c < 3; ++c) {
      const uint32_t v = mesh.triangles[f][c];
      if (seen[v]) continue;
      seen[v] = true;
      out[v] = atlas.uv(f, c);
    }
  return out;
}

}  // namespace translucent::material
