// SPDX-License-Identifier: GPL-3.0-or-later
// The flat BVH for GPU ray queries (geometry/flat_bvh.h, shaders/reference/bvh.glsl): the tree's
// structure, its CPU traversal against Embree's own queries (geometry::RayScene) and for
// watertightness at shared edges and vertices, and the GPU traversal (bvh.glsl, through
// shaders/tests/bvh_query.comp) against the CPU traversal ray for ray. GL runs on whatever EGL
// offers (Mesa llvmpipe here): ~10k rays per dispatch.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <set>
#include <span>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>

#include "translucent/geometry/flat_bvh.h"
#include "translucent/geometry/icosphere.h"
#include "translucent/geometry/ray_scene.h"
#include "translucent/gpu/compute.h"
#include "gpu/gpu_test.h"
#include "translucent/gpu/program.h"
#include "test_meshes.h"

namespace translucent::geometry {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

struct TestRay {
  glm::vec3 o, d;
  float tMin = 0.0f, tMax = kInf;
};

bool inside(const FlatBvhNode& box, const float* lower, const float* upper) {
  for (int k = 0; k < 3; ++k)
    if (lower[k] < box.lower[k] || upper[k] > box.upper[k]) return false;
  return true;
}

// Walks the tree from the root: every node reached once, children in range, boxes nested, leaf
// ranges partitioning the triangle array, every mesh triangle once with its float positions.
void expectWellFormed(const FlatBvh& bvh, const TriangleMesh& mesh) {
  ASSERT_FALSE(bvh.nodes.empty());
  ASSERT_EQ(bvh.triangles.size(), mesh.triangleCount());
  EXPECT_GE(bvh.depth, 1);
  EXPECT_LE(bvh.depth, 64);  // bvh.glsl's traversal stack
  std::vector<int> nodeSeen(bvh.nodes.size(), 0), slotSeen(bvh.triangles.size(), 0);
  std::vector<int> triangleSeen(mesh.triangleCount(), 0);
  int maxLevel = 0, badBoxes = 0, badChildren = 0;
  std::vector<std::pair<uint32_t, int>> todo{{0u, 1}};
  while (!todo.empty()) {
    const auto [i, level] = todo.back();
    todo.pop_back();
    ++nodeSeen[i];
    maxLevel = std::max(maxLevel, level);
    const FlatBvhNode& n = bvh.nodes[i];
    for (int k = 0; k < 3; ++k) EXPECT_LE(n.lower[k], n.upper[k]) << "node " << i;
    if (n.count > 0) {
      EXPECT_LE(n.count, 4u) << "leaf " << i;  // maxLeafSize
      ASSERT_LE(size_t(n.a) + n.count, bvh.triangles.size()) << "leaf " << i;
      for (uint32_t k = n.a; k < n.a + n.count; ++k) {
        ++slotSeen[k];
        const FlatBvhTriangle& t = bvh.triangles[k];
        ASSERT_LT(t.index, mesh.triangleCount());
        ++triangleSeen[t.index];
        for (int c = 0; c < 3; ++c) {
          const float* v = c == 0 ? t.v0 : c == 1 ? t.v1 : t.v2;
          const glm::dvec3& p = mesh.positions[mesh.triangles[t.index][c]];
          for (int a = 0; a < 3; ++a) ASSERT_EQ(v[a], static_cast<float>(p[a])) << t.index;
          badBoxes += !inside(n, v, v);
        }
      }
    } else {
      const uint32_t left = i + 1, right = n.a;
      if (left >= bvh.nodes.size() || right >= bvh.nodes.size() || right <= left) {
        ++badChildren;
        continue;
      }
      for (uint32_t c : {left, right}) {
        badBoxes += !inside(n, bvh.nodes[c].lower, bvh.nodes[c].upper);
        todo.push_back({c, level + 1});
      }
    }
  }
  EXPECT_EQ(badChildren, 0);
  EXPECT_EQ(badBoxes, 0);
  EXPECT_EQ(maxLevel, bvh.depth);
  EXPECT_EQ(std::count(nodeSeen.begin(), nodeSeen.end(), 1), std::ssize(nodeSeen));
  EXPECT_EQ(std::count(slotSeen.begin(), slotSeen.end(), 1), std::ssize(slotSeen));
  EXPECT_EQ(std::count(triangleSeen.begin(), triangleSeen.end(), 1), std::ssize(triangleSeen));
}

glm::dvec3 randomUnit(std::mt19937_64& rng) {
  std::normal_distribution<double> g;
  for (;;) {
    const glm::dvec3 v(g(rng), g(rng), g(rng));
    const double l = glm::length(v);
    if (l > 1e-6) return v / l;
  }
}

glm::dvec3 randomInBox(std::mt19937_64& rng, const Bounds& b) {
  std::uniform_real_distribution<double> u;
  return b.lower + glm::dvec3(u(rng), u(rng), u(rng)) * (b.upper - b.lower);
}

// Rays from a sphere three bounding radii out, aimed at random points of the bounding box (hits
// and misses).
std::vector<TestRay> outsideRays(const TriangleMesh& mesh, size_t count, uint64_t seed) {
  std::mt19937_64 rng(seed);
  const Bounds b = mesh.bounds();
  std::vector<TestRay> rays;
  for (size_t i = 0; i < count; ++i) {
    const glm::dvec3 o = b.center() + 3.0 * b.radius() * randomUnit(rng);
    rays.push_back({glm::vec3(o), glm::vec3(glm::normalize(randomInBox(rng, b) - o))});
  }
  return rays;
}

// Points inside the closed mesh (by Embree's parity votes).
std::vector<glm::dvec3> insidePoints(const TriangleMesh& mesh, const RayScene& scene, size_t count,
                                     uint64_t seed) {
  std::mt19937_64 rng(seed);
  const Bounds b = mesh.bounds();
  std::vector<glm::dvec3> points;
  while (points.size() < count) {
    const glm::dvec3 p = randomInBox(rng, b);
    if (insideClosedMesh(scene, p)) points.push_back(p);
  }
  return points;
}

// Rays from inside points in random directions (they all hit a closed mesh).
std::vector<TestRay> insideRays(const std::vector<glm::dvec3>& points, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<TestRay> rays;
  for (const glm::dvec3& p : points) rays.push_back({glm::vec3(p), glm::vec3(randomUnit(rng))});
  return rays;
}

bool relativeNear(double a, double b, double tolerance) {
  return std::abs(a - b) <= tolerance * std::max(std::abs(a), std::abs(b));
}

TEST(FlatBvh, OneTriangleIsALeafRoot) {
  TriangleMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  m.triangles = {{0, 1, 2}};
  const FlatBvh bvh = FlatBvh::build(m, "one triangle");
  ASSERT_EQ(bvh.nodes.size(), 1u);
  EXPECT_EQ(bvh.nodes[0].count, 1u);
  EXPECT_EQ(bvh.nodes[0].a, 0u);
  EXPECT_EQ(bvh.depth, 1);
  expectWellFormed(bvh, m);
  float t = 0.0f;
  glm::vec3 n(0.0f);
  uint32_t tri = 7;
  ASSERT_TRUE(bvh.intersect({0.25f, 0.25f, 2.0f}, {0.0f, 0.0f, -1.0f}, 0.0f, kInf, t, n, tri));
  EXPECT_FLOAT_EQ(t, 2.0f);
  EXPECT_EQ(n, glm::vec3(0.0f, 0.0f, 1.0f));  // counter-clockwise seen from +z
  EXPECT_EQ(tri, 0u);
  EXPECT_FALSE(bvh.intersect({0.25f, 0.25f, 2.0f}, {0.0f, 0.0f, -1.0f}, 0.0f, 1.5f, t, n, tri));
  EXPECT_FALSE(bvh.intersect({0.75f, 0.75f, 2.0f}, {0.0f, 0.0f, -1.0f}, 0.0f, kInf, t, n, tri));
  EXPECT_FALSE(bvh.intersect({0.25f, 0.25f, 2.0f}, {0.0f, 0.0f, 1.0f}, 0.0f, kInf, t, n, tri));
}

TEST(FlatBvh, InvalidMeshIsAMeshErrorNamingIt) {
  TriangleMesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  m.triangles = {{0, 1, 3}};
  try {
    (void)FlatBvh::build(m, "broken.obj");
    FAIL() << "no MeshError";
  } catch (const MeshError& e) {
    EXPECT_NE(std::string(e.what()).find("broken.obj"), std::string::npos) << e.what();
  }
}

TEST(FlatBvh, StructureOfBunnyIcosphereAndBox) {
  const TriangleMesh& bunny = testing::bunny();
  const FlatBvh b = FlatBvh::build(bunny, "bunny");
  expectWellFormed(b, bunny);
  size_t leaves = 0;
  for (const FlatBvhNode& n : b.nodes) leaves += n.count > 0;
  EXPECT_EQ(b.nodes.size(), 2 * leaves - 1);  // a full binary tree
  std::printf("bunny: %zu triangles, %zu nodes (%zu leaves), depth %d, built in %.3f s\n",
              bunny.triangleCount(), b.nodes.size(), leaves, b.depth, b.buildSeconds);
  ::testing::Test::RecordProperty("bunny_nodes", std::to_string(b.nodes.size()));
  ::testing::Test::RecordProperty("bunny_depth", std::to_string(b.depth));
  ::testing::Test::RecordProperty("bunny_build_seconds", std::to_string(b.buildSeconds));
  EXPECT_GT(b.depth, 10);  // a tree, not a list of leaves

  const TriangleMesh sphere = makeIcosphere(4, 1.0, {0.3, -0.2, 0.1});
  expectWellFormed(FlatBvh::build(sphere, "icosphere"), sphere);
  const TriangleMesh box = makeBox({-1, -2, -3}, {1, 2, 3});  // flat leaves (faces)
  expectWellFormed(FlatBvh::build(box, "box"), box);
}

// ~20k rays on the bunny: the CPU traversal against Embree. Both trace in float, with different
// triangle tests (Embree's own against Woop et al.), so t agrees to a few ulp of the distance:
// 1e-4 relative is loose. Hit or miss must agree for every ray (no ray here is aimed at an edge
// on purpose; random rays graze silhouettes with probability ~0). Where the two find different
// triangles (a ray through an edge or vertex, within rounding), at most 1 ray in 1000 — and t
// must still agree.
TEST(FlatBvh, CpuTraversalMatchesEmbreeOnTheBunny) {
  const TriangleMesh& bunny = testing::bunny();
  const FlatBvh bvh = FlatBvh::build(bunny, "bunny");
  const RayScene scene(bunny, "bunny");
  std::vector<TestRay> rays = outsideRays(bunny, 10000, 1);
  const std::vector<TestRay> in = insideRays(insidePoints(bunny, scene, 10000, 2), 3);
  rays.insert(rays.end(), in.begin(), in.end());

  size_t hits = 0, hitMismatch = 0, triangleMismatch = 0, tMismatch = 0, insideMisses = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    const TestRay& r = rays[i];
    float t = 0.0f;
    glm::vec3 n(0.0f);
    uint32_t tri = 0;
    const bool ours = bvh.intersect(r.o, r.d, r.tMin, r.tMax, t, n, tri);
    RayHit e;
    const bool embree = scene.intersect(glm::dvec3(r.o), glm::dvec3(r.d), r.tMin,
                                        std::numeric_limits<double>::infinity(), e, true);
    if (i >= 10000 && !ours) ++insideMisses;
    if (ours != embree) {
      ++hitMismatch;
      ADD_FAILURE() << "ray " << i << ": ours " << ours << ", Embree " << embree;
      continue;
    }
    if (!ours) continue;
    ++hits;
    if (tri != e.triangle) ++triangleMismatch;
    if (!relativeNear(t, e.t, 1e-4)) {
      ++tMismatch;
      ADD_FAILURE() << "ray " << i << ": t " << t << " vs Embree " << e.t;
    }
    if (tri == e.triangle) {
      EXPECT_GT(glm::dot(glm::dvec3(n), e.normal), 1.0 - 1e-5) << i;
    }
  }
  std::printf("%zu rays, %zu hits; triangle differs from Embree's on %zu\n", rays.size(), hits,
              triangleMismatch);
  EXPECT_EQ(hitMismatch, 0u);
  EXPECT_EQ(tMismatch, 0u);
  EXPECT_EQ(insideMisses, 0u);  // a closed mesh: every ray from inside hits
  EXPECT_GT(hits, 12000u);      // a fair share of the outside rays hit
  EXPECT_LT(hits, 19000u);      // and a fair share miss
  EXPECT_LT(double(triangleMismatch), 1e-3 * double(hits));
}

