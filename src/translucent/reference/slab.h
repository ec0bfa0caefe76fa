// SPDX-License-Identifier: GPL-3.0-or-later
// Reference Monte Carlo photon transport in a homogeneous slab lit by a pencil beam: the
// searchlight problem of seed section 2.3 and the one-layer case of MCML (Wang, Jacques & Zheng
// 1995), traced by the unbiased random walk of seed section 3.2 (Algorithm 1).
//
// Geometry and units: the slab fills 0 <= z <= thickness (z points into the medium; thickness =
// infinity gives the semi-infinite medium). Coefficients are per length unit (the presets use
// 1/mm, MCML uses 1/cm); radii come out in the same unit and Rd(r) per squared unit. Indices are
// absolute refractive indices of the medium above, inside and below. The beam hits the origin
// from above at polar angle theta (in the medium above) and azimuth phi.
//
// What is traced, per incident photon:
//   - specular reflection at entry: Rsp = Fresnel(cos theta) exactly (MCML); the photon enters
//     with weight 1 - Rsp along the refracted direction (so Rsp has no Monte Carlo error);
//   - free flights with density σt e^{-σt s} (fast float -log ξ);
//   - at each boundary, exact unpolarised Fresnel reflectance F of the interface
//     (translucent::fresnelReflectance; the lane walker evaluates the same formula in float,
//     fastmath.h): internal reflection with probability F, else the photon leaves (Algorithm 1
//     lines 5-11); the unused part of the flight continues after reflection;
//   - at each collision either (Absorption::Analog, Algorithm 1 line 15) absorption with
//     probability 1 - α, or (Absorption::Weighted, MCML) weight w -> α w with the loss scored as
//     absorbed and Russian roulette (survive with chance 1/10, weight x10) once w < 1e-4.
//     Analog is the default: it traces far fewer events per photon, and per second of CPU it
//     gives the smaller variance of Rd in semi-infinite and thick media (1.6-2.5x, measured in
//     bench_reference); in thin slabs the weighted mode is up to ~1.3x better, and it always
//     estimates the absorbed fraction with less variance;
//   - Henyey-Greenstein scattering (phase.h);
//   - optionally the seed's long-path roulette: after `long_path_roulette` scattering events each
//     further event keeps the photon with probability 1/10 and multiplies its weight by 10.
// All of these are unbiased; the tallies are per-photon sums of weights and of squared weights,
// so every estimate comes with its standard error.
//
// Determinism: photons are traced in fixed blocks of kBlockPhotons, block b with its own random
// streams (the scalar walker: Rng(seed, b); the lane walker: Rng(seed, 8b + lane) for its 8
// lanes); block tallies are merged in block order. The result is a function of (setup, options,
// seed, walker) only: bit-identical for any thread count. (The lane walker's AVX2 build uses
// fused multiply-adds, so its results differ in the last bits from the portable build's.)
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "translucent/optics/medium.h"

namespace translucent::reference {

struct SlabSetup {
  double sigma_a = 0.0;  // absorption coefficient σa [1/length]
  double sigma_s = 1.0;  // scattering coefficient σs [1/length]
  double g = 0.0;        // Henyey-Greenstein mean cosine, in (-1, 1)
  double n_inside = 1.0;  // refractive index of the slab
  double n_above = 1.0;   // refractive index above (z < 0), where the beam comes from
  double n_below = 1.0;   // refractive index below (z > thickness)
  double thickness = std::numeric_limits<double>::infinity();  // [length]; inf: semi-infinite
  double theta = 0.0;  // polar angle of incidence in the medium above [radians], in [0, π/2)
  double phi = 0.0;    // azimuth of incidence [radians]

  // A semi-infinite slab of this medium channel under air (n = 1 above, η inside).
  static SlabSetup semiInfinite(const ScalarMedium& m);
  // Throws ParameterError naming the offending parameter.
  void validate() const;
  bool finite() const { return thickness < std::numeric_limits<double>::infinity(); }
};

enum class Absorption {
  Analog,    // Russian roulette on the albedo (Algorithm 1): one outcome per photon
  Weighted,  // MCML: implicit capture w *= α, roulette of small weights
};

enum class Kernel {
  Lanes,          // 8 photons at once in structure-of-arrays form, vectorised; uses AVX2 + FMA
                  // when the CPU has them (fast; the default)
  LanesPortable,  // the same, built for the baseline instruction set only
  Scalar,         // one photon at a time, Algorithm 1 as written (the readable reference)
};

// Photons per block; part of the determinism contract (results depend on it).
inline constexpr uint64_t kBlockPhotons = 1024;

struct TraceOptions {
  uint64_t photons = 1'000'000;
  uint64_t seed = 1;
  int threads = 0;  // 0: all hardware threads
  Absorption absorption = Absorption::Analog;
  Kernel kernel = Kernel::Lanes;
  // Radial tally of the diffuse reflectance: `radial_bins` annuli of equal width on
  // [0, radial_max] (none if radial_bins == 0).
  int radial_bins = 0;
  double radial_max = 0.0;
  // Exit-angle tally (polar angle outside, [0, π/2] in equal steps; none if 0). With radial bins
  // also the joint Rd(r, θ).
  int angle_bins = 0;
  // Long-path roulette after this many scattering events (0: off).
  uint64_t long_path_roulette = 0;
  // A share of the run (issue 17: shards): trace only its blocks first_block .. first_block +
  // blocks - 1 of kBlockPhotons photons (0 blocks: to the end). Block b is the same photons in
  // any share, so the shards' run states (run_state.h) add up to the whole run's.
  uint64_t first_block = 0, blocks = 0;

