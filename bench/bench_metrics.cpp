// SPDX-License-Identifier: GPL-3.0-or-later
// The compare report's image metrics (src/analysis/metrics.h) on 512x512 images, the largest the
// report computes them for (about ten per report): all metrics together, and the two perceptual
// maps alone (they dominate: separable filters of radius 10 and 9 for ꟻLIP at 67 px/°, 5 for
// SSIM).
// Run: build/release/bin/bench_metrics
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <vector>

#include "translucent/analysis/metrics.h"

namespace {

using namespace translucent::analysis;

struct Pair {
  int w = 512, h = 512;
  std::vector<float> ref, test, se;
  Pair() {
    std::mt19937 rng(1);
    std::normal_distribution<float> n(0.0f, 1.0f);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        for (int c = 0; c < 3; ++c) {
          const float v = 0.5f + 0.4f * std::sin(0.05f * static_cast<float>(x) +
                                                  0.03f * static_cast<float>(y) +
                                                  static_cast<float>(c));
          ref.push_back(v);
          se.push_back(0.02f);
          test.push_back(1.05f * v + 0.02f * n(rng));
        }
  }
  ImageRef t() const { return {w, h, test, se}; }
  ImageRef r() const { return {w, h, ref, {}}; }
};

const Pair& pair() {
  static const Pair p;
  return p;
}

void BM_ComputeMetrics512(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(computeMetrics(pair().t(), pair().r()));
}
BENCHMARK(BM_ComputeMetrics512)->Unit(benchmark::kMillisecond);

void BM_FlipMap512(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(flipMap(pair().t(), pair().r(), {}));
}
BENCHMARK(BM_FlipMap512)->Unit(benchmark::kMillisecond);

void BM_SsimMap512(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(ssimMap(pair().t(), pair().r(), {}));
}
BENCHMARK(BM_SsimMap512)->Unit(benchmark::kMillisecond);

}  // namespace
