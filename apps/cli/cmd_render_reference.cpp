// SPDX-License-Identifier: GPL-3.0-or-later
// Reference images of scenes, written as HDR (OpenEXR) and optionally tone-mapped PNG:
//
//   translucent pathtrace sphere   the lit sphere, volumetric path tracing (seed 3.2, 3.6.2;
//                                  src/reference/sphere.h)
//   translucent pathtrace mesh     a closed triangle mesh from a JSON scene file
//                                  (src/reference/mesh_tracer.h, mesh_scene.h)
//   translucent integrate sphere   a BSSRDF model integrated over the lit sphere (seed 3.5;
//                                  src/reference/sphere_integration.h)
//   translucent integrate mesh     a BSSRDF model integrated over a mesh scene for every visible
//                                  pixel: compare's "model" reference (src/reference/
//                                  model_reference.h)
//
// The EXR holds the chosen quantity in R, G, B and its per-pixel standard error in the layer
// "stderr" (stderr.R, ...), every quantity computed as layers "<name>" and "<name>_stderr"
// (exitance, radiance, cone_radiance), `integrate mesh` also the layer "coverage" (fraction of
// the pixel's camera rays that hit the mesh, in R = G = B), and metadata saying what the pixels are. Passes accumulate into the
// same images (which are rewritten after every pass); Ctrl-C or --time-limit stops the current
// pass and writes what was computed so far, marked partial.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>

#include "safe_print.h"
#include "translucent/compare/compare.h"  // referenceKey: `compare --reference-from` takes these runs
#include "translucent/io/image_io.h"
#include "translucent/bssrdf/registry.h"
#include "bssrdf_models.h"
#include "translucent/gpu/bssrdf_profiles.h"
#include "commands.h"
#include "output_guard.h"
#include "shard.h"
#include "translucent/geometry/mesh.h"
#include "options.h"
#include "progress.h"
#include "translucent/scene/mesh_scene.h"
#include "translucent/reference/camera_paths.h"
#include "translucent/reference/mesh_tracer.h"
#include "translucent/reference/model_reference.h"
#include "translucent/reference/gpu/device.h"
#include "translucent/reference/gpu/sphere_integration_gpu.h"
#include "translucent/reference/sphere.h"
#include "translucent/reference/sphere_integration.h"

namespace translucent::cli {
namespace {

using reference::McImage;

glm::dvec3 parseVec3(const std::string& text, const char* option) {
  const auto parts = splitList(text);
  if (parts.size() != 3)
    throw ParameterError(fmt::format("{} '{}': expected three comma-separated numbers x,y,z",
                                     option, text));
  double v[3];
  for (size_t i = 0; i < 3; ++i) {
    char* end = nullptr;
    v[i] = std::strtod(parts[i].c_str(), &end);
    if (end == parts[i].c_str() || *end != '\0' || !std::isfinite(v[i]))
      throw ParameterError(fmt::format("{} '{}': '{}' is not a finite number", option, text, parts[i]));
  }
  const glm::dvec3 d(v[0], v[1], v[2]);
  if (!(glm::length(d) > 0.0))
    throw ParameterError(fmt::format("{} '{}': expected a non-zero vector", option, text));
  return d;
}

// Options shared by every subcommand here: the run and the outputs.
struct RunArgs {
  std::string count = "1e6";  // photons (or samples) per pass
  int passes = 1;
  uint64_t seed = 1;
  int threads = 0;
  std::optional<double> time_limit;
  std::string quantity = "exitance";
  std::string exr, png, json;
  double exposure = 0.0, gamma = 2.2;
  ShardArgs shard;  // the path tracers' --shard I/N --partial FILE (shard.h)
  bool split_orders = false;  // the path tracers' --split-orders
  // `pathtrace mesh --method light|camera` and the camera method's --samples (camera_paths.h).
  std::string method = "light";
  std::string samples = "16";
  std::string complement_photons = "4";  // the camera method's, at eta != 1

  // The path tracers' flag: images by scattering order as further EXR layers.
  void addSplitOrders(CLI::App& cmd) {
    cmd.add_flag("--split-orders", split_orders,
                 "Also write every quantity split by scattering order (Bitterli 2013, Eq. 2.13): layers "
                 "<quantity>_unscattered, _single and _multiple (each with _stderr), which add "
                 "up to <quantity>");
  }
  reference::TracerOptions tracerOptions() const {
    reference::TracerOptions o;
    o.seed = seed;
    o.threads = threads;
    o.split_orders = split_orders;
    return o;
  }

  void add(CLI::App& cmd, const char* countOption, const char* countHelp,
           const std::vector<std::string>& quantities) {
    cmd.add_option(countOption, count, countHelp)->capture_default_str();
    cmd.add_option("--passes", passes, "Passes, accumulated into the same images (rewritten "
                                       "after each)")->capture_default_str();
    cmd.add_option("--seed", seed, "Random seed (same seed: same images on any thread count)")
        ->capture_default_str();
    cmd.add_option("--threads", threads, "Worker threads (0: all cores)")->capture_default_str();
    cmd.add_option("--time-limit", time_limit, "Stop after this many seconds and write the partial "
                                               "images");
    cmd.add_option("--quantity", quantity,
                   "What the EXR/PNG pixels hold: exitance (radiant exitance B), radiance "
                   "(Ft(η,ω_o) B/π, the diffusion models' radiance)" +
                       std::string(quantities.size() > 2
                                       ? ", cone-radiance (true radiance towards the camera, "
                                         "averaged over a cone of --cone-angle)"
                                       : ""))
        ->check(CLI::IsMember(quantities))
        ->capture_default_str();
    outputOption(cmd.add_option("--exr", exr, "Output OpenEXR file (linear; layer 'stderr': "
                                             "standard error); required but with --shard"));
    outputOption(cmd.add_option("--png", png, "Also write a tone-mapped PNG"));
    cmd.add_option("--exposure", exposure, "PNG exposure [stops]: values x 2^exposure")
        ->capture_default_str();
    cmd.add_option("--gamma", gamma, "PNG display gamma")->capture_default_str();
    outputOption(cmd.add_option("--json", json, "Also write a JSON summary (settings, timing, energy)"));
  }

