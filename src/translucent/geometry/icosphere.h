// SPDX-License-Identifier: GPL-3.0-or-later
// Icosphere: a closed triangle mesh approximating a sphere, from the regular icosahedron by
// splitting every triangle into four and pushing the new vertices onto the sphere, `subdivisions`
// times (20 · 4^s triangles, 10 · 4^s + 2 vertices). Vertex normals are the radial directions.
#pragma once

#include <glm/vec3.hpp>

#include "translucent/geometry/mesh.h"

namespace translucent::geometry {

// Throws MeshError for subdivisions > 9 (5.2 million triangles) or a radius that is not
// positive and finite.
TriangleMesh makeIcosphere(unsigned subdivisions, double radius = 1.0,
                           const glm::dvec3& center = glm::dvec3(0.0));

}  // namespace translucent::geometry
