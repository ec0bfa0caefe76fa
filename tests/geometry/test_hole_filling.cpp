// SPDX-License-Identifier: GPL-3.0-or-later
// Hole filling (geometry/hole_filling.h) on CGAL's open head meshes, found on the scene data
// search path (scripts/install-test-data extracts them): every hole is filled, the result passes
// the closed-mesh check the references use (TriangleMesh::requireClosed), the patches are a small
// part of the area and the body has a positive volume once oriented.
//
// The patch area is bounded below exactly: the vector area ∫n dA of a surface depends only on its
// boundary, so the patches' vector area is minus the open mesh's, and a patch's area is at least
// the length of its vector area (equality for a flat patch). Above, a faired patch bulges like a
// shallow dome, not a balloon: at most 1.5 times that (a hemisphere would be 2).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <string>

#include <glm/geometric.hpp>

#include "translucent/geometry/hole_filling.h"
#include "translucent/scene/data_path.h"

namespace translucent::geometry {
namespace {
namespace fs = std::filesystem;

// The CGAL mesh `name` from the data search path; fails (never skips) when it is not installed.
TriangleMesh cgalMesh(const std::string& name) {
  for (const fs::path& dir : scene::dataSearchPath())
    if (fs::exists(dir / "cgal" / name)) return loadMesh((dir / "cgal" / name).string());
  std::string where;
  for (const fs::path& dir : scene::dataSearchPath()) {
    where += ' ';  // not " " + ...: GCC 12's -Wrestrict false positive
    where += (dir / "cgal").string();
  }
  ADD_FAILURE() << "cgal/" << name << " is not installed (looked in" << where
                << "): run scripts/install-test-data";
  return {};
}

glm::dvec3 vectorArea(const TriangleMesh& m) {
  glm::dvec3 a(0.0);
  for (const glm::uvec3& t : m.triangles)
    a += 0.5 * glm::cross(m.positions[t.y] - m.positions[t.x], m.positions[t.z] - m.positions[t.x]);
  return a;
}

double signedVolume(const TriangleMesh& m) {
  double v6 = 0.0;
  for (const glm::uvec3& t : m.triangles)
    v6 += glm::dot(m.positions[t.x], glm::cross(m.positions[t.y], m.positions[t.z]));
  return v6 / 6.0;
}

struct OpenHead {
  const char* file;
  size_t open_edges;       // boundary edges as distributed
  double max_patch_share;  // of the mesh area: the openings' size (measured 11%, 23%, 14%)
};

class HoleFillingHeads : public ::testing::TestWithParam<OpenHead> {};

TEST_P(HoleFillingHeads, BecomesClosedWithSmallPatchesAndPositiveVolume) {
  TriangleMesh m = cgalMesh(GetParam().file);
  ASSERT_FALSE(m.triangles.empty());
  ASSERT_EQ(m.openEdgeCount(), GetParam().open_edges) << "not the mesh these numbers are for";
  const double area = m.area();
  const double openVectorArea = glm::length(vectorArea(m));
  const size_t triangles = m.triangleCount();

  const HoleFillStats st = fillHoles(m, GetParam().file);
  std::cout << GetParam().file << ": " << st.holes << " holes, " << st.faired << " faired, "
            << st.refined_unfaired << " refined without fairing, " << st.triangles_added
            << " triangles added, patch area " << st.area_added / area << " of the mesh's\n";
  EXPECT_GE(st.holes, 1u);
  EXPECT_EQ(st.unfilled, 0u);
  EXPECT_EQ(st.filled(), st.holes);
  EXPECT_GT(st.triangles_added, 0u);
  EXPECT_EQ(m.triangleCount(), triangles + st.triangles_added);
  EXPECT_DOUBLE_EQ(st.area_before, area);

  EXPECT_EQ(m.openEdgeCount(), 0u);
  EXPECT_NO_THROW(m.requireClosed(GetParam().file));  // the model reference's and tracer's check
  EXPECT_NO_THROW(m.validate(GetParam().file));       // no degenerate patch triangles
  // The patches' area is what the mesh gained (1e-9: summation order only).
  EXPECT_NEAR(m.area(), area + st.area_added, 1e-9 * area);
  // The file's winding is consistent (the vector-area bound below relies on it).
  EXPECT_NEAR(glm::length(vectorArea(m)), 0.0, 1e-9 * area) << "closed: zero vector area";
  EXPECT_GE(st.area_added, openVectorArea * (1.0 - 1e-9));
  EXPECT_LE(st.area_added, 1.5 * openVectorArea) << st.area_added / openVectorArea;
  // The openings (neck, eyes; the back of a mask or bust) are a small part of the surface.
  EXPECT_LT(st.area_added, GetParam().max_patch_share * area) << st.area_added / area;

  m.orientOutwards();
  EXPECT_GT(signedVolume(m), 0.0);
  EXPECT_FALSE(m.orientOutwards()) << "a closed, consistently wound mesh orients once";
}

INSTANTIATE_TEST_SUITE_P(CgalHeads, HoleFillingHeads,
                         ::testing::Values(OpenHead{"head.off", 58, 0.15},
                                           OpenHead{"lion-head.off", 36, 0.30},
                                           OpenHead{"mannequin-devil.off", 64, 0.20}),
                         [](const ::testing::TestParamInfo<OpenHead>& p) {
                           std::string n = fs::path(p.param.file).stem().string();
                           for (char& c : n)
                             if (c == '-') c = '_';
                           return n;
                         });

TEST(HoleFilling, BoxWithoutItsTopGetsOnePatchSpanningTheSquare) {
  TriangleMesh box = makeBox({0, 0, 0}, {1, 1, 1});
  // makeBox's fourth quad is the top (y = 1): triangles 6 and 7.
  box.triangles.erase(box.triangles.begin() + 6, box.triangles.begin() + 8);
  ASSERT_EQ(box.openEdgeCount(), 4u);
  const HoleFillStats st = fillHoles(box, "box");
  EXPECT_EQ(st.holes, 1u);
  EXPECT_EQ(st.filled(), 1u);
  EXPECT_EQ(box.openEdgeCount(), 0u);
  // At least the unit square (projection onto y = 1), and the fairing does not balloon it.
  EXPECT_GE(st.area_added, 1.0 - 1e-12);
  EXPECT_LT(st.area_added, 1.5);
  EXPECT_NEAR(box.area(), 6.0 - 1.0 + st.area_added, 1e-12);
  box.orientOutwards();
  EXPECT_GT(signedVolume(box), 0.999);  // the unit cube, or a little more where it bulges
}

TEST(HoleFilling, ClosedMeshIsLeftAsItIs) {
  TriangleMesh box = makeBox({0, 0, 0}, {2, 1, 1});
  const TriangleMesh before = box;
  const HoleFillStats st = fillHoles(box, "box");
  EXPECT_EQ(st.holes, 0u);
  EXPECT_EQ(st.triangles_added, 0u);
  EXPECT_EQ(box.positions, before.positions);
  EXPECT_EQ(box.triangles, before.triangles);
}

// refineMesh on a thin box (12 triangles, the compare suite's plate): the same closed solid
// (area and bounding box to rounding: flat faces stay flat, the sharp rims stay), every edge
// within the isotropic remesher's band around the target ([4/5, 4/3] of it, with room for the
// split rims' remainders), and many more triangles.
TEST(RefineMesh, KeepsABoxAndShortensItsEdges) {
  TriangleMesh box = makeBox({-0.5, -0.5, -0.03}, {0.5, 0.5, 0.03});
  const double area = box.area();
  const size_t added = refineMesh(box, 0.05, "box");
  EXPECT_GT(added, 500u);
  EXPECT_EQ(box.openEdgeCount(), 0u);
  EXPECT_NEAR(box.area(), area, 1e-9 * area);
  const Bounds b = box.bounds();
  EXPECT_NEAR(b.lower.x, -0.5, 1e-12);
  EXPECT_NEAR(b.upper.z, 0.03, 1e-12);
  double longest = 0.0;
  for (const glm::uvec3& t : box.triangles)
    for (int k = 0; k < 3; ++k)
      longest = std::max(longest, glm::length(box.positions[t[k]] - box.positions[t[(k + 1) % 3]]));
  EXPECT_LT(longest, 0.05 * 4.0 / 3.0 + 1e-9);
  EXPECT_THROW((void)refineMesh(box, 0.0, "box"), MeshError);
}

}  // namespace
}  // namespace translucent::geometry
