// SPDX-License-Identifier: GPL-3.0-or-later
// The one file that includes CGAL (its headers are heavy and not warning-clean under our flags;
// see src/geometry/CMakeLists.txt): a chart as a CGAL::Surface_mesh, mapped by
// Surface_mesh_parameterization.
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_parameterization/Circular_border_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/Discrete_authalic_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/Error_code.h>
#include <CGAL/Surface_mesh_parameterization/LSCM_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/Mean_value_coordinates_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/parameterize.h>

#include "translucent/geometry/atlas_chart.h"

namespace translucent::geometry::detail {
namespace {
using Kernel = CGAL::Simple_cartesian<double>;
using SurfaceMesh = CGAL::Surface_mesh<Kernel::Point_3>;
using VertexIndex = SurfaceMesh::Vertex_index;
namespace SMP = CGAL::Surface_mesh_parameterization;
using Border = SMP::Circular_border_arc_length_parameterizer_3<SurfaceMesh>;
}  // namespace

ChartUV parameterizeChart(std::span<const glm::dvec3> positions,
                          std::span<const glm::uvec3> triangles, ChartMap map) {
  ChartUV result;
  SurfaceMesh sm;
  std::vector<VertexIndex> vertices;
  vertices.reserve(positions.size());
  for (const glm::dvec3& p : positions) vertices.push_back(sm.add_vertex({p.x, p.y, p.z}));
  for (const glm::uvec3& t : triangles)
    if (sm.add_face(vertices[t.x], vertices[t.y], vertices[t.z]) == SurfaceMesh::null_face()) {
      result.error = "the chart is not a manifold surface (CGAL add_face)";
      return result;
    }
  SurfaceMesh::Halfedge_index border = SurfaceMesh::null_halfedge();
  for (const auto h : sm.halfedges())
    if (sm.is_border(h)) {
      border = h;
      break;
    }
  if (border == SurfaceMesh::null_halfedge()) {
    result.error = "the chart has no boundary";
    return result;
  }
  auto uvmap = sm.add_property_map<VertexIndex, Kernel::Point_2>("v:uv").first;
  SMP::Error_code err = SMP::OK;
  switch (map) {
    case ChartMap::Authalic:
      err = SMP::parameterize(sm, SMP::Discrete_authalic_parameterizer_3<SurfaceMesh, Border>(),
                              border, uvmap);
      break;
    case ChartMap::MeanValue:
      err = SMP::parameterize(
          sm, SMP::Mean_value_coordinates_parameterizer_3<SurfaceMesh, Border>(), border, uvmap);
      break;
    case ChartMap::Lscm:
      err = SMP::parameterize(sm, SMP::LSCM_parameterizer_3<SurfaceMesh>(), border, uvmap);
      break;
  }
  if (err != SMP::OK) {
    result.error = SMP::get_error_message(err);
    return result;
  }
  result.uv.reserve(vertices.size());
  for (const VertexIndex v : vertices) {
    const Kernel::Point_2& q = uvmap[v];
    result.uv.emplace_back(q.x(), q.y());
  }
  return result;
}

}  // namespace translucent::geometry::detail