  void validate(const OutputSet& inputs = {}) const {
    if (passes < 1) throw ParameterError(fmt::format("--passes is {}: expected >= 1", passes));
    if (threads < 0) throw ParameterError(fmt::format("--threads is {}: expected >= 0", threads));
    if (time_limit && !(*time_limit > 0.0))
      throw ParameterError(fmt::format("--time-limit is {}: expected seconds > 0", *time_limit));
    if (!std::isfinite(exposure)) throw ParameterError("--exposure: expected a finite number");
    if (!(std::isfinite(gamma) && gamma > 0.0))
      throw ParameterError(fmt::format("--gamma is {}: expected a value > 0", gamma));
    // Fail before spending the time if an output cannot be written or would replace an input
    // (`inputs`: the scene and its files, a .bssrdf model) or another output. Nothing is created
    // here: the files appear, complete, when they are written (temporary file + rename). A shard
    // writes its partial file only.
    if (shard.active()) {
      refuseOutputsWithShard({{"--exr", exr}, {"--png", png}, {"--json", json}});
      checkPartialOutput(shard, inputs);
      return;
    }
    if (exr.empty()) throw ParameterError("--exr: required (the output OpenEXR file)");
    OutputSet outputs = inputs;
    outputs.output("--exr", exr);
    outputs.output("--png", png);
    outputs.output("--json", json);
    outputs.check();
  }
};

const char* describe(const std::string& quantity) {
  if (quantity == "exitance") return "radiant exitance B [W/unit^2] (pixel average)";
  if (quantity == "radiance")
    return "diffusion radiance Ft(eta, w_o) B / pi [W/(unit^2 sr)] (pixel average)";
  return "true radiance towards the camera, cone-averaged [W/(unit^2 sr)] (pixel average)";
}

// A quantity of a run: RGB values and their standard errors, interleaved, rows from the top.
struct Quantity {
  std::string name;
  std::vector<float> value, stderr_;
};

// The chosen quantity in R, G, B, its standard error in the layer "stderr", every quantity the
// run computed as layers "<name>" and "<name>_stderr" (so one file holds B and both radiances),
// and any further RGB layers (`extra`, e.g. coverage).
void writeImage(OutputFiles& out, const RunArgs& a, int width, int height, const Quantity& chosen,
                const std::vector<Quantity>& all, const std::string& what, bool partial,
                const std::string& samples,
                const std::vector<std::pair<std::string, std::vector<float>>>& extra = {}) {
  const std::vector<float>& rgb = chosen.value;
  std::vector<analysis::ExrLayer> layers;
  layers.push_back({"stderr", chosen.stderr_});
  for (const Quantity& q : all) {
    layers.push_back({q.name, q.value});
    layers.push_back({q.name + "_stderr", q.stderr_});
  }
  for (const auto& [name, data] : extra) layers.push_back({name, data});
  const std::pair<std::string, std::string> attrs[] = {
      {"translucent:quantity", describe(a.quantity)},
      {"translucent:layers", "stderr: standard error of R,G,B; <quantity> and <quantity>_stderr "
                             "for every quantity computed"},
      {"translucent:source", what},
      {"translucent:samples", samples},
      {"translucent:seed", std::to_string(a.seed)},
      {"translucent:partial", partial ? "true" : "false"}};
  out.file("--exr", a.exr, [&](const std::string& p) {
    analysis::writeExr(p, width, height, rgb, layers, attrs);
  });
  if (!a.png.empty())
    out.file("--png", a.png, [&](const std::string& p) {
      analysis::writePng(p, width, height, rgb, {a.exposure, a.gamma});
    });
}

void writeImage(OutputFiles& out, const RunArgs& a, const McImage& img,
                const std::vector<std::pair<std::string, const McImage*>>& all,
                const std::string& what, bool partial, const std::string& samples) {
  std::vector<Quantity> quantities;
  for (const auto& [name, image] : all)
    quantities.push_back({name, image->rgb(), image->rgbStdError()});
  writeImage(out, a, img.width(), img.height(), {"", img.rgb(), img.rgbStdError()}, quantities, what,
             partial, samples);
}

std::vector<std::pair<std::string, const McImage*>> layersOf(const reference::CameraImages& i) {
  return {{"exitance", &i.exitance}, {"radiance", &i.radiance}, {"cone_radiance", &i.cone_radiance}};
}

// A path tracer's images, and with --split-orders those of each scattering order
// ("exitance_single", ...).
template <class Tracer>
std::vector<std::pair<std::string, const McImage*>> layersOf(const Tracer& tracer) {
  auto all = layersOf(tracer.images());
  if (tracer.splitsOrders())
    for (reference::ScatteringOrder o : reference::kAllScatteringOrders)
      for (const auto& [name, image] : layersOf(tracer.orderImages(o)))
        all.emplace_back(name + "_" + reference::toString(o), image);
  return all;
}

void writeJson(OutputFiles& out, const RunArgs& a, nlohmann::json j) {
  if (a.json.empty()) return;
  j["quantity"] = describe(a.quantity);
  j["exr"] = a.exr;
  if (!a.png.empty()) j["png"] = a.png;
  j["seed"] = a.seed;
  out.text("--json", a.json, j.dump(2) + "\n");
}


// Runs the passes of a progressive tracer: pass(k, progress) -> partial?; after each pass
// `write(partial)`.
template <class Pass, class Write>
void runPasses(const RunArgs& a, const std::string& label, const std::string& unit, Pass&& pass,
               Write&& write) {
  InterruptGuard guard;
  ProgressBar bar(label, unit, a.time_limit);
  const auto start = std::chrono::steady_clock::now();
  auto elapsed = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  bool partial = false;
  uint64_t per_pass = 0;  // photons or samples of one pass, from the tracer's progress
  for (int k = 0; k < a.passes && !partial; ++k) {
    partial = pass([&](const reference::TraceProgress& p) {
      per_pass = p.photons_total;
      const uint64_t total = p.photons_total * static_cast<uint64_t>(a.passes);
      return bar.update(static_cast<uint64_t>(k) * p.photons_total + p.photons_done, total, elapsed());
    });
    if (!partial && k + 1 < a.passes) {
      // Between passes too: passes shorter than the bar's tick would never see its projection
      // (10^9 passes of 2000 photons ran on with an ETA of 13,000 hours).
      const uint64_t passes = static_cast<uint64_t>(a.passes);
      partial = InterruptGuard::interrupted() || (a.time_limit && elapsed() >= *a.time_limit) ||
                !bar.update(static_cast<uint64_t>(k + 1) * per_pass, per_pass * passes, elapsed());
      write(partial);  // progressive refresh; the final write follows the loop
    }
  }
  bar.end();
  write(partial);
}

// ---------------------------------------------------------------------------------------------
// The lit sphere (shared by pathtrace sphere and integrate sphere).

struct SphereArgs {
  MediumOptions medium;
  double radius = 1.0;
  std::string light_dir = "1,1,1", view_dir = "0,0,1";
  int width = 256, height = 256;
  double cone_angle = 5.0;

