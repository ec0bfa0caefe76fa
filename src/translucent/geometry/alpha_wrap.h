// SPDX-License-Identifier: GPL-3.0-or-later
// Watertight wrapping of meshes that are not closed manifolds: CGAL's 3D alpha wrapping
// (Portaneri, Rouxel-Labbé, Hemmer, Cohen-Steiner & Alliez 2022, "Alpha Wrapping with an Offset").
//
// Why: the reference transport needs a closed body with a well-defined inside
// (TriangleMesh::requireClosed). Hole filling (hole_filling.h) closes a surface that is already an
// oriented manifold with a few holes; scanned meshes such as the npm Stanford dragon are not —
// its res2 file has 1489 duplicate faces and 2534 edges shared by more than two triangles, and
// its holes at res3/res4 are tangled so that no triangulation fills them. Alpha wrapping does not
// repair the input: it shrink-wraps a new surface around it, which is by construction a closed,
// 2-manifold, outward-oriented, self-intersection-free triangle mesh at a distance `offset`
// outside the input, with no cavity or tunnel narrower than `alpha`.
//
// The price: the wrap is a different mesh (new vertices, slightly inflated by the offset, features
// thinner than alpha are thickened). Every technique and reference of a scene sees the same wrap,
// so comparisons stay like with like. alpha and offset are relative to the input's bounding-box
// diagonal (CGAL's examples use diag / alpha_rel, diag / offset_rel); defaults 1/300 and 1/3000:
// a dragon at unit size keeps its scales and claws within ~0.3% of the diagonal.
//
// CGAL is included only by alpha_wrap.cpp (CGAL's -frounding-math object library, as hole_filling).
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>

#include "translucent/geometry/mesh.h"

namespace translucent::geometry {

struct AlphaWrapOptions {
  double alpha = 1.0 / 300.0;   // relative to the bounding-box diagonal, in (0, 1]
  double offset = 1.0 / 3000.0; // relative to the bounding-box diagonal, in (0, 1]
};

struct AlphaWrapStats {
  size_t triangles_in = 0, triangles_out = 0;
  double diagonal = 0.0;      // of the input's bounding box, in its units
  double area_in = 0.0, area_out = 0.0;
  bool from_cache = false;
  std::filesystem::path cache_file;  // "" when caching is off
  std::string note;                  // why the cache was not read or written ("" when it was)
};

// The wrap of `mesh` (any triangle soup: open, non-manifold, duplicated faces). Throws MeshError
// naming `what` when the input has no extent or the wrap comes out empty; std::invalid_argument
// for options outside (0, 1] (the scene reader checks them first and names the key). Normals and texture
// coordinates are not carried over (consumers compute normals from the faces).
TriangleMesh alphaWrap(const TriangleMesh& mesh, const AlphaWrapOptions& options,
                       const std::string& what, AlphaWrapStats* stats = nullptr);

// The same through an on-disk cache in `cacheDir` (a wrap of a large scan takes seconds to
// minutes): the file is named by the input's content hash and the options, holds a content hash
// of its own and is regenerated (with a note) when it is missing, truncated or edited. An empty
// `cacheDir` disables the cache; a folder that cannot be written is a note, not an error.
TriangleMesh loadOrAlphaWrap(const TriangleMesh& mesh, const AlphaWrapOptions& options,
                             const std::string& what, const std::filesystem::path& cacheDir,
                             AlphaWrapStats* stats = nullptr);

}  // namespace translucent::geometry
