// SPDX-License-Identifier: GPL-3.0-or-later
// Slab runs from user requests (slab_request.h).
#include "translucent/reference/slab_request.h"

#include <fmt/format.h>

#include <cmath>
#include <numbers>

#include "translucent/optics/presets.h"

namespace translucent::reference {
namespace {

// Legal numbers that lead nowhere (issue 15): with almost no absorption a walk in a thick slab
// goes on for ~1/(1 − α') scattering events before it is absorbed, and in a half-space the walk
// lengths are heavy-tailed (the depth is a 1D random walk: P(N > k) ~ k^{-1/2}), so the longest
// of n photons is ~n² events. A photon is never interrupted mid-walk, so Ctrl-C and time limits
// cannot stop such a run either. Without long-path roulette (which ends every walk) a longest walk
// over kMaxWalkEvents is refused with the estimate.
constexpr double kMaxWalkEvents = 1e10;  // ~minutes for one photon at ~1e8 events/s

// The total: the longest walk may be fine while the run is not (`--sigma-a 1e-20 --sigma-s 1
// --photons 1e4` ran for many minutes). A half-space walk that absorption or the longest-walk
// scale c cuts off averages ~2 sqrt(c) events (P(N > k) ~ k^{-1/2}), in a finite slab too (c
// then at most its crossing, ~(σt' L)²).
// Measured: 1e3 photons of σa = 1e-20 (estimate 2e6 events) take 1.4 s on one core, the time
// growing as the square of the photons: such walks run at ~1.5e6 events/s, not the ~1e8 of a
// normal medium, since one long walk holds its SIMD lane while the other seven idle: 1e4 photons
// (2e8 events) take ~2.5 minutes. A run that is long only because it has many photons of a
// normal medium (~10-100 events each) is the user's choice and never refused.
constexpr double kMaxMeanEvents = 1e3;   // per photon: ~100x a typical medium's
constexpr double kMaxTotalEvents = 1e8;  // estimated events of the run: ~1 min on one core

void checkWalkLength(const SlabSetup& s, const TraceOptions& o, bool time_limited,
                     const std::string& what = "--sigma-a") {
  if (o.long_path_roulette != 0) return;
  // σa = 0 in a half-space: traceSlab says why. In a finite slab a walk without absorption ends
  // only by leaving it, after ~(σt' L)² steps: that estimate alone decides (a thick slab of a
  // scattering layer without absorption never ended; fuzz_layers).
  if (!(s.sigma_a > 0.0) && !s.finite()) return;
  const double sigmaTPrime = s.sigma_a + (1.0 - s.g) * s.sigma_s;
  const double absorbed = s.sigma_a / sigmaTPrime;  // 1 − α': absorption chance per step
  const double n = static_cast<double>(o.photons);
  double longest = std::min(absorbed > 0.0 ? 1.0 / absorbed : HUGE_VAL, n * n);
  // A finite slab: a diffusing walk crosses it after ~(σt' L)² steps and leaves.
  if (s.finite()) longest = std::min(longest, 10.0 * std::pow(sigmaTPrime * s.thickness, 2) + 10.0);
  if (longest > kMaxWalkEvents && !(s.sigma_a > 0.0))
    throw ParameterError(fmt::format(
        "{} is 0 with σs' = {} and a thickness of {}: without absorption a walk ends only by "
        "leaving the slab, after ~(σt' L)² = {:.3g} scattering events, and no photon is "
        "interrupted mid-walk; give --long-path-roulette N (e.g. 1e6) to end long walks "
        "without bias, some absorption, or a thinner slab",
        what, (1.0 - s.g) * s.sigma_s, s.thickness, longest));
  if (longest > kMaxWalkEvents)
    throw ParameterError(fmt::format(
        "{} is {} with σs' = {}: absorption ends a walk only after ~1/(1 − α') = {:.3g} "
        "scattering events, and the longest of {} walks would take ~{:.3g} events (hours to years, "
        "and no photon is interrupted mid-walk); give --long-path-roulette N (e.g. 1e6) to end "
        "long walks without bias, a larger --sigma-a, or a --thickness",
        what, s.sigma_a, (1.0 - s.g) * s.sigma_s, absorbed > 0.0 ? 1.0 / absorbed : HUGE_VAL,
        o.photons, longest));
  if (time_limited) return;
  const double mean = 2.0 * std::sqrt(longest);
  const double total = mean * n;
  if (mean > kMaxMeanEvents && total > kMaxTotalEvents)
    throw ParameterError(fmt::format(
        "{} is {} with σs' = {}: a walk takes ~{:.3g} scattering events on average, ~{:.3g} for "
        "the {} photons, which would take minutes to hours; "
        "give --time-limit SECONDS to trace what fits in that time, --long-path-roulette N (e.g. "
        "1e4) to end long walks without bias, fewer --photons, a larger --sigma-a or a "
        "--thickness",
        what, s.sigma_a, (1.0 - s.g) * s.sigma_s, mean, total, o.photons));
}

SlabSetup buildSetup(const SlabRequest& a, bool layered, std::string& lengthUnit) {
  SlabSetup s;
  const bool scalar = a.sigma_a || a.sigma_s;
  if (layered) {
    // The layers give the media; the slab's surfaces and beam come from the request.
    if (scalar || a.g || !a.preset.empty() || !a.channel.empty() || a.thickness)
      throw ParameterError("--layers gives the media and thicknesses: it cannot be combined "
                           "with --sigma-a, --sigma-s, --g, --preset, --channel or --thickness");
    if (!a.eta)
      throw ParameterError("--eta: required with --layers (index of every layer, e.g. 1.4)");
    s.n_inside = *a.eta;
    lengthUnit = "length unit of the coefficients";
  } else if (scalar) {
    if (!a.preset.empty())
      throw ParameterError("--preset cannot be combined with --sigma-a/--sigma-s");
    if (!a.sigma_a || !a.sigma_s)
      throw ParameterError("--sigma-a and --sigma-s must be given together");
    if (!a.eta)
      throw ParameterError("--eta: required with --sigma-a/--sigma-s (index of the slab, e.g. 1.3)");
    if (!a.channel.empty()) throw ParameterError("--channel applies to --preset only");
    s.sigma_a = *a.sigma_a;
    s.sigma_s = *a.sigma_s;
    s.g = a.g.value_or(0.0);
    s.n_inside = *a.eta;
    lengthUnit = "length unit of the coefficients";
  } else {
    if (a.preset.empty())
      throw ParameterError("give the medium: --sigma-a A --sigma-s S --eta N, or --material NAME "
                           "--channel r|g|b");
    int c = -1;
    if (a.channel == "r" || a.channel == "red") c = 0;
    if (a.channel == "g" || a.channel == "green") c = 1;
    if (a.channel == "b" || a.channel == "blue") c = 2;
    if (c < 0)
      throw ParameterError(fmt::format("--channel '{}': expected r, g or b with --preset",
                                       a.channel));
    const Preset& p = translucent::preset(a.preset);
    const double g = a.g.value_or(p.g);
    const Medium m = Medium::fromReduced(p.sigma_a, p.sigma_s_prime, g, a.eta.value_or(p.eta));
    const ScalarMedium ch = m.channel(c);
    s.sigma_a = ch.sigma_a;
    s.sigma_s = ch.sigma_s;
    s.g = ch.g;
    s.n_inside = ch.eta;
    lengthUnit = "mm";
  }
  s.n_above = a.eta_above;
  s.n_below = a.eta_below;
  if (a.thickness) {
    if (!(std::isfinite(*a.thickness) && *a.thickness > 0.0))
      throw ParameterError(fmt::format("--thickness is {}: expected a positive length "
                                       "(leave it out for a semi-infinite medium)",
                                       *a.thickness));
    s.thickness = *a.thickness;
  }
  if (!(a.theta >= 0.0 && a.theta < 90.0))
    throw ParameterError(fmt::format("--theta is {}: expected degrees in [0, 90)", a.theta));
  s.theta = a.theta * std::numbers::pi / 180.0;
  s.phi = a.phi * std::numbers::pi / 180.0;
  if (!layered) s.validate();
  return s;
}

TraceOptions buildOptions(const SlabRequest& a) {
  TraceOptions o;
  o.photons = a.photons;
  o.seed = a.seed;
  o.threads = a.threads;
  if (a.radial_bins < 0)
    throw ParameterError(fmt::format("--radial-bins is {}: expected >= 0", a.radial_bins));
  if ((a.radial_bins > 0) != a.radial_max.has_value())
    throw ParameterError("--radial-bins and --radial-max must be given together");
  o.radial_bins = a.radial_bins;
  o.radial_max = a.radial_max.value_or(0.0);
  o.angle_bins = a.angle_bins;
  o.long_path_roulette = a.long_path_roulette;
  if (a.absorption != "analog" && a.absorption != "weighted" && a.absorption != "auto")
    throw ParameterError(
        fmt::format("--absorption '{}': expected auto, analog or weighted", a.absorption));
  if (a.kernel != "lanes" && a.kernel != "portable" && a.kernel != "scalar")
    throw ParameterError(fmt::format("--kernel '{}': expected lanes, portable or scalar", a.kernel));
  o.absorption = a.absorption == "weighted" ? Absorption::Weighted : Absorption::Analog;
  o.kernel = a.kernel == "scalar"     ? Kernel::Scalar
             : a.kernel == "portable" ? Kernel::LanesPortable
                                      : Kernel::Lanes;
  o.validate();
  return o;
}

// --absorption auto: MCML's weighted walk (implicit capture, roulette below 1e-4) where it reaches
// a given error on Rd in less CPU time than the analog walk, by bench_reference's measured Rd
// efficiencies (BENCHMARKS.md, "Reference slab Monte Carlo against classic MCML"; weighted ÷
// analog at reduced optical thickness σt'·d: 0.98 at 0.11, 1.43 at 0.65, 1.12 at 1.1, 0.40 at
// 11, 0.43-0.50 for half-spaces): slabs with σt'·d <= 2; the analog walk for thicker slabs,
// half-spaces and layered slabs (traced by the scalar walker either way).
Absorption autoAbsorption(const SlabSetup& s, bool layered) {
  if (layered || !s.finite()) return Absorption::Analog;
  const double reducedDepth = (s.sigma_a + (1.0 - s.g) * s.sigma_s) * s.thickness;
  return reducedDepth <= 2.0 ? Absorption::Weighted : Absorption::Analog;
}

void estimate(nlohmann::json& j, const std::string& key, const Estimate& e) {
  j[key] = e.value;
  j[key + "_stderr"] = e.std_error;
}

}  // namespace

SlabRun makeSlabRun(const SlabRequest& a, const std::optional<std::vector<SlabLayer>>& layers,
                    const std::string& layers_what) {
  SlabRun run;
  run.setup = buildSetup(a, layers.has_value(), run.length_unit);
  run.options = buildOptions(a);
  if (a.absorption == "auto") run.options.absorption = autoAbsorption(run.setup, layers.has_value());
  if (a.device != "cpu" && a.device != "gpu" && a.device != "auto")
    throw ParameterError(fmt::format("--device '{}': expected cpu, gpu or auto", a.device));
  run.device = a.device;
  checkWalkLength(run.setup, run.options, a.time_limited);
  run.shown = run.setup;
  if (!layers) return run;
  LayeredSlabSetup L;
  L.layers = *layers;
  L.n_inside = run.setup.n_inside;
  L.n_above = run.setup.n_above;
  L.n_below = run.setup.n_below;
  L.theta = run.setup.theta;
  L.phi = run.setup.phi;
  try {
    L.validate();
  } catch (const ParameterError& e) {
    throw ParameterError(fmt::format("--layers {}: {}", layers_what, e.what()));
  }
  run.shown.sigma_a = L.layers[0].sigma_a;
  run.shown.sigma_s = L.layers[0].sigma_s;
  run.shown.g = L.layers[0].g;
  run.shown.thickness = L.totalThickness();
  // Each layer on its own, as a slab of its thickness (the last one semi-infinite): a walk stays
  // at least as long in the stack as in its most transparent thick layer.
  for (size_t i = 0; i < L.layers.size(); ++i) {
    SlabSetup one = run.shown;
    one.sigma_a = L.layers[i].sigma_a;
    one.sigma_s = L.layers[i].sigma_s;
    one.g = L.layers[i].g;
    one.thickness = L.layers[i].thickness;
    checkWalkLength(one, run.options, a.time_limited, fmt::format("--layers {}: layer [{}]: sigma_a", layers_what, i));
  }
  // The finite layers together, as one slab of their total thickness, reduced optical depth and
  // absorption (σa weighted by thickness): layers that each pass alone may not together (a
  // stack of thin layers without absorption is one thick one, whose walks would not end).
  double depth = 0.0, tauA = 0.0, tauS = 0.0;
  size_t finiteLayers = 0;
  for (const SlabLayer& layer : L.layers) {
    if (!std::isfinite(layer.thickness)) break;  // only the last layer may be semi-infinite
    depth += layer.thickness;
    tauA += layer.sigma_a * layer.thickness;
    tauS += (1.0 - layer.g) * layer.sigma_s * layer.thickness;
    ++finiteLayers;
  }
  if (finiteLayers > 1) {
    SlabSetup stack = run.shown;
    stack.thickness = depth;
    stack.sigma_a = tauA / depth;
    stack.sigma_s = tauS / depth;
    stack.g = 0.0;
    checkWalkLength(stack, run.options, a.time_limited,
                    fmt::format("--layers {}: layers [0] to [{}] together: their mean sigma_a",
                                layers_what, finiteLayers - 1));
  }
  run.layered = std::move(L);
  return run;
}

SlabResult traceSlabRun(const SlabRun& run, const ProgressCallback& progress, RunState* state) {
  return run.layered ? traceLayeredSlab(*run.layered, run.options, progress, state)
                     : traceSlab(run.setup, run.options, progress, state);
}

nlohmann::json slabResultJson(const SlabRun& run, const SlabResult& r) {
  const SlabSetup& s = run.shown;
  const TraceOptions& o = run.options;
  nlohmann::json j;
  j["geometry"] = run.layered ? "layered slab" : "slab";
  if (run.layered) {
    nlohmann::json layers = nlohmann::json::array();
    for (const auto& L : run.layered->layers)
      layers.push_back({{"thickness", std::isfinite(L.thickness) ? nlohmann::json(L.thickness)
                                                                 : nlohmann::json(nullptr)},
                        {"sigma_a", L.sigma_a}, {"sigma_s", L.sigma_s}, {"g", L.g}});
    j["medium"] = {{"layers", layers}, {"eta", s.n_inside}, {"eta_above", s.n_above},
                   {"eta_below", s.n_below}, {"length_unit", run.length_unit}};
  } else {
    j["medium"] = {{"sigma_a", s.sigma_a}, {"sigma_s", s.sigma_s}, {"g", s.g},
                   {"eta", s.n_inside}, {"eta_above", s.n_above}, {"eta_below", s.n_below},
                   {"length_unit", run.length_unit}};
  }
  j["thickness"] = s.finite() ? nlohmann::json(s.thickness) : nlohmann::json(nullptr);
  j["theta_deg"] = s.theta * 180.0 / std::numbers::pi;
  j["phi_deg"] = s.phi * 180.0 / std::numbers::pi;
  j["absorption"] = o.absorption == Absorption::Analog ? "analog" : "weighted";
  j["device"] = r.device;
  j["long_path_roulette"] = o.long_path_roulette;
  estimate(j, "specular_reflectance", r.specular_reflectance);
  estimate(j, "diffuse_reflectance", r.diffuse_reflectance);
  estimate(j, "transmittance", r.transmittance);
  estimate(j, "diffuse_transmittance", r.diffuse_transmittance);
  estimate(j, "unscattered_transmittance", r.unscattered_transmittance);
  estimate(j, "absorbed", r.absorbed);
  // The radial and angular tallies of all exits or of one scattering order.
  auto profiles = [&](nlohmann::json& out, const RadialProfileTally& rad, const AngularTally& ang) {
    if (o.radial_bins > 0) {
      out["radial"] = {{"dr", rad.dr},
                       {"r", rad.r},
                       {"rd", rad.rd},
                       {"rd_stderr", rad.rd_stderr},
                       {"beyond_rmax", rad.beyond.value},
                       {"beyond_rmax_stderr", rad.beyond.std_error},
                       {"unit", fmt::format("per {}^2 per incident photon", run.length_unit)}};
    }
    if (o.angle_bins > 0) {
      std::vector<double> deg;
      for (double t : ang.theta) deg.push_back(t * 180.0 / std::numbers::pi);
      out["angular"] = {{"theta_deg", deg},
                        {"rd", ang.rd},
                        {"rd_stderr", ang.rd_stderr},
                        {"unit", "per steradian per incident photon (exit angle outside)"}};
      if (o.radial_bins > 0) {
        out["angular"]["rd_r_theta"] = ang.rd_r_theta;
        out["angular"]["rd_r_theta_stderr"] = ang.rd_r_theta_stderr;
      }
    }
  };
  profiles(j, r.radial, r.angular);
  // Seed Eq. 2.13: the same tallies for the light that left unscattered, after one scattering
  // event, or after more; each set adds up to the totals above.
  nlohmann::json orders = nlohmann::json::object();
  for (ScatteringOrder k : kAllScatteringOrders) {
    const SlabResult::Order& ord = r.order(k);
    nlohmann::json oj;
    estimate(oj, "diffuse_reflectance", ord.diffuse_reflectance);
    estimate(oj, "transmittance", ord.transmittance);
    profiles(oj, ord.radial, ord.angular);
    orders[toString(k)] = std::move(oj);
  }
  j["scattering_orders"] = std::move(orders);
  j["photons"] = r.photons;
  j["scattering_events"] = r.scattering_events;
  j["seconds"] = r.seconds;
  j["photons_per_second"] = r.photonsPerSecond();
  j["threads"] = r.threads;
  j["seed"] = r.seed;
  j["partial"] = r.partial;
  return j;
}

}  // namespace translucent::reference
