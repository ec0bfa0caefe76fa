// SPDX-License-Identifier: GPL-3.0-or-later
// Reference Monte Carlo transport in a layered slab lit by a pencil beam: MCML's multi-layer mode
// (Wang, Jacques & Zheng 1995) with every layer at the slab's one refractive index, traced by the
// walk of slab.h. `translucent pathtrace slab --layers layers.json`.
//
// Geometry: layer 0 fills 0 <= z <= t0, layer 1 t0 <= z <= t0 + t1, and so on down (z into the
// medium); only the last layer may be semi-infinite. The layers are index-matched (one η, the
// surface's), so a layer boundary neither reflects nor refracts: the coefficients are piecewise
// constant in z and the free flight is sampled exactly in optical depth, τ = −ln ξ spent layer by
// layer (σt,i times the distance in layer i) until it runs out (no null collisions). At a
// collision the layer's albedo and g apply (analog absorption by default, or MCML's weighted
// mode, as in slab.h); the top and bottom surfaces reflect and refract as in slab.h.
//
// Outputs: a SlabResult exactly as the homogeneous slab's (diffuse reflectance, transmittance,
// absorbed, Rd(r), angular tallies, standard errors). Determinism: block b of kBlockPhotons
// photons draws from Rng(seed, b), blocks are merged in block order: bit-identical for any thread
// count. The walker is scalar, in double precision (TraceOptions::kernel is ignored).
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "translucent/reference/slab.h"

namespace translucent::reference {

struct SlabLayer {
  double thickness = std::numeric_limits<double>::infinity();  // [length]; inf: semi-infinite
  double sigma_a = 0.0;  // [1/length]
  double sigma_s = 1.0;  // [1/length]
  double g = 0.0;
};

struct LayeredSlabSetup {
  std::vector<SlabLayer> layers;  // top first
  double n_inside = 1.0;  // every layer's refractive index
  double n_above = 1.0, n_below = 1.0;
  double theta = 0.0, phi = 0.0;  // incidence [radians], as in SlabSetup

  // Throws ParameterError naming the layer (1-based, top first) and the parameter.
  void validate() const;
  bool finite() const;
  double totalThickness() const;  // infinity when the last layer is semi-infinite
};

// Traces options.photons photons (throws ParameterError for a bad setup or options).
// With `state`, also the run's order-independent sums (run_state.h; traceSlab).
SlabResult traceLayeredSlab(const LayeredSlabSetup& setup, const TraceOptions& options,
                            const ProgressCallback& progress = {}, RunState* state = nullptr);
// The result of a run from its state (slabResult).
SlabResult layeredSlabResult(const LayeredSlabSetup& setup, const TraceOptions& options,
                             const RunState& state);

namespace detail {
// Per-layer constants of a walk; boundary[i] .. boundary[i + 1] is layer i (z down, the last
// boundary infinite for a semi-infinite slab).
struct Layers {
  std::vector<double> boundary, sigmaT;
  std::vector<uint64_t> absorbThreshold;  // as Walk::absorbThreshold, per layer
  std::vector<double> albedo;
  std::vector<float> g;
};
// The setup and options validated as traceLayeredSlab validates them, the layers' constants,
// and in `slab` the homogeneous slab of the top layer and the total thickness, whose entry,
// surfaces and tallies the layered walk shares (the GPU walk, reference/gpu/slab_gpu.h, too).
Layers layeredWalk(const LayeredSlabSetup& setup, const TraceOptions& options, SlabSetup& slab);
}  // namespace detail

// The layers of a JSON array, top layer first, of {"thickness": t or null (semi-infinite, last
// layer only), "sigma_a": …, "sigma_s": …, "g": …} ("g" optional, default 0). Errors name `what`
// (the file), the index (0-based, as in the array) and the key.
std::vector<SlabLayer> parseSlabLayers(const std::string& json_text, const std::string& what);
// The same from a file; a missing or unreadable file is a ParameterError naming it.
std::vector<SlabLayer> loadSlabLayers(const std::string& path);

}  // namespace translucent::reference
