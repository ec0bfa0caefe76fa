// SPDX-License-Identifier: GPL-3.0-or-later
// Internal to src/reference: the run constants, tallies and exit scoring shared by the two photon
// walkers (walk_scalar.cpp: one photon at a time, Algorithm 1 as written; walk_lanes.cpp: the
// same walk for kLanes photons at once in structure-of-arrays form).
#pragma once

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <functional>
#include <vector>

#include "translucent/optics/fresnel.h"
#include "translucent/reference/phase.h"
#include "translucent/reference/rng.h"
#include "translucent/reference/run_state.h"
#include "translucent/reference/slab.h"
#include "translucent/reference/walk_lanes.h"

namespace translucent::reference::detail {

// Per-photon sums of weights and of squared weights (each photon leaves at most once, so adding
// w and w² at its exit accumulates the per-photon second moment).
struct Sums {
  double s = 0.0, s2 = 0.0;
  void add(double w) {
    s += w;
    s2 += w * w;
  }
  void merge(const Sums& o) {
    s += o.s;
    s2 += o.s2;
  }
  // Mean per photon and its standard error, divided by `measure` (an area or a solid angle).
  Estimate estimate(uint64_t n, double measure = 1.0) const {
    return meanAndError(s, s2, n, measure);
  }
};

// The tallies scored at exits, for one class of photons (all, or one scattering order).
struct ExitSums {
  Sums reflected, transmitted;
  std::vector<Sums> radial;       // radial bins, then one "beyond radial_max" bin
  std::vector<Sums> angular;      // exit-angle bins
  std::vector<Sums> radialAngle;  // [radial bin][angle bin]

  ExitSums(int nr, int na)
      : radial(nr > 0 ? static_cast<size_t>(nr) + 1 : 0),
        angular(static_cast<size_t>(na)),
        radialAngle(static_cast<size_t>(nr) * static_cast<size_t>(na)) {}
  void merge(const ExitSums& o) {
    reflected.merge(o.reflected);
    transmitted.merge(o.transmitted);
    for (size_t i = 0; i < radial.size(); ++i) radial[i].merge(o.radial[i]);
    for (size_t i = 0; i < angular.size(); ++i) angular[i].merge(o.angular[i]);
    for (size_t i = 0; i < radialAngle.size(); ++i) radialAngle[i].merge(o.radialAngle[i]);
  }
};

struct Tally : ExitSums {
  uint64_t photons = 0, events = 0;
  Sums unscattered, absorbed;
  // The exit tallies again by scattering order (slab.h: ScatteringOrder). Each photon leaves
  // once, into one order, so the orders' sums of squares add up to the total's as well.
  std::array<ExitSums, kScatteringOrders> orders;

  Tally(int nr, int na)
      : ExitSums(nr, na), orders{ExitSums(nr, na), ExitSums(nr, na), ExitSums(nr, na)} {}

  void merge(const Tally& o) {
    photons += o.photons;
    events += o.events;
    ExitSums::merge(o);
    unscattered.merge(o.unscattered);
    absorbed.merge(o.absorbed);
    for (size_t k = 0; k < orders.size(); ++k) orders[k].merge(o.orders[k]);
  }
};

// The run total of the block tallies, order-independent (exact_sum.h) so that shards merge into
// it bit for bit; weights are those of one incident photon (<= 1 but for the roulettes'
// factors of 10), on the unit grid.
struct ExactExitSums {
  MomentSum reflected, transmitted;
  std::vector<MomentSum> radial, angular, radialAngle;
  ExactExitSums(int nr, int na)
      : radial(nr > 0 ? static_cast<size_t>(nr) + 1 : 0),
        angular(static_cast<size_t>(na)),
        radialAngle(static_cast<size_t>(nr) * static_cast<size_t>(na)) {}
  void merge(const ExitSums& block);
  void toSums(ExitSums& out) const;
};

struct ExactTally : ExactExitSums {
  uint64_t photons = 0, events = 0;
  MomentSum unscattered, absorbed;
  std::array<ExactExitSums, kScatteringOrders> orders;

