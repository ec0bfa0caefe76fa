// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/geometry/icosphere.h"

#include <fmt/format.h>

#include <cmath>
#include <unordered_map>

#include <glm/geometric.hpp>

namespace translucent::geometry {

TriangleMesh makeIcosphere(unsigned subdivisions, double radius, const glm::dvec3& center) {
  if (subdivisions > 9)
    throw MeshError(fmt::format("icosphere subdivisions is {}: expected at most 9", subdivisions));
  if (!(radius > 0.0) || !std::isfinite(radius))
    throw MeshError(fmt::format("icosphere radius is {}: expected a positive finite radius",
                                radius));
  // Unit icosahedron: the 12 vertices (0, ±1, ±φ) and their cyclic permutations.
  const double phi = 0.5 * (1.0 + std::sqrt(5.0));
  std::vector<glm::dvec3> v = {{-1, phi, 0}, {1, phi, 0},  {-1, -phi, 0}, {1, -phi, 0},
                               {0, -1, phi}, {0, 1, phi},  {0, -1, -phi}, {0, 1, -phi},
                               {phi, 0, -1}, {phi, 0, 1},  {-phi, 0, -1}, {-phi, 0, 1}};
  for (auto& p : v) p = glm::normalize(p);
  std::vector<glm::uvec3> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                               {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                               {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                               {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7}, {9, 8, 1}};
  for (unsigned s = 0; s < subdivisions; ++s) {
    // One midpoint per undirected edge, shared by its two triangles (keeps the mesh closed).
    std::unordered_map<uint64_t, uint32_t> mid;
    const auto midpoint = [&](uint32_t a, uint32_t b) {
      const uint64_t key = (uint64_t(std::min(a, b)) << 32) | std::max(a, b);
      const auto [it, inserted] = mid.try_emplace(key, static_cast<uint32_t>(v.size()));
      if (inserted) v.push_back(glm::normalize(v[a] + v[b]));
      return it->second;
    };
    std::vector<glm::uvec3> next;
    next.reserve(4 * f.size());
    for (const auto& t : f) {
      const uint32_t ab = midpoint(t.x, t.y), bc = midpoint(t.y, t.z), ca = midpoint(t.z, t.x);
      next.emplace_back(t.x, ab, ca);
      next.emplace_back(t.y, bc, ab);
      next.emplace_back(t.z, ca, bc);
      next.emplace_back(ab, bc, ca);
    }
    f = std::move(next);
  }
  TriangleMesh m;
  m.normals = v;
  m.positions.reserve(v.size());
  for (const auto& p : v) m.positions.push_back(center + radius * p);
  m.triangles = std::move(f);
  return m;
}

}  // namespace translucent::geometry