// Rays from `origin` through every vertex and every edge midpoint of `mesh` (rounded to float):
// on a closed mesh they must all hit when `origin` is inside.
std::vector<TestRay> edgeAndVertexRays(const TriangleMesh& mesh, const glm::dvec3& origin) {
  std::set<std::pair<uint32_t, uint32_t>> edges;
  for (const glm::uvec3& t : mesh.triangles)
    for (int k = 0; k < 3; ++k)
      edges.insert(std::minmax(t[k], t[(k + 1) % 3]));
  const glm::vec3 o(origin);
  std::vector<TestRay> rays;
  for (const glm::dvec3& p : mesh.positions) rays.push_back({o, glm::vec3(p) - o});
  for (const auto& [a, b] : edges)
    rays.push_back({o, glm::vec3(0.5 * (mesh.positions[a] + mesh.positions[b])) - o});
  return rays;
}

// Rays aimed at shared edges and vertices of closed meshes (from inside) always hit: the
// watertight test decides an edge consistently for both its triangles. The icosphere has vertices
// and edges in the planes x = 0, y = 0, z = 0 (direction components exactly zero: the slabs'
// 1e30 inverse); the box's face centres lie on the diagonals that split its faces, and rays to
// its corners and edges run along its faces' planes.
TEST(FlatBvh, WatertightAtSharedEdgesAndVertices) {
  struct Case {
    TriangleMesh mesh;
    std::vector<glm::dvec3> origins;
  };
  std::vector<Case> cases;
  cases.push_back({makeIcosphere(3), {{0, 0, 0}, {0.31, -0.22, 0.17}, {-0.6, 0.5, 0.1}}});
  cases.push_back({makeIcosphere(3, 2.0, {0.3, -0.2, 0.1}), {{0.3, -0.2, 0.1}, {1.1, 0.4, -0.5}}});
  {
    TriangleMesh box = makeBox({-1, -1, -1}, {1, 1, 1});
    // Face centres as extra vertices of no triangle: rays through the face diagonals.
    for (int k = 0; k < 3; ++k)
      for (double s : {-1.0, 1.0}) {
        glm::dvec3 c(0.0);
        c[k] = s;
        box.positions.push_back(c);
      }
    cases.push_back({box, {{0, 0, 0}, {0.25, -0.5, 0.125}, {0.5, 0.5, 0.0}}});
  }
  const TriangleMesh& bunny = testing::bunny();
  {
    const RayScene scene(bunny, "bunny");
    cases.push_back({bunny, insidePoints(bunny, scene, 2, 11)});
  }
  for (size_t c = 0; c < cases.size(); ++c) {
    const FlatBvh bvh = FlatBvh::build(cases[c].mesh, "case");
    for (const glm::dvec3& origin : cases[c].origins) {
      size_t misses = 0;
      const std::vector<TestRay> rays = edgeAndVertexRays(cases[c].mesh, origin);
      for (const TestRay& r : rays) {
        float t = 0.0f;
        glm::vec3 n(0.0f);
        uint32_t tri = 0;
        if (!bvh.intersect(r.o, r.d, 0.0f, kInf, t, n, tri)) ++misses;
      }
      EXPECT_EQ(misses, 0u) << "case " << c << ", origin " << origin.x << " " << origin.y << " "
                            << origin.z << ": of " << rays.size() << " rays";
    }
  }
}