  ExactTally(int nr, int na)
      : ExactExitSums(nr, na),
        orders{ExactExitSums(nr, na), ExactExitSums(nr, na), ExactExitSums(nr, na)} {}
  void merge(const Tally& block);
  Tally toTally() const;  // the sums as doubles (for finishSlab)
  void write(RunState& state) const;
  void read(const RunState& state);
};

// The block loop of the slab tracers over the options' share of blocks: block(b, count, tally,
// stop) traces `count` photons of block b into a fresh tally. With `state`, the run state too.
using SlabBlock = std::function<bool(uint64_t b, uint64_t count, Tally& t,
                                     const std::atomic<bool>& stop)>;
SlabResult runSlabBlocks(const TraceOptions& O, double rsp, const SlabBlock& block,
                         const ProgressCallback& progress, RunState* state);
// The options' share of the run's blocks (all of them unless first_block / blocks say otherwise)
// and the photons in it.
struct BlockShare {
  uint64_t first = 0, count = 0, photons = 0;
};
BlockShare blockShare(const TraceOptions& O);
// The end of a slab run, whoever traced it: the result from the total (partial when it holds
// fewer than `expected` photons), the state written, the last progress report.
SlabResult finishSlabRun(const ExactTally& total, const TraceOptions& O, double rsp,
                         uint64_t expected, double seconds, int threads,
                         const ProgressCallback& progress, RunState* state);
// The result of a run from its state (slabResult, traceLayeredSlab's counterpart).
SlabResult slabFromState(const TraceOptions& O, double rsp, const RunState& state);

// An interface seen from inside: relative index n_outside / n_inside, or index matched.
struct Interface {
  bool matched = true;
  double eta = 1.0;
};

// Constants of one run, in the precision the walkers use.
struct Walk {
  float invSigmaT = 1.0f;
  float g = 0.0f;
  float thickness = 0.0f;  // 0 for semi-infinite
  Dir entry{0.0f, 0.0f, 1.0f};
  double entryWeight = 1.0;  // 1 - Rsp
  // Analog absorption happens when a uniform 64-bit integer is below absorbThreshold: the
  // probability is 1 - α to 2^-64. (A float comparison would misrepresent 1 - α by up to 3e-8,
  // a 0.3% error at α = 0.99999.) The weighted mode multiplies by the double albedo.
  uint64_t absorbThreshold = 0;
  double albedo = 1.0;
  Interface top, bottom;
  int nr = 0, na = 0;
  float invDr = 0.0f;
  double invDtheta = 0.0;
  uint64_t longPath = 0;  // 0: off
};

// Roulette keeping a photon with probability 1/10 (to 2^-32) and multiplying its weight by the
// exact inverse, so that the expected weight is unchanged.
inline constexpr uint32_t kSurviveThreshold = 429496730u;  // round(0.1 * 2^32)
inline constexpr double kSurviveBoost = 4294967296.0 / kSurviveThreshold;

// The low word of the 64-bit absorption test, needed only when the high word ties (2^-32).
// The 64-bit threshold of an absorption with probability p (Walk::absorbThreshold).
inline uint64_t absorbThreshold(double p) {
  return p >= 1.0 ? ~uint64_t{0} : static_cast<uint64_t>(std::ldexp(p, 64));
}

inline bool absorbsLowWord(uint32_t low, uint64_t threshold) {
  return low < static_cast<uint32_t>(threshold);
}

// Fresnel reflectance of the interface seen from inside, and the cosine of the transmitted
// direction outside.
struct Crossing {
  double reflectance, cosOut;
};
inline Crossing cross(const Interface& f, double cos_in) {
  if (f.matched) return {0.0, cos_in};
  return {fresnelReflectance(cos_in, f.eta), refractedCosine(cos_in, f.eta)};
}

// Adds w to one exit's bins of `E`: the radial bin `ir` (-1: none) and the angle bin `ia`.
inline void addTop(ExitSums& E, const Walk& W, int ir, int ia, double w) {
  E.reflected.add(w);
  if (ir >= 0) E.radial[static_cast<size_t>(ir)].add(w);
  if (ia >= 0) {
    E.angular[static_cast<size_t>(ia)].add(w);
    if (ir >= 0 && ir < W.nr)
      E.radialAngle[static_cast<size_t>(ir) * static_cast<size_t>(W.na) + static_cast<size_t>(ia)]
          .add(w);
  }
}

// A photon of weight w leaves through the top at (x, y) with outside cosine cos_out after
// `scatters` scattering events.
inline void scoreTop(const Walk& W, Tally& T, float x, float y, double cos_out, uint64_t scatters,
                     double w) {
  int ir = -1, ia = -1;
  if (W.nr > 0) {
    const float fr = std::sqrt(x * x + y * y) * W.invDr;
    ir = fr < static_cast<float>(W.nr) ? static_cast<int>(fr) : W.nr;
  }
  if (W.na > 0) {
    const double theta = std::acos(std::clamp(cos_out, 0.0, 1.0));
    ia = std::min(static_cast<int>(theta * W.invDtheta), W.na - 1);
  }
  addTop(T, W, ir, ia, w);
  addTop(T.orders[static_cast<size_t>(scatteringOrder(scatters))], W, ir, ia, w);
}

// A photon of weight w leaves through the bottom after `scatters` scattering events.
inline void scoreBottom(Tally& T, uint64_t scatters, double w) {
  T.transmitted.add(w);
  if (scatters == 0) T.unscattered.add(w);
  T.orders[static_cast<size_t>(scatteringOrder(scatters))].transmitted.add(w);
}

// The run constants of a slab (entry direction and weight, interfaces, tallies; rsp: the exact
// specular reflectance) and the result from a tally (slab.cpp; also used by layered_slab.cpp).
Walk makeWalk(const SlabSetup& S, const TraceOptions& O, double& rsp);
SlabResult finishSlab(const Tally& T, const TraceOptions& O, double rsp);

// Traces `count` photons of block `block`; returns false (and leaves T incomplete) when `stop`
// was raised before the block was done.
using BlockKernel = bool (*)(const Walk& W, uint64_t seed, uint64_t block, uint64_t count,
                             Tally& T, const std::atomic<bool>& stop);

BlockKernel scalarKernel(Absorption absorption, bool finite);

// The lane walker: its vector pass (chosen for the CPU, or the portable one) and the block loop.
struct LanesKernel {
  VectorPass pass = nullptr;
  bool (*run)(const Walk& W, VectorPass pass, uint64_t seed, uint64_t block, uint64_t count,
              Tally& T, const std::atomic<bool>& stop) = nullptr;
};
LanesKernel lanesKernel(Absorption absorption, bool finite, float g, bool portable);

}  // namespace translucent::reference::detail
