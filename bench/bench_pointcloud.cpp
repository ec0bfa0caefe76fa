// SPDX-License-Identifier: GPL-3.0-or-later
// Point-cloud technique on the CPU (seed 2.6.4, 3.3): surface sampling (sample elimination vs
// random), octree build and refit, and the radiant exitance per query point by hierarchical
// traversal (Algorithm 2) at the default ε against the brute-force sum; plus the ε study that
// chose kDefaultEpsilon (relative RMS error and work per query, as counters).
// Mesh: the closed Stanford bunny of Debian's glmark2-data (scripts/install-deps).
// Run: build/release/bin/bench_pointcloud [--benchmark_filter=...]
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <vector>

#include <glm/geometric.hpp>

#include "translucent/bssrdf/profile_table.h"
#include "translucent/bssrdf/registry.h"
#include "translucent/geometry/mesh.h"
#include "translucent/geometry/octree.h"
#include "translucent/geometry/point_cloud.h"
#include "translucent/optics/presets.h"
#include "translucent/techniques/pointcloud/cpu_traversal.h"

namespace {

using namespace translucent;
using geometry::Octree;
using geometry::PointCloud;
using geometry::SamplingMethod;

const geometry::TriangleMesh& bunny() {
  static const geometry::TriangleMesh mesh =
      geometry::loadMesh("/usr/share/glmark2/models/bunny.obj");
  return mesh;
}

PointCloud sample(size_t count, SamplingMethod method, uint64_t seed = 1) {
  geometry::SamplingOptions o;
  o.count = count;
  o.method = method;
  o.seed = seed;
  return geometry::samplePointCloud(bunny(), o);
}

// A lit point cloud and its octree (blue-noise points, from the on-disk cache after the first
// run), and query points on the surface.
struct Scene {
  PointCloud cloud;
  Octree tree;
  std::vector<glm::dvec3> queries;
};
const Scene& scene(size_t count) {
  static std::map<size_t, std::unique_ptr<Scene>> scenes;
  auto& s = scenes[count];
  if (!s) {
    s = std::make_unique<Scene>();
    geometry::SamplingOptions o;
    o.count = count;
    s->cloud = geometry::loadOrSamplePointCloud(bunny(), o).cloud;
    const glm::vec3 l = glm::normalize(glm::vec3(0.3f, 1.0f, 0.5f));
    s->cloud.irradiance.resize(s->cloud.size());
    for (size_t i = 0; i < s->cloud.size(); ++i)
      s->cloud.irradiance[i] =
          std::max(0.0f, glm::dot(s->cloud.normals[i], l)) * glm::vec3(1.0f, 0.8f, 0.6f);
    s->tree = Octree(s->cloud);
    for (const auto& p : sample(1024, SamplingMethod::Random, 99).positions)
      s->queries.emplace_back(p);
  }
  return *s;
}

// Dipole tables of a preset at `scale` mm per scene unit (the bunny is about 2 units wide).
const pointcloud::RgbKernel& kernel(const std::string& preset, double scale) {
  static std::map<std::pair<std::string, double>, pointcloud::RgbKernel> kernels;
  const auto key = std::make_pair(preset, scale);
  auto it = kernels.find(key);
  if (it == kernels.end()) {
    const auto p = bssrdf::profiles(bssrdf::model("dipole"), translucent::preset(preset).medium(scale));
    it = kernels
             .emplace(key, pointcloud::RgbKernel::fromTables(
                               {bssrdf::tabulate(*p[0]), bssrdf::tabulate(*p[1]),
                                bssrdf::tabulate(*p[2])}))
             .first;
  }
  return it->second;
}

// ---- Sampling, octree ------------------------------------------------------------------------
void BM_Sample(benchmark::State& state, SamplingMethod method) {
  const auto n = static_cast<size_t>(state.range(0));
  (void)bunny();
  PointCloud c;
  for (auto _ : state) {
    c = sample(n, method);
    benchmark::DoNotOptimize(c.positions.data());
  }
  const auto nn = geometry::nearestNeighbourStats(c);
  state.counters["nn_cv"] = nn.cv;
  state.counters["nn_min_over_mean"] = nn.min / nn.mean;
  state.SetItemsProcessed(state.iterations() * state.range(0));
}

void BM_OctreeBuild(benchmark::State& state) {
  const Scene& s = scene(static_cast<size_t>(state.range(0)));
  for (auto _ : state) {
    Octree t(s.cloud);
    benchmark::DoNotOptimize(t.nodes().data());
  }
  state.counters["nodes"] = double(s.tree.nodeCount());
  state.counters["depth"] = double(s.tree.depth());
  state.SetItemsProcessed(state.iterations() * state.range(0));
}

void BM_OctreeRefit(benchmark::State& state) {
  const Scene& s = scene(static_cast<size_t>(state.range(0)));
  Octree t = s.tree;
  for (auto _ : state) {
    t.refit(s.cloud.irradiance);
    benchmark::DoNotOptimize(t.nodes().data());
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
}

// ---- Radiant exitance per query point --------------------------------------------------------
void BM_Hierarchical(benchmark::State& state) {
  const Scene& s = scene(static_cast<size_t>(state.range(0)));
  const auto& k = kernel("Marble", 20.0);
  pointcloud::TraversalStats stats;
  size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(pointcloud::radiantExitance(s.tree, s.queries[i++ & 1023], k, {}, &stats));
  }
  const double q = double(state.iterations());
  state.counters["visits"] = double(stats.nodesVisited) / q;
  state.counters["kernel_evals"] = double(stats.pointEvaluations + stats.clusterEvaluations) / q;
  state.SetItemsProcessed(state.iterations());
}

void BM_BruteForce(benchmark::State& state) {
  const Scene& s = scene(static_cast<size_t>(state.range(0)));
  const auto& k = kernel("Marble", 20.0);
  size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(pointcloud::radiantExitanceBruteForce(s.cloud, s.queries[i++ & 1023], k));
  }
  state.counters["kernel_evals"] = double(s.cloud.size());
  state.SetItemsProcessed(state.iterations());
}

