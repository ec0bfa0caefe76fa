// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <random>
#include <vector>

#include <glm/geometric.hpp>

#include "translucent/geometry/icosphere.h"
#include "translucent/geometry/octree.h"
#include "translucent/geometry/point_cloud.h"
#include "test_meshes.h"

namespace translucent::geometry {
namespace {
namespace desc = descriptor;

// A directional light (about half the points dark) times a random tint per point.
void relight(PointCloud& c, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 2.0f);
  const glm::vec3 l = glm::normalize(glm::vec3(0.3f, 1.0f, -0.2f));
  c.irradiance.resize(c.size());
  for (size_t i = 0; i < c.size(); ++i)
    c.irradiance[i] = std::max(0.0f, glm::dot(c.normals[i], l)) * glm::vec3(u(rng), u(rng), u(rng));
}

PointCloud cloudWithIrradiance(const TriangleMesh& mesh, size_t count, uint64_t seed) {
  SamplingOptions o;
  o.count = count;
  o.seed = seed;
  o.method = SamplingMethod::Random;  // clumpy on purpose: uneven leaves
  PointCloud c = samplePointCloud(mesh, o);
  relight(c, static_cast<unsigned>(seed));
  return c;
}

// The slot range [first, last) of every node, checking that ranges of siblings are consecutive.
struct Range {
  uint32_t first = 0, last = 0;
};
std::vector<Range> nodeRanges(const Octree& t) {
  std::vector<Range> r(t.nodeCount());
  for (size_t v = t.nodeCount(); v-- > 0;) {
    const uint32_t d = t.descriptors()[v];
    if (desc::isLeaf(d)) {
      r[v] = {desc::index(d), desc::index(d) + desc::pointCount(d)};
    } else {
      const uint32_t c0 = desc::index(d), n = desc::childCount(d);
      for (uint32_t c = c0 + 1; c < c0 + n; ++c) EXPECT_EQ(r[c].first, r[c - 1].last);
      r[v] = {r[c0].first, r[c0 + n - 1].last};
    }
  }
  return r;
}

void checkInvariants(const PointCloud& cloud, const Octree& t) {
  const size_t n = cloud.size();
  const uint32_t maxLeaf = t.options().maxLeafPoints;
  ASSERT_EQ(t.pointCount(), n);
  ASSERT_EQ(t.nodes().size(), t.nodeCount());
  ASSERT_EQ(t.pointIrradiance().size(), n);

  // pointOrder is a permutation and the points are the cloud's, reordered.
  std::vector<int> seen(n, 0);
  for (size_t s = 0; s < n; ++s) {
    const uint32_t i = t.pointOrder()[s];
    ASSERT_LT(i, n);
    ++seen[i];
    EXPECT_EQ(glm::vec3(t.points()[s].positionArea), cloud.positions[i]);
    EXPECT_EQ(t.points()[s].positionArea.w, cloud.areas[i]);
    EXPECT_EQ(glm::vec3(t.points()[s].normal), cloud.normals[i]);
    EXPECT_EQ(glm::vec3(t.pointIrradiance()[s]), cloud.irradiance[i]);
  }
  EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](int k) { return k == 1; }));

  // Every point in exactly one leaf; leaf sizes 1..maxLeaf; children after their parent;
  // depth as reported.
  std::vector<int> inLeaf(n, 0);
  std::vector<uint32_t> depth(t.nodeCount(), 0);
  uint32_t maxDepth = 0;
  for (size_t v = 0; v < t.nodeCount(); ++v) {
    const uint32_t d = t.descriptors()[v];
    maxDepth = std::max(maxDepth, depth[v]);
    if (desc::isLeaf(d)) {
      EXPECT_GE(desc::pointCount(d), 1u);
      EXPECT_LE(desc::pointCount(d), maxLeaf);
      for (uint32_t s = desc::index(d); s < desc::index(d) + desc::pointCount(d); ++s) {
        ASSERT_LT(s, n);
        ++inLeaf[s];
      }
    } else {
      EXPECT_EQ(desc::pointCount(d), 0u);
      EXPECT_GE(desc::childCount(d), v == 0 ? 1u : 2u);
      EXPECT_LE(desc::childCount(d), 8u);
      EXPECT_GT(desc::index(d), v);
      ASSERT_LE(desc::index(d) + desc::childCount(d), t.nodeCount());
      for (uint32_t c = desc::index(d); c < desc::index(d) + desc::childCount(d); ++c)
        depth[c] = depth[v] + 1;
    }
  }
  EXPECT_EQ(maxDepth, t.depth());
  EXPECT_TRUE(std::all_of(inLeaf.begin(), inLeaf.end(), [](int k) { return k == 1; }));
  EXPECT_EQ(t.leafCount(), static_cast<size_t>(std::count_if(
                               t.descriptors().begin(), t.descriptors().end(), desc::isLeaf)));

  // Node attributes equal the sums over the node's points (in double, relative 1e-5: float
  // storage), boxes are the tight boxes of the points, centroids the weighted means.
  const auto ranges = nodeRanges(t);
  EXPECT_EQ(ranges[0].first, 0u);
  EXPECT_EQ(ranges[0].last, n);
  for (size_t v = 0; v < t.nodeCount(); ++v) {
    glm::dvec3 power(0.0), weighted(0.0), areaPos(0.0);
    double area = 0.0, weight = 0.0;
    glm::vec3 lo(1e30f), hi(-1e30f);
    for (uint32_t s = ranges[v].first; s < ranges[v].last; ++s) {
      const glm::vec3 p(t.points()[s].positionArea);
      const double a = t.points()[s].positionArea.w;
      const glm::dvec3 e(t.pointIrradiance()[s]);
      power += e * a;
      area += a;
      const double w = a * (e.x + e.y + e.z) / 3.0;
      weight += w;
      weighted += w * glm::dvec3(p);
      areaPos += a * glm::dvec3(p);
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
    const OctreeNode& node = t.nodes()[v];
    EXPECT_NEAR(node.powerArea.w, area, 1e-6 * area) << "node " << v;
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(node.powerArea[c], power[c], 1e-6 * power[c] + 1e-30) << "node " << v;
    EXPECT_EQ(glm::vec3(node.lower), lo) << "node " << v;
    EXPECT_EQ(glm::vec3(node.upper), hi) << "node " << v;
    const glm::dvec3 centroid = weight > 0.0 ? weighted / weight : areaPos / area;
    // Float storage: rounding relative to the coordinates, not to the node's size.
    const double tol = 1e-6 * (glm::length(centroid) + glm::length(glm::dvec3(hi) - glm::dvec3(lo)));
    EXPECT_LT(glm::length(glm::dvec3(node.centroid) - centroid), tol) << "node " << v;
    // Inside the box (up to rounding): a convex combination of the points.
    for (int c = 0; c < 3; ++c) {
      EXPECT_GE(double(node.centroid[c]), double(lo[c]) - tol);
      EXPECT_LE(double(node.centroid[c]), double(hi[c]) + tol);
    }
  }
}

