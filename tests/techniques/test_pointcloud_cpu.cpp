// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include <glm/geometric.hpp>

#include "cloud_helpers.h"
#include "../geometry/test_meshes.h"
#include "translucent/bssrdf/profile_table.h"
#include "translucent/bssrdf/registry.h"
#include "translucent/geometry/icosphere.h"
#include "translucent/geometry/octree.h"
#include "translucent/geometry/point_cloud.h"
#include "translucent/optics/presets.h"
#include "translucent/techniques/pointcloud/cpu_traversal.h"

namespace translucent::pointcloud {
namespace {
using geometry::Octree;
using geometry::PointCloud;
using geometry::SamplingMethod;
using geometry::SamplingOptions;
using geometry::TriangleMesh;
namespace desc = geometry::descriptor;

using testing::light;
using testing::sample;

// Dipole profiles of a preset at `scale` mm per scene unit.
struct Material {
  bssrdf::RgbProfiles profiles;
  std::array<bssrdf::ProfileTable, 3> tables;
  Material(const char* preset, double scale)
      : profiles(bssrdf::profiles(bssrdf::model("dipole"), translucent::preset(preset).medium(scale))),
        tables{bssrdf::tabulate(*profiles[0]), bssrdf::tabulate(*profiles[1]),
               bssrdf::tabulate(*profiles[2])} {}
  RgbKernel exact() const {
    return RgbKernel::fromProfiles({profiles[0].get(), profiles[1].get(), profiles[2].get()});
  }
  RgbKernel table() const { return RgbKernel::fromTables(tables); }
};

struct Study {
  glm::dvec3 relativeRmse{0.0};  // sqrt(Σ (B_h - B)²) / sqrt(Σ B²) per channel
  double speedup = 0.0;          // brute-force evaluations / (nodes visited + points summed)
  double visits = 0.0;           // per query
};

// Hierarchical against brute force at query points on the surface (drawn independently).
Study compare(const PointCloud& cloud, const Octree& tree, const TriangleMesh& mesh,
              const RgbKernel& kernel, const TraversalOptions& options, size_t queries) {
  const PointCloud q = sample(mesh, queries, 1234, SamplingMethod::Random);
  glm::dvec3 err(0.0), ref(0.0);
  TraversalStats stats;
  for (size_t i = 0; i < q.size(); ++i) {
    const glm::dvec3 x(q.positions[i]);
    const glm::dvec3 b = radiantExitanceBruteForce(cloud, x, kernel);
    const glm::dvec3 h = radiantExitance(tree, x, kernel, options, &stats);
    err += (h - b) * (h - b);
    ref += b * b;
  }
  Study s;
  s.relativeRmse = glm::sqrt(err / ref);
  s.visits = double(stats.nodesVisited) / double(q.size());
  s.speedup = double(cloud.size()) * double(q.size()) /
              double(stats.nodesVisited + stats.pointEvaluations);
  return s;
}

TEST(PointCloudTraversal, TinyEpsilonVisitsEveryNodeOnceAndIsExact) {
  const TriangleMesh mesh = geometry::makeIcosphere(4);
  PointCloud c = sample(mesh, 3000, 1);
  c.irradiance.assign(c.size(), glm::vec3(1.0f, 0.5f, 0.25f));  // everything lit
  const Octree t(c);
  const Material m("Marble", 50.0);
  const RgbKernel k = m.exact();
  TraversalOptions o;
  o.epsilon = 1e-300;  // every interior node is subdivided
  for (const glm::dvec3 x : {glm::dvec3(c.positions[17]), glm::dvec3(0.0), glm::dvec3(0, 0, 5)}) {
    TraversalStats s;
    const glm::dvec3 h = radiantExitance(t, x, k, o, &s);
    const glm::dvec3 b = radiantExitanceBruteForce(c, x, k);
    for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(h[ch], b[ch], 1e-12 * b[ch]);
    EXPECT_EQ(s.nodesVisited, t.nodeCount());
    EXPECT_EQ(s.pointEvaluations, c.size());
    EXPECT_EQ(s.clusterEvaluations, 0u);
    EXPECT_EQ(s.maxStack, t.depth() - 1);  // the root is never pushed
  }
}

TEST(PointCloudTraversal, DarkNodesAreSkippedExactly) {
  const TriangleMesh mesh = geometry::makeIcosphere(4);
  PointCloud c = sample(mesh, 3000, 2);
  light(c, glm::vec3(0, 0, 1));  // the lower hemisphere is dark
  const Octree t(c);
  const Material m("Marble", 50.0);
  const RgbKernel k = m.exact();
  TraversalOptions o;
  o.epsilon = 1e-300;
  TraversalStats s;
  const glm::dvec3 x(0, 0, -1);
  const glm::dvec3 h = radiantExitance(t, x, k, o, &s);
  const glm::dvec3 b = radiantExitanceBruteForce(c, x, k);
  for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(h[ch], b[ch], 1e-12 * b[ch]);
  // Visited: the root and the children of every lit interior node; summed: lit leaves' points.
  uint64_t visits = 1, points = 0;
  for (size_t v = 0; v < t.nodeCount(); ++v) {
    const uint32_t d = t.descriptors()[v];
    if (t.nodes()[v].powerArea.x == 0.0f) continue;
    if (desc::isLeaf(d)) points += desc::pointCount(d);
    else visits += desc::childCount(d);
  }
  EXPECT_EQ(s.nodesVisited, visits);
  EXPECT_EQ(s.pointEvaluations, points);
  EXPECT_LT(points, c.size());

  c.irradiance.assign(c.size(), glm::vec3(0.0f));
  const Octree dark(c);
  TraversalStats none;
  EXPECT_EQ(radiantExitance(dark, x, k, o, &none), glm::dvec3(0.0));
  EXPECT_EQ(none.nodesVisited, 1u);
}

TEST(PointCloudTraversal, FarAwayTheRootIsOneCluster) {
  PointCloud c = sample(geometry::makeIcosphere(3), 2000, 3);
  light(c, glm::vec3(1, 1, 0));
  const Octree t(c);
  const Material m("Ketchup", 0.2);  // long range: the profile is non-zero 3 units away
  const RgbKernel k = m.exact();
  const glm::dvec3 x(3.0, 0.0, 0.0);
  for (const Criterion criterion : {Criterion::BoundingBox, Criterion::Centroid}) {
    TraversalOptions o;
    o.epsilon = 10.0;  // A_root / d² ≈ 12.6 / 4 < 10
    o.criterion = criterion;
    TraversalStats s;
    const glm::dvec3 h = radiantExitance(t, x, k, o, &s);
    const auto& root = t.nodes()[0];
    const glm::dvec3 expected =
        k(glm::length(x - glm::dvec3(root.centroid))) * glm::dvec3(root.powerArea);
    EXPECT_EQ(s.nodesVisited, 1u);
    EXPECT_EQ(s.clusterEvaluations, 1u);
    EXPECT_GT(expected.x, 0.0);
    for (int ch = 0; ch < 3; ++ch) EXPECT_DOUBLE_EQ(h[ch], expected[ch]);
  }
}

TEST(PointCloudTraversal, UniformIrradianceGivesTheTotalDiffuseReflectanceOnAverage) {
  // On a sphere, the cap of points within chord distance c of x has area π c² exactly
  // (Archimedes), so for a uniformly lit sphere ∫ R(|x - y|) dA_y = 2π ∫0^2R R(c) c dc = Rd
  // (Eq. 3.1) whatever the curvature. Averaged over query points x drawn uniformly, the point sum
  // Σ_i R(|x - p_i|) A_i has that same expectation however coarse the points are, so the mean
  // of B / E over queries must match Rd within its standard error: a check of the areas, the
  // profile units and the traversal together. The icosphere's facets and the table's 99.9%
  // range add a bias below 0.5%.
  const TriangleMesh mesh = geometry::makeIcosphere(6);
  PointCloud c = sample(mesh, 20000, 4);
  c.irradiance.assign(c.size(), glm::vec3(1.0f));
  const Octree t(c);
  const Material m("Skin1", 50.0);  // ℓd = 0.04 to 0.07 units, radius 1
  const RgbKernel k = m.table();
  const PointCloud q = sample(mesh, 400, 77, SamplingMethod::Random);
  glm::dvec3 sum(0.0), sum2(0.0);
  for (size_t i = 0; i < q.size(); ++i) {
    const glm::dvec3 b = radiantExitance(t, glm::dvec3(q.positions[i]), k);
    sum += b;
    sum2 += b * b;
  }
  const double n = double(q.size());
  for (int ch = 0; ch < 3; ++ch) {
    const double rd = m.tables[ch].rd * double(m.tables[ch].cdf.back());
    const double mean = sum[ch] / n;
    const double stderr = std::sqrt((sum2[ch] / n - mean * mean) / (n - 1.0));
    std::printf("%s: mean B / Rd = %.4f +- %.4f\n", kChannelNames[ch], mean / rd, stderr / rd);
    EXPECT_LT(stderr, 0.02 * rd);
    EXPECT_NEAR(mean, rd, 4.0 * stderr + 0.005 * rd) << kChannelNames[ch];
  }
}

TEST(PointCloudTraversal, DefaultEpsilonStaysWithinOnePercentWithASpeedup) {
  struct Case {
    const char* preset;
    double scale;  // mm per scene unit
  };
  const TriangleMesh sphere = geometry::makeIcosphere(5);
  const struct {
    const char* name;
    const TriangleMesh* mesh;
    std::vector<Case> materials;
  } scenes[] = {{"icosphere", &sphere, {{"Marble", 50.0}}},
                {"bunny", &geometry::testing::bunny(),
                 {{"Marble", 20.0}, {"Skin1", 50.0}, {"Ketchup", 20.0}}}};
  for (const auto& scene : scenes) {
    PointCloud c = sample(*scene.mesh, 30000, 5);
    light(c, glm::vec3(0.3f, 1.0f, 0.5f));
    const Octree t(c);
    for (const Case& cs : scene.materials) {
      const Material m(cs.preset, cs.scale);
      const Study s = compare(c, t, *scene.mesh, m.table(), TraversalOptions{}, 150);
      std::printf("%s, %s at %g mm, 30000 points, eps %.2g: relative RMSE (%.2e, %.2e, %.2e), "
                  "%.0f node visits per query, speedup %.1fx\n", scene.name, cs.preset, cs.scale,
                  kDefaultEpsilon, s.relativeRmse.x, s.relativeRmse.y, s.relativeRmse.z, s.visits,
                  s.speedup);
      for (int ch = 0; ch < 3; ++ch) EXPECT_LT(s.relativeRmse[ch], 0.01) << scene.name << cs.preset;
      EXPECT_GT(s.speedup, 1.0) << scene.name;
    }
  }
}

TEST(PointCloudTraversal, BoundingBoxDistanceIsMoreAccurateThanCentroidDistance) {
  // Seed 2.6.4: |x_o - P_v| overestimates the distance to a node's points, so at equal ε the
  // centroid criterion accepts clusters too early; the box distance never overestimates.
  const TriangleMesh& mesh = geometry::testing::bunny();
  PointCloud c = sample(mesh, 20000, 6);
  light(c, glm::vec3(-0.5f, 1.0f, 0.2f));
  const Octree t(c);
  const Material m("Marble", 20.0);
  for (const double eps : {0.2, 0.5, 1.0}) {
    const Study box = compare(c, t, mesh, m.table(), {eps, Criterion::BoundingBox}, 100);
    const Study cen = compare(c, t, mesh, m.table(), {eps, Criterion::Centroid}, 100);
    for (int ch = 0; ch < 3; ++ch) EXPECT_LT(box.relativeRmse[ch], cen.relativeRmse[ch]) << eps;
    EXPECT_GT(box.visits, cen.visits) << eps;
  }
}

TEST(PointCloudTraversal, KernelsAgree) {
  const Material m("Skin1", 10.0);
  const RgbKernel exact = m.exact(), table = m.table();
  const RgbKernel mono = RgbKernel::fromTable(m.tables[1]);
  for (double r = 0.001; r < 0.5 * m.tables[0].r_max; r *= 1.7) {
    const glm::dvec3 a = exact(r), b = table(r);
    for (int ch = 0; ch < 3; ++ch) {
      if (r < 0.9 * m.tables[ch].r_max) {
        EXPECT_NEAR(b[ch], a[ch], 0.02 * a[ch]) << r;
      }
    }
    EXPECT_EQ(mono(r), glm::dvec3(b.y));
  }
  EXPECT_EQ(table(2.0 * m.tables[0].r_max).x, 0.0);
  EXPECT_THROW((void)RgbKernel::fromProfiles({nullptr, nullptr, nullptr}), std::invalid_argument);
}

TEST(PointCloudTraversal, RejectsBadInput) {
  PointCloud c = sample(geometry::makeIcosphere(2), 100, 1);
  const Material m("Marble", 10.0);
  EXPECT_THROW((void)radiantExitanceBruteForce(c, glm::dvec3(0.0), m.table()),
               geometry::PointCloudError);
  light(c, glm::vec3(0, 1, 0));
  const Octree t(c);
  for (const double eps : {0.0, -1.0, std::nan("")}) {
    try {
      (void)radiantExitance(t, glm::dvec3(0.0), m.table(), {eps});
      FAIL() << "epsilon " << eps << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("epsilon is"), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW((void)radiantExitance(Octree{}, glm::dvec3(0.0), m.table()), geometry::OctreeError);
}

}  // namespace
}  // namespace translucent::pointcloud
