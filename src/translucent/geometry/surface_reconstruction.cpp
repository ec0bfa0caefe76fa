// SPDX-License-Identifier: GPL-3.0-or-later
// CGAL's advancing-front surface reconstruction (surface_reconstruction.h). The only file that
// includes CGAL/Advancing_front_surface_reconstruction.h; built in the CGAL object library
// (geometry/CMakeLists.txt) for its -frounding-math.
#include "translucent/geometry/surface_reconstruction.h"

#include <fmt/format.h>

#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <vector>

#include <glm/geometric.hpp>

#include <CGAL/Advancing_front_surface_reconstruction.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

namespace translucent::geometry {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Facet = std::array<std::size_t, 3>;

}  // namespace

TriangleMesh reconstructSurface(const PointCloud& cloud, const std::string& what,
                                ReconstructionStats* stats,
                                std::vector<uint32_t>* vertex_of_point) {
  const auto start = std::chrono::steady_clock::now();
  cloud.validate(what);
  std::vector<Point> points;
  points.reserve(cloud.size());
  for (const glm::vec3& p : cloud.positions) points.emplace_back(p.x, p.y, p.z);

  std::vector<Facet> facets;
  // The defaults of CGAL's free function: radius_ratio_bound 5 (facets whose circumradius is
  // more than 5 times the shortest edge of their neighbours are candidates only at the end) and
  // beta π/6 (the largest dihedral deviation a facet may make with its neighbour).
  if (points.size() >= 4)
    CGAL::advancing_front_surface_reconstruction(points.begin(), points.end(),
                                                 std::back_inserter(facets));

  constexpr uint32_t kUnused = std::numeric_limits<uint32_t>::max();
  std::vector<uint32_t> vertex(cloud.size(), kUnused);
  TriangleMesh mesh;
  ReconstructionStats st;
  st.points = cloud.size();
  for (const Facet& f : facets) {
    const glm::dvec3 a(cloud.positions[f[0]]), b(cloud.positions[f[1]]), c(cloud.positions[f[2]]);
    const glm::dvec3 n = glm::cross(b - a, c - a);
    if (!(glm::dot(n, n) > 0.0)) continue;  // zero area: validate() would refuse the mesh
    std::array<size_t, 3> idx = {f[0], f[1], f[2]};
    // The winding that agrees with the points' normals (their mean over the facet).
    const glm::dvec3 normal = glm::dvec3(cloud.normals[f[0]]) + glm::dvec3(cloud.normals[f[1]]) +
                              glm::dvec3(cloud.normals[f[2]]);
    if (glm::dot(n, normal) < 0.0) {
      std::swap(idx[1], idx[2]);
      ++st.flipped;
    }
    glm::uvec3 t;
    for (int k = 0; k < 3; ++k) {
      uint32_t& v = vertex[idx[static_cast<size_t>(k)]];
      if (v == kUnused) {
        v = static_cast<uint32_t>(mesh.positions.size());
        mesh.positions.emplace_back(cloud.positions[idx[static_cast<size_t>(k)]]);
        mesh.normals.emplace_back(cloud.normals[idx[static_cast<size_t>(k)]]);
      }
      t[k] = v;
    }
    mesh.triangles.push_back(t);
  }
  if (mesh.triangles.empty())
    throw MeshError(fmt::format("{}: no surface could be reconstructed through its {} points "
                                "(advancing front): expected at least 4 points spread over a "
                                "surface", what, cloud.size()));
  for (const uint32_t v : vertex) st.unused_points += v == kUnused ? 1 : 0;
  st.triangles = mesh.triangles.size();
  st.open_edges = mesh.openEdgeCount();
  st.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  mesh.validate(what);
  if (stats) *stats = st;
  if (vertex_of_point) *vertex_of_point = std::move(vertex);
  return mesh;
}

std::string describe(const ReconstructionStats& s) {
  return fmt::format("{} points, {} triangles, {} point{} unused, {}, {:.2g} s", s.points,
                     s.triangles, s.unused_points, s.unused_points == 1 ? "" : "s",
                     s.open_edges == 0 ? std::string("closed")
                                       : fmt::format("open ({} edges on its boundary)", s.open_edges),
                     s.seconds);
}

}  // namespace translucent::geometry
