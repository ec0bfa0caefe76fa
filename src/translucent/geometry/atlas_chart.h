// SPDX-License-Identifier: GPL-3.0-or-later
// Internal to the atlas (atlas.cpp): mapping one chart, a topological disk, to the plane with
// CGAL's Surface_mesh_parameterization. Kept apart so that CGAL is compiled in one file only
// (atlas_parameterize.cpp) and stays out of every header.
#pragma once

#include <span>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "translucent/geometry/atlas.h"

namespace translucent::geometry::detail {

enum class ChartMap { Authalic, Lscm, MeanValue };

struct ChartUV {
  std::vector<glm::dvec2> uv;  // per chart vertex; empty when CGAL failed
  std::string error;           // CGAL's reason when it failed
};

// `triangles` index `positions` and form one disk with one boundary loop, consistently oriented.
// Authalic and MeanValue fix the boundary on a circle (arc-length spacing); Lscm pins two
// boundary vertices and leaves the rest free.
ChartUV parameterizeChart(std::span<const glm::dvec3> positions,
                          std::span<const glm::uvec3> triangles, ChartMap map);

// Atlas::surfaceArea and texelArea from the mesh and Atlas::uvs (also for atlases read back from
// the cache).
void computeAtlasAreas(const TriangleMesh& mesh, Atlas& atlas);

}  // namespace translucent::geometry::detail
