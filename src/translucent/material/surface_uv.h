// SPDX-License-Identifier: GPL-3.0-or-later
// Atlas UVs of surface points, for surface-map materials (Material::Kind::Surface reads its map
// at a point's atlas UV, material.h). Shared by the point-cloud technique (its cloud points and
// vertices) and the model reference (its samples and camera hits), so that both read the map at
// the same UVs for the same point.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "translucent/geometry/atlas.h"
#include "translucent/geometry/mesh.h"

namespace translucent::material {

// The atlas UV of point x on triangle `face`: the triangle's corner UVs at x's barycentrics (of
// the point of the triangle's plane nearest to x, clamped to the triangle; a degenerate triangle
// gives its centroid's UV).
glm::dvec2 atlasUvAt(const geometry::TriangleMesh& mesh, const geometry::Atlas& atlas,
                     uint32_t face, const glm::dvec3& x);
// atlasUvAt of every point (faces[i]: the triangle point i lies on). Throws ParameterError when
// the sizes differ.
std::vector<glm::vec2> atlasUvs(const geometry::TriangleMesh& mesh, const geometry::Atlas& atlas,
                                std::span<const uint32_t> faces,
                                std::span<const glm::vec3> positions);
// One UV per vertex, from the first triangle that uses it (a vertex on a chart seam has one UV
// per chart, and the map is read at one of them); 0 for unused vertices.
std::vector<glm::vec2> vertexAtlasUvs(const geometry::TriangleMesh& mesh,
                                      const geometry::Atlas& atlas);

}  // namespace translucent::material
