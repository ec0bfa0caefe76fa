// translucent pathtrace slab: reference Monte Carlo transport in a slab lit by a pencil beam
// (seed section 3.2, Algorithm 1; MCML with one layer), written as JSON (and the radial profile
// as CSV). See src/reference/slab.h for what is traced and tallied.
//
// Medium: --sigma-a A --sigma-s S [--g G] --eta N (one channel, coefficients per length unit),
// or --preset NAME --channel r|g|b (Jensen et al. 2001, 1/mm, σs = σs'/(1-g) for the given g).
// No --thickness: semi-infinite. Layered slab (MCML's multi-layer mode, reference/layered_slab.h):
// --layers FILE --eta N, the file a JSON array of layers, top first, each {"thickness": t or null,
// "sigma_a", "sigma_s", "g"} in the units of the other options, every layer at --eta. Ctrl-C (or --time-limit) stops the run; what was traced so far
// is written with "partial": true.
#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <numbers>
#include <optional>

#include "safe_print.h"
#include "commands.h"
#include "output_guard.h"
#include "progress.h"
#include "optics/presets.h"
#include "reference/layered_slab.h"
#include "reference/slab.h"

namespace translucent::cli {
namespace {

using reference::Absorption;
using reference::Kernel;
using reference::SlabResult;
using reference::SlabSetup;
using reference::TraceOptions;

struct PathtraceArgs {
  std::optional<double> sigma_a, sigma_s, g, eta;
  std::string preset, channel;
  double eta_above = 1.0, eta_below = 1.0;
  std::optional<double> thickness;
  double theta = 0.0, phi = 0.0;  // degrees
  std::string photons = "1e6";
  uint64_t seed = 1;
  int threads = 0;
  int radial_bins = 0;
  std::optional<double> radial_max;
  int angle_bins = 0;
  uint64_t long_path_roulette = 0;
  std::string absorption = "analog", kernel = "lanes";
  std::optional<double> time_limit;
  std::string json, csv;
  std::string layers;  // --layers FILE
};

uint64_t parsePhotons(const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (end == text.c_str() || *end != '\0' || !(v >= 1.0) || v > 1e18 || std::floor(v) != v)
    throw ParameterError(
        fmt::format("--photons '{}': expected a whole number >= 1 (e.g. 1000000 or 1e6)", text));
  return static_cast<uint64_t>(v);
}

SlabSetup buildSetup(const PathtraceArgs& a, std::string& lengthUnit) {
  SlabSetup s;
  const bool scalar = a.sigma_a || a.sigma_s;
  if (!a.layers.empty()) {
    // The layers come from the file; the slab's surfaces and beam from the options. The returned
    // setup is the top layer with the total thickness (what the output's surfaces refer to).
    if (scalar || a.g || !a.preset.empty() || !a.channel.empty() || a.thickness)
      throw ParameterError("--layers gives the media and thicknesses: it cannot be combined "
                           "with --sigma-a, --sigma-s, --g, --preset, --channel or --thickness");
    if (!a.eta)
      throw ParameterError("--eta: required with --layers (index of every layer, e.g. 1.4)");
    lengthUnit = "length unit of the coefficients";
  } else if (scalar && !a.preset.empty())
    throw ParameterError("--preset cannot be combined with --sigma-a/--sigma-s");
  if (scalar && !a.preset.empty())
    throw ParameterError("--preset cannot be combined with --sigma-a/--sigma-s");
  if (!a.layers.empty()) {
    s.n_inside = *a.eta;
  } else if (scalar) {
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
      throw ParameterError("give the medium: --sigma-a A --sigma-s S --eta N, or --preset NAME "
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
  if (a.layers.empty()) s.validate();
  return s;
}

reference::LayeredSlabSetup buildLayered(const PathtraceArgs& a, SlabSetup& s) {
  reference::LayeredSlabSetup L;
  L.layers = reference::loadSlabLayers(a.layers);
  L.n_inside = s.n_inside;
  L.n_above = s.n_above;
  L.n_below = s.n_below;
  L.theta = s.theta;
  L.phi = s.phi;
  try {
    L.validate();
  } catch (const ParameterError& e) {
    throw ParameterError(fmt::format("--layers {}: {}", a.layers, e.what()));
  }
  s.sigma_a = L.layers[0].sigma_a;
  s.sigma_s = L.layers[0].sigma_s;
  s.g = L.layers[0].g;
  s.thickness = L.totalThickness();
  return L;
}

TraceOptions buildOptions(const PathtraceArgs& a) {
  TraceOptions o;
  o.photons = parsePhotons(a.photons);
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
  o.absorption = a.absorption == "weighted" ? Absorption::Weighted : Absorption::Analog;
  o.kernel = a.kernel == "scalar" ? Kernel::Scalar
             : a.kernel == "portable" ? Kernel::LanesPortable
                                      : Kernel::Lanes;
  if (!a.csv.empty() && o.radial_bins == 0)
    throw ParameterError("--csv writes the radial profile: give --radial-bins and --radial-max");
  o.validate();
  return o;
}

void estimate(nlohmann::json& j, const std::string& key, const reference::Estimate& e) {
  j[key] = e.value;
  j[key + "_stderr"] = e.std_error;
}

void writeJson(const std::string& path, const SlabSetup& s, const TraceOptions& o,
               const SlabResult& r, const std::string& lengthUnit,
               const reference::LayeredSlabSetup* layered = nullptr,
               const std::string& layersFile = "") {
  nlohmann::json j;
  j["geometry"] = layered ? "layered slab" : "slab";
  if (layered) {
    nlohmann::json layers = nlohmann::json::array();
    for (const auto& L : layered->layers)
      layers.push_back({{"thickness", std::isfinite(L.thickness) ? nlohmann::json(L.thickness)
                                                                 : nlohmann::json(nullptr)},
                        {"sigma_a", L.sigma_a}, {"sigma_s", L.sigma_s}, {"g", L.g}});
    j["layers_file"] = layersFile;
    j["medium"] = {{"layers", layers}, {"eta", s.n_inside}, {"eta_above", s.n_above},
                   {"eta_below", s.n_below}, {"length_unit", lengthUnit}};
  } else {
    j["medium"] = {{"sigma_a", s.sigma_a}, {"sigma_s", s.sigma_s}, {"g", s.g},
                   {"eta", s.n_inside}, {"eta_above", s.n_above}, {"eta_below", s.n_below},
                   {"length_unit", lengthUnit}};
  }
  j["thickness"] = s.finite() ? nlohmann::json(s.thickness) : nlohmann::json(nullptr);
  j["theta_deg"] = s.theta * 180.0 / std::numbers::pi;
  j["phi_deg"] = s.phi * 180.0 / std::numbers::pi;
  j["absorption"] = o.absorption == Absorption::Analog ? "analog" : "weighted";
  j["long_path_roulette"] = o.long_path_roulette;
  estimate(j, "specular_reflectance", r.specular_reflectance);
  estimate(j, "diffuse_reflectance", r.diffuse_reflectance);
  estimate(j, "transmittance", r.transmittance);
  estimate(j, "diffuse_transmittance", r.diffuse_transmittance);
  estimate(j, "unscattered_transmittance", r.unscattered_transmittance);
  estimate(j, "absorbed", r.absorbed);
  if (o.radial_bins > 0) {
    j["radial"] = {{"dr", r.radial.dr},
                   {"r", r.radial.r},
                   {"rd", r.radial.rd},
                   {"rd_stderr", r.radial.rd_stderr},
                   {"beyond_rmax", r.radial.beyond.value},
                   {"beyond_rmax_stderr", r.radial.beyond.std_error},
                   {"unit", fmt::format("per {}^2 per incident photon", lengthUnit)}};
  }
  if (o.angle_bins > 0) {
    std::vector<double> deg;
    for (double t : r.angular.theta) deg.push_back(t * 180.0 / std::numbers::pi);
    j["angular"] = {{"theta_deg", deg},
                    {"rd", r.angular.rd},
                    {"rd_stderr", r.angular.rd_stderr},
                    {"unit", "per steradian per incident photon (exit angle outside)"}};
    if (o.radial_bins > 0) {
      j["angular"]["rd_r_theta"] = r.angular.rd_r_theta;
      j["angular"]["rd_r_theta_stderr"] = r.angular.rd_r_theta_stderr;
    }
  }
  j["photons"] = r.photons;
  j["scattering_events"] = r.scattering_events;
  j["seconds"] = r.seconds;
  j["photons_per_second"] = r.photonsPerSecond();
  j["threads"] = r.threads;
  j["seed"] = r.seed;
  j["partial"] = r.partial;
  writeTextOutput("--json", path, j.dump(2) + "\n");
}

void writeCsv(const std::string& path, const SlabResult& r) {
  std::string text = "r,rd,rd_stderr\n";
  for (size_t i = 0; i < r.radial.r.size(); ++i)
    text += fmt::format("{},{},{}\n", r.radial.r[i], r.radial.rd[i], r.radial.rd_stderr[i]);
  writeTextOutput("--csv", path, text);
}

// Legal numbers that lead nowhere (issue 15): with almost no absorption a walk in a thick slab
// goes on for ~1/(1 − α') scattering events before it is absorbed, and in a half-space the walk
// lengths are heavy-tailed (the depth is a 1D random walk: P(N > k) ~ k^{-1/2}), so the longest
// of n photons is ~n² events. A photon is never interrupted mid-walk, so Ctrl-C and --time-limit
// cannot stop such a run either. Without long-path roulette (which ends every walk) a longest walk
// over kMaxWalkEvents is refused with the estimate.
constexpr double kMaxWalkEvents = 1e10;  // ~minutes for one photon at ~1e8 events/s

void checkWalkLength(const SlabSetup& s, const TraceOptions& o,
                     const std::string& what = "--sigma-a") {
  if (o.long_path_roulette != 0 || !(s.sigma_a > 0.0)) return;  // σa = 0: traceSlab says why
  const double sigmaTPrime = s.sigma_a + (1.0 - s.g) * s.sigma_s;
  const double absorbed = s.sigma_a / sigmaTPrime;  // 1 − α': absorption chance per step
  const double n = static_cast<double>(o.photons);
  double longest = std::min(absorbed > 0.0 ? 1.0 / absorbed : HUGE_VAL, n * n);
  // A finite slab: a diffusing walk crosses it after ~(σt' L)² steps and leaves.
  if (s.finite()) longest = std::min(longest, 10.0 * std::pow(sigmaTPrime * s.thickness, 2) + 10.0);
  if (longest > kMaxWalkEvents)
    throw ParameterError(fmt::format(
        "{} is {} with σs' = {}: absorption ends a walk only after ~1/(1 − α') = {:.3g} "
        "scattering events, and the longest of {} walks would take ~{:.3g} events (hours to years, "
        "and no photon is interrupted mid-walk); give --long-path-roulette N (e.g. 1e6) to end "
        "long walks without bias, a larger --sigma-a, or a --thickness",
        what, s.sigma_a, (1.0 - s.g) * s.sigma_s, absorbed > 0.0 ? 1.0 / absorbed : HUGE_VAL,
        o.photons, longest));
}

void runSlab(const PathtraceArgs& a) {
  std::string unit;
  const SlabSetup setup = buildSetup(a, unit);
  const TraceOptions options = buildOptions(a);
  checkWalkLength(setup, options);
  if (a.time_limit && !(*a.time_limit > 0.0))
    throw ParameterError(fmt::format("--time-limit is {}: expected seconds > 0", *a.time_limit));
  // Make sure the outputs can be written, and are two different files, before spending the time;
  // nothing is created until a file is complete (temporary file + rename).
  OutputSet outputs;
  outputs.output("--json", a.json);
  outputs.output("--csv", a.csv);
  outputs.check();
  // A layered slab: the layers from the file; `shown` is then the top layer with the total
  // thickness (what the JSON's surfaces and thickness refer to).
  SlabSetup shown = setup;
  std::optional<reference::LayeredSlabSetup> layered;
  if (!a.layers.empty()) {
    layered = buildLayered(a, shown);
    // Each layer on its own, as a slab of its thickness (the last one semi-infinite): a walk
    // stays at least as long in the stack as in its most transparent thick layer.
    for (size_t i = 0; i < layered->layers.size(); ++i) {
      const reference::SlabLayer& L = layered->layers[i];
      SlabSetup one = shown;
      one.sigma_a = L.sigma_a;
      one.sigma_s = L.sigma_s;
      one.g = L.g;
      one.thickness = L.thickness;
      checkWalkLength(one, options, fmt::format("--layers {}: layer [{}]: sigma_a", a.layers, i));
    }
  }
  if (options.long_path_roulette > 0)
    printStderr(
               "pathtrace: note: long-path roulette keeps estimates unbiased, but each roulette "
               "multiplies the second moment by 10 x (chance to continue); where that exceeds "
               "1 the variance is infinite and the standard errors are not reliable\n");

  SlabResult r;
  {
    InterruptGuard guard;
    ProgressBar progress("pathtrace", "photons", a.time_limit);
    const auto cb = [&](const reference::TraceProgress& p) { return progress(p); };
    r = layered ? reference::traceLayeredSlab(*layered, options, cb)
                : reference::traceSlab(setup, options, cb);
    progress.end();
  }

  writeJson(a.json, shown, options, r, unit, layered ? &*layered : nullptr, a.layers);
  if (!a.csv.empty()) writeCsv(a.csv, r);
  printStderr(
             "pathtrace: {}{} photons in {:.2f} s ({:.3g} photons/s, {} threads): Rsp {:.5f}, "
             "Rd {:.5f} ± {:.5f}, T {:.5f} ± {:.5f}, A {:.5f} ± {:.5f}; wrote {}{}\n",
             r.partial ? "stopped early, partial result: " : "", r.photons, r.seconds,
             r.photonsPerSecond(), r.threads, r.specular_reflectance.value,
             r.diffuse_reflectance.value, r.diffuse_reflectance.std_error, r.transmittance.value,
             r.transmittance.std_error, r.absorbed.value, r.absorbed.std_error, a.json,
             a.csv.empty() ? "" : " and " + a.csv);
}

}  // namespace

void addPathtraceCommand(CLI::App& app) {
  auto* pt = app.add_subcommand(
      "pathtrace", "Reference Monte Carlo transport (volumetric path tracing, seed 3.2)");
  pt->require_subcommand(1);
  auto args = std::make_shared<PathtraceArgs>();
  auto* cmd = pt->add_subcommand(
      "slab", "Pencil beam on a slab (MCML, one layer): reflectance, transmittance, absorption "
              "and the radial profile Rd(r), each with its standard error");
  cmd->add_option("--sigma-a", args->sigma_a, "Absorption coefficient σa [1/length]");
  cmd->add_option("--sigma-s", args->sigma_s, "Scattering coefficient σs [1/length]");
  cmd->add_option("--g", args->g, "Henyey-Greenstein mean cosine in (-1, 1) (default 0, or the "
                                  "preset's)");
  cmd->add_option("--eta", args->eta, "Refractive index of the slab (required with --sigma-a)");
  cmd->add_option("--preset", args->preset,
                  "Measured material (Jensen et al. 2001; see `translucent presets`), in mm");
  cmd->add_option("--channel", args->channel, "Colour channel of the preset: r, g or b");
  cmd->add_option("--eta-above", args->eta_above, "Refractive index above the slab")
      ->capture_default_str();
  cmd->add_option("--eta-below", args->eta_below, "Refractive index below the slab")
      ->capture_default_str();
  cmd->add_option("--layers", args->layers,
                  "Layered slab (MCML multi-layer): JSON array, top first, of {\"thickness\": t "
                  "or null (last only: semi-infinite), \"sigma_a\", \"sigma_s\", \"g\"}, "
                  "every layer at --eta (scalar walker; --kernel does not apply)");
  cmd->add_option("--thickness", args->thickness, "Slab thickness [length]; omit: semi-infinite");
  cmd->add_option("--theta", args->theta, "Polar angle of the incident beam [degrees]")
      ->capture_default_str();
  cmd->add_option("--phi", args->phi, "Azimuth of the incident beam [degrees]")
      ->capture_default_str();
  cmd->add_option("--photons", args->photons, "Photons to trace (e.g. 1e7)")
      ->capture_default_str();
  cmd->add_option("--seed", args->seed, "Random seed (same seed: same result on any thread count)")
      ->capture_default_str();
  cmd->add_option("--threads", args->threads, "Worker threads (0: all cores)")
      ->capture_default_str();
  cmd->add_option("--radial-bins", args->radial_bins, "Annuli of the radial profile Rd(r)");
  cmd->add_option("--radial-max", args->radial_max, "Outer radius of the radial profile [length]");
  cmd->add_option("--angle-bins", args->angle_bins,
                  "Exit-angle bins over [0°, 90°] for Rd(θ) (and Rd(r, θ) with radial bins)");
  cmd->add_option("--long-path-roulette", args->long_path_roulette,
                  "After N scattering events continue with chance 1/10 at weight x10 (0: off)")
      ->capture_default_str();
  cmd->add_option("--absorption", args->absorption,
                  "analog: Russian roulette on the albedo (Algorithm 1; fewest events per "
                  "photon, smallest Rd error per CPU second except in thin slabs); weighted: "
                  "MCML's w *= albedo with roulette below 1e-4")
      ->check(CLI::IsMember({"analog", "weighted"}))
      ->capture_default_str();
  cmd->add_option("--kernel", args->kernel,
                  "lanes: 8 photons per SIMD loop (AVX2 if available); portable: the same "
                  "without AVX2; scalar: one photon at a time")
      ->check(CLI::IsMember({"lanes", "portable", "scalar"}))
      ->capture_default_str();
  cmd->add_option("--time-limit", args->time_limit,
                  "Stop after this many seconds and write the partial result");
  outputOption(cmd->add_option("--json", args->json, "Output JSON file"))->required();
  outputOption(cmd->add_option("--csv", args->csv, "Radial profile as CSV: r,rd,rd_stderr"));
  cmd->callback([args] { runSlab(*args); });
}

}  // namespace translucent::cli
