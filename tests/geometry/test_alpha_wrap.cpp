// SPDX-License-Identifier: GPL-3.0-or-later
// Alpha wrapping (geometry/alpha_wrap.h): a soup that is neither closed nor manifold comes out as a
// closed, outward-oriented surface that encloses the input at about the offset; the cache returns
// the same mesh and recomputes a tampered file.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>

#include <unistd.h>

#include <glm/geometric.hpp>

#include "translucent/geometry/alpha_wrap.h"
#include "translucent/geometry/icosphere.h"
#include "translucent/geometry/ray_scene.h"

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

// A sphere of radius 0.5 (icosphere, 1280 triangles of edge ~0.066) broken the way scans are:
// one triangle missing (a hole smaller than alpha: alpha wrapping closes holes narrower than
// alpha and, by design, wraps the walls of wider ones from inside), one triangle duplicated, and
// a fin hanging off an edge (so that this edge has three triangles).
TriangleMesh brokenSphere() {
  TriangleMesh m = makeIcosphere(3, 0.5);
  const glm::uvec3 gone = m.triangles[7];
  m.triangles.erase(m.triangles.begin() + 7);
  m.triangles.push_back(m.triangles[0]);
  const glm::dvec3 a = m.positions[gone.x], b = m.positions[gone.y];
  m.positions.push_back(0.5 * (a + b) * 1.3);  // a fin sticking out by 0.15
  m.triangles.emplace_back(gone.x, gone.y, static_cast<unsigned>(m.positions.size() - 1));
  return m;
}

TEST(AlphaWrap, ABrokenSoupBecomesAClosedOrientedSurfaceAroundIt) {
  const TriangleMesh in = brokenSphere();
  ASSERT_GT(in.openEdgeCount(), 0u);  // the premise: not closed
  const AlphaWrapOptions opt{0.1, 0.005};
  AlphaWrapStats st;
  const TriangleMesh w = alphaWrap(in, opt, "broken sphere", &st);
  EXPECT_EQ(w.openEdgeCount(), 0u);
  EXPECT_NO_THROW(w.validate("wrap"));
  EXPECT_EQ(st.triangles_in, in.triangles.size());
  EXPECT_EQ(st.triangles_out, w.triangles.size());
  const double d = st.diagonal * opt.offset;  // the offset in scene units
  // Outward (positive) and the volume of the input grown by the offset: at least the
  // icosphere's (the wrap lies outside it), at most the sphere of radius 0.5 + d plus the fin's
  // thickened wedge (alpha wide: < 0.15 × 0.066 × alpha) and 3% for the wrap's facets.
  const TriangleMesh closed = makeIcosphere(3, 0.5);
  const double v = volume(w), v0 = volume(closed);
  const double ball = 4.0 / 3.0 * std::numbers::pi * std::pow(0.5 + d, 3.0);
  EXPECT_GT(v, v0);
  EXPECT_LT(v, 1.03 * ball + 0.15 * 0.066 * opt.alpha * st.diagonal);
  // It encloses the input: points inside the sphere lie inside the wrap, and the wrap stays
  // within the offset plus half an alpha (its facets are about alpha wide) of the sphere,
  // except near the fin.
  const RayScene rays(w, "wrap");
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-0.45, 0.45);
  int inside = 0, tried = 0;
  while (tried < 200) {
    const glm::dvec3 p(u(rng), u(rng), u(rng));
    if (glm::length(p) > 0.45) continue;
    ++tried;
    inside += insideClosedMesh(rays, p);
  }
  EXPECT_EQ(inside, tried);
  const glm::dvec3 fin = in.positions.back();
  const double tol = d + 0.5 * opt.alpha * st.diagonal;
  for (const glm::dvec3& p : w.positions) {
    if (glm::length(p - fin) < 0.2) continue;
    EXPECT_GT(glm::length(p), 0.5 * std::cos(std::numbers::pi / 20.0) - 1e-9);  // icosphere's inradius bound
    EXPECT_LT(glm::length(p), 0.5 + tol);
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
  const TriangleMesh in = brokenSphere();
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
