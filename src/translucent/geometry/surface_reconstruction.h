// SPDX-License-Identifier: GPL-3.0-or-later
// A triangle surface through the points of a point cloud, for the techniques and references that
// need a surface where only points exist (a PLY point cloud as a scene's mesh file: the explorer
// paper's point-cloud files of positions, normals and areas, rendered directly, with a surface
// reconstructed for display).
//
// Advancing-front surface reconstruction (Cohen-Steiner & Da 2004, "A greedy Delaunay-based
// surface reconstruction algorithm"; CGAL's implementation): it interpolates, so every vertex of
// the result is one of the cloud's points (a point it cannot attach is left out and counted), and
// it picks facets of the points' 3D Delaunay triangulation by a plausibility of the angle between
// neighbouring facets, which suits the dense, even samples that `translucent pointcloud` writes
// (blue noise by sample elimination). The facets are oriented by the cloud's normals (each
// triangle's winding agrees with the mean of its three points' normals), and the mesh's vertex
// normals are the points' own. Faces of zero area are dropped.
//
// CGAL is included only by surface_reconstruction.cpp (the CGAL object library, for its
// -frounding-math).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "translucent/geometry/mesh.h"
#include "translucent/geometry/point_cloud.h"

namespace translucent::geometry {

struct ReconstructionStats {
  size_t points = 0;         // in the cloud
  size_t unused_points = 0;  // not a vertex of any facet (outliers, isolated samples)
  size_t triangles = 0;
  size_t flipped = 0;        // facets whose winding the normals reversed
  size_t open_edges = 0;     // 0: a closed surface
  double seconds = 0.0;
};

// The surface through `cloud` (validate()d first). `vertex_of_point`, when given, receives per
// point its vertex in the result (UINT32_MAX for an unused point). Throws MeshError naming `what`
// when no facet results (fewer than 4 points, all on a line or a plane without area).
TriangleMesh reconstructSurface(const PointCloud& cloud, const std::string& what,
                                ReconstructionStats* stats = nullptr,
                                std::vector<uint32_t>* vertex_of_point = nullptr);

// "12,000 points, 23,990 triangles, 3 points unused, closed, 0.4 s": for notes and --json.
std::string describe(const ReconstructionStats& stats);

}  // namespace translucent::geometry