// ---------------------------------------------------------------------------------------------
// The GPU traversal (bvh.glsl) against the CPU traversal.

struct GpuQuery {  // bvh_query.comp's Query (std430)
  float origin[4];
  float direction[4];
  float result[4];
  uint32_t hit[4];
};
static_assert(sizeof(GpuQuery) == 64);

std::vector<GpuQuery> gpuIntersect(const FlatBvh& bvh, const std::vector<TestRay>& rays) {
  const gpu::ShaderProgram p = gpu::ShaderProgram::compute("tests/bvh_query.comp");
  std::vector<GpuQuery> queries(rays.size());
  for (size_t i = 0; i < rays.size(); ++i) {
    const TestRay& r = rays[i];
    queries[i] = GpuQuery{{r.o.x, r.o.y, r.o.z, r.tMin}, {r.d.x, r.d.y, r.d.z, r.tMax}, {}, {}};
  }
  const gpu::Buffer q = gpu::makeStorageBuffer(std::span<const GpuQuery>(queries));
  const gpu::Buffer nodes = gpu::makeStorageBuffer(std::span<const FlatBvhNode>(bvh.nodes));
  const gpu::Buffer tris = gpu::makeStorageBuffer(std::span<const FlatBvhTriangle>(bvh.triangles));
  gpu::bindStorage(0, q);
  gpu::bindStorage(1, nodes);
  gpu::bindStorage(2, tris);
  p.set("Count", static_cast<unsigned>(rays.size()));
  gpu::dispatch1D(p, rays.size());
  return gpu::download<GpuQuery>(q, rays.size());
}

