// SPDX-License-Identifier: GPL-3.0-or-later
// `translucent compare` for one scene (apps/cli/cmd_compare.cpp compareScene): the references
// (cached as the CLI caches them), the techniques rendered and timed on the GPU, the metrics and
// the optional sweep, the report folder written by the library (analysis/report.h), returned as
// the dict of its report.json. Not bound: --suite (a loop over scenes in Python), the sweep's
// Qt plot (sweep.png: the examples plot the dict with matplotlib), --reference-from.
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <algorithm>
#include <ctime>
#include <fstream>
#include <map>
#include <random>
#include <set>

#include "translucent/compare/compare.h"
#include "translucent/compare/compare_run.h"
#include "translucent/compare/report.h"
#include "bind.h"
#include "common.h"
#include "translucent/geometry/mesh.h"
#include "translucent/gpu/context.h"
#include "translucent/io/json.h"
#include "gl_lock.h"
#include "json_py.h"
#include "translucent/scene/scene.h"
#include "translucent/techniques/registry.h"
#include "translucent/techniques/technique.h"

namespace translucent::python {

namespace {
namespace fs = std::filesystem;
using analysis::PairMetrics;
using analysis::PassStat;

using analysis::makeTechniqueSpec;
using analysis::renderTimed;
using analysis::utcNow;

struct CompareArgs {
  std::vector<std::string> names;
  std::vector<analysis::ReferenceKind> kinds;
  uint64_t photons = 0, samples = 0;
  int subpixels = 1, frames = 5, warmup = 2, threads = 0;
  uint64_t seed = 1;
  std::string reference_device = "cpu";  // of the physical reference: cpu or gpu
  std::string physical_method = "light";  // compare --physical-method: light or camera
  uint64_t physical_samples = 256;        // compare --physical-samples (camera)
  std::vector<fs::path> reference_from;   // compare --reference-from: pathtrace mesh JSON files
  bool sweep = false, force = false;
  fs::path cacheDir;  // "": off
};

// The folder removed when the call ends (out=None: a temporary report folder).
struct TemporaryFolder {
  fs::path dir;
  ~TemporaryFolder() {
    std::error_code ec;
    if (!dir.empty()) fs::remove_all(dir, ec);
  }
};

py::dict compareScene(scene::Scene s, const std::string& sceneFile, const CompareArgs& a,
                      const fs::path& out, Interruptible& stop) {
  s.camera.validate();
  analysis::prepareReportDirectory(out, a.force, a.cacheDir, "--out");
  analysis::CompareReport report;
  geometry::HoleFillStats fill;
  geometry::AlphaWrapStats wrap;
  {
    py::gil_scoped_release release;
    const geometry::TriangleMesh mesh = scene::loadSceneMesh(s, &fill, &wrap);
    scene::requireOutsideMesh(s, mesh);
    report.scene_file = sceneFile;
    report.scene = s;
    report.version = "translucent " TRANSLUCENT_VERSION;
    report.created = utcNow();
    report.cache_dir = a.cacheDir;
    report.command = fmt::format(
        "translucent.compare({}, techniques={}, photons={}, samples={}, subpixels={}, seed={}, "
        "width={}, height={}, frames={}, warmup={}, sweep={})",
        sceneFile.empty() ? "None" : "'" + sceneFile + "'", a.names, a.photons, a.samples,
        a.subpixels, a.seed, s.camera.width, s.camera.height, a.frames, a.warmup,
        a.sweep ? "True" : "False");
    if (s.mesh_fill_holes) report.notes.push_back("mesh.fill_holes: " + scene::describeHoleFill(fill));
    if (s.mesh_wrap)
      report.notes.push_back("mesh.wrap: " + scene::describeAlphaWrap(*s.mesh_wrap, wrap));
    std::string refs;
    for (auto k : a.kinds) refs += std::string(refs.empty() ? "" : ",") + toString(k);
    report.settings = {{"techniques", fmt::format("{}", fmt::join(a.names, ","))},
                       {"reference", refs},
                       {"photons_per_channel", std::to_string(a.photons)},
                       {"samples", std::to_string(a.samples)},
                       {"subpixels", std::to_string(a.subpixels)},
                       {"reference_device", a.reference_device},
                       {"physical_method", a.physical_method},
                       {"physical_samples", std::to_string(a.physical_samples)},
                       {"seed", std::to_string(a.seed)},
                       {"threads", std::to_string(a.threads)},
                       {"width", std::to_string(s.camera.width)},
                       {"height", std::to_string(s.camera.height)},
                       {"frames", std::to_string(a.frames)},
                       {"warmup", std::to_string(a.warmup)},
                       {"sweep", a.sweep ? "true" : "false"},
                       {"cache", a.cacheDir.empty() ? "off" : a.cacheDir.string()},
                       {"out", out.string()}};

    // References (cmd_compare.cpp: the material says which one is physical).
    report.material = analysis::materialReferences(scene::sceneMaterial(s, mesh));
    const std::optional<analysis::ReferenceCache> cache =
        a.cacheDir.empty() ? std::nullopt : std::optional<analysis::ReferenceCache>(a.cacheDir);
    for (const auto kind : a.kinds) {
      if (stop.interrupted()) {
        report.notes.push_back(fmt::format("{} reference skipped (Ctrl-C)", toString(kind)));
        report.partial = true;
        continue;
      }
      if (kind == analysis::ReferenceKind::Physical && !report.material.physical) {
        report.notes.push_back(
            fmt::format("physical reference skipped: {}", report.material.text));
        continue;
      }
      analysis::ReferenceRequest req;
      req.kind = kind;
      req.count = kind == analysis::ReferenceKind::Physical ? a.photons : a.samples;
      req.seed = a.seed;
      req.threads = a.threads;
      req.subpixels = a.subpixels;
      req.device = a.reference_device;
      if (kind == analysis::ReferenceKind::Physical && a.physical_method == "camera") {
        req.method = "camera";
        req.count = a.physical_samples;
      }
      analysis::Reference ref;
      if (kind == analysis::ReferenceKind::Physical && !a.reference_from.empty()) {
        // As `compare --reference-from`: the file traced for this scene, or an error saying
        // what differs in each.
        std::string why;
        std::optional<analysis::ReferenceFromFile> found =
            analysis::findPathtracedReference(a.reference_from, s, &why);
        if (!found) throw ParameterError(why);
        ref = std::move(found->reference);
        report.notes.push_back(fmt::format(
            "physical reference: read from {} ({} photons per channel, seed {}, traced in {:.2f} s)",
            found->file.string(), ref.count_done, ref.request.seed, ref.seconds));
        report.references.push_back(std::move(ref));
        continue;
      }
      try {
        ref = analysis::cachedReference(s, mesh, req, cache ? &*cache : nullptr, stop.callback());
        stop.finish();  // a run projected past 24 hours is refused, as the CLI's progress bar does
      } catch (const ParameterError& e) {
        throw ParameterError(fmt::format("{} reference: {}", toString(kind), e.what()));
      } catch (const std::exception& e) {
        throw std::runtime_error(fmt::format("{} reference: {}", toString(kind), e.what()));
      }
      const std::string what = analysis::referenceOrigin(ref);
      report.notes.push_back(fmt::format("{} reference: {}", toString(kind), what));
      report.partial = report.partial || ref.partial;
      report.references.push_back(std::move(ref));
    }
    std::span<const float> coverage;
    for (const auto& r : report.references)
      if (r.kind == analysis::ReferenceKind::Model) coverage = r.coverage;
    report.masks = analysis::compareMasks(s, mesh, coverage,
                                          analysis::physicalConeAngle(report.references));
    report.regions = analysis::reportRegions(s, mesh, report.references, report.masks.interior);
  }
  const double eta = s.medium.eta;
  analysis::MetricOptions display;
  display.exposure = s.exposure;
  display.gamma = s.gamma;

  // Techniques (the module's context: created on first use, current on this thread).
  GlLock lock;
  gpu::Context& gl = lock.gl();
  report.gpu = fmt::format("{} ({})", gl.info().renderer, gl.info().version);
  std::set<bssrdf::ExitConvention> conventions;
  {
    py::gil_scoped_release release;
    for (const std::string& name : a.names) {
      if (stop.interrupted()) break;
      analysis::TechniqueRun run;
      run.images.name = name;
      run.description = techniques::description(name.substr(0, name.find(':')));
      std::unique_ptr<techniques::Technique> t;
      std::vector<PairMetrics> rows;
      try {
        t = makeTechniqueSpec(name, &s);
        t->prepare(s, gl);
        analysis::TimedRender r = renderTimed(*t, name, s, a.warmup, a.frames);
        rows = analysis::techniqueMetrics(r.images, report.references, eta, report.masks, display);
        run.passes = r.passes;
        run.frame_ms = r.frame_ms;
        run.timed_frames = a.frames;
        run.warmup_frames = a.warmup;
        run.notes = r.notes;
        run.images = std::move(r.images);
      } catch (const std::exception& e) {
        run.error = e.what();  // this technique cannot do this scene: a failed row
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
      if (a.sweep && !stop.interrupted()) {
        // As the CLI: a technique that accumulates frames sweeps its real-time frames.
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
          for (double v : p.sweep) {
            if (!stop.poll(0, 0)) break;
            try {
              t->setParameter(p.name, v);
              analysis::TimedRender sr = renderTimed(*t, name, s, a.warmup, a.frames);
              report.sweep.push_back(analysis::SweepPoint{
                  name, p.name, v, sr.frame_ms,
                  analysis::techniqueMetrics(sr.images, report.references, eta, report.masks,
                                             display)});
            } catch (const std::exception& e) {
              run.notes.push_back(fmt::format("sweep {} = {:g} failed, sweep of {} stopped: {}",
                                              p.name, v, p.name, e.what()));
              break;
            }
          }
          t->setParameter(p.name, keep);
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
    if (a.sweep && stop.interrupted()) report.notes.push_back("sweep skipped (Ctrl-C)");
    if (stop.interrupted()) report.partial = true;
    (void)analysis::writeReport(out, report);
  }
  py::dict d = toPython(io::readJsonFile(out / "report.json"));
  return d;
}

constexpr const char* kCompareDoc = R"doc(
Compares real-time techniques with the references for one scene: `translucent compare`.

    report = translucent.compare("data/scenes/cube.json", techniques=["empirical"],
                                 photons=1e5, samples=20000, frames=3)
    for m in report["metrics"]: print(m["test"], m["reference"], m["quantity"],
                                      m["metrics"]["rel_rmse"])

scene: a translucent.Scene, a scene file name, or None (the built-in bunny).
techniques: names or variants "name:key=value:..." (default: every registered technique).
references: "physical" (the volumetric path tracer, `photons` per channel) and/or "model" (the
  scene's BSSRDF integrated over the surface, `samples` samples); subpixels (1 to 16), seed,
  threads (0: all cores). reference_device: "cpu" or "gpu" (the physical reference's GL walk,
  `compare --reference-device`). physical_method: "light" (photons) or "camera" (paths from the
  camera, `physical_samples` per pixel and channel: its cone radiance is the true radiance, and
  the leaderboard ranks against it; `compare --physical-method`). reference_from: a file name or a list of them, the --json of
  `translucent pathtrace mesh` or of `translucent merge` (`compare --reference-from`): the
  physical reference is read from the one traced for this scene (a ValueError says what
  differs in each otherwise), not traced.
width, height, time: override the scene's. frames, warmup: timed and untimed frames per technique
  (GPU time: the median over the timed frames).
sweep: also render each quality parameter over its sweep values (report["sweep"]: error against
  GPU time; the CLI's sweep.png is not drawn).
cache: the reference cache folder (None: the CLI's default, ~/.cache/translucent/references;
  False: no cache). out: the report folder to write (index.html, report.json, EXRs, PNGs);
  None: a temporary folder, removed after reading its report.json. force: replace a previous
  report in `out`.
Returns report.json as a CompareReport: "metrics" (test, reference, quantity, convention, mask and the
metrics: rel_rmse, bias, ssim, flip, ...), "techniques" (frame_ms, passes, parameters, notes,
status), "references", "sweep", "notes", "partial", "scene", "settings". The GIL is released;
Ctrl-C stops the references and the techniques, and the report (then marked "partial") is still
written and returned as the KeyboardInterrupt's `partial_result`.
)doc";

}  // namespace

void bindCompare(py::module_& m) {
  m.def(
      "compare",
      [](const py::object& sceneArg, const std::optional<std::vector<std::string>>& names,
         const std::vector<std::string>& references, double photons, double samples,
         int subpixels, uint64_t seed, int threads, std::optional<int> width,
         std::optional<int> height, std::optional<double> time, int frames, int warmup,
         bool sweep, const py::object& cache, const std::optional<fs::path>& out, bool force,
         const std::string& reference_device, const py::object& reference_from,
         const std::string& physical_method, double physical_samples) {
        CompareArgs a;
        if (physical_method != "light" && physical_method != "camera")
          throw ParameterError(fmt::format(
              "physical_method='{}': expected \"light\" or \"camera\"", physical_method));
        a.physical_method = physical_method;
        a.physical_samples = photonCount(physical_samples, "physical_samples");
        const py::object pathLike = py::module_::import("os").attr("PathLike");
        if (py::isinstance<py::str>(reference_from) || py::isinstance(reference_from, pathLike)) {
          a.reference_from.push_back(pathArgument(reference_from, "reference_from"));
        } else if (!reference_from.is_none()) {
          if (!py::isinstance<py::sequence>(reference_from))
            throw py::type_error(fmt::format(
                "reference_from={}: expected a file name, a list of file names or None",
                reprOf(reference_from)));
          for (const auto& f : reference_from)
            a.reference_from.push_back(pathArgument(f, "reference_from"));
        }
        if (reference_device != "cpu" && reference_device != "gpu")
          throw ParameterError(
              fmt::format("--reference-device '{}': expected cpu or gpu", reference_device));
        a.reference_device = reference_device;
        if (physical_method == "camera" && !a.reference_from.empty())
          throw ParameterError("reference_from: the runs of `pathtrace mesh` it reads are the "
                               "light method's; not with physical_method='camera'");
        a.names = names ? *names : techniques::names();
        if (a.names.empty())
          throw ParameterError("techniques=[]: expected technique names, or None for all");
        for (const auto& n : a.names) (void)makeTechniqueSpec(n, nullptr);  // names and settings exist
        for (const auto& k : references) {
          const auto kind = analysis::parseReferenceKind(k, "references");
          if (std::find(a.kinds.begin(), a.kinds.end(), kind) == a.kinds.end())
            a.kinds.push_back(kind);
        }
        if (a.kinds.empty())
          throw ParameterError("references=[]: expected \"physical\", \"model\" or both");
        a.photons = photonCount(photons, "--photons");
        a.samples = photonCount(samples, "--samples");
        if (subpixels < 1 || subpixels > 16)
          throw ParameterError(fmt::format("--subpixels {}: expected 1 to 16", subpixels));
        if (frames < 1) throw ParameterError(fmt::format("--frames {}: expected at least 1", frames));
        if (warmup < 0) throw ParameterError(fmt::format("--warmup {}: expected 0 or more", warmup));
        if (threads < 0) throw ParameterError(fmt::format("--threads {}: expected >= 0", threads));
        if (time && !std::isfinite(*time))
          throw ParameterError(fmt::format("--time {}: expected a finite time", *time));
        a.subpixels = subpixels;
        a.frames = frames;
        a.warmup = warmup;
        a.threads = threads;
        a.seed = seed;
        a.sweep = sweep;
        a.force = force;
        if (cache.is_none())
          a.cacheDir = analysis::defaultReferenceCacheDirectory();
        else if (py::isinstance<py::bool_>(cache) && !cache.cast<bool>())
          a.cacheDir.clear();
        else if (py::isinstance<py::str>(cache) || py::isinstance(cache, pathLike))
          a.cacheDir = fs::absolute(pathArgument(cache, "cache"));
        else
          throw py::type_error(fmt::format(
              "cache={}: expected a folder name, None (the default cache) or False (none)",
              reprOf(cache)));
        scene::Scene s;
        std::string sceneFile;
        if (sceneArg.is_none()) {
          s = scene::defaultScene();
        } else if (py::isinstance<scene::Scene>(sceneArg)) {
          s = sceneArg.cast<scene::Scene>();
        } else {
          if (!py::isinstance<py::str>(sceneArg) && !py::isinstance(sceneArg, pathLike))
            throw py::type_error(fmt::format(
                "scene={}: expected a translucent.Scene, a scene file name or None",
                reprOf(sceneArg)));
          sceneFile = pathArgument(sceneArg, "scene").string();
          s = scene::loadScene(sceneFile);
        }
        if (width) s.camera.width = *width;
        if (height) s.camera.height = *height;
        if (time) s.time = *time;
        TemporaryFolder temporary;
        fs::path dir;
        if (out) {
          dir = *out;
        } else {
          std::random_device rd;
          temporary.dir = fs::temp_directory_path() /
                          fmt::format("translucent-compare-{:016x}", (uint64_t(rd()) << 32) | rd());
          dir = temporary.dir;
        }
        Interruptible stop;
        py::dict d = compareScene(std::move(s), sceneFile, a, dir, stop);
        if (out) d["out"] = dir;
        py::object report = result("CompareReport", d);
        stop.rethrow(report);
        return report;
      },
      py::arg("scene") = py::none(), py::kw_only(), py::arg("techniques") = py::none(),
      py::arg("references") = std::vector<std::string>{"physical", "model"},
      py::arg("photons") = 1e6, py::arg("samples") = 200000, py::arg("subpixels") = 1,
      py::arg("seed") = 1, py::arg("threads") = 0, py::arg("width") = py::none(),
      py::arg("height") = py::none(), py::arg("time") = py::none(), py::arg("frames") = 5,
      py::arg("warmup") = 2, py::arg("sweep") = false, py::arg("cache") = py::none(),
      py::arg("out") = py::none(), py::arg("force") = false, py::arg("reference_device") = "cpu",
      py::arg("reference_from") = py::none(), py::arg("physical_method") = "light",
      py::arg("physical_samples") = 256, kCompareDoc);
}

}  // namespace translucent::python
