// SPDX-License-Identifier: GPL-3.0-or-later
// translucent pathtrace slab: reference Monte Carlo transport in a slab lit by a pencil beam
// (seed section 3.2, Algorithm 1; MCML with one layer), written as JSON (and the radial profile
// as CSV). See src/reference/slab.h for what is traced and tallied.
//
// Medium: --sigma-a A --sigma-s S [--g G] --eta N (one channel, coefficients per length unit),
// or --material NAME --channel r|g|b (Jensen et al. 2001, 1/mm, σs = σs'/(1-g) for the given g).
// No --thickness: semi-infinite. Layered slab (MCML's multi-layer mode, reference/layered_slab.h):
// --layers FILE --eta N, the file a JSON array of layers, top first, each {"thickness": t or null,
// "sigma_a", "sigma_s", "g"} in the units of the other options, every layer at --eta. Ctrl-C, SIGTERM (or --time-limit) stop the run; what was traced so far
// is written with "partial": true.
#include <fmt/format.h>
#include <fmt/ranges.h>

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
#include "options.h"
#include "output_guard.h"
#include "shard.h"
#include "progress.h"
#include "translucent/optics/presets.h"
#include "translucent/reference/gpu/device.h"
#include "translucent/reference/layered_slab.h"
#include "translucent/reference/slab.h"
#include "translucent/reference/slab_request.h"

