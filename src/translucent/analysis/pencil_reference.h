// SPDX-License-Identifier: GPL-3.0-or-later
// The path-traced pencil-beam reference of the pencil plot (seed 3.6.3), refined progressively:
// Rd(r) of a semi-infinite slab of the medium under a pencil beam at normal incidence, traced by
// reference::traceSlab in passes of doubling photon counts, every pass merged into a running total
// so that the curve sharpens while the user watches (the explorer redraws after each pass).
//
// Merging: each pass uses its own seed (seed + 3·pass + channel), so passes are independent; two
// estimates of one mean from n_a and n_b photons pool into the estimate from n_a + n_b photons by
// rebuilding the per-photon sums Σw and Σw² from (mean, standard error, n) (reference/walk.h:
// var = (Σw²/n - mean²) n/(n-1), s.e. = sqrt(var/n)) and adding them. The pooled result equals
// one run over the union of the photons, up to rounding.
//
// Units: radii in scene units (Medium::channel: σ · scale), Rd(r) per squared scene unit per unit
// flux entering the medium (the tally per incident photon divided by 1 - Rsp, the exact entry
// transmittance), as the models' R(r) (Eq. 2.16 applies Ft(ωi) separately).
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "translucent/bssrdf/profile_curves.h"
#include "translucent/reference/slab.h"

namespace translucent::analysis {

// Pools two independent estimates of the same mean, from n_a and n_b photons.
reference::Estimate poolEstimates(const reference::Estimate& a, uint64_t n_a,
                                  const reference::Estimate& b, uint64_t n_b);

// Adds `pass` (same setup and tallies, another seed) into `total` (diffuse reflectance,
// transmittances, absorption and the radial tally, and those by scattering order; photons, events
// and seconds add up). An empty total (0 photons) becomes a copy of `pass`. Throws ParameterError
// when the radial grids differ.
void accumulateSlab(reference::SlabResult& total, const reference::SlabResult& pass);

// The reference curve of channel `ch` from per-channel results (index 0, 1, 2 = red, green,
// blue; only those the channel needs are read: one, or all three for luminance, whose error
// combines in quadrature). Named "reference", optionally multiplied by r. With `order`, only the
// light of that scattering order (the seed's "multi + single scattering" selector): named
// "reference (single)" etc.
Curve pencilReferenceCurve(const std::array<const reference::SlabResult*, 3>& results, Channel ch,
                           bool times_r,
                           std::optional<reference::ScatteringOrder> order = std::nullopt);

// The reference's light a selection names (the seed's "multi + single scattering" selector):
// "all" (every order together: nullopt), "single", "multiple", or "split" (all, then single,
// then multiple). ParameterError naming the valid names otherwise.
inline constexpr std::array<const char*, 4> kScatteringSelections{"all", "single", "multiple", "split"};
std::vector<std::optional<reference::ScatteringOrder>> scatteringSelection(std::string_view name);

struct PencilReferenceOptions {
  double r_max = 0.0;       // radial tally on [0, r_max] [scene units]
  int bins = 100;           // annuli
  uint64_t photons = 1'000'000;       // budget per channel (total over all passes)
  uint64_t first_pass = 16'384;       // photons per channel in the first pass; then doubling
  uint64_t seed = 1;
  int threads = 0;          // traceSlab threads (0: all)
  // Where it is traced (reference/gpu/device.h): "cpu", "gpu" (a GL 4.5 context of its own, made
  // on the calling thread) or "auto" (the GPU on a hardware GPU, else the CPU).
  std::string device = "auto";
  double theta = 0.0;       // polar angle of the beam [radians, outside, in [0, π/2)]
};

struct PencilReferencePass {
  int pass = 0;                 // 0, 1, ...
  uint64_t photons = 0;         // photons per channel traced so far (all passes)
  bool last = false;            // the budget is reached
  std::string device;           // what traced it: "cpu" or "gpu (<renderer>)"
  std::array<reference::SlabResult, 3> results;  // running totals; unused channels empty
};

// Traces the channels `channel` needs in passes (first_pass, 2·first_pass, ... photons per
// channel, the last cut to the budget), calling on_pass with the running totals after each pass.
// `stop` (may be null) set to true ends the run promptly (within ~0.1 s): the pass in flight is
// dropped and the function returns false. Returns true when the budget was traced. Throws
// ParameterError for a channel without absorption (the semi-infinite walk would never end), bad
// options, or device "gpu" where EGL gives no GL 4.5 context.
bool tracePencilReference(const Medium& medium, Channel channel,
                          const PencilReferenceOptions& options,
                          const std::function<void(const PencilReferencePass&)>& on_pass,
                          const std::atomic<bool>* stop = nullptr);

}  // namespace translucent::analysis