// ---- ε study ---------------------------------------------------------------------------------
// Relative RMS error of B (per channel, sqrt(Σ (B_h - B)²) / sqrt(Σ B²)) over 150 queries of the
// 30k-point bunny, and the work per query; one benchmark per (material, ε).
void BM_EpsilonStudy(benchmark::State& state, std::string preset, double scale, double eps,
                     pointcloud::Criterion criterion) {
  const Scene& s = scene(30000);
  const auto& k = kernel(preset, scale);
  static std::map<std::pair<std::string, double>, std::vector<glm::dvec3>> references;
  auto& ref = references[{preset, scale}];
  if (ref.empty())
    for (size_t i = 0; i < 150; ++i)
      ref.push_back(pointcloud::radiantExitanceBruteForce(s.cloud, s.queries[i], k));
  pointcloud::TraversalStats stats;
  glm::dvec3 err(0.0), sum(0.0);
  for (auto _ : state) {
    stats = {};
    err = sum = glm::dvec3(0.0);
    for (size_t i = 0; i < ref.size(); ++i) {
      const glm::dvec3 h = pointcloud::radiantExitance(s.tree, s.queries[i], k, {eps, criterion}, &stats);
      err += (h - ref[i]) * (h - ref[i]);
      sum += ref[i] * ref[i];
    }
  }
  const glm::dvec3 rel = glm::sqrt(err / sum);
  const double q = double(ref.size());
  state.counters["rmse_r"] = rel.x;
  state.counters["rmse_g"] = rel.y;
  state.counters["rmse_b"] = rel.z;
  state.counters["visits"] = double(stats.nodesVisited) / q;
  state.counters["speedup"] = double(s.cloud.size()) * q / double(stats.nodesVisited + stats.pointEvaluations);
}

const bool registered = [] {
  benchmark::RegisterBenchmark("sample/elimination", BM_Sample, SamplingMethod::Elimination)
      ->Arg(30000)->Arg(300000)->Unit(benchmark::kMillisecond)->Iterations(1)->MeasureProcessCPUTime()->UseRealTime();
  benchmark::RegisterBenchmark("sample/random", BM_Sample, SamplingMethod::Random)
      ->Arg(30000)->Arg(300000)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();
  benchmark::RegisterBenchmark("octree/build", BM_OctreeBuild)
      ->Arg(30000)->Arg(300000)->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("octree/refit", BM_OctreeRefit)
      ->Arg(30000)->Arg(300000)->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("exitance/hierarchical", BM_Hierarchical)
      ->Arg(30000)->Arg(300000)->Unit(benchmark::kMicrosecond);
  benchmark::RegisterBenchmark("exitance/brute_force", BM_BruteForce)
      ->Arg(30000)->Arg(300000)->Unit(benchmark::kMicrosecond);
  const struct {
    const char* preset;
    double scale;
  } materials[] = {{"Marble", 20.0}, {"Skin1", 50.0}, {"Ketchup", 20.0}, {"Skimmilk", 20.0}};
  for (const auto& m : materials)
    for (double eps : {0.02, 0.05, 0.1, 0.2, 0.5, 1.0, 2.0})
      for (auto criterion : {pointcloud::Criterion::BoundingBox, pointcloud::Criterion::Centroid})
        benchmark::RegisterBenchmark(
            ("epsilon/" + std::string(m.preset) + "/" +
             (criterion == pointcloud::Criterion::BoundingBox ? "box/" : "centroid/") +
             std::to_string(eps).substr(0, 4))
                .c_str(),
            BM_EpsilonStudy, std::string(m.preset), m.scale, eps, criterion)
            ->Iterations(1)
            ->Unit(benchmark::kMillisecond);
  return true;
}();

}  // namespace
