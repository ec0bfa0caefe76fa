// SPDX-License-Identifier: GPL-3.0-or-later
// Scenes shared by the mesh tracer's CPU and GPU tests: cameras looking at the origin, three unit
// cubes in a row (exits and re-entries along a pencil beam), the unit bunny.
#pragma once

#include <cmath>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "translucent/geometry/mesh.h"
#include "translucent/optics/medium.h"
#include "translucent/reference/camera.h"
#include "translucent/reference/transport.h"

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

#ifdef TRANSLUCENT_BUNNY_OBJ
// The closed bunny of glmark2-data, centred and scaled to a bounding radius of 1.
inline const geometry::TriangleMesh& unitBunny() {
  static const geometry::TriangleMesh mesh = [] {
    geometry::TriangleMesh m = geometry::loadMesh(TRANSLUCENT_BUNNY_OBJ);
    const geometry::Bounds b = m.bounds();
    m.transform(1.0 / b.radius(), -b.center() / b.radius());
    return m;
  }();
  return mesh;
}
#endif

// A sun, a point light and a beam of radius 0.4 around the unit sphere, coloured: every kind of
// delta light at once (the camera method's sphere tests).
inline std::vector<Light> threeLightTypes() {
  return {Light{DirectionalLight{glm::normalize(glm::dvec3(0.4, 0.3, 1.0)), 1.0}, {1.0, 0.9, 0.8}},
          Light{PointLight{{1.2, 1.5, 1.4}, 1.5}, {0.8, 0.8, 1.0}},
          Light{BeamLight{{-0.3, 0.2, 3.0}, {0.0, 0.0, -1.0}, 0.4, 0.4}, {1.0, 1.0, 1.0}}};
}

// A homogeneous, index-matched medium of coefficients per scene unit.
inline Medium indexMatched(const Rgb& sigma_a, const Rgb& sigma_s, double g) {
  Medium m;
  m.sigma_a = sigma_a;
  m.sigma_s = sigma_s;
  m.g = g;
  m.eta = 1.0;
  m.scale = 1.0;
  return m;
}

// A pinhole camera at `position` looking at the origin, fov 40°, size x size pixels.
inline Camera pinholeAtOrigin(const glm::dvec3& position, int size) {
  Camera camera;
  camera.position = position;
  camera.look_at = {0.0, 0.0, 0.0};
  camera.fov = 40.0;
  camera.width = camera.height = size;
  return camera;
}

}  // namespace translucent::reference::test_support