class FlatBvhGpu : public gpu::testing::GpuTest {};

// 10k rays on the bunny (outside; inside; inside with tMin > 0 and a finite tMax, so that some
// miss): the GPU finds what FlatBvh::intersect finds. The arithmetic is the same, but GLSL allows
// a driver to round divisions (1/d, the shear, T/det) and normalize() differently from IEEE, so
// a ray through an edge may pick the neighbour triangle, or a grazing one hit or miss: at most 1
// ray in 1000 may differ in hit or triangle; t within 1e-5 relative and the normal within 1e-5
// where both hit the same triangle.
TEST_F(FlatBvhGpu, GpuTraversalMatchesTheCpu) {
  const TriangleMesh& bunny = testing::bunny();
  const FlatBvh bvh = FlatBvh::build(bunny, "bunny");
  const RayScene scene(bunny, "bunny");
  std::vector<TestRay> rays = outsideRays(bunny, 4000, 21);
  const std::vector<glm::dvec3> points = insidePoints(bunny, scene, 6000, 22);
  const std::vector<TestRay> in = insideRays(points, 23);
  std::mt19937_64 rng(24);
  std::uniform_real_distribution<float> u(0.0f, 0.3f);
  for (size_t i = 0; i < in.size(); ++i) {
    TestRay r = in[i];
    if (i % 2 == 1) {
      r.tMin = u(rng) * 0.1f;
      r.tMax = r.tMin + u(rng);
    }
    rays.push_back(r);
  }
  const std::vector<GpuQuery> gpu = gpuIntersect(bvh, rays);

  size_t hits = 0, misses = 0, hitMismatch = 0, triangleMismatch = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    const TestRay& r = rays[i];
    float t = 0.0f;
    glm::vec3 n(0.0f);
    uint32_t tri = 0;
    const bool cpu = bvh.intersect(r.o, r.d, r.tMin, r.tMax, t, n, tri);
    const bool g = gpu[i].hit[0] == 1u;
    if (cpu != g) {
      ++hitMismatch;
      continue;
    }
    if (!cpu) {
      ++misses;
      continue;
    }
    ++hits;
    EXPECT_TRUE(relativeNear(gpu[i].result[3], t, 1e-5))
        << "ray " << i << ": GPU t " << gpu[i].result[3] << ", CPU " << t;
    if (gpu[i].hit[1] != tri) {
      ++triangleMismatch;
      continue;
    }
    const glm::vec3 gn(gpu[i].result[0], gpu[i].result[1], gpu[i].result[2]);
    EXPECT_LT(glm::length(gn - n), 1e-5f) << "ray " << i;
  }
  std::printf("%zu rays: %zu hits, %zu misses; GPU differs in hit on %zu, in triangle on %zu\n",
              rays.size(), hits, misses, hitMismatch, triangleMismatch);
  EXPECT_GT(misses, 1000u);  // misses from outside and short rays inside are tested too
  EXPECT_LT(double(hitMismatch + triangleMismatch), 1e-3 * double(rays.size()));
}

// The GPU traversal is watertight too: rays from inside an icosphere through its vertices and
// edge midpoints all hit.
TEST_F(FlatBvhGpu, GpuTraversalIsWatertight) {
  const TriangleMesh sphere = makeIcosphere(3);
  const FlatBvh bvh = FlatBvh::build(sphere, "icosphere");
  std::vector<TestRay> rays = edgeAndVertexRays(sphere, {0, 0, 0});
  const std::vector<TestRay> more = edgeAndVertexRays(sphere, {0.31, -0.22, 0.17});
  rays.insert(rays.end(), more.begin(), more.end());
  const std::vector<GpuQuery> gpu = gpuIntersect(bvh, rays);
  size_t misses = 0;
  for (const GpuQuery& q : gpu) misses += q.hit[0] != 1u;
  EXPECT_EQ(misses, 0u) << "of " << rays.size() << " rays";
}

}  // namespace
}  // namespace translucent::geometry
