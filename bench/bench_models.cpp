// SPDX-License-Identifier: GPL-3.0-or-later
// Nanoseconds per profile evaluation R(r) and per radial sample, for every registered model.
// Run: build/release/bin/bench_models
#include <benchmark/benchmark.h>

#include <random>

#include "translucent/bssrdf/registry.h"
#include "translucent/optics/presets.h"

namespace {

using namespace translucent;

// Marble, green channel, radii spread over the 99% range.
std::unique_ptr<bssrdf::RadialProfile> marble(const std::string& name) {
  return bssrdf::model(name).profile(preset("Marble").medium().channel(1));
}

void BM_Evaluate(benchmark::State& state, const std::string& name) {
  const auto p = marble(name);
  const double rMax = p->radiusForFraction(0.99);
  std::vector<double> radii(1024);
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(0.0, rMax);
  for (auto& r : radii) r = u(rng);
  size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(p->R(radii[i++ & 1023]));
  }
  state.SetItemsProcessed(state.iterations());
}

void BM_Sample(benchmark::State& state, const std::string& name) {
  const auto p = marble(name);
  (void)p->cumulative();  // build the table outside the timed loop
  std::mt19937_64 rng(2);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (auto _ : state) {
    benchmark::DoNotOptimize(p->sample(u(rng)));
  }
  state.SetItemsProcessed(state.iterations());
}

void BM_BuildProfile(benchmark::State& state, const std::string& name) {
  for (auto _ : state) {
    const auto p = marble(name);
    benchmark::DoNotOptimize(p->cumulative().total());
  }
}

const bool registered = [] {
  for (const auto& name : bssrdf::modelNames()) {
    benchmark::RegisterBenchmark(("evaluate/" + name).c_str(), BM_Evaluate, name);
    benchmark::RegisterBenchmark(("sample/" + name).c_str(), BM_Sample, name);
    benchmark::RegisterBenchmark(("build/" + name).c_str(), BM_BuildProfile, name)
        ->Unit(benchmark::kMicrosecond);
  }
  return true;
}();

}  // namespace