  // Blocks of the whole run, and the photons of blocks [first, first + count).
  uint64_t totalBlocks() const { return (photons + kBlockPhotons - 1) / kBlockPhotons; }
  uint64_t photonsInBlocks(uint64_t first, uint64_t count) const;
  void validate() const;
};


// A Monte Carlo estimate per incident photon and its standard error.
struct Estimate {
  double value = 0.0;
  double std_error = 0.0;
};

// The seed's split of the BSSRDF by scattering order (Eq. 2.13, S = S(0) + S(1) + S_d): light
// that leaves without scattering (reduced radiance), after exactly one scattering event, or after
// more. Internal reflections at the boundary do not count as scattering. Every tally of the
// tracers is kept for each order too; the three add up to the total.
enum class ScatteringOrder { Unscattered = 0, Single = 1, Multiple = 2 };
inline constexpr size_t kScatteringOrders = 3;
inline constexpr ScatteringOrder scatteringOrder(uint64_t scatters) {
  return scatters == 0 ? ScatteringOrder::Unscattered
                       : scatters == 1 ? ScatteringOrder::Single : ScatteringOrder::Multiple;
}
// "unscattered", "single", "multiple": the orders' names in outputs (JSON keys, EXR layers).
const char* toString(ScatteringOrder order);
inline constexpr std::array<ScatteringOrder, kScatteringOrders> kAllScatteringOrders{
    ScatteringOrder::Unscattered, ScatteringOrder::Single, ScatteringOrder::Multiple};

struct RadialProfileTally {
  double dr = 0.0;
  std::vector<double> r;          // annulus centres (i + 1/2) dr
  std::vector<double> rd;         // Rd(r) per unit area per incident photon [1/length²]
  std::vector<double> rd_stderr;  // its standard error
  Estimate beyond;                // diffuse reflectance exiting at r >= radial_max
};

struct AngularTally {
  double dtheta = 0.0;
  std::vector<double> theta;      // bin centres [radians], exit angle outside the slab
  std::vector<double> rd;         // diffuse reflectance per steradian per incident photon
  std::vector<double> rd_stderr;
  // Joint Rd(r, θ) [1/(length² sr)], row-major [radial bin][angle bin]; empty without radial bins.
  std::vector<double> rd_r_theta, rd_r_theta_stderr;
};

struct SlabResult {
  Estimate specular_reflectance;       // Rsp, exact
  Estimate diffuse_reflectance;        // everything leaving the top except Rsp
  Estimate transmittance;              // everything leaving the bottom
  Estimate diffuse_transmittance;      // ... after at least one scattering event
  Estimate unscattered_transmittance;  // ... without scattering
  Estimate absorbed;
  RadialProfileTally radial;
  AngularTally angular;
  // The exit tallies by scattering order, indexed by ScatteringOrder: diffuse reflectance and
  // transmittance (order 0 of the transmittance is unscattered_transmittance), the radial and
  // angular profiles (each the same layout as `radial` and `angular`, empty where those are).
  struct Order {
    Estimate diffuse_reflectance, transmittance;
    RadialProfileTally radial;
    AngularTally angular;
  };
  std::array<Order, kScatteringOrders> orders;
  const Order& order(ScatteringOrder o) const { return orders[static_cast<size_t>(o)]; }
  uint64_t photons = 0;             // photons traced (fewer than asked when stopped)
  uint64_t scattering_events = 0;   // collisions that scattered, summed over photons
  double seconds = 0.0;
  int threads = 0;
  uint64_t seed = 0;
  bool partial = false;  // stopped before all photons were traced
  std::string device = "cpu";  // what traced it: "cpu", or "gpu (<GL renderer>)" (slab_gpu.h)

  double photonsPerSecond() const { return seconds > 0.0 ? photons / seconds : 0.0; }
};

struct TraceProgress {
  uint64_t photons_done = 0;
  uint64_t photons_total = 0;
  double seconds = 0.0;
};
// Called on the calling thread about ten times a second and once at the end; return false to
// stop (the photons traced so far are returned with partial = true).
using ProgressCallback = std::function<bool(const TraceProgress&)>;

struct RunState;

// Traces options.photons photons, or the blocks of the share options.first_block/blocks
// (throws ParameterError for bad setup or options). With `state`, also the run's
// order-independent sums (run_state.h): what a shard writes for `translucent merge`.
SlabResult traceSlab(const SlabSetup& setup, const TraceOptions& options,
                     const ProgressCallback& progress = {}, RunState* state = nullptr);
// The result of a run from its state (e.g. the merged states of its shards): what traceSlab
// returns for the whole run, bit for bit (timings aside). std::runtime_error when the state's
// layout is not that of these options.
SlabResult slabResult(const SlabSetup& setup, const TraceOptions& options, const RunState& state);

}  // namespace translucent::reference