TEST(OctreeDescriptor, BitLayoutAndRoundTrip) {
  // Fig. 3.5: child count in bits 0-3, point count in bits 4-7, index in bits 8-31.
  EXPECT_EQ(desc::pack(0x123456, 5, 0), 0x12345605u);
  EXPECT_EQ(desc::pack(7, 0, 8), 0x00000780u);
  EXPECT_EQ(desc::pack(desc::kMaxIndex, 8, 0), 0xFFFFFF08u);
  for (uint32_t index : {0u, 1u, 255u, 256u, 65535u, 1234567u, desc::kMaxIndex})
    for (uint32_t children = 0; children <= 8; ++children)
      for (uint32_t points = 0; points <= desc::kMaxCount; ++points) {
        const uint32_t d = desc::pack(index, children, points);
        EXPECT_EQ(desc::index(d), index);
        EXPECT_EQ(desc::childCount(d), children);
        EXPECT_EQ(desc::pointCount(d), points);
        EXPECT_EQ(desc::isLeaf(d), children == 0);
      }
}

TEST(OctreeLayout, Std430CompatibleStructs) {
  EXPECT_EQ(offsetof(OctreeNode, powerArea), 0u);
  EXPECT_EQ(offsetof(OctreeNode, centroid), 16u);
  EXPECT_EQ(offsetof(OctreeNode, lower), 32u);
  EXPECT_EQ(offsetof(OctreeNode, upper), 48u);
  EXPECT_EQ(sizeof(OctreeNode), 64u);
  EXPECT_EQ(offsetof(OctreePoint, positionArea), 0u);
  EXPECT_EQ(offsetof(OctreePoint, normal), 16u);
  EXPECT_EQ(sizeof(OctreePoint), 32u);
}

