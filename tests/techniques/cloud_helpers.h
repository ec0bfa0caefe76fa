// SPDX-License-Identifier: GPL-3.0-or-later
// Point clouds for the CPU traversal tests (test_pointcloud_cpu, test_pointcloud_hetero_cpu):
// sampled from a mesh and lit by a directional light without shadows.
#pragma once

#include <algorithm>
#include <cstdint>

#include <glm/geometric.hpp>

#include "translucent/geometry/mesh.h"
#include "translucent/geometry/point_cloud.h"

namespace translucent::pointcloud::testing {

inline geometry::PointCloud sample(const geometry::TriangleMesh& mesh, size_t count, uint64_t seed,
                                   geometry::SamplingMethod method =
                                       geometry::SamplingMethod::Elimination) {
  geometry::SamplingOptions o;
  o.count = count;
  o.seed = seed;
  o.method = method;
  return geometry::samplePointCloud(mesh, o);
}

// Directional light from `l` without shadows: E = max(0, n·l) · (1, 0.8, 0.6).
inline void light(geometry::PointCloud& c, const glm::vec3& l) {
  c.irradiance.resize(c.size());
  for (size_t i = 0; i < c.size(); ++i)
    c.irradiance[i] = std::max(0.0f, glm::dot(c.normals[i], glm::normalize(l))) *
                      glm::vec3(1.0f, 0.8f, 0.6f);
}

}  // namespace translucent::pointcloud::testing
