// SPDX-License-Identifier: GPL-3.0-or-later
// CGAL's alpha wrapping (alpha_wrap.h). The only file that includes CGAL/alpha_wrap_3.h; built in
// the CGAL object library (geometry/CMakeLists.txt) for its -frounding-math.
#include "translucent/geometry/alpha_wrap.h"

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <stdexcept>
#include <vector>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/alpha_wrap_3.h>

namespace translucent::geometry {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;

bool inUnitRange(double v) { return std::isfinite(v) && v > 0.0 && v <= 1.0; }

}  // namespace

TriangleMesh alphaWrap(const TriangleMesh& mesh, const AlphaWrapOptions& options,
                       const std::string& what, AlphaWrapStats* stats) {
  if (!inUnitRange(options.alpha) || !inUnitRange(options.offset))
    throw std::invalid_argument(fmt::format("alphaWrap: alpha {} and offset {} must be in (0, 1]",
                                            options.alpha, options.offset));
  const Bounds b = mesh.bounds();
  const glm::dvec3 extent = b.upper - b.lower;
  const double diagonal = std::sqrt(extent.x * extent.x + extent.y * extent.y + extent.z * extent.z);
  if (!(diagonal > 0.0) || !std::isfinite(diagonal) || mesh.triangles.empty())
    throw MeshError(fmt::format("{}: nothing to wrap: expected triangles with a finite, non-empty "
                                "bounding box", what));

  // The input as a soup: alpha_wrap_3 needs neither welded vertices nor a manifold, which is the
  // point (duplicate faces and edges shared by three triangles are wrapped like any other).
  std::vector<Point> points;
  points.reserve(mesh.positions.size());
  for (const glm::dvec3& p : mesh.positions) points.emplace_back(p.x, p.y, p.z);
  std::vector<std::array<size_t, 3>> faces;
  faces.reserve(mesh.triangles.size());
  for (const glm::uvec3& t : mesh.triangles) faces.push_back({t.x, t.y, t.z});

  Mesh wrap;
  CGAL::alpha_wrap_3(points, faces, options.alpha * diagonal, options.offset * diagonal, wrap);
  if (wrap.number_of_faces() == 0)
    throw MeshError(fmt::format("{}: the alpha wrap came out empty (alpha {}, offset {} of the "
                                "diagonal): expected a larger alpha", what, options.alpha,
                                options.offset));

  // Surface_mesh indices are dense after alpha_wrap_3 (it builds the mesh without removals).
  TriangleMesh out;
  out.positions.reserve(wrap.number_of_vertices());
  for (const Mesh::Vertex_index v : wrap.vertices()) {
    const Point& p = wrap.point(v);
    out.positions.emplace_back(CGAL::to_double(p.x()), CGAL::to_double(p.y()),
                               CGAL::to_double(p.z()));
  }
  out.triangles.reserve(wrap.number_of_faces());
  for (const Mesh::Face_index f : wrap.faces()) {
    std::array<unsigned, 3> idx{};
    int k = 0;
    for (const Mesh::Vertex_index v : CGAL::vertices_around_face(wrap.halfedge(f), wrap)) {
      if (k == 3) throw MeshError(fmt::format("{}: the alpha wrap has a non-triangular face", what));
      idx[static_cast<size_t>(k++)] = static_cast<unsigned>(v.idx());
    }
    if (k != 3) throw MeshError(fmt::format("{}: the alpha wrap has a degenerate face", what));
    out.triangles.emplace_back(idx[0], idx[1], idx[2]);
  }
  if (stats) {
    stats->triangles_in = mesh.triangles.size();
    stats->triangles_out = out.triangles.size();
    stats->diagonal = diagonal;
    stats->area_in = mesh.area();
    stats->area_out = out.area();
  }
  return out;
}

}  // namespace translucent::geometry
