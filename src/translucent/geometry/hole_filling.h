// SPDX-License-Identifier: GPL-3.0-or-later
// Closing open meshes (and refining coarse ones, refineMesh below): every hole (boundary cycle) of a triangle mesh is triangulated, refined
// to the density of the surrounding triangles and faired (CGAL Polygon Mesh Processing,
// Liepa 2003, "Filling holes in meshes"). The reference transport needs a closed body with a
// well-defined interior (TriangleMesh::requireClosed); scanned heads and busts (CGAL's head.off,
// lion-head.off, mannequin-devil.off) are open at the neck and eyes.
//
// Per hole: triangulate_refine_and_fair_hole (the patch blends into the surface with C1
// continuity); when fairing fails (its sparse linear system is singular, e.g. for a hole with too
// few fixed neighbours) the patch is left as triangulate_and_refine_hole made it: the same
// triangles, unfaired. A hole that cannot be triangulated at all is counted as unfilled.
//
// CGAL is only included by hole_filling.cpp (its own object library: CGAL wants -frounding-math
// for its exact predicates, which the rest of the geometry code does not).
#pragma once

#include <cstddef>
#include <string>

#include "translucent/geometry/mesh.h"

namespace translucent::geometry {

struct HoleFillStats {
  size_t holes = 0;             // boundary cycles found
  size_t faired = 0;            // filled by triangulate_refine_and_fair_hole
  size_t refined_unfaired = 0;  // filled, fairing failed: triangulate_and_refine_hole's patch
  size_t unfilled = 0;          // no triangulation found: the hole stays open
  size_t triangles_added = 0;
  size_t vertices_added = 0;
  double area_before = 0.0;     // of the input mesh, in its units squared
  double area_added = 0.0;      // of the patches, in the same units

  size_t filled() const { return faired + refined_unfaired; }
};

// Fills every hole of `mesh` in place. Vertices with identical positions are welded first (files
// often repeat a vertex per face); the result's vertices are the welded input vertices in their
// first-occurrence order, then the patches' new vertices. Vertex normals are dropped when
// anything was added (consumers then compute them from the faces, as for files without normals).
// A closed mesh is left unchanged (holes = 0). Throws MeshError naming `what` when the triangles
// do not form an orientable manifold surface CGAL can build (e.g. an edge shared by three
// triangles).
HoleFillStats fillHoles(TriangleMesh& mesh, const std::string& what);

// Refines `mesh` in place until its edges are about `targetLength` long (CGAL Polygon Mesh
// Processing isotropic remeshing, three iterations; Botsch & Kobbelt 2004), with the sharp
// edges (dihedral angle above 60°) kept as constraints, so that corners and flat faces keep their
// shape. For renderers that interpolate per vertex over a mesh whose triangles are too large for
// it (a box of 12 triangles). Vertices are welded first (as fillHoles); vertex normals are
// dropped. Returns the number of triangles added. Throws MeshError naming `what` for a length
// that is not finite and positive, or a surface CGAL cannot build.
size_t refineMesh(TriangleMesh& mesh, double targetLength, const std::string& what);

}  // namespace translucent::geometry
