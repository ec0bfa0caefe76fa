// SPDX-License-Identifier: GPL-3.0-or-later
// Distance from a point to a triangle mesh (unsigned: the distance to the closest point of any
// triangle), through a bounding volume hierarchy built here: Embree 3's point queries would do
// too, but the ray scene (geometry/ray_scene.h) is single precision and keeps Embree private,
// and depths of layers need double precision near the surface. Thread-safe once built.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

namespace translucent::material {

class SurfaceDistance {
 public:
  // Triangles as vertex triples (any winding). Throws ParameterError when there are none.
  SurfaceDistance(std::vector<glm::dvec3> positions, const std::vector<glm::uvec3>& triangles);
  double distance(const glm::dvec3& q) const;
  size_t triangleCount() const { return tris_.size(); }

  struct Tri {
    glm::dvec3 a, b, c;
  };
  struct Node {
    glm::dvec3 lo, hi;
    uint32_t first = 0, count = 0;  // leaf: tris_[first, first + count)
    uint32_t left = 0, right = 0;   // inner (count == 0)
  };
  // The tree, root first (for the GPU twin, reference/gpu/field_gpu.h).
  const std::vector<Tri>& triangles() const { return tris_; }
  const std::vector<Node>& nodes() const { return nodes_; }

 private:
  uint32_t build(uint32_t first, uint32_t count);
  std::vector<Tri> tris_;
  std::vector<Node> nodes_;
};

// Closest point of triangle abc to p (Ericson, Real-Time Collision Detection, 5.1.5).
glm::dvec3 closestPointOnTriangle(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b,
                                  const glm::dvec3& c);

}  // namespace translucent::material
