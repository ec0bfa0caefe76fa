// Alpha wrapping (geometry/alpha_wrap.h): a soup that is neither closed nor manifold comes out as a
// closed, outward-oriented surface that encloses the input at about the offset; the cache returns
// the same mesh and recomputes a tampered file.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

#include <unistd.h>

#include <glm/geometric.hpp>

#include "geometry/alpha_wrap.h"
#include "geometry/ray_scene.h"

namespace translucent::geometry {
namespace {

// The unit cube [0,1]³ as 12 triangles, outward.
TriangleMesh cube() {
  TriangleMesh m;
  for (int i = 0; i < 8; ++i) m.positions.emplace_back(i & 1, (i >> 1) & 1, (i >> 2) & 1);
  m.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                 {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return m;
}

// Signed volume by the divergence theorem: positive for an outward-oriented closed surface.
double volume(const TriangleMesh& m) {
  double v = 0.0;
  for (const glm::uvec3& t : m.triangles)
    v += glm::dot(m.positions[t.x], glm::cross(m.positions[t.y], m.positions[t.z])) / 6.0;
  return v;
}

// The cube broken the way scans are: one face missing (a hole), one triangle duplicated, and a
// fin (a triangle hanging off an edge, so that the edge has three triangles).
TriangleMesh brokenCube() {
  TriangleMesh m = cube();
  m.triangles.erase(m.triangles.begin() + 2, m.triangles.begin() + 4);  // the z = 1 face
  m.triangles.push_back(m.triangles[0]);
  m.positions.emplace_back(0.5, -0.4, 0.0);
  m.triangles.emplace_back(0, 1, static_cast<unsigned>(m.positions.size() - 1));
  return m;
}

TEST(AlphaWrap, ABrokenSoupBecomesAClosedOrientedSurfaceAroundIt) {
  const TriangleMesh in = brokenCube();
  ASSERT_GT(in.openEdgeCount(), 0u);  // the premise: not closed
  const AlphaWrapOptions opt{0.05, 0.005};
  AlphaWrapStats st;
  const TriangleMesh w = alphaWrap(in, opt, "broken cube", &st);
  EXPECT_EQ(w.openEdgeCount(), 0u);
  EXPECT_NO_THROW(w.validate("wrap"));
  EXPECT_EQ(st.triangles_in, in.triangles.size());
  EXPECT_EQ(st.triangles_out, w.triangles.size());
  const double d = st.diagonal * opt.offset;  // the offset in scene units
  // Outward and about the size of the input: the cube grown by the offset (the fin adds a thin
  // wedge; rounded corners and edges remove a little of the (1 + 2d)³ box). 5% covers both.
  const double v = volume(w);
  EXPECT_GT(v, 0.95);
  EXPECT_LT(v, 1.05 * std::pow(1.0 + 2.0 * d, 3.0) + 0.2 * 0.4 * 0.5);
  // It encloses the input: every input point (and the centre) lies inside the wrap, and every
  // point of the wrap within the bounding box of the input grown by the offset and a tolerance
  // of half an alpha (the wrap's facets are about alpha wide).
  const RayScene rays(w, "wrap");
  EXPECT_TRUE(insideClosedMesh(rays, glm::dvec3(0.5)));
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(0.02, 0.98);
  for (int i = 0; i < 200; ++i) EXPECT_TRUE(insideClosedMesh(rays, {u(rng), u(rng), u(rng)}));
  const double tol = d + 0.5 * opt.alpha * st.diagonal;
  for (const glm::dvec3& p : w.positions) {
    EXPECT_GT(p.x, -tol);
    EXPECT_LT(p.x, 1.0 + tol);
    EXPECT_GT(p.y, -0.4 - tol);
    EXPECT_LT(p.z, 1.0 + tol);
  }
}

TEST(AlphaWrap, NothingToWrapIsAMeshErrorNamingTheInput) {
  TriangleMesh empty;
  try {
    (void)alphaWrap(empty, {}, "mesh file 'x.ply'");
    FAIL() << "no error";
  } catch (const MeshError& e) {
    EXPECT_NE(std::string(e.what()).find("mesh file 'x.ply': nothing to wrap"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW((void)alphaWrap(cube(), {0.0, 0.01}, "cube"), std::invalid_argument);
}

TEST(AlphaWrap, TheCacheReturnsTheSameWrapAndRecomputesATamperedFile) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("translucent-wrap-test-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  const TriangleMesh in = brokenCube();
  const AlphaWrapOptions opt{0.1, 0.01};
  AlphaWrapStats first, second, third;
  const TriangleMesh a = loadOrAlphaWrap(in, opt, "cube", dir, &first);
  EXPECT_FALSE(first.from_cache);
  EXPECT_EQ(first.note, "");
  ASSERT_TRUE(std::filesystem::exists(first.cache_file));
  const TriangleMesh b = loadOrAlphaWrap(in, opt, "cube", dir, &second);
  EXPECT_TRUE(second.from_cache);
  EXPECT_EQ(a.positions, b.positions);
  EXPECT_EQ(a.triangles, b.triangles);
  // Flip one byte of the payload: detected by the content hash, recomputed, noted.
  {
    std::fstream f(first.cache_file, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(-5, std::ios::end);
    f.put('\x7f');
  }
  const TriangleMesh c = loadOrAlphaWrap(in, opt, "cube", dir, &third);
  EXPECT_FALSE(third.from_cache);
  EXPECT_NE(third.note.find("content hash mismatch"), std::string::npos) << third.note;
  EXPECT_EQ(c.triangles, a.triangles);
  // Other options: another file.
  AlphaWrapStats other;
  (void)loadOrAlphaWrap(in, {0.2, 0.01}, "cube", dir, &other);
  EXPECT_NE(other.cache_file, first.cache_file);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace translucent::geometry
