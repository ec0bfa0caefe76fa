// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/geometry/hole_filling.h"

#include <fmt/format.h>

#include <array>
#include <cmath>
#include <iterator>
#include <map>
#include <vector>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/detect_features.h>
#include <CGAL/Polygon_mesh_processing/remesh.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>
#include <CGAL/Surface_mesh.h>

namespace translucent::geometry {
namespace {

namespace PMP = CGAL::Polygon_mesh_processing;
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
using Halfedge = boost::graph_traits<Mesh>::halfedge_descriptor;
using Face = boost::graph_traits<Mesh>::face_descriptor;
using Vertex = boost::graph_traits<Mesh>::vertex_descriptor;
using Edge = boost::graph_traits<Mesh>::edge_descriptor;

// The mesh as a CGAL surface: identical positions welded (CGAL needs the connectivity that the
// file's per-face vertex copies hide), then oriented consistently if the soup is not already an
// oriented manifold.
Mesh toSurfaceMesh(const TriangleMesh& in, const std::string& what) {
  std::vector<Point> points;
  std::map<std::array<double, 3>, size_t> ids;
  std::vector<size_t> weld(in.positions.size());
  for (size_t i = 0; i < in.positions.size(); ++i) {
    const glm::dvec3& p = in.positions[i];
    const auto [it, fresh] = ids.try_emplace({p.x, p.y, p.z}, points.size());
    if (fresh) points.emplace_back(p.x, p.y, p.z);
    weld[i] = it->second;
  }
  std::vector<std::array<size_t, 3>> polygons;
  polygons.reserve(in.triangles.size());
  for (const glm::uvec3& t : in.triangles) {
    const std::array<size_t, 3> f{weld[t.x], weld[t.y], weld[t.z]};
    // Welding can collapse a sliver whose corners coincide: it has no area to lose.
    if (f[0] != f[1] && f[1] != f[2] && f[0] != f[2]) polygons.push_back(f);
  }
  if (!PMP::is_polygon_soup_a_polygon_mesh(polygons)) {
    // Duplicates the points at non-manifold vertices and flips faces to one orientation.
    PMP::orient_polygon_soup(points, polygons);
    if (!PMP::is_polygon_soup_a_polygon_mesh(polygons))
      throw MeshError(fmt::format("{}: the triangles do not form an orientable manifold surface "
                                  "(after welding identical vertices): expected one that holes "
                                  "can be filled in", what));
  }
  Mesh m;
  PMP::polygon_soup_to_polygon_mesh(points, polygons, m);
  return m;
}

// Back to our representation; the mesh's indices must be dense (nothing removed, or collected).
TriangleMesh fromSurfaceMesh(const Mesh& m, const std::string& what) {
  TriangleMesh out;
  out.positions.reserve(m.number_of_vertices());
  for (const Vertex v : m.vertices()) {
    const Point& p = m.point(v);
    out.positions.emplace_back(p.x(), p.y(), p.z());
  }
  out.triangles.reserve(m.number_of_faces());
  for (const Face f : m.faces()) {
    std::array<uint32_t, 3> t{};
    size_t k = 0;
    for (const Vertex v : CGAL::vertices_around_face(m.halfedge(f), m)) {
      if (k == 3)
        throw MeshError(fmt::format("{}: a face with more than three corners: expected "
                                    "triangles", what));
      t[k++] = static_cast<uint32_t>(v.idx());
    }
    out.triangles.emplace_back(t[0], t[1], t[2]);
  }
  return out;
}

}  // namespace

HoleFillStats fillHoles(TriangleMesh& mesh, const std::string& what) {
  HoleFillStats st;
  st.area_before = mesh.area();
  if (mesh.openEdgeCount() == 0) return st;  // closed: nothing to weld or fill

  Mesh m = toSurfaceMesh(mesh, what);
  const size_t verticesBefore = m.number_of_vertices(), facesBefore = m.number_of_faces();
  std::vector<Halfedge> cycles;
  PMP::extract_boundary_cycles(m, std::back_inserter(cycles));
  st.holes = cycles.size();
  for (const Halfedge h : cycles) {
    std::vector<Face> patch;
    std::vector<Vertex> added;
    const bool faired = std::get<0>(PMP::triangulate_refine_and_fair_hole(
        m, h, std::back_inserter(patch), std::back_inserter(added)));
    if (patch.empty()) {
      ++st.unfilled;
      continue;
    }
    ++(faired ? st.faired : st.refined_unfaired);
    for (const Face f : patch) st.area_added += PMP::face_area(f, m);
  }
  st.triangles_added = m.number_of_faces() - facesBefore;
  st.vertices_added = m.number_of_vertices() - verticesBefore;

  // Nothing was removed, so the indices are dense and in insertion order: the welded input
  // vertices first, then the patches'.
  TriangleMesh out = fromSurfaceMesh(m, what);
  // Welding alone may change the vertex count; normals of the input no longer line up then.
  if (st.triangles_added == 0 && out.positions.size() == mesh.positions.size())
    out.normals = mesh.normals;
  mesh = std::move(out);
  return st;
}

}  // namespace translucent::geometry

namespace translucent::geometry {

size_t refineMesh(TriangleMesh& mesh, double targetLength, const std::string& what) {
  if (!(targetLength > 0.0) || !std::isfinite(targetLength))
    throw MeshError(fmt::format("{}: refinement to an edge length of {}: expected a finite "
                                "length > 0", what, targetLength));
  Mesh m = toSurfaceMesh(mesh, what);
  const size_t before = m.number_of_faces();
  // Sharp edges (dihedral angle above 60°: a box's, a fin's rim) are constraints: split where
  // they are long, never flipped or collapsed, so the shape keeps its corners and flat faces stay
  // flat; everything else is remeshed isotropically and projected back onto the input surface.
  auto sharp = m.add_property_map<Edge, bool>("e:sharp", false).first;
  PMP::detect_sharp_edges(m, 60.0, sharp);
  PMP::isotropic_remeshing(faces(m), targetLength, m,
                           CGAL::parameters::number_of_iterations(3)
                               .edge_is_constrained_map(sharp)
                               .protect_constraints(false));
  m.collect_garbage();
  mesh = fromSurfaceMesh(m, what);  // normals of the input no longer line up: dropped
  return m.number_of_faces() > before ? m.number_of_faces() - before : 0;
}

}  // namespace translucent::geometry
