// SPDX-License-Identifier: GPL-3.0-or-later
// Scenes shared by the mesh tracer's CPU and GPU tests: an orthographic camera looking at the
// origin, and three unit cubes in a row (exits and re-entries along a pencil beam).
#pragma once

#include <cmath>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "translucent/geometry/mesh.h"
#include "translucent/reference/camera.h"

namespace translucent::reference::test_support {

inline Camera orthographic(glm::dvec3 position, double height, int size) {
  Camera c;
  c.projection = Camera::Projection::Orthographic;
  c.position = position;
  c.look_at = glm::dvec3(0.0);
  c.up = std::abs(position.y) > 0.9 * glm::length(position) ? glm::dvec3(1.0, 0.0, 0.0)
                                                              : glm::dvec3(0.0, 1.0, 0.0);
  c.view_height = height;
  c.width = c.height = size;
  return c;
}

// Three unit cubes along z, 0.5 apart (one closed mesh of three parts): z in [-2.5, -1.5],
// [-1, 0], [0.5, 1.5].
inline geometry::TriangleMesh threeCubes() {
  geometry::TriangleMesh row;
  for (int k = 0; k < 3; ++k) {
    const double z0 = -2.5 + 1.5 * k;
    const geometry::TriangleMesh box = geometry::makeBox({-0.5, -0.5, z0}, {0.5, 0.5, z0 + 1.0});
    const auto base = static_cast<unsigned>(row.positions.size());
    row.positions.insert(row.positions.end(), box.positions.begin(), box.positions.end());
    for (const auto& tri : box.triangles) row.triangles.push_back(tri + glm::uvec3(base));
  }
  return row;
}

}  // namespace translucent::reference::test_support