namespace translucent::cli {
namespace {

using reference::SlabResult;

// The request (medium, beam, tallies, run; reference/slab_request.h checks it) and the CLI's own
// options.
struct PathtraceArgs {
  reference::SlabRequest request;
  std::string photons = "1e6";
  std::optional<double> time_limit;
  std::string json, csv;
  std::string layers;  // --layers FILE
  ShardArgs shard;     // --shard I/N --partial FILE (shard.h)
};

uint64_t parsePhotons(const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (end == text.c_str() || *end != '\0' || !(v >= 1.0) || v > 1e18 || std::floor(v) != v)
    throw ParameterError(
        fmt::format("--photons '{}': expected a whole number >= 1 (e.g. 1000000 or 1e6)", text));
  return static_cast<uint64_t>(v);
}

void writeCsv(OutputFiles& out, const std::string& path, const SlabResult& r) {
  // The total, then the scattering orders' parts of it (seed Eq. 2.13; they add up to rd).
  std::string text = "r,rd,rd_stderr";
  for (reference::ScatteringOrder k : reference::kAllScatteringOrders)
    text += fmt::format(",rd_{0},rd_{0}_stderr", reference::toString(k));
  text += "\n";
  for (size_t i = 0; i < r.radial.r.size(); ++i) {
    text += fmt::format("{},{},{}", r.radial.r[i], r.radial.rd[i], r.radial.rd_stderr[i]);
    for (reference::ScatteringOrder k : reference::kAllScatteringOrders)
      text += fmt::format(",{},{}", r.order(k).radial.rd[i], r.order(k).radial.rd_stderr[i]);
    text += "\n";
  }
  out.text("--csv", path, text);
}

void runSlab(const PathtraceArgs& a) {
  reference::SlabRequest request = a.request;
  request.photons = parsePhotons(a.photons);
  request.device = a.shard.device(request.device);
  request.time_limited = a.time_limit.has_value();  // a long estimated run is traced up to it
  if (!a.csv.empty() && request.radial_bins == 0)
    throw ParameterError("--csv writes the radial profile: give --radial-bins and --radial-max");
  const reference::SlabRun run =
      a.layers.empty() ? reference::makeSlabRun(request)
                       : reference::makeSlabRun(request, reference::loadSlabLayers(a.layers), a.layers);
  const reference::TraceOptions& options = run.options;
  if (a.time_limit && !(*a.time_limit > 0.0))
    throw ParameterError(fmt::format("--time-limit is {}: expected seconds > 0", *a.time_limit));
  // Make sure the outputs can be written, and are two different files, before spending the time;
  // nothing is created until a file is complete (temporary file + rename). A shard writes only
  // its partial file (shard.h).
  OutputSet inputs;
  if (!a.layers.empty()) inputs.input("the layers (--layers)", a.layers);
  if (a.shard.active()) {
    refuseOutputsWithShard({{"--json", a.json}, {"--csv", a.csv}});
    checkPartialOutput(a.shard, inputs);
  } else {
    OutputSet outputs = inputs;
    outputs.output("--json", a.json);
    outputs.output("--csv", a.csv);
    outputs.check();
  }
  if (a.shard.active()) (void)a.shard.range(options.totalBlocks());  // --shard I/N well-formed
  if (!beginWork()) return;
  if (options.long_path_roulette > 0)
    printStderr(
               "pathtrace: warning: long-path roulette keeps estimates unbiased, but each roulette "
               "multiplies the second moment by 10 x (chance to continue); where that exceeds "
               "1 the variance is infinite and the standard errors are not reliable: with little "
               "absorption a run is typically LOW by the share of light in walks longer than N "
               "events, and its ± does not show it (sigma_a = 0, eta 1.3: Rd 0.749, 0.904, 0.959 "
               "at N = 100, 1000, 10^4 against the true 0.983; README, 'Long-path roulette')\n");

  SlabResult r;
  if (const MergedRun* merged = mergedRun()) {
    // `translucent merge`: the shards' summed state instead of tracing (bit for bit the result
    // of the unsharded run; the timing is the shards' total).
    checkMergedInputs(inputs);
    r = run.layered ? reference::layeredSlabResult(*run.layered, options, merged->state)
                    : reference::slabResult(run.setup, options, merged->state);
    r.seconds = merged->seconds;
    r.device = mergedDevice(run.device);
    r.threads = merged->threads;
  } else {
    reference::SlabRun shard = run;
    reference::TraceOptions& o = shard.options;
    std::optional<ShardRange> range;
    std::optional<Checkpoint> checkpoint;
    uint64_t resumed = 0;  // blocks of the shard in its checkpoint
    if (a.shard.active()) {
      range = a.shard.range(options.totalBlocks());
      // A re-run of a shard that stopped early resumes from its partial file: the blocks after
      // those done.
      checkpoint = readCheckpoint(a.shard, *range, inputs);
      if (checkpoint) resumed = checkpoint->blocks_done;
      // An empty shard (more shards than blocks) starts at the end: it traces nothing.
      o.first_block = range->blocks == resumed ? range->total : range->first + resumed;
      o.blocks = range->blocks - resumed;
    }
    const reference::TraceDevice dev = reference::openTraceDevice(run.device);
    reference::RunState state;
    InterruptGuard guard;
    ProgressBar progress("pathtrace", "photons", a.time_limit);
    const auto cb = [&](const reference::TraceProgress& p) { return progress(p); };
    r = reference::traceSlabRun(dev, shard, cb, &state);
    progress.end();
    if (range) {
      // The blocks traced now: on the CPU a prefix of those asked for (a stop keeps whole blocks
      // in order); the GPU's stop is not block-wise, so its stopped shard starts over.
      const uint64_t done =
          !r.partial ? range->blocks
          : run.device == "cpu"
              ? resumed + std::min<uint64_t>(o.blocks, r.photons / reference::kBlockPhotons)
              : 0;
      if (checkpoint) state.merge(checkpoint->state);
      writePartial(a.shard, *range, inputs, state, r.seconds + (checkpoint ? checkpoint->seconds : 0.0),
                   r.threads, !r.partial, done);
      return;
    }
  }

  nlohmann::json j = reference::slabResultJson(run, r);
  if (run.layered) j["layers_file"] = a.layers;
  OutputFiles out;  // all or nothing
  if (!a.json.empty()) out.text("--json", a.json, j.dump(2) + "\n");
  if (!a.csv.empty()) writeCsv(out, a.csv, r);
  out.commit();
  std::vector<std::string> wrote;
  for (const std::string& file : {a.json, a.csv})
    if (!file.empty()) wrote.push_back(isStdoutPath(file) ? "stdout" : file);
  // The summary is the result when no file is written: then it goes to stdout.
  const std::string summary = fmt::format(
             "pathtrace: {}{} photons in {:.2f} s ({:.3g} photons/s, {}): Rsp {:.5f}, "
             "Rd {:.5f} ± {:.5f} (single scattering {:.5f}, multiple {:.5f}), T {:.5f} ± {:.5f}, "
             "A {:.5f} ± {:.5f}{}\n",
             stoppedEarly(r.partial), r.photons, r.seconds,
             r.photonsPerSecond(),
             tracedBy(r.device, r.threads), r.specular_reflectance.value,
             r.diffuse_reflectance.value, r.diffuse_reflectance.std_error,
             r.order(reference::ScatteringOrder::Single).diffuse_reflectance.value,
             r.order(reference::ScatteringOrder::Multiple).diffuse_reflectance.value, r.transmittance.value,
             r.transmittance.std_error, r.absorbed.value, r.absorbed.std_error,
             wrote.empty() ? "" : fmt::format("; wrote {}", fmt::join(wrote, " and ")));
  if (wrote.empty())
    fmt::print("{}", summary);
  else
    printStderr("{}", summary);
}

}  // namespace

void addPathtraceCommand(CLI::App& app) {
  auto* pt = app.add_subcommand(
      "pathtrace", "Reference Monte Carlo transport (volumetric path tracing, Bitterli 2013, §3.2)");
  pt->require_subcommand(1);
  auto args = std::make_shared<PathtraceArgs>();
  auto* cmd = pt->add_subcommand(
      "slab", "Pencil beam on a slab (MCML, one layer): reflectance, transmittance, absorption "
              "and the radial profile Rd(r), each with its standard error");
  cmd->add_option("--sigma-a", args->request.sigma_a, "Absorption coefficient σa [1/length]");
  cmd->add_option("--sigma-s", args->request.sigma_s, "Scattering coefficient σs [1/length]");
  cmd->add_option("--g", args->request.g, "Henyey-Greenstein mean cosine in (-1, 1) (default 0, or the "
                                  "preset's)");
  cmd->add_option("--eta", args->request.eta, "Refractive index of the slab (required with --sigma-a)");
  auto* material = cmd->add_option(
      "--material", args->request.preset,
      "Measured material (Jensen et al. 2001; see `translucent presets`), in mm");
  cmd->add_option_function<std::string>(
         "--preset",
         [args](const std::string& v) {
           warnDeprecated("pathtrace slab", "--preset", "use --material " + v);
           args->request.preset = v;
         },
         "Deprecated: --material")
      ->excludes(material);
  cmd->add_option("--channel", args->request.channel, "Colour channel of the preset: r, g or b");
  cmd->add_option("--eta-above", args->request.eta_above, "Refractive index above the slab")
      ->capture_default_str();
  cmd->add_option("--eta-below", args->request.eta_below, "Refractive index below the slab")
      ->capture_default_str();
  cmd->add_option("--layers", args->layers,
                  "Layered slab (MCML multi-layer): JSON array, top first, of {\"thickness\": t "
                  "or null (last only: semi-infinite), \"sigma_a\", \"sigma_s\", \"g\"}, "
                  "every layer at --eta (scalar walker; --kernel does not apply)");
  cmd->add_option("--thickness", args->request.thickness, "Slab thickness [length]; omit: semi-infinite");
  cmd->add_option("--theta", args->request.theta, "Polar angle of the incident beam [degrees]")
      ->capture_default_str();
  cmd->add_option("--phi", args->request.phi, "Azimuth of the incident beam [degrees]")
      ->capture_default_str();
  cmd->add_option("--photons", args->photons, "Photons to trace (e.g. 1e7)")
      ->capture_default_str();
  cmd->add_option("--seed", args->request.seed, "Random seed (same seed: same result on any thread count)")
      ->capture_default_str();
  cmd->add_option("--threads", args->request.threads, "Worker threads (0: all cores)")
      ->capture_default_str();
  cmd->add_option("--radial-bins", args->request.radial_bins, "Annuli of the radial profile Rd(r)");
  cmd->add_option("--radial-max", args->request.radial_max, "Outer radius of the radial profile [length]");
  cmd->add_option("--angle-bins", args->request.angle_bins,
                  "Exit-angle bins over [0°, 90°] for Rd(θ) (and Rd(r, θ) with radial bins)");
  cmd->add_option("--long-path-roulette", args->request.long_path_roulette,
                  "After N scattering events continue with chance 1/10 at weight x10 (0: off)")
      ->capture_default_str();
  cmd->add_option("--absorption", args->request.absorption,
                  "analog: Russian roulette on the albedo (Algorithm 1; fewest events per "
                  "photon, smallest Rd error per CPU second except in thin slabs); weighted: "
                  "MCML's w *= albedo with roulette below 1e-4; auto: weighted where the slab's "
                  "reduced optical thickness σt'·d is at most 2, else analog (the faster to a "
                  "given Rd error, as measured)")
      ->check(CLI::IsMember({"auto", "analog", "weighted"}))
      ->capture_default_str();
  cmd->add_option("--kernel", args->request.kernel,
                  "lanes: 8 photons per SIMD loop (AVX2 if available); portable: the same "
                  "without AVX2; scalar: one photon at a time")
      ->check(CLI::IsMember({"lanes", "portable", "scalar"}))
      ->capture_default_str();
  cmd->add_option("--device", args->request.device,
                  "cpu: the CPU tracer; gpu: the GL compute-shader tracer (any GL 4.5 context, "
                  "Philox streams: agrees with the CPU within the standard errors, not bit for "
                  "bit); auto: the GPU on a hardware GPU, else the CPU (with --shard: the CPU)")
      ->check(CLI::IsMember({"cpu", "gpu", "auto"}))
      ->capture_default_str();
  cmd->add_option("--time-limit", args->time_limit,
                  "Stop after this many seconds and write the partial result");
  outputOption(cmd->add_option("--json", args->json, "Output JSON file ('-': stdout); without --json and --csv the summary is printed to stdout"));
  outputOption(cmd->add_option("--csv", args->csv, "Radial profile as CSV: r,rd,rd_stderr, then rd and its stderr of the light scattered 0, 1 and more times (rd_unscattered, rd_single, rd_multiple)"));
  args->shard.add(*cmd);
  cmd->callback([args] { runSlab(*args); });
}

}  // namespace translucent::cli