TEST(Octree, InvariantsOnTheBunnyAndASphere) {
  const PointCloud bunny = cloudWithIrradiance(testing::bunny(), 20000, 3);
  const Octree t(bunny);
  checkInvariants(bunny, t);
  EXPECT_LT(t.depth(), 16u);
  std::printf("bunny, 20000 random points: %zu nodes, %zu leaves, depth %u\n", t.nodeCount(),
              t.leafCount(), t.depth());

  const PointCloud sphere = cloudWithIrradiance(makeIcosphere(4), 3000, 4);
  for (uint32_t leaf : {1u, 3u, 8u, 15u}) {
    const Octree s(sphere, OctreeOptions{leaf});
    checkInvariants(sphere, s);
  }
}

TEST(Octree, ChildrenAreTheOccupiedOctantsInLabelOrder) {
  // Each child of a geometric split holds the points of one octant of the parent's box centre,
  // and the children follow the counting sort: increasing octant labels.
  const PointCloud c = cloudWithIrradiance(testing::bunny(), 5000, 8);
  const Octree t(c);
  const auto ranges = nodeRanges(t);
  for (size_t v = 0; v < t.nodeCount(); ++v) {
    const uint32_t d = t.descriptors()[v];
    if (desc::isLeaf(d)) continue;
    const glm::dvec3 centre = 0.5 * (glm::dvec3(glm::vec3(t.nodes()[v].lower)) +
                                     glm::dvec3(glm::vec3(t.nodes()[v].upper)));
    int previous = -1;
    for (uint32_t ch = desc::index(d); ch < desc::index(d) + desc::childCount(d); ++ch) {
      int label = -1;
      for (uint32_t s = ranges[ch].first; s < ranges[ch].last; ++s) {
        const glm::dvec3 p(glm::vec3(t.points()[s].positionArea));
        const int l = int(p.x >= centre.x) | int(p.y >= centre.y) << 1 | int(p.z >= centre.z) << 2;
        if (label < 0) label = l;
        ASSERT_EQ(l, label) << "node " << v << " child " << ch;
      }
      EXPECT_GT(label, previous);
      previous = label;
    }
  }
}

TEST(Octree, RefitEqualsRebuild) {
  const PointCloud c = cloudWithIrradiance(testing::bunny(), 8000, 5);
  Octree t(c);
  PointCloud other = c;  // same points, another light
  relight(other, 6);
  ASSERT_NE(other.irradiance, c.irradiance);
  t.refit(other.irradiance);
  const Octree rebuilt(other);
  ASSERT_EQ(t.descriptors(), rebuilt.descriptors());
  ASSERT_EQ(t.pointOrder(), rebuilt.pointOrder());
  for (size_t v = 0; v < t.nodeCount(); ++v) {
    EXPECT_EQ(t.nodes()[v].powerArea, rebuilt.nodes()[v].powerArea);
    EXPECT_EQ(t.nodes()[v].centroid, rebuilt.nodes()[v].centroid);
    EXPECT_EQ(t.nodes()[v].lower, rebuilt.nodes()[v].lower);
    EXPECT_EQ(t.nodes()[v].upper, rebuilt.nodes()[v].upper);
  }
  EXPECT_EQ(t.pointIrradiance(), rebuilt.pointIrradiance());
  checkInvariants(other, t);
}

