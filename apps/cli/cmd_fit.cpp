// SPDX-License-Identifier: GPL-3.0-or-later
// translucent fit empirical [SCENE | --suite DIR] --reference physical --out DIR
//
// Fits the empirical translucency shader's parameters (Gascons 2011, Eqs. 3.6-3.10: it has no
// physical calibration) to a reference of each scene, the references being compare's (same
// cache, same keys): per scene DIR/<scene>.json (the parameters and the errors before and
// after), DIR/<scene>-fitted.json (the scene with the technique and the fitted values, for the
// explorer and `render`), and DIR/fit.md / fit.json (the before/after table over the scenes).
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "commands.h"
#include "options.h"
#include "output_guard.h"
#include "progress.h"
#include "safe_print.h"
#include "translucent/compare/compare.h"
#include "translucent/compare/compare_run.h"
#include "translucent/compare/fit.h"
#include "translucent/compare/leaderboard.h"
#include "translucent/compare/report.h"
#include "translucent/geometry/atomic_file.h"
#include "translucent/gpu/context.h"
#include "translucent/scene/scene.h"
#include "translucent/techniques/registry.h"

namespace translucent::cli {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

constexpr const char* kGenerator = "translucent fit";

struct FitArgs {
  std::string technique;
  std::string scene;
  std::string suite;
  std::string reference = "physical";
  std::string photons = "300000";
  std::string samples = "100000";
  int subpixels = 1;
  uint64_t seed = 1;
  int threads = 0;
  std::optional<int> width, height;
  int max_evaluations = 1000;
  std::string cache;
  bool no_cache = false;
  std::string out;
  bool force = false;
};

json num(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

std::string pct(double v) { return std::isfinite(v) ? fmt::format("{:.2f}%", 100.0 * v) : "n/a"; }

void writeText(const fs::path& path, const std::string& text) {
  if (const std::string why = geometry::writeFileAtomically(path, text); !why.empty())
    throw std::runtime_error(fmt::format("cannot write '{}': {}", path.string(), why));
}

json metricsJson(const analysis::Metrics& m) {
  return {{"rel_rmse", num(m.rel_rmse)}, {"rel_rmse_raw", num(m.rel_rmse_raw)},
          {"bias", num(m.bias)}, {"pixels", m.pixels}};
}

struct SceneFit {
  std::string scene;  // file stem
  std::string material;
  analysis::FitResult fit;
  std::string error;
};

SceneFit fitScene(const FitArgs& a, const std::string& file, const fs::path& out,
                  analysis::ReferenceKind kind, uint64_t count,
                  const std::optional<analysis::ReferenceCache>& cache,
                  std::vector<std::string>& files) {
  SceneFit r;
  r.scene = file.empty() ? "bunny" : fs::path(file).stem().string();
  // Loaded by its absolute name, so that every file it names resolves to an absolute path: the
  // fitted scene written into --out then finds them wherever it is opened from.
  scene::Scene s = file.empty() ? scene::defaultScene() : scene::loadScene(fs::absolute(file));
  r.material = s.preset.empty() ? "custom" : s.preset;
  if (a.width) s.camera.width = *a.width;
  if (a.height) s.camera.height = *a.height;
  s.camera.validate();
  const geometry::TriangleMesh mesh = scene::loadSceneMesh(s);
  scene::requireOutsideMesh(s, mesh);
  if (kind == analysis::ReferenceKind::Physical &&
      !analysis::materialReferences(scene::sceneMaterial(s, mesh)).physical)
    throw ParameterError(fmt::format("{}: its material has no physical reference (--reference model)", file));
  analysis::ReferenceRequest req;
  req.kind = kind;
  req.count = count;
  req.seed = a.seed;
  req.threads = a.threads;
  req.subpixels = a.subpixels;
  analysis::Reference ref;
  {
    InterruptGuard guard;
    ProgressBar bar(fmt::format("fit {}: {} reference", r.scene, toString(kind)),
                    kind == analysis::ReferenceKind::Physical ? "photons" : "pixels");
    ref = analysis::cachedReference(s, mesh, req, cache ? &*cache : nullptr,
                                    [&](const reference::TraceProgress& p) { return bar(p); });
    bar.end();
  }
  if (ref.partial) throw std::runtime_error("the reference was stopped before it was complete");
  printStderr("fit {}: {} reference {}\n", r.scene, toString(kind), analysis::referenceOrigin(ref));
  const analysis::Masks masks = analysis::compareMasks(
      s, mesh, kind == analysis::ReferenceKind::Model ? std::span<const float>(ref.coverage) : std::span<const float>());

  gpu::Context gl;
  std::unique_ptr<techniques::Technique> t = analysis::makeTechniqueSpec(a.technique, &s);
  t->prepare(s, gl);
  const analysis::CompareImage target =
      ref.radianceFor(techniques::radianceConvention(*t), s.medium.eta);
  const std::vector<analysis::FitParameter> params = analysis::empiricalFitParameters();
  analysis::FitOptions o;
  o.max_evaluations = a.max_evaluations;
  InterruptGuard guard;
  int next_line = 0;
  r.fit = analysis::fitTechnique(*t, s, target, masks.interior, params, o, [&](int n, double best) {
    if (n >= next_line) {
      printStderr("fit {}: {} renders, error {}\n", r.scene, n, pct(best));
      next_line += 50;
    }
    return !InterruptGuard::interrupted();
  });
  printStderr("fit {}: {} -> {} vs the {} reference ({} renders, {:.1f} s, {})\n", r.scene,
              pct(r.fit.before_metrics.rel_rmse), pct(r.fit.after_metrics.rel_rmse), toString(kind),
              r.fit.evaluations, r.fit.seconds, r.fit.stop_reason);

  // The scene with the technique at the fitted values: a starting point in the explorer.
  scene::Scene fitted = s;
  fitted.technique = a.technique;
  for (const auto& [name, v] : r.fit.after) fitted.settings[name] = v;
  const std::string fitted_name = r.scene + "-fitted.json";
  writeText(out / fitted_name, scene::toJson(fitted));
  files.push_back(fitted_name);
  json j = {{"generator", kGenerator},
            {"scene_file", file},
            {"technique", a.technique},
            {"reference", {{"kind", toString(kind)}, {"count", ref.count_done}, {"seed", a.seed}}},
            {"width", s.camera.width},
            {"height", s.camera.height},
            {"before", metricsJson(r.fit.before_metrics)},
            {"after", metricsJson(r.fit.after_metrics)},
            {"evaluations", r.fit.evaluations},
            {"seconds", r.fit.seconds},
            {"stop", r.fit.stop_reason},
            {"fitted_scene", fitted_name}};
  for (const auto& [name, v] : r.fit.before) j["parameters_before"][name] = v;
  for (const auto& [name, v] : r.fit.after) j["parameters_after"][name] = v;
  const std::string name = r.scene + ".json";
  writeText(out / name, j.dump(2) + "\n");
  files.push_back(name);
  return r;
}

void writeSummary(const FitArgs& a, const fs::path& out, const std::vector<SceneFit>& fits,
                  std::vector<std::string> files, const std::string& command) {
  std::string md = fmt::format(
      "# The empirical shader fitted to the {} reference\n"
      "<!-- Generated by translucent fit (its fit.json beside it): do not edit. -->\n\n"
      "Generated by `{}`.\n\n"
      "Relative RMSE of the technique's radiance against the reference over the interior pixels "
      "(compare's metric, noise taken out), with the technique's defaults and after fitting its "
      "parameters (k_a, K_d, w_d, w_s, w_b, the thickness exponent r, K_b; Gascons 2011, Eqs. "
      "3.6-3.10) per scene by BOBYQA. The fitted scene files (`<scene>-fitted.json`) open in the "
      "explorer with these values as its starting point.\n\n"
      "| scene | material | before | after | renders | seconds |\n|---|---|---:|---:|---:|---:|\n",
      a.reference, command);
  json rows = json::array();
  std::vector<double> before, after;
  for (const SceneFit& f : fits) {
    if (!f.error.empty()) {
      md += fmt::format("| {} | {} | failed: {} | | | |\n", f.scene, f.material, f.error);
      rows.push_back({{"scene", f.scene}, {"error", f.error}});
      continue;
    }
    md += fmt::format("| {} | {} | {} | {} | {} | {:.1f} |\n", f.scene, f.material,
                      pct(f.fit.before_metrics.rel_rmse), pct(f.fit.after_metrics.rel_rmse),
                      f.fit.evaluations, f.fit.seconds);
    before.push_back(f.fit.before_metrics.rel_rmse);
    after.push_back(f.fit.after_metrics.rel_rmse);
    json p;
    for (const auto& [name, v] : f.fit.after) p[name] = v;
    rows.push_back({{"scene", f.scene}, {"material", f.material},
                    {"before", num(f.fit.before_metrics.rel_rmse)},
                    {"after", num(f.fit.after_metrics.rel_rmse)},
                    {"evaluations", f.fit.evaluations}, {"seconds", f.fit.seconds},
                    {"parameters", p}});
  }
  auto median = [](std::vector<double> v) {
    if (v.empty()) return std::nan("");
    std::sort(v.begin(), v.end());
    return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
  };
  if (!before.empty())
    md += fmt::format("\nMedian over the scenes: {} before, {} after.\n", pct(median(before)),
                      pct(median(after)));
  writeText(out / "fit.md", md);
  files.push_back("fit.md");
  json j = {{"generator", kGenerator}, {"command", command}, {"reference", a.reference},
            {"scenes", rows}, {"files", files}};
  writeText(out / "fit.json", j.dump(2) + "\n");
}

void runFit(const FitArgs& a) {
  if (a.technique != "empirical")
    throw ParameterError(fmt::format("fit: technique '{}': only the empirical shader has artist "
                                     "parameters to fit (valid: empirical)", a.technique));
  if (!a.scene.empty() && !a.suite.empty())
    throw ParameterError("fit: give a scene or --suite, not both");
  const analysis::ReferenceKind kind = analysis::parseReferenceKind(a.reference, "--reference");
  const uint64_t count = parseCount(kind == analysis::ReferenceKind::Physical ? a.photons : a.samples,
                                    kind == analysis::ReferenceKind::Physical ? "--photons" : "--samples");
  if (a.max_evaluations < 1 || a.max_evaluations > 100000)
    throw ParameterError(fmt::format("--max-evaluations {}: expected 1 to 100000", a.max_evaluations));
  std::vector<std::string> scenes;
  if (!a.suite.empty())
    for (const fs::path& f : analysis::suiteSceneFiles(fs::absolute(a.suite), "--suite"))
      scenes.push_back(f.string());
  else
    scenes.push_back(a.scene);
  if (!beginWork()) return;
  const fs::path out = fs::absolute(a.out);
  // Created, or empty, or a previous fit's (its fit.json lists the files it wrote, which are
  // removed); anything else needs --force, so a user's files are never overwritten.
  analysis::prepareOwnedFolder(out, a.force, {}, "--out", "fit.json", kGenerator, "a previous fit");
  const fs::path cacheDir = a.cache.empty() ? analysis::defaultReferenceCacheDirectory() : fs::path(a.cache);
  const std::optional<analysis::ReferenceCache> cache =
      a.no_cache ? std::nullopt : std::optional<analysis::ReferenceCache>(cacheDir);
  std::string command = fmt::format("translucent fit {}", a.technique);
  if (!a.suite.empty()) command += " --suite " + a.suite;
  else if (!a.scene.empty()) command += " " + a.scene;
  command += fmt::format(" --reference {} --{} {} --subpixels {} --seed {}", a.reference,
                         kind == analysis::ReferenceKind::Physical ? "photons" : "samples",
                         count, a.subpixels, a.seed);
  if (a.width) command += fmt::format(" --width {}", *a.width);
  if (a.height) command += fmt::format(" --height {}", *a.height);
  command += fmt::format(" --max-evaluations {} --out {}", a.max_evaluations, a.out);
  std::vector<SceneFit> fits;
  std::vector<std::string> files;
  for (const std::string& f : scenes) {
    if (InterruptGuard::interrupted()) break;
    try {
      fits.push_back(fitScene(a, f, out, kind, count, cache, files));
    } catch (const std::exception& e) {
      if (a.suite.empty()) throw;  // a single scene: its error is the command's
      SceneFit failed;
      failed.scene = fs::path(f).stem().string();
      failed.error = e.what();
      try {
        failed.material = scene::loadScene(f).preset;
      } catch (const std::exception&) {
        // the error above says what is wrong with the scene
      }
      printStderr("fit {}: failed: {}\n", failed.scene, failed.error);
      fits.push_back(std::move(failed));
    }
    writeSummary(a, out, fits, files, command);  // after every scene: a stop keeps what is done
  }
  printStderr("fit: {}wrote {}\n", stoppedEarly(InterruptGuard::interrupted()), (out / "fit.md").string());
}

}  // namespace

void addFitCommand(CLI::App& app) {
  auto a = std::make_shared<FitArgs>();
  auto* cmd = app.add_subcommand(
      "fit", "Fit a technique's artist parameters to a reference of each scene (the empirical "
             "shader of Gascons 2011 against the path tracer): per scene the values, the errors "
             "before and after, and a scene file with the fitted values");
  cmd->add_option("technique", a->technique, "The technique to fit: empirical")->required();
  cmd->add_option("scene", a->scene, "Scene file (JSON); omitted: the built-in bunny");
  cmd->add_option("--suite", a->suite, "Fit every scene (*.json) of this folder");
  cmd->add_option("--reference", a->reference, "The reference to fit to: physical or model")
      ->check(CLI::IsMember({"physical", "model"}))
      ->capture_default_str();
  cmd->add_option("--photons", a->photons, "Physical reference: photons per channel")->capture_default_str();
  cmd->add_option("--samples", a->samples, "Model reference: surface samples")->capture_default_str();
  cmd->add_option("--subpixels", a->subpixels, "Model reference: camera rays per pixel per axis")
      ->capture_default_str();
  cmd->add_option("--seed", a->seed, "Seed of the reference")->capture_default_str();
  cmd->add_option("--threads", a->threads, "Reference worker threads (0: all cores)")->capture_default_str();
  cmd->add_option("--width", a->width, "Image width [pixels] (default: the scene camera's)");
  cmd->add_option("--height", a->height, "Image height [pixels] (default: the scene camera's)");
  cmd->add_option("--max-evaluations", a->max_evaluations, "Renders per scene at most")
      ->capture_default_str();
  cmd->add_option("--cache", a->cache, "Reference cache folder (compare's; default: "
                                       "$TRANSLUCENT_CACHE_DIR or ~/.cache/translucent/references)");
  cmd->add_flag("--no-cache", a->no_cache, "Neither read nor store cached references");
  outputOption(cmd->add_option("--out", a->out, "Output folder (created; a previous fit there is "
                                                "replaced)"))
      ->required();
  cmd->add_flag("--force", a->force, "Write into --out even when it holds other files");
  cmd->callback([a] { runFit(*a); });
}

}  // namespace translucent::cli
