// SPDX-License-Identifier: GPL-3.0-or-later
// A slab run as a user asks for it: the options of `translucent pathtrace slab` and the arguments
// of the Python binding's `translucent.pathtrace_slab`, checked once for both (messages name the
// CLI's options, which the binding's keyword arguments mirror), and the JSON both return.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "translucent/reference/layered_slab.h"
#include "translucent/reference/slab.h"

namespace translucent::reference {

struct SlabRequest {
  // The medium: sigma_a, sigma_s (g, eta), or a preset and a channel; or layers (below).
  std::optional<double> sigma_a, sigma_s, g, eta;
  std::string preset, channel;  // "" when not given
  double eta_above = 1.0, eta_below = 1.0;
  std::optional<double> thickness;  // none: semi-infinite
  double theta = 0.0, phi = 0.0;    // beam direction [degrees]
  uint64_t photons = 1'000'000;
  uint64_t seed = 1;
  int threads = 0;
  int radial_bins = 0;
  std::optional<double> radial_max;
  int angle_bins = 0;
  uint64_t long_path_roulette = 0;
  // auto: weighted for thin slabs (reduced optical thickness <= 2), analog elsewhere (the walk
  // that reaches an error on Rd sooner: slab_request.cpp autoAbsorption).
  std::string absorption = "auto", kernel = "lanes";
  std::string device = "auto";  // cpu | gpu | auto (reference/gpu/device.h opens it)
  // A time limit bounds the run (--time-limit: it stops between photons): an estimated total
  // beyond the bound below is traced then, up to the limit, instead of refused.
  bool time_limited = false;
};

// The checked run.
struct SlabRun {
  SlabSetup setup;  // what traceSlab traces (a homogeneous slab)
  SlabSetup shown;  // what the output's medium and thickness describe (layered: the top layer
                    // with the total thickness)
  std::optional<LayeredSlabSetup> layered;
  TraceOptions options;
  std::string length_unit;  // of the coefficients ("mm" for presets)
  std::string device = "auto";  // as requested: cpu, gpu or auto
};

// Checks the request and builds the run; `layers` (with `layers_what`, the file or "layers", for
// messages): a layered slab, each layer at --eta. Refuses, naming the options, contradictory or
// missing media, bad numbers, and legal numbers that lead nowhere: without long-path roulette, a
// longest walk of more than ~1e10 scattering events (almost no absorption in a thick slab or a
// half-space) could not end in any reasonable time, nor be interrupted (Ctrl-C and time limits act
// between photons); and, without a time limit, a run whose walks average more than ~1e3 events
// and total more than ~1e9 (hours on one core), naming --time-limit and the other ways out.
SlabRun makeSlabRun(const SlabRequest& request,
                    const std::optional<std::vector<SlabLayer>>& layers = std::nullopt,
                    const std::string& layers_what = "layers");

// Traces the run (traceSlab or traceLayeredSlab, with their options).
SlabResult traceSlabRun(const SlabRun& run, const ProgressCallback& progress = {},
                        RunState* state = nullptr);

// The JSON of `translucent pathtrace slab --json` (the caller adds "layers_file").
nlohmann::json slabResultJson(const SlabRun& run, const SlabResult& result);

}  // namespace translucent::reference