TEST(Octree, UnlitNodesUseTheAreaWeightedCentroid) {
  PointCloud c = cloudWithIrradiance(makeIcosphere(3), 2000, 7);
  for (auto& e : c.irradiance) e = glm::vec3(0.0f);
  const Octree t(c);  // also without irradiance at all:
  PointCloud none = c;
  none.irradiance.clear();
  const Octree u(none);
  glm::dvec3 mean(0.0);
  double area = 0.0;
  for (size_t i = 0; i < c.size(); ++i) {
    mean += double(c.areas[i]) * glm::dvec3(c.positions[i]);
    area += double(c.areas[i]);
  }
  mean /= area;
  EXPECT_LT(glm::length(glm::dvec3(t.nodes()[0].centroid) - mean), 1e-6);
  EXPECT_EQ(t.nodes()[0].powerArea, glm::vec4(0.0f, 0.0f, 0.0f, float(area)));
  for (size_t v = 0; v < t.nodeCount(); ++v) EXPECT_EQ(t.nodes()[v].centroid, u.nodes()[v].centroid);
  checkInvariants(c, t);
}

TEST(Octree, CoincidentPointsStillEndInSmallLeaves) {
  PointCloud c;
  c.positions.assign(1000, glm::vec3(0.5f, -1.0f, 2.0f));
  c.positions.resize(1100, glm::vec3(0.25f, 0.0f, 0.0f));  // and a second location
  c.normals.assign(c.positions.size(), glm::vec3(0, 1, 0));
  c.areas.assign(c.positions.size(), 1e-3f);
  c.irradiance.assign(c.positions.size(), glm::vec3(1.0f));
  const Octree t(c);
  checkInvariants(c, t);
  // Root -> the two locations -> 1000 coincident points in runs of 125 -> 16 -> 8: depth 4.
  EXPECT_EQ(t.depth(), 4u);
}

TEST(Octree, RejectsBadOptionsAndIrradiance) {
  const PointCloud c = cloudWithIrradiance(makeIcosphere(2), 200, 1);
  EXPECT_THROW(Octree(c, OctreeOptions{0}), OctreeError);
  EXPECT_THROW(Octree(c, OctreeOptions{16}), OctreeError);
  EXPECT_THROW(Octree(c, OctreeOptions{8, 0}), OctreeError);
  EXPECT_THROW(Octree(c, OctreeOptions{8, 25}), OctreeError);
  EXPECT_THROW(Octree(PointCloud{}), PointCloudError);
  Octree t(c);
  try {
    t.refit(std::vector<glm::vec3>(199));
    FAIL() << "wrong size accepted";
  } catch (const OctreeError& e) {
    EXPECT_NE(std::string(e.what()).find("199 irradiance values for an octree of 200 points"),
              std::string::npos) << e.what();
  }
  std::vector<glm::vec3> negative(200, glm::vec3(1.0f));
  negative[17].z = -0.5f;
  try {
    t.refit(negative);
    FAIL() << "negative irradiance accepted";
  } catch (const OctreeError& e) {
    EXPECT_NE(std::string(e.what()).find("irradiance of point 17"), std::string::npos) << e.what();
  }
}

TEST(Octree, SinglePointAndSmallClouds) {
  const PointCloud c = cloudWithIrradiance(makeIcosphere(2), 5, 2);
  const Octree t(c);
  EXPECT_EQ(t.nodeCount(), 1u);  // the root is a leaf
  EXPECT_EQ(t.depth(), 0u);
  EXPECT_EQ(t.descriptors()[0], desc::pack(0, 0, 5));
  checkInvariants(c, t);
}

}  // namespace
}  // namespace translucent::geometry