  void add(CLI::App& cmd, bool cone) {
    medium.add(cmd, "Marble");
    cmd.add_option("--radius", radius, "Sphere radius [scene units; --scale mm each]")
        ->capture_default_str();
    cmd.add_option("--light-dir", light_dir, "Direction towards the directional light x,y,z "
                                             "(irradiance 1)")->capture_default_str();
    cmd.add_option("--view-dir", view_dir, "Direction towards the orthographic camera x,y,z")
        ->capture_default_str();
    cmd.add_option("--width", width, "Image width [pixels]")->capture_default_str();
    cmd.add_option("--height", height, "Image height [pixels]")->capture_default_str();
    if (cone)
      cmd.add_option("--cone-angle", cone_angle,
                     "Half-angle of the cone for the true radiance [degrees]")
          ->capture_default_str();
  }

  reference::SphereScene scene() const {
    reference::SphereScene s;
    s.radius = radius;
    s.light_direction = parseVec3(light_dir, "--light-dir");
    s.view_direction = parseVec3(view_dir, "--view-dir");
    s.width = width;
    s.height = height;
    s.cone_half_angle = cone_angle;
    s.validate();
    return s;
  }
};

nlohmann::json sceneJson(const SphereArgs& s, const Medium& m) {
  return {{"radius", s.radius}, {"light_dir", s.light_dir}, {"view_dir", s.view_dir},
          {"width", s.width}, {"height", s.height},
          {"medium", {{"sigma_a", m.sigma_a}, {"sigma_s", m.sigma_s}, {"g", m.g}, {"eta", m.eta},
                      {"scale", m.scale}}}};
}

const McImage& pick(const reference::CameraImages& images, const std::string& quantity) {
  if (quantity == "radiance") return images.radiance;
  if (quantity == "cone-radiance") return images.cone_radiance;
  return images.exitance;
}

// Per channel, the median of se / value over the pixels (interleaved RGB) with value > 0 that
// `use(p)` accepts: the noise level of an image.
template <class Use>
std::vector<double> medianRelativeError(const std::vector<float>& value,
                                        const std::vector<float>& se, Use&& use) {
  std::vector<double> out;
  for (size_t c = 0; c < 3; ++c) {
    std::vector<double> rel;
    for (size_t p = 0; 3 * p + c < value.size(); ++p)
      if (use(p) && value[3 * p + c] > 0.0f)
        rel.push_back(double(se[3 * p + c]) / double(value[3 * p + c]));
    if (rel.empty()) {
      out.push_back(0.0);
      continue;
    }
    std::nth_element(rel.begin(), rel.begin() + long(rel.size() / 2), rel.end());
    out.push_back(rel[rel.size() / 2]);
  }
  return out;
}

// The median relative standard error of a tracer's exitance over the pixels it reached.
std::vector<double> medianRelativeError(const McImage& exitance) {
  return medianRelativeError(exitance.rgb(), exitance.rgbStdError(), [](size_t) { return true; });
}

// Per channel, the median over fully covered pixels of exitance_se / exitance: the noise level.
std::vector<double> medianRelativeError(const reference::ModelReferenceImages& img) {
  return medianRelativeError(img.exitance, img.exitance_se,
                             [&](size_t p) { return img.coverage[p] == 1.0f; });
}

// A shard of a progressive tracer's run (shard.h): its blocks of the run's passes × blocks per
// pass, traced in one go, written to the partial file. A re-run of a shard that stopped early
// resumes from its partial file: on the CPU the tracer merges blocks in order, so a stop leaves
// the first blocks of the shard whole (block_driver.h), and tracing the rest and adding the two
// states gives the uninterrupted shard bit for bit (exact sums). The GPU walk's stop is not
// block-wise: a shard stopped there keeps only what an earlier checkpoint held.
template <class Tracer>
void runShard(const RunArgs& a, Tracer& tracer, uint64_t photons, const std::string& label,
              const OutputSet& inputs) {
  const uint64_t perPass = (photons + reference::kBlockPhotons - 1) / reference::kBlockPhotons;
  const ShardRange range = a.shard.range(perPass * static_cast<uint64_t>(a.passes));
  const std::optional<Checkpoint> checkpoint = readCheckpoint(a.shard, range, inputs);
  const uint64_t resumed = checkpoint ? checkpoint->blocks_done : 0;
  const uint64_t left = range.blocks - resumed;
  reference::TransportStats st;
  {
    InterruptGuard guard;
    ProgressBar bar(label, "photons", a.time_limit);
    // An empty remainder (more shards than blocks, or a checkpoint that holds them all) starts
    // at the end: it traces nothing.
    st = tracer.addBlocks(left == 0 ? range.total : range.first + resumed, left,
                          [&](const reference::TraceProgress& p) { return bar(p); });
    bar.end();
  }
  reference::RunState state;
  const bool cpu = tracer.device() == "cpu";
  uint64_t done = range.blocks;
  if (st.partial) {
    const uint64_t merged = st.photons.empty() ? 0 : st.photons[0] / reference::kBlockPhotons;
    done = cpu ? resumed + std::min(left, merged) : resumed;
  }
  if (!st.partial || cpu) tracer.write(state);
  if (checkpoint) {
    if (state.sums.empty() && state.counts.empty())
      state = checkpoint->state;
    else
      state.merge(checkpoint->state);
  }
  writePartial(a.shard, range, inputs, state, st.seconds + (checkpoint ? checkpoint->seconds : 0.0),
               st.threads, !st.partial, done);
}

void runPathtraceSphere(const SphereArgs& s, const RunArgs& a, std::string device) {
  a.validate();
  const Medium medium = s.medium.medium();
  const reference::SphereScene scene = s.scene();
  const uint64_t photons = parseCount(a.count, "--photons");
  device = a.shard.device(device);
  if (!beginWork()) return;
  const MergedRun* merged = mergedRun();
  // Declared before the tracer: the context outlives the walker the tracer holds.
  const reference::TraceDevice dev =
      merged ? reference::TraceDevice{} : reference::openTraceDevice(device);
  reference::SpherePathTracer tracer(scene, medium, a.tracerOptions());
  reference::useDevice(dev, tracer);
  const std::string traced = merged ? mergedDevice(device) : tracer.device();
  if (a.shard.active()) return runShard(a, tracer, photons, "pathtrace sphere", {});
  auto pass = [&](const reference::ProgressCallback& cb) { return tracer.addPass(photons, cb).partial; };
  auto write = [&](bool partial) {
    OutputFiles out;  // the images and the JSON of this pass, all or nothing
    const auto& st = tracer.stats();
    writeImage(out, a, pick(tracer.images(), a.quantity), layersOf(tracer),
               "translucent pathtrace sphere", partial,
               fmt::format("{} photons per channel", st.photons.empty() ? 0 : st.photons[0]));
    nlohmann::json j = {{"command", "pathtrace sphere"}, {"scene", sceneJson(s, medium)},
                        {"photons_per_channel", st.photons.empty() ? 0 : st.photons[0]},
                        {"passes", merged ? a.passes : tracer.passes()}, {"seconds", st.seconds},
                        {"photons_per_second", st.photonsPerSecond()}, {"threads", st.threads},
                        {"device", traced},
                        {"cone_angle", s.cone_angle}, {"split_orders", tracer.splitsOrders()},
                        {"flux_per_channel", reference::fluxPerChannelJson(st)},
                        {"partial", partial}};
    writeJson(out, a, j);
    out.commit();
  };
  if (merged) {
    checkMergedInputs({});
    tracer.read(merged->state, merged->seconds, merged->threads);
    write(false);
  } else {
    runPasses(a, "pathtrace sphere", "photons", pass, write);
  }
  const auto& st = tracer.stats();
  printStderr("pathtrace sphere: {}{} photons per channel in {:.2f} s ({:.3g} photons/s, "
                     "{}); wrote {}{}\n",
             stoppedEarly(st.partial),
             st.photons.empty() ? 0 : st.photons[0], st.seconds, st.photonsPerSecond(),
             tracedBy(traced, st.threads), a.exr,
             a.png.empty() ? "" : " and " + a.png);
}

void runIntegrateSphere(const SphereArgs& s, const RunArgs& a, const std::string& model,
                        const std::string& sampling, double defensive) {
  OutputSet inputs;
  inputs.input("the BSSRDF model (--model)", model);  // skipped unless a file
  a.validate(inputs);
  const Medium medium = s.medium.medium();
  const reference::SphereScene scene = s.scene();
  const uint64_t samples = parseCount(a.count, "--samples");
  reference::IntegrationOptions o;
  o.sampling = sampling == "uniform" ? reference::SurfaceSampling::Uniform
                                     : reference::SurfaceSampling::Importance;
  o.defensive = defensive;
  o.seed = a.seed;
  o.threads = a.threads;
  if (!isBssrdfFile(model)) (void)bssrdf::model(model);  // an unknown name, before any work
  if (!beginWork()) return;
  // A radial .bssrdf plug-in is integrated through its GPU values tabulated for this medium
  // (gpu::bssrdfTabulatedModel): the integrator samples and evaluates R(r) on the CPU. A
  // directional one (line 1 without `radial`) is integrated on the GPU with the light's and the
  // camera's directions (GpuSphereIntegrator: uniform sampling).
  std::unique_ptr<bssrdf::TabulatedModel> plugin;
  std::unique_ptr<gpu::Context> gl;
  std::unique_ptr<gpu::BssrdfEvaluator> evaluator;
  std::string used = sampling;
  if (isBssrdfFile(model)) {
    gl = bssrdfContext("--model " + model);
    evaluator = loadBssrdfModel(model, {});
    if (evaluator->file().attributes.radial) {
      plugin = gpu::bssrdfTabulatedModel(*evaluator, medium, model);
    } else {
      if (sampling != "uniform")
        printStderr("integrate sphere: --model {} is directional: integrated on the GPU with "
                    "uniform sampling (the importance sampler needs a radial profile)\n",
                    model);
      used = "uniform";
    }
  }
  auto run = [&](auto& integrator, const std::string& where) {
    auto pass = [&](const reference::ProgressCallback& cb) {
      return integrator.addPass(samples, cb).partial;
    };
    auto write = [&](bool partial) {
      OutputFiles out;  // the images and the JSON of this pass, all or nothing
      const auto& st = integrator.stats();
      const McImage& img =
          a.quantity == "radiance" ? integrator.images().radiance : integrator.images().exitance;
      writeImage(out, a, img,
                 {{"exitance", &integrator.images().exitance},
                  {"radiance", &integrator.images().radiance}},
                 fmt::format("translucent integrate sphere --model {} --sampling {}", model, used),
                 partial, fmt::format("{} samples per pixel", st.samples));
      nlohmann::json j = {{"command", "integrate sphere"}, {"model", model},
                          {"sampling", used}, {"defensive", used == "uniform" ? 1.0 : defensive},
                          {"device", where},
                          {"scene", sceneJson(s, medium)}, {"samples_per_pixel", st.samples},
                          {"seconds", st.seconds}, {"threads", st.threads}, {"partial", partial}};
      writeJson(out, a, j);
      out.commit();
    };
    runPasses(a, "integrate sphere", "samples", pass, write);
    const auto& st = integrator.stats();
    printStderr("integrate sphere: {}{} ({} sampling), {} samples per pixel in {:.2f} s "
                "({}); wrote {}{}\n",
                stoppedEarly(st.partial), model, used, st.samples,
                st.seconds, where == "cpu" ? fmt::format("{} threads", st.threads) : where, a.exr,
                a.png.empty() ? "" : " and " + a.png);
  };
  if (evaluator && !plugin) {
    reference::GpuSphereIntegrator integrator(*evaluator, scene, medium, a.seed);
    run(integrator, "gpu (" + gl->info().renderer + ")");
    return;
  }
  reference::SphereIntegrator integrator(plugin ? *plugin : bssrdf::model(model), scene, medium, o);
  run(integrator, "cpu");
}

// `pathtrace mesh --method camera` (reference/camera_paths.h): paths from the camera with
// next-event estimation, every pixel its own samples. The images and JSON as the light method's,
// but for the statistics (per pixel: "samples_per_pixel") and the cone: its cone_radiance layer
// is the true radiance towards the camera (cone half-angle 0).
void runPathtraceMeshCamera(const reference::MeshScene& scene, const std::string& sceneFile,
                            const RunArgs& a, const std::string& device) {
  if (a.shard.active())
    throw ParameterError("--shard: not available with --method camera (more samples per pixel "
                         "come from --samples and --passes)");
  if (a.count != RunArgs{}.count)
    throw ParameterError("--photons: the camera method traces camera paths per pixel (--samples), "
                         "not photons");
  const uint64_t samples = parseCount(a.samples, "--samples");
  if (!beginWork()) return;
  if (mergedRun())
    throw ParameterError("merge: the camera method has no shards to merge");
  const geometry::TriangleMesh mesh = scene::loadSceneMesh(scene);  // normalised and placed
  scene::requireOutsideMesh(scene, mesh);
  reference::CameraPathOptions o;
  o.seed = a.seed;
  o.threads = a.threads;
  o.split_orders = a.split_orders;
  o.exitance = a.quantity != "cone-radiance";  // the cosine-distributed paths only when asked for
  o.complement_photons = a.complement_photons == "0" ? 0 : parseCount(a.complement_photons, "--complement-photons");
  // Declared before the tracer: the context outlives the walker the tracer holds.
  const reference::TraceDevice dev = reference::openTraceDevice(device);
  reference::CameraPathTracer tracer(mesh, scene::sceneMaterial(scene, mesh),
                                     scene::referenceLights(scene), scene.camera, o);
  reference::useDevice(dev, device, tracer, mesh, sceneFile);
  auto pass = [&](const reference::ProgressCallback& cb) {
    return tracer.addPass(samples, cb).partial;
  };
  auto write = [&](bool partial) {
    OutputFiles out;  // the images and the JSON of this pass, all or nothing
    std::vector<std::pair<std::string, const McImage*>> all;
    auto add = [&](const reference::CameraImages& im, const std::string& suffix) {
      all.emplace_back("cone_radiance" + suffix, &im.cone_radiance);
      if (!o.exitance) return;
      all.emplace_back("exitance" + suffix, &im.exitance);
      all.emplace_back("radiance" + suffix, &im.radiance);
    };
    add(tracer.images(), "");
    if (tracer.splitsOrders())
      for (reference::ScatteringOrder k : reference::kAllScatteringOrders)
        add(tracer.orderImages(k), std::string("_") + reference::toString(k));
    const auto& st = tracer.stats();
    const McImage& chosen = pick(tracer.images(), a.quantity);
    writeImage(out, a, chosen, all,
               fmt::format("translucent pathtrace mesh --method camera --scene {} (cone "
                           "half-angle 0: the true radiance{})", sceneFile,
                           tracer.complementCone() > 0.0
                               ? fmt::format("; the light that meets the surface again before it "
                                             "first scatters by light-traced photons, its cone "
                                             "average over {} degrees", tracer.complementCone())
                               : std::string()),
               partial, fmt::format("{} camera paths per pixel and channel", st.samples));
    nlohmann::json j = {{"command", "pathtrace mesh"}, {"method", "camera"},
                        {"scene_file", sceneFile},
                        {"scene", nlohmann::json::parse(reference::toJson(scene))},
                        {"triangles", tracer.body().triangleCount()},
                        {"samples_per_pixel", st.samples}, {"paths", st.paths},
                        {"seconds", st.seconds}, {"scattering_events", st.scattering_events},
                        {"shadow_rays", st.shadow_rays}, {"cone_angle", 0.0},
                        {"complement_photons", st.complement_photons},
                        {"complement_cone_angle", tracer.complementCone()},
                        {"median_relative_stderr", medianRelativeError(chosen)},
                        {"majorant_violations", tracer.majorantViolations()},
                        {"split_orders", tracer.splitsOrders()}, {"threads", st.threads},
                        {"device", tracer.device()}, {"partial", partial}};
    writeJson(out, a, j);
    out.commit();
  };
  runPasses(a, "pathtrace mesh", "samples", pass, write);
  const auto& st = tracer.stats();
  printStderr("pathtrace mesh: {}{} camera paths per pixel and channel in {:.2f} s ({}, "
              "{} triangles, camera method); wrote {}{}\n",
              st.partial ? "stopped early, partial result: " : "", st.samples, st.seconds,
              tracer.device() == "cpu" ? fmt::format("{} threads", st.threads) : tracer.device(),
              tracer.body().triangleCount(), a.exr,
              a.png.empty() ? "" : " and " + a.png);
}

// ---------------------------------------------------------------------------------------------

// The scene file with --time (the deformations' time, scene.h "time") applied when given.
// The scene file at --time, with the material options over its material (options.h).
reference::MeshScene loadTimedScene(const std::string& sceneFile, std::optional<double> time,
                                    const MediumOptions& material) {
  reference::MeshScene scene = reference::loadMeshScene(sceneFile);
  material.apply(scene);
  if (time) {
    if (!std::isfinite(*time))
      throw ParameterError(fmt::format("--time {}: expected a finite time", *time));
    scene.time = *time;
  }
  return scene;
}

void runPathtraceMesh(const std::string& sceneFile, std::optional<double> time,
                      const MediumOptions& material, const RunArgs& a, std::string device) {
  const reference::MeshScene scene = loadTimedScene(sceneFile, time, material);
  OutputSet inputs;
  inputs.sceneInputs(sceneFile, scene);
  a.validate(inputs);
  if (a.method == "camera") return runPathtraceMeshCamera(scene, sceneFile, a, device);
  const uint64_t photons = parseCount(a.count, "--photons");
  device = a.shard.device(device);
  if (!beginWork()) return;
  const geometry::TriangleMesh mesh = scene::loadSceneMesh(scene);  // normalised and placed
  scene::requireOutsideMesh(scene, mesh);
  const MergedRun* merged = mergedRun();
  // Declared before the tracer: the context outlives the walker the tracer holds.
  const reference::TraceDevice dev =
      merged ? reference::TraceDevice{} : reference::openTraceDevice(device);
  // The scene's material: homogeneous (the walk of transport.h), or a 3D field delta-tracked
  // through a majorant grid; a 2D-map material has no volume and is refused with the reason.
  reference::MeshPathTracer tracer(mesh, scene::sceneMaterial(scene, mesh),
                                   scene::referenceLights(scene), scene.camera, scene.cone_angle,
                                   a.tracerOptions());
  reference::useDevice(dev, device, tracer, mesh, sceneFile);
  const std::string traced = merged ? mergedDevice(device) : tracer.device();
  if (a.shard.active()) return runShard(a, tracer, photons, "pathtrace mesh", inputs);
  auto pass = [&](const reference::ProgressCallback& cb) { return tracer.addPass(photons, cb).partial; };
  auto write = [&](bool partial) {
    OutputFiles out;  // the images and the JSON of this pass, all or nothing
    const auto& st = tracer.stats();
    writeImage(out, a, pick(tracer.images(), a.quantity), layersOf(tracer),
               fmt::format("translucent pathtrace mesh --scene {}", sceneFile), partial,
               fmt::format("{} photons per channel", st.photons.empty() ? 0 : st.photons[0]));
    nlohmann::json j = {{"command", "pathtrace mesh"}, {"scene_file", sceneFile},
                        {"scene", nlohmann::json::parse(reference::toJson(scene))},
                        {"triangles", tracer.body().triangleCount()},
                        {"photons_per_channel", st.photons.empty() ? 0 : st.photons[0]},
                        {"seconds", st.seconds}, {"photons_per_second", st.photonsPerSecond()},
                        {"scattering_events", st.scattering_events},
                        {"photons_in_several_pixels", tracer.severalPixelPhotons()},
                        // Over the pixels with exitance > 0 (silhouette pixels included).
                        {"median_relative_stderr", medianRelativeError(tracer.images().exitance)},
                        {"majorant_violations", tracer.majorantViolations()},
                        {"split_orders", tracer.splitsOrders()},
                        {"threads", st.threads}, {"device", traced},
                        {"flux_per_channel", reference::fluxPerChannelJson(st)},
                        {"partial", partial}};
    // What `compare --reference-from` checks: the key of compare's physical reference of this
    // scene, photon count, seed and device (the same tracer and blocks: the same images).
    analysis::ReferenceRequest req;
    req.kind = analysis::ReferenceKind::Physical;
    req.count = st.photons.empty() ? 0 : st.photons[0];
    req.seed = a.seed;
    req.device = traced == "cpu" ? "cpu" : "gpu";
    const std::string keyText = analysis::referenceKeyText(scene, req);
    j["reference_key"] = analysis::referenceKey(scene, req);
    j["reference_key_text"] = nlohmann::json::parse(keyText);
    writeJson(out, a, j);
    out.commit();
  };
  if (merged) {
    checkMergedInputs(inputs);
    tracer.read(merged->state, merged->seconds, merged->threads);
    write(false);
  } else {
    runPasses(a, "pathtrace mesh", "photons", pass, write);
  }
  const auto& st = tracer.stats();
  printStderr("pathtrace mesh: {}{} photons per channel in {:.2f} s ({:.3g} photons/s, "
                     "{}, {} triangles); wrote {}{}\n",
             stoppedEarly(st.partial),
             st.photons.empty() ? 0 : st.photons[0], st.seconds, st.photonsPerSecond(),
             tracedBy(traced, st.threads), tracer.body().triangleCount(), a.exr, a.png.empty() ? "" : " and " + a.png);
}

// Options of `integrate mesh` beyond RunArgs.
struct ModelReferenceArgs {
  std::string scene;
  MediumOptions material;  // over the scene's material
  reference::ModelReferenceOptions options;
  std::string convention = "jensen";
  bool jitter = false;
  std::optional<double> time;  // --time: the deformations' time (the scene's when not given)
};

void runIntegrateMesh(const ModelReferenceArgs& m, const RunArgs& a) {
  if (a.passes != 1)
    throw ParameterError(fmt::format("--passes is {}: `integrate mesh` renders in one pass (more "
                                     "--samples give less noise)", a.passes));
  const reference::MeshScene scene = loadTimedScene(m.scene, m.time, m.material);
  OutputSet inputs;
  inputs.sceneInputs(m.scene, scene);
  a.validate(inputs);
  reference::ModelReferenceOptions o = m.options;
  o.samples = parseCount(a.count, "--samples");
  o.seed = a.seed;
  o.threads = a.threads;
  o.convention = bssrdf::parseExitConvention(m.convention);
  o.jitter = m.jitter;
  if (!beginWork()) return;
  const geometry::TriangleMesh mesh = scene::loadSceneMesh(scene);  // normalised and placed
  scene::requireOutsideMesh(scene, mesh);
  const std::vector<reference::Light> lights = scene::referenceLights(scene);
  reference::ModelReferenceImages img;
  // The scene's material (homogeneous: exactly the medium's reference; heterogeneous: brute-force
  // Eq. 8, model_reference.h).
  const material::Material material = scene::sceneMaterial(scene, mesh);
  auto pass = [&](const reference::ProgressCallback& cb) {
    img = reference::renderModelReference(mesh, material, lights, scene.camera, o, cb);
    return img.partial;
  };
  auto write = [&](bool partial) {
    OutputFiles out;  // the images and the JSON of this pass, all or nothing
    std::vector<float> coverage;
    coverage.reserve(3 * img.coverage.size());
    for (const float c : img.coverage) coverage.insert(coverage.end(), {c, c, c});
    const std::vector<Quantity> all = {{"exitance", img.exitance, img.exitance_se},
                                       {"radiance", img.radiance, img.radiance_se}};
    writeImage(out, a, img.width, img.height, a.quantity == "radiance" ? all[1] : all[0], all,
               fmt::format("translucent integrate mesh --scene {} (model {}, radiance convention "
                           "{}, {} rays per pixel)", m.scene, scene.model, m.convention,
                           o.subpixels * o.subpixels),
               partial, fmt::format("{} surface samples", img.samples), {{"coverage", coverage}});
    nlohmann::json j = {{"command", "integrate mesh"}, {"scene_file", m.scene},
                        {"scene", nlohmann::json::parse(reference::toJson(scene))},
                        {"triangles", mesh.triangleCount()}, {"samples", img.samples},
                        {"lit_samples", img.lit_samples}, {"subpixels", o.subpixels},
                        {"jitter", o.jitter}, {"convention", m.convention},
                        {"area", img.area}, {"near_radius", img.near_radius},
                        {"near_fraction", img.near_fraction}, {"prune_radius", img.prune_radius},
                        {"tail_fraction", img.tail_fraction}, {"table_size", img.table_size},
                        {"table_error", img.table_error},
                        {"median_relative_stderr", medianRelativeError(img)},
                        {"seconds", img.seconds},
                        {"threads", img.threads}, {"partial", partial}};
    if (img.heterogeneous)
      j["heterogeneous"] = {{"profile_segments", img.profile_segments},
                            {"profile_radius", img.profile_radius},
                            {"sample_media", img.sample_media}, {"hit_media", img.hit_media}};
    writeJson(out, a, j);
    out.commit();
  };
  runPasses(a, "integrate mesh", "pixels", pass, write);
  printStderr("integrate mesh: {}{} ({}), {} surface samples ({} lit), {}x{} pixels, {} "
                     "rays per pixel, in {:.2f} s ({} threads); wrote {}{}\n",
             stoppedEarly(img.partial), scene.model, m.convention,
             img.samples, img.lit_samples, img.width, img.height, o.subpixels * o.subpixels,
             img.seconds, img.threads, a.exr, a.png.empty() ? "" : " and " + a.png);
}

CLI::App* subcommand(CLI::App& app, const std::string& name, const std::string& help) {
  for (auto* sub : app.get_subcommands([](CLI::App*) { return true; }))
    if (sub->get_name() == name) return sub;
  auto* cmd = app.add_subcommand(name, help);
  cmd->require_subcommand(1);
  return cmd;
}

}  // namespace

void addRenderReferenceCommands(CLI::App& app) {
  const std::vector<std::string> tracerQuantities = {"exitance", "radiance", "cone-radiance"};
  auto* pt = subcommand(app, "pathtrace",
                        "Reference Monte Carlo transport (volumetric path tracing, Bitterli 2013, §3.2)");
  {
    auto s = std::make_shared<SphereArgs>();
    auto a = std::make_shared<RunArgs>();
    auto* cmd = pt->add_subcommand(
        "sphere", "Lit sphere under a directional light, orthographic view: per-pixel radiant "
                  "exitance (or radiance) by photon tracing, as EXR/PNG");
    s->add(*cmd, true);
    a->add(*cmd, "--photons", "Photons per channel per pass (e.g. 1e6)", tracerQuantities);
    a->addSplitOrders(*cmd);
    auto device = std::make_shared<std::string>("auto");
    cmd->add_option("--device", *device,
                    "cpu: the CPU tracer; gpu: the GL compute-shader walk (any GL 4.5 context, "
                    "Philox streams: agrees with the CPU within the standard errors, not bit for "
                    "bit); auto: the GPU on a hardware GPU, else the CPU (with --shard: the CPU)")
        ->check(CLI::IsMember({"cpu", "gpu", "auto"}))
        ->capture_default_str();
    a->shard.add(*cmd);
    cmd->callback([s, a, device] { runPathtraceSphere(*s, *a, *device); });
  }
  {
    auto scene = std::make_shared<std::string>();
    auto a = std::make_shared<RunArgs>();
    auto* cmd = pt->add_subcommand(
        "mesh", "Closed triangle mesh from a JSON scene (mesh, material, lights, camera; see "
                "README): per-pixel exitance or radiance by photon tracing, as EXR/PNG");
    auto time = std::make_shared<std::optional<double>>();
    cmd->add_option("--scene", *scene, "Scene file (JSON)")->required();
    cmd->add_option("--time", *time,
                    "Time of the mesh's deformations (mesh.deform; default: the scene's \"time\", 0)");
    auto material = std::make_shared<MediumOptions>();
    material->addOverrides(*cmd, false);  // the path tracer uses no BSSRDF model
    a->add(*cmd, "--photons", "Photons per channel per pass (e.g. 1e6)", tracerQuantities);
    a->addSplitOrders(*cmd);
    auto device = std::make_shared<std::string>("auto");
    cmd->add_option("--method", a->method,
                    "light: photons from the lights, splatted through a cone at the camera; "
                    "camera: paths from the camera with next-event estimation to every light "
                    "(per-pixel samples, --samples; no --shard; its cone-radiance is the "
                    "true radiance, cone half-angle 0; at eta > 1 exact connections through every "
                    "refracting facet, plus light-traced photons for light that meets the "
                    "surface again before it scatters)")
        ->check(CLI::IsMember({"light", "camera"}))
        ->capture_default_str();
    cmd->add_option("--complement-photons", a->complement_photons,
                    "--method camera at eta != 1: photons of the light-traced complement (light that "
                    "meets the surface again before it first scatters) per camera path, per pixel "
                    "and channel; 0: none (the images then miss that light)")
        ->capture_default_str();
    cmd->add_option("--samples", a->samples,
                    "--method camera: camera paths per pixel and channel per pass (e.g. 64)")
        ->capture_default_str();
    cmd->add_option("--device", *device,
                    "cpu: the CPU tracer (Embree); gpu: the GL compute-shader walk against a BVH "
                    "of the mesh (homogeneous media and 3D fields, deformed or not; with "
                    "--method camera too; Philox streams: "
                    "agrees with the "
                    "CPU within the standard errors, not bit for bit); "
                    "auto: the GPU on a hardware GPU where it can trace the scene, else the CPU "
                    "(with --shard: the CPU)")
        ->check(CLI::IsMember({"cpu", "gpu", "auto"}))
        ->capture_default_str();
    a->shard.add(*cmd);
    cmd->callback([scene, time, material, a, device] {
      runPathtraceMesh(*scene, *time, *material, *a, *device);
    });
  }
  auto* in = subcommand(app, "integrate", "Monte Carlo integration of BSSRDF models on geometry");
  {
    auto s = std::make_shared<SphereArgs>();
    auto a = std::make_shared<RunArgs>();
    auto model = std::make_shared<std::string>("dipole");
    auto sampling = std::make_shared<std::string>("importance");
    auto defensive = std::make_shared<double>(0.1);
    a->count = "64";
    auto* cmd = in->add_subcommand(
        "sphere", "A model's radiant exitance on the lit sphere by integrating its profile over "
                  "the surface (Bitterli 2013, §3.5), same scene and pixels as `pathtrace sphere`");
    s->add(*cmd, false);
    cmd->add_option("--model", *model, "Model name (" + fmt::format("{}", fmt::join(bssrdf::modelNames(), ", ")) + "), a radial .bssrdf file (tabulated on the GPU for the medium) or a tabulated profile FILE.csv")
        ->capture_default_str();
    cmd->add_option("--sampling", *sampling,
                    "uniform: points uniform on the lit hemisphere (the method of Bitterli 2013); "
                    "importance: probe rays from the model's radial sampler")
        ->check(CLI::IsMember({"uniform", "importance"}))
        ->capture_default_str();
    cmd->add_option("--defensive", *defensive,
                    "Importance sampling: fraction of uniform samples (keeps it unbiased for any "
                    "profile)")
        ->capture_default_str();
    a->add(*cmd, "--samples", "Samples per pixel and channel per pass", {"exitance", "radiance"});
    cmd->callback([s, a, model, sampling, defensive] {
      runIntegrateSphere(*s, *a, *model, *sampling, *defensive);
    });
  }
  {
    auto m = std::make_shared<ModelReferenceArgs>();
    auto a = std::make_shared<RunArgs>();
    a->count = "200000";
    auto* cmd = in->add_subcommand(
        "mesh", "The scene's BSSRDF model integrated over the whole mesh for every visible pixel "
                "(dense area-uniform samples, no hierarchy): the \"model\" reference of "
                "`compare`; same scene file and pixels as `pathtrace mesh`");
    cmd->add_option("--scene", m->scene, "Scene file (JSON)")->required();
    cmd->add_option("--time", m->time,
                    "Time of the mesh's deformations (mesh.deform; default: the scene's \"time\", 0)");
    m->material.addOverrides(*cmd);
    cmd->add_option("--subpixels", m->options.subpixels,
                    "Camera rays per pixel per axis (stratified)")->capture_default_str();
    cmd->add_option("--convention", m->convention,
                    "Radiance from B: jensen (Ft B/pi) or normalized (Ft B/(pi 4C_phi(1/eta)))")
        ->check(CLI::IsMember(bssrdf::exitConventionNames()))
        ->capture_default_str();
    cmd->add_flag("--jitter", m->jitter,
                  "Jitter the rays in their strata (unbiased pixel averages; the standard error "
                  "then includes a conservative estimate of the rays' part). Default: strata "
                  "centres (--subpixels 1: the pixel centre, where a rasteriser shades)");
    cmd->add_option("--near-field", m->options.near_field,
                    "Radius of the analytic disc about each shaded point [sample spacings]")
        ->capture_default_str();
    cmd->add_option("--tail", m->options.tail,
                    "Fraction of Rd beyond the pruning radius (samples farther are skipped)")
        ->capture_default_str();
    cmd->add_option("--environment-rays", m->options.environment_rays,
                    "Shadow rays per surface sample for an environment light's irradiance (even; "
                    "half from the map, half cosine-distributed; 4x at the camera hits)")
        ->capture_default_str();
    a->add(*cmd, "--samples", "Surface samples (area-uniform, up to 2^24 - 1)",
           {"exitance", "radiance"});
    cmd->callback([m, a] { runIntegrateMesh(*m, *a); });
  }
}

}  // namespace translucent::cli
