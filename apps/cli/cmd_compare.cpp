// SPDX-License-Identifier: GPL-3.0-or-later
// translucent compare: a scene rendered with real-time techniques on the GPU and compared with
// two references (analysis/compare.h): the volumetric path tracer (physical) and the scene's
// BSSRDF integrated over the whole surface (model). Technique vs model is the technique's own
// error, model vs physical the model's, technique vs physical the total; for the exitance B (when
// the technique has it), the diffusion radiance L and the true (cone-averaged) radiance. Writes a
// self-contained report folder (analysis/report.h): index.html, report.json, EXRs and PNGs.
//
// This file does the GPU part (headless context, techniques, frame timing, the sweep) and the
// sweep's plot (Qt Charts); the references, their cache, the masks, the metrics and the report
// are library code in src/analysis.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <set>

#include "safe_print.h"
#include "translucent/compare/compare_run.h"
#include "translucent/compare/leaderboard.h"
#include "translucent/compare/report.h"
#include "commands.h"
#include "output_guard.h"
#include "translucent/gpu/context.h"
#include "options.h"
#include "plot/profile_plot.h"
#include "progress.h"
#include "translucent/scene/scene.h"
#include "translucent/techniques/registry.h"

namespace translucent::cli {
namespace {
namespace fs = std::filesystem;
using analysis::PassStat;
using analysis::PairMetrics;

struct CompareArgs {
  std::string scene;
  MediumOptions material;  // over every scene's material (options.h)
  std::string suite;  // --suite DIR: every *.json in it
  std::string techniques = "all";
  std::string references = "physical,model";
  // --reference-from, once per file: physical references from pathtrace runs (a suite's scenes
  // each take the one traced for them)
  std::vector<std::string> reference_from;
  std::string photons = "1e6", samples = "200000";
  std::string reference_device = "cpu";  // --reference-device: where the physical reference runs
  int subpixels = 1;  // pixel centres, as the techniques shade them
  bool sweep = false;
  std::string out = "compare-report";
  bool force = false;
  std::string cache;  // "" : the default folder
  bool no_cache = false;
  uint64_t seed = 1;
  int threads = 0;
  std::optional<int> width, height;
  int frames = 5, warmup = 2;
  std::optional<double> time;  // of the mesh's deformations (the scene's when not given)
};

using analysis::makeTechniqueSpec;
using analysis::parseTechniqueSpec;
using analysis::renderTimed;
using analysis::utcNow;

std::vector<std::string> techniqueList(const std::string& text) {
  const std::vector<std::string> all = techniques::names();
  if (text == "all") return all;
  std::vector<std::string> out;
  for (const std::string& n : splitList(text)) {
    if (n == "all") {  // every registered technique, beside variants: all,tsis:mode=hybrid
      for (const std::string& a : all)
        if (std::find(out.begin(), out.end(), a) == out.end()) out.push_back(a);
      continue;
    }
    const std::string base = parseTechniqueSpec(n).base;
    if (std::find(all.begin(), all.end(), base) == all.end())
      throw ParameterError(fmt::format("--techniques '{}': unknown technique '{}': valid techniques "
                                       "are {} (or all)", text, base, fmt::join(all, ", ")));
    (void)makeTechniqueSpec(n, nullptr);  // the settings exist and take their values
    if (std::find(out.begin(), out.end(), n) == out.end()) out.push_back(n);
  }
  if (out.empty())
    throw ParameterError(fmt::format("--techniques '{}': expected a list of techniques or all", text));
  return out;
}

std::string quoted(const std::string& s) {
  if (!s.empty() && s.find_first_of(" \t'\"\\$`;&|<>()*?") == std::string::npos) return s;
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}


// The options that apply to every scene, checked once (before a suite's first scene).
struct Parsed {
  std::vector<std::string> names;
  std::vector<analysis::ReferenceKind> kinds;
  uint64_t photons = 0, samples = 0;
  fs::path cacheDir;  // "" : caching off
};

Parsed parseOptions(const CompareArgs& a) {
  Parsed p;
  p.names = techniqueList(a.techniques);
  for (const std::string& k : splitList(a.references)) {
    const auto kind = analysis::parseReferenceKind(k, "--reference");
    if (std::find(p.kinds.begin(), p.kinds.end(), kind) == p.kinds.end()) p.kinds.push_back(kind);
  }
  if (p.kinds.empty())
    throw ParameterError(fmt::format("--reference '{}': expected physical, model or both",
                                     a.references));
  p.photons = parseCount(a.photons, "--photons");
  p.samples = parseCount(a.samples, "--samples");
  if (a.subpixels < 1 || a.subpixels > 16)
    throw ParameterError(fmt::format("--subpixels {}: expected 1 to 16", a.subpixels));
  if (a.frames < 1) throw ParameterError(fmt::format("--frames {}: expected at least 1", a.frames));
  if (a.warmup < 0) throw ParameterError(fmt::format("--warmup {}: expected 0 or more", a.warmup));
  if (a.threads < 0) throw ParameterError(fmt::format("--threads {}: expected >= 0", a.threads));
  if (a.time && !std::isfinite(*a.time))
    throw ParameterError(fmt::format("--time {}: expected a finite time", *a.time));
  if (!a.cache.empty() && a.no_cache)
    throw ParameterError("--cache and --no-cache: expected one of them");
  p.cacheDir = a.no_cache ? fs::path()
               : a.cache.empty() ? analysis::defaultReferenceCacheDirectory()
                                 : fs::absolute(a.cache);
  return p;
}

// What a scene's compare that wrote its report tells the caller.
struct SceneOutcome {
  bool partial = false;                         // stopped early (Ctrl-C)
  std::vector<std::string> failed_techniques;   // ran into an error; the report has the others
  size_t techniques = 0;
};

// "pointcloud, empirical"
std::string joined(const std::vector<std::string>& v) { return fmt::format("{}", fmt::join(v, ", ")); }

// One scene's compare into the report folder `out` (the caller holds the InterruptGuard, so that
// a suite sees one Ctrl-C across its scenes). A technique that throws is recorded in the report
// with its error and the others still run; anything else that throws (the scene, its mesh, a
// reference: without the references there is nothing to compare against) fails the scene.
std::vector<fs::path> referenceFiles(const CompareArgs& a) {
  return {a.reference_from.begin(), a.reference_from.end()};
}

SceneOutcome compareScene(const CompareArgs& a, const Parsed& parsed, const std::string& sceneFile,
                          const fs::path& out) {
  const std::vector<std::string>& names = parsed.names;
  const std::vector<analysis::ReferenceKind>& kinds = parsed.kinds;
  const uint64_t photons = parsed.photons, samples = parsed.samples;
  const fs::path& cacheDir = parsed.cacheDir;
  scene::Scene s = sceneFile.empty() ? scene::defaultScene() : scene::loadScene(sceneFile);
  a.material.apply(s);
  if (a.width) s.camera.width = *a.width;
  if (a.height) s.camera.height = *a.height;
  // The references and the techniques all see the mesh deformed at this time (loadSceneMesh,
  // Technique::prepare), and the references' cache key holds it (the scene's JSON).
  if (a.time) s.time = *a.time;
  s.camera.validate();
  // A suite's scenes come here in its work only; a single scene's checks end here.
  if (!beginWork()) return {};
  analysis::prepareReportDirectory(out, a.force, cacheDir, "--out");
  geometry::HoleFillStats fill;
  geometry::AlphaWrapStats wrap;
  const geometry::TriangleMesh mesh = scene::loadSceneMesh(s, &fill, &wrap);
  scene::requireOutsideMesh(s, mesh);

  analysis::CompareReport report;
  report.scene_file = sceneFile;
  report.scene = s;
  report.version = "translucent " TRANSLUCENT_VERSION;
  report.created = utcNow();
  report.cache_dir = cacheDir;
  std::string cmd = "translucent compare";
  if (!sceneFile.empty()) cmd += " " + quoted(fs::absolute(sceneFile).string());
  cmd += fmt::format(" --techniques {} --reference {} --photons {} --samples {} --subpixels {} "
                     "--seed {} --width {} --height {} --frames {} --warmup {}{} --out {}",
                     fmt::join(names, ","), quoted(a.references), photons, samples, a.subpixels,
                     a.seed, s.camera.width, s.camera.height, a.frames, a.warmup,
                     a.sweep ? " --sweep" : "", quoted(out.string()));
  if (a.time) cmd += fmt::format(" --time {}", *a.time);
  cmd += a.material.commandLine();
  for (const std::string& f : a.reference_from) cmd += " --reference-from " + quoted(f);
  if (a.reference_device != "cpu") cmd += " --reference-device " + a.reference_device;
  if (a.no_cache) cmd += " --no-cache";
  else if (!a.cache.empty()) cmd += " --cache " + quoted(cacheDir.string());
  report.command = cmd;
  if (s.mesh_fill_holes) {
    const std::string what = "mesh.fill_holes: " + scene::describeHoleFill(fill);
    printStderr("{}\n", what);
    report.notes.push_back(what);
  }
  if (s.mesh_wrap) {
    // Every technique and reference renders the wrap, not the file's triangles: say so.
    const std::string what = "mesh.wrap: " + scene::describeAlphaWrap(*s.mesh_wrap, wrap);
    printStderr("{}\n", what);
    report.notes.push_back(what);
  }
  report.settings = {{"techniques", fmt::format("{}", fmt::join(names, ","))},
                     {"reference", a.references},
                     {"photons_per_channel", std::to_string(photons)},
                     {"samples", std::to_string(samples)},
                     {"subpixels", std::to_string(a.subpixels)},
                     {"reference_device", a.reference_device},
                     {"seed", std::to_string(a.seed)},
                     {"threads", std::to_string(a.threads)},
                     {"width", std::to_string(s.camera.width)},
                     {"height", std::to_string(s.camera.height)},
                     {"frames", std::to_string(a.frames)},
                     {"warmup", std::to_string(a.warmup)},
                     {"sweep", a.sweep ? "true" : "false"},
                     {"cache", a.no_cache ? "off" : cacheDir.string()},
                     {"out", out.string()}};

  // ---- References --------------------------------------------------------------------------
  // The material says which reference is physical (a 2D surface map has none: its reference is
  // the model reference, brute-force Eq. 8); the model reference integrates the material itself.
  report.material = analysis::materialReferences(scene::sceneMaterial(s, mesh));
  const std::optional<analysis::ReferenceCache> cache =
      a.no_cache ? std::nullopt : std::optional<analysis::ReferenceCache>(cacheDir);
  for (const auto kind : kinds) {
    if (InterruptGuard::interrupted()) {
      report.notes.push_back(fmt::format("{} reference skipped (Ctrl-C)", toString(kind)));
      report.partial = true;
      continue;
    }
    if (kind == analysis::ReferenceKind::Physical && !report.material.physical) {
      const std::string why = fmt::format("physical reference skipped: {}", report.material.text);
      printStderr("{}\n", why);
      report.notes.push_back(why);
      continue;
    }
    analysis::ReferenceRequest req;
    req.kind = kind;
    req.count = kind == analysis::ReferenceKind::Physical ? photons : samples;
    req.seed = a.seed;
    req.threads = a.threads;
    req.subpixels = a.subpixels;
    req.device = a.reference_device;
    const bool physical = kind == analysis::ReferenceKind::Physical;
    ProgressBar bar(fmt::format("compare: {} reference", toString(kind)),
                    physical ? "photons" : "pixels");
    printStderr("{} reference ({} {}):\n", toString(kind), req.count,
               physical ? "photons per channel" : "surface samples");
    analysis::Reference ref;
    if (physical && !a.reference_from.empty()) {
      // Traced elsewhere (e.g. sharded on a cluster and merged, issue 17): the file whose
      // reference key is this scene's. A single scene must find one; a suite's scene without
      // one is traced here, with a note.
      std::string why;
      if (std::optional<analysis::ReferenceFromFile> found =
              analysis::findPathtracedReference(referenceFiles(a), s, &why)) {
        ref = std::move(found->reference);
        const std::string what = fmt::format("read from {} ({} photons per channel, seed {}, "
                                             "traced in {:.2f} s)", found->file.string(),
                                             ref.count_done, ref.request.seed, ref.seconds);
        bar.end();
        printStderr("physical reference: {}\n", what);
        report.notes.push_back("physical reference: " + what);
        report.references.push_back(std::move(ref));
        continue;
      }
      if (a.suite.empty()) throw ParameterError(why);
      const std::string note = "physical reference: traced here, none of the --reference-from "
                               "files is this scene's (" + why + ")";
      printStderr("{}\n", note);
      report.notes.push_back(note);
    }
    try {
      ref = analysis::cachedReference(
          s, mesh, req, cache ? &*cache : nullptr,
          [&](const reference::TraceProgress& p) { return bar(p); });
    } catch (const ParameterError& e) {
      // The scene fails: named by the reference, since every technique needs it.
      throw ParameterError(fmt::format("{} reference: {}", toString(kind), e.what()));
    } catch (const std::exception& e) {
      throw std::runtime_error(fmt::format("{} reference: {}", toString(kind), e.what()));
    }
    bar.end();
    const std::string what = analysis::referenceOrigin(ref);
    printStderr("{} reference: {}\n", toString(kind), what);
    report.notes.push_back(fmt::format("{} reference: {}", toString(kind), what));
    report.partial = report.partial || ref.partial;
    report.references.push_back(std::move(ref));
  }
  std::span<const float> coverage;
  for (const auto& r : report.references)
    if (r.kind == analysis::ReferenceKind::Model) coverage = r.coverage;
  report.masks = analysis::compareMasks(s, mesh, coverage);
  const double eta = s.medium.eta;
  analysis::MetricOptions display;
  display.exposure = s.exposure;
  display.gamma = s.gamma;

  // ---- Techniques --------------------------------------------------------------------------
  // The context first: the techniques' GL objects must be deleted while it is alive.
  gpu::Context gl;
  report.gpu = fmt::format("{} ({})", gl.info().renderer, gl.info().version);
  std::set<bssrdf::ExitConvention> conventions;
  std::vector<plot::XySeries> sweepSeries;
  for (const std::string& name : names) {
    analysis::TechniqueRun run;
    run.images.name = name;
    run.description = techniques::description(parseTechniqueSpec(name).base);
    std::unique_ptr<techniques::Technique> t;
    std::vector<PairMetrics> rows;
    try {
      // The scene's settings belong to the scene's technique; the others run at their defaults;
      // then a variant's own settings.
      t = makeTechniqueSpec(name, &s);
      printStderr("{}: preparing on {}\n", name, report.gpu);
      t->prepare(s, gl);
      analysis::TimedRender r = renderTimed(*t, name, s, a.warmup, a.frames);
      printStderr("  frame {:.3f} ms (median of {}), L by the {} convention{}\n", r.frame_ms,
                 a.frames, toString(r.images.convention),
                 r.images.exitance.empty() ? ", no exitance" : "");
      rows = analysis::techniqueMetrics(r.images, report.references, eta, report.masks, display);
      run.passes = r.passes;
      run.frame_ms = r.frame_ms;
      run.timed_frames = a.frames;
      run.warmup_frames = a.warmup;
      run.notes = r.notes;
      run.images = std::move(r.images);
    } catch (const std::exception& e) {
      // This technique cannot do this scene (e.g. the point cloud's shadow map and a point light
      // inside the bounding sphere): the other techniques and the references still say
      // something, so the report keeps them and lists this one with its reason.
      run.error = e.what();
      printStderr("{}: failed: {}\n", name, run.error);
    }
    if (t)
      for (const auto& p : t->parameters())
        run.parameters.emplace_back(p.name, techniques::toString(t->parameter(p.name)));
    if (run.failed()) {
      report.techniques.push_back(std::move(run));
      continue;
    }
    conventions.insert(run.images.convention);
    report.metrics.insert(report.metrics.end(), rows.begin(), rows.end());

    // The sweep: each quality parameter over its values (the others as above), then restored. A
    // value that fails ends that parameter's sweep with a note; the technique's own result stands.
    if (a.sweep && !InterruptGuard::interrupted()) {
      // A sweep measures the real-time image at each value: a technique that accumulates frames
      // into a converged image (tsis) would give every sample count the same converged error,
      // so its accumulation is off during the sweep (and restored after).
      std::optional<techniques::ParameterValue> accumulate;
      for (const auto& p : t->parameters())
        if (p.name == "accumulate" && p.type == techniques::ParameterType::Bool) {
          accumulate = t->parameter(p.name);
          t->setParameter(p.name, false);
        }
      if (accumulate) run.notes.push_back("sweep: accumulate false (real-time frames)");
      for (const auto& p : t->parameters()) {
        if (p.sweep.empty()) continue;
        const techniques::ParameterValue keep = t->parameter(p.name);
        std::map<std::string, plot::XySeries> series;  // per reference
        for (double v : p.sweep) {
          try {
            t->setParameter(p.name, v);
            analysis::TimedRender sr = renderTimed(*t, name, s, a.warmup, a.frames);
            analysis::SweepPoint point{name, p.name, v, sr.frame_ms,
                                       analysis::techniqueMetrics(sr.images, report.references,
                                                                  eta, report.masks, display)};
            printStderr("  sweep {} = {:g}: {:.3f} ms\n", p.name, v, sr.frame_ms);
            for (const PairMetrics& m : point.metrics) {
              if (m.quantity != "radiance") continue;
              auto& xy = series[m.reference];
              xy.label = fmt::format("{} {} vs {}", name, p.name, m.reference);
              xy.x.push_back(sr.frame_ms);
              xy.y.push_back(100.0 * m.metrics.rel_rmse);
            }
            report.sweep.push_back(std::move(point));
          } catch (const std::exception& e) {
            const std::string note =
                fmt::format("sweep {} = {:g} failed, sweep of {} stopped: {}", p.name, v, p.name,
                            e.what());
            printStderr("  {}\n", note);
            run.notes.push_back(note);
            break;
          }
        }
        t->setParameter(p.name, keep);
        for (auto& [ref, xy] : series) sweepSeries.push_back(std::move(xy));
      }
      if (accumulate) t->setParameter("accumulate", *accumulate);
    }
    report.techniques.push_back(std::move(run));
  }
  if (conventions.empty()) conventions.insert(bssrdf::ExitConvention::Jensen);
  for (const auto conv : conventions) {
    const auto rows = analysis::modelMetrics(report.references, conv, eta, report.masks, display);
    report.metrics.insert(report.metrics.end(), rows.begin(), rows.end());
  }
  if (a.sweep && InterruptGuard::interrupted()) report.notes.push_back("sweep skipped (Ctrl-C)");

  // ---- Report ------------------------------------------------------------------------------
  if (!sweepSeries.empty()) {
    plot::XyPlotOptions o;
    o.title = "Radiance error against GPU frame time (sweep of each quality parameter)";
    o.x_label = "GPU time per frame [ms]";
    o.y_label = "relative RMSE of L, noise-aware [%]";
    o.log_x = o.log_y = true;
    o.width = 1200;
    o.height = 750;
    plot::writeXyPlot((out / "sweep.png").string(), sweepSeries, o);
    report.figures.push_back(
        {"sweep.png", "Noise-aware relative RMSE of the radiance L (interior pixels) against the "
                      "median GPU frame time, one point per value of each technique's quality "
                      "parameter; vs model: the technique's own error, vs physical: the total."});
  }
  const auto files = analysis::writeReport(out, report);
  fmt::print("{:<12} {:<9} {:<14} {:>10} {:>10} {:>8} {:>8}\n", "test", "reference", "quantity",
             "relRMSE", "bias", "SSIM", "FLIP");
  for (const PairMetrics& m : report.metrics)
    fmt::print("{:<12} {:<9} {:<14} {:>9.2f}% {:>+9.2f}% {:>8.4f} {:>8.4f}\n", m.test,
               m.reference, m.quantity, 100.0 * m.metrics.rel_rmse, 100.0 * m.metrics.bias,
               m.metrics.ssim, m.metrics.flip);
  SceneOutcome outcome;
  outcome.partial = report.partial;
  outcome.techniques = report.techniques.size();
  for (const auto& t : report.techniques) {
    if (t.failed()) {
      fmt::print("{:<12} failed: {}\n", t.images.name, t.error);
      outcome.failed_techniques.push_back(t.images.name);
      continue;
    }
    fmt::print("{}: {:.3f} ms per frame (GPU, median of {})\n", t.images.name, t.frame_ms,
               t.timed_frames);
  }
  fmt::print("wrote {} ({} files){}\n", (out / "index.html").string(), files.size(),
             report.partial ? " (partial: stopped early)" : "");
  return outcome;
}

std::string sceneStem(const fs::path& file) { return file.stem().string(); }

// --suite: every scene of the folder into OUT/<scene>/, then the leaderboard (analysis/
// leaderboard.h). A scene that fails is a row with its error; Ctrl-C ends the scene being
// compared (its report partial, as a single compare) and skips the rest.
void runSuite(const CompareArgs& a, const Parsed& o) {
  const auto started = std::chrono::steady_clock::now();
  const fs::path suiteDir = fs::absolute(a.suite);
  const std::vector<fs::path> files = analysis::suiteSceneFiles(suiteDir, "--suite");
  std::vector<std::string> stems;
  for (const fs::path& f : files) stems.push_back(sceneStem(f));
  const fs::path out = fs::absolute(a.out);
  analysis::prepareSuiteDirectory(out, a.force, o.cacheDir, stems, "--out");

  analysis::SuiteInfo info;
  info.version = "translucent " TRANSLUCENT_VERSION;
  info.created = utcNow();
  info.suite_dir = suiteDir;
  std::string cmd = fmt::format(
      "translucent compare --suite {} --techniques {} --reference {} --photons {} --samples {} "
      "--subpixels {} --seed {}{}{} --frames {} --warmup {}{} --out {}", quoted(suiteDir.string()),
      fmt::join(o.names, ","), quoted(a.references), o.photons, o.samples, a.subpixels, a.seed,
      a.width ? fmt::format(" --width {}", *a.width) : "",
      a.height ? fmt::format(" --height {}", *a.height) : "", a.frames, a.warmup,
      a.sweep ? " --sweep" : "", quoted(out.string()));
  if (a.time) cmd += fmt::format(" --time {}", *a.time);
  cmd += a.material.commandLine();
  for (const std::string& f : a.reference_from) cmd += " --reference-from " + quoted(f);
  if (a.reference_device != "cpu") cmd += " --reference-device " + a.reference_device;
  if (a.no_cache) cmd += " --no-cache";
  else if (!a.cache.empty()) cmd += " --cache " + quoted(o.cacheDir.string());
  info.command = cmd;

  std::vector<analysis::SuiteScene> scenes;
  size_t failedRuns = 0, scenesWithFailedRuns = 0;
  InterruptGuard guard;
  for (size_t i = 0; i < files.size(); ++i) {
    analysis::SuiteScene sc;
    sc.name = stems[i];
    sc.scene_file = files[i];
    if (InterruptGuard::interrupted()) {
      sc.status = analysis::SuiteScene::Status::NotRun;
      sc.error = "not run (Ctrl-C)";
      info.partial = true;
      scenes.push_back(sc);
      continue;
    }
    printStderr("==== suite {}/{}: {}\n", i + 1, files.size(), files[i].string());
    const auto t0 = std::chrono::steady_clock::now();
    try {
      const SceneOutcome r = compareScene(a, o, files[i].string(), out / sc.name);
      sc.status = r.partial ? analysis::SuiteScene::Status::Partial
                            : analysis::SuiteScene::Status::Done;
      failedRuns += r.failed_techniques.size();
      scenesWithFailedRuns += !r.failed_techniques.empty();
    } catch (const std::exception& e) {
      sc.status = analysis::SuiteScene::Status::Failed;
      // Named by its file, as a single compare's error would be from its command line.
      const std::string what = e.what();
      sc.error = what.find(files[i].string()) == std::string::npos
                     ? fmt::format("{}: {}", files[i].string(), what)
                     : what;
      printStderr("{}: failed: {}\n", files[i].string(), e.what());
    }
    sc.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (InterruptGuard::interrupted()) info.partial = true;
    scenes.push_back(sc);
  }
  info.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  analysis::writeLeaderboard(out, info, scenes);
  size_t failed = 0;
  for (const auto& sc : scenes) failed += sc.status == analysis::SuiteScene::Status::Failed;
  fmt::print("wrote {} ({} scenes in {:.0f} s){}\n", (out / "index.html").string(), scenes.size(),
             info.seconds, info.partial ? " (partial: stopped early)" : "");
  // The leaderboard is complete either way; the exit status tells scripts that a scene or a
  // technique failed.
  std::vector<std::string> what;
  if (failed) what.push_back(fmt::format("{} of {} scenes failed", failed, scenes.size()));
  if (failedRuns)
    what.push_back(fmt::format("{} technique run{} failed in {} scene{}", failedRuns,
                               failedRuns == 1 ? "" : "s", scenesWithFailedRuns,
                               scenesWithFailedRuns == 1 ? "" : "s"));
  if (!what.empty())
    throw std::runtime_error(fmt::format("--suite '{}': {} (see {})", suiteDir.string(),
                                         joined(what), (out / "leaderboard.md").string()));
}

void runCompare(const CompareArgs& a) {
  if (!a.suite.empty() && !a.scene.empty())
    throw ParameterError(fmt::format("--suite '{}' and scene '{}': expected one of them",
                                     a.suite, a.scene));
  const Parsed o = parseOptions(a);
  if (!a.suite.empty()) {
    if (!beginWork()) return;
    return runSuite(a, o);
  }
  InterruptGuard guard;
  const fs::path out = fs::absolute(a.out);
  const SceneOutcome r = compareScene(a, o, a.scene, out);
  // The report is written either way; the exit status (1, through main's error line) tells
  // scripts that it lacks a technique.
  if (!r.failed_techniques.empty())
    throw std::runtime_error(fmt::format(
        "compare: {} of {} techniques failed ({}); the report has the others: {}",
        r.failed_techniques.size(), r.techniques, joined(r.failed_techniques),
        (out / "index.html").string()));
}

}  // namespace

void addCompareCommand(CLI::App& app) {
  auto a = std::make_shared<CompareArgs>();
  auto* cmd = app.add_subcommand(
      "compare", "Compare real-time techniques with the physical (path-traced) and model "
                 "(integrated BSSRDF) references of a scene: errors of B, L and the true "
                 "radiance, GPU times, an HTML/JSON report with images and error maps");
  cmd->add_option("scene", a->scene, "Scene file (JSON, see README); omitted: the built-in bunny");
  cmd->add_option("--suite", a->suite,
                  "Compare every scene (*.json, by name) of this folder into OUT/<scene>/ and write "
                  "OUT/leaderboard.md, leaderboard.json and index.html (instead of a scene)");
  cmd->add_option("--techniques", a->techniques,
                  fmt::format("Techniques to compare, comma-separated: {} or all; a variant with "
                              "its own settings is name:key=value:key=value (e.g. "
                              "all,tsis:mode=hybrid:samples=900), its row named so",
                              fmt::join(techniques::names(), ", ")))
      ->capture_default_str();
  cmd->add_option("--reference", a->references,
                  "References: physical (volumetric path tracing), model (the scene's BSSRDF "
                  "integrated over the surface), or both, comma-separated")
      ->capture_default_str();
  a->material.addOverrides(*cmd);
  cmd->add_option("--photons", a->photons, "Physical reference: photons per channel (e.g. 1e6)")
      ->capture_default_str();
  cmd->add_option("--reference-from", a->reference_from,
                  "Physical reference: take it from the --json of `translucent pathtrace mesh` "
                  "of this scene (or of `translucent merge` of its shards, e.g. traced on a "
                  "cluster) instead of tracing it (any photon count and seed); checked against "
                  "the scene, mesh and material. Once per file: each scene (of --suite) takes "
                  "the file traced for it; a suite's scene with none is traced")
      ->allow_extra_args(false);
  cmd->add_option("--reference-device", a->reference_device,
                  "Physical reference: cpu (Embree, the default) or gpu (the GL compute-shader "
                  "walk: homogeneous materials and 3D fields, deformed or not; its own "
                  "random streams, so its "
                  "own cache entries)")
      ->check(CLI::IsMember({"cpu", "gpu"}))
      ->capture_default_str();
  cmd->add_option("--samples", a->samples, "Model reference: surface samples (e.g. 2e5)")
      ->capture_default_str();
  cmd->add_option("--subpixels", a->subpixels,
                  "Model reference: camera rays per pixel per axis (strata centres). 1: the pixel "
                  "centre, where the techniques shade, so that technique vs model carries no "
                  "pixel-filter difference; more: pixel averages like the physical reference")
      ->capture_default_str();
  // The swept parameters from the techniques' descriptors (those with sweep values).
  std::vector<std::string> swept;
  for (const std::string& n : techniques::names()) {
    std::vector<std::string> ps;
    // The technique must outlive the loop: parameters() refers into it, and a temporary in a
    // range-for's initializer dies before the loop runs (until C++23); ASan caught it.
    const std::unique_ptr<techniques::Technique> t = techniques::make(n);
    for (const auto& p : t->parameters())
      if (!p.sweep.empty()) ps.push_back(p.name);
    if (!ps.empty()) swept.push_back(fmt::format("{}: {}", n, fmt::join(ps, ", ")));
  }
  cmd->add_flag("--sweep", a->sweep,
                fmt::format("Also render each technique's quality parameter over its sweep values "
                            "and plot error against GPU time ({}; real-time frames: accumulation "
                            "off)", fmt::join(swept, "; ")));
  // An empty --out would be the current folder (fs::absolute("")): refused like every output.
  outputOption(cmd->add_option("--out", a->out,
                               "Report folder (created; a previous report there is replaced)"))
      ->capture_default_str();
  cmd->add_flag("--force", a->force,
                "Write into --out even when it holds files that are not a previous report");
  cmd->add_option("--cache", a->cache,
                  "Reference cache folder (default: $TRANSLUCENT_CACHE_DIR, $XDG_CACHE_HOME/"
                  "translucent or ~/.cache/translucent, then references/)");
  cmd->add_flag("--no-cache", a->no_cache, "Neither read nor store cached references");
  cmd->add_option("--seed", a->seed, "Seed of both references (same seed: same images on any "
                                     "thread count)")->capture_default_str();
  cmd->add_option("--threads", a->threads, "Reference worker threads (0: all cores)")
      ->capture_default_str();
  cmd->add_option("--time", a->time,
                  "Time of the mesh's deformations (mesh.deform; default: each scene's \"time\", 0)");
  cmd->add_option("--width", a->width, "Image width [pixels] (default: the scene camera's)");
  cmd->add_option("--height", a->height, "Image height [pixels] (default: the scene camera's)");
  cmd->add_option("--frames", a->frames, "Timed frames per technique (the median is reported)")
      ->capture_default_str();
  cmd->add_option("--warmup", a->warmup, "Untimed frames before the timed ones")
      ->capture_default_str();
  cmd->callback([a] { runCompare(*a); });
}

}  // namespace translucent::cli
