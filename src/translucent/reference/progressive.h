// SPDX-License-Identifier: GPL-3.0-or-later
// Progressive, cancellable runs of the accumulating Monte Carlo estimators (seed 3.6.2: the lit
// sphere widgets refine their images while the user watches, and start over when a parameter
// changes).
//
// An estimator here is anything with `Stats addPass(uint64_t count, const ProgressCallback&)`
// whose Stats has a `partial` flag: SpherePathTracer (count = photons per channel), SphereIntegrator
// (count = samples per pixel), MeshPathTracer. Passes accumulate into the estimator's images, so
// the image after pass k is the estimate from all the samples of passes 0..k.
//
// Pass sizes double (first, 2 first, 4 first, ...) so that the first image comes quickly and the
// number of refreshes grows only logarithmically with the budget, up to an optional cap; the last
// pass is cut so that the passes add up to the budget. With a granularity (the path tracers' kBlockPhotons) every pass is
// a whole number of blocks, and K passes of the schedule then give bit for bit the images of one
// pass of the whole budget (sphere.h); the integrator draws fresh streams per pass, so its result
// depends on the schedule (but, as always, not on the thread count).
//
// Cancellation: `stop` is polled before each pass and by the estimator's progress callback, which
// the block driver calls about ten times a second (block_driver.h); workers then finish the block
// in hand and drop it. A cancelled pass leaves a partial pass in the estimator, which is therefore
// discarded by the caller; the passes reported through `onPass` before it were complete.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "translucent/reference/slab.h"  // ProgressCallback, TraceProgress

namespace translucent::reference {

// Pass sizes: first, 2 first, 4 first, ..., each rounded up to a multiple of `granularity` and
// growing no further than `cap` (0: no cap; rounded up to a multiple of `granularity`), so that
// refreshes keep coming at a steady pace once the images are good; the last pass is cut so that
// they sum to the budget rounded up to a multiple of `granularity`. Throws ParameterError for a
// zero first pass, budget or granularity, or a cap below the first pass.
std::vector<uint64_t> doublingPasses(uint64_t first, uint64_t budget, uint64_t granularity = 1,
                                     uint64_t cap = 0);

struct ProgressiveResult {
  int passes = 0;          // complete passes
  uint64_t done = 0;       // sum of the complete passes' counts
  bool stopped = false;    // `stop` was seen before the schedule ended
};

// Within-pass progress: the pass index, the count of complete passes so far, and the
// estimator's progress in the current pass.
using PassProgress = std::function<void(int pass, uint64_t done, const TraceProgress&)>;

// Runs the passes in order until the schedule ends or `stop` becomes true. After each complete
// pass k calls onPass(k, done) (on the calling thread, with the estimator not running, so onPass
// may read or copy its images). Exceptions from the estimator propagate.
template <class Estimator, class OnPass>
ProgressiveResult runProgressive(Estimator& estimator, std::span<const uint64_t> passes,
                                 const std::atomic<bool>& stop, OnPass&& onPass,
                                 const PassProgress& progress = {}) {
  ProgressiveResult r;
  for (size_t k = 0; k < passes.size(); ++k) {
    if (stop.load()) {
      r.stopped = true;
      return r;
    }
    const int pass = static_cast<int>(k);
    const uint64_t done = r.done;
    const auto stats = estimator.addPass(passes[k], [&](const TraceProgress& p) {
      if (progress) progress(pass, done, p);
      return !stop.load();
    });
    if (stats.partial || stop.load()) {
      // A pass that ran to its end before `stop` was seen is complete all the same, but the
      // caller asked to stop: report it as stopped either way (the images stay consistent).
      r.stopped = true;
      if (!stats.partial) {
        ++r.passes;
        r.done += passes[k];
      }
      return r;
    }
    ++r.passes;
    r.done += passes[k];
    onPass(pass, r.done);
  }
  return r;
}

}  // namespace translucent::reference
