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
#include <sstream>
#include <thread>

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <fstream>

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

// --budget's default [s]: a technique or reference still running after it is stopped.
constexpr double kDefaultBudget = 120.0;

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
  std::string physical_method = "light";   // --physical-method: photons or camera paths
  std::string physical_samples = "256";    // --physical-samples: camera paths per pixel
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
  double budget = kDefaultBudget;  // --budget: seconds per technique and per reference, 0: none
};

using analysis::makeTechniqueSpec;
using analysis::parseTechniqueSpec;
using analysis::renderTimed;
using analysis::utcNow;

std::vector<std::string> techniqueList(const std::string& text) {
  const std::vector<std::string> all = techniques::names();
  if (text == "all") return all;
  // Only the references (the model against the physical truth, e.g. one run per model of
  // scripts/model-leaderboard).
  if (text == "none") return {};
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
    throw ParameterError(fmt::format("--techniques '{}': expected a list of techniques, all or none", text));
  return out;
}

std::string quoted(const std::string& s) {
  if (!s.empty() && s.find_first_of(" \t'\"\\$`;&|<>()*?") == std::string::npos) return s;
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// ---- A technique in a process of its own -----------------------------------------------------
// A technique renders in a worker process with its own GL context: one that runs past
// --budget, or that is still inside a draw call when Ctrl-C or SIGTERM asks the run to stop, is
// ended (SIGKILL) and the others continue. The child sends its images and timings back through a
// temporary file; compare computes the metrics from them.

// A rendering of a technique's sweep (its quality parameter at one value), or why it failed.
struct SweepRender {
  std::string parameter;
  double value = 0.0;
  std::string failure;  // "" when it rendered
  double frame_ms = 0.0;
  analysis::TechniqueImages images;
};

struct WorkerResult {
  std::string gpu;    // renderer and GL version
  std::string error;  // the technique failed on the scene
  std::vector<std::pair<std::string, std::string>> parameters;
  analysis::TimedRender render;
  std::vector<std::string> sweep_notes;
  std::vector<SweepRender> sweep;
};

class Bytes {
 public:
  Bytes() = default;
  explicit Bytes(std::string b) : b_(std::move(b)) {}
  const std::string& str() const { return b_; }
  template <class T> void put(T v) { b_.append(reinterpret_cast<const char*>(&v), sizeof v); }
  void put(const std::string& s) { put<uint64_t>(s.size()); b_ += s; }
  void put(const std::vector<float>& v) {
    put<uint64_t>(v.size());
    b_.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(float));
  }
  void put(const analysis::CompareImage& im) { put<int32_t>(im.width); put<int32_t>(im.height); put(im.rgb); put(im.se); }
  void put(const analysis::TechniqueImages& im) {
    put(im.name);
    put<int32_t>(static_cast<int32_t>(im.convention));
    put(im.radiance);
    put(im.exitance);
  }
  template <class T> T get() {
    T v;
    read(&v, sizeof v);
    return v;
  }
  std::string text() {
    std::string s(size(1), '\0');
    read(s.data(), s.size());
    return s;
  }
  std::vector<float> floats() {
    std::vector<float> v(size(sizeof(float)));
    read(v.data(), v.size() * sizeof(float));
    return v;
  }
  analysis::CompareImage image() {
    analysis::CompareImage im;
    im.width = get<int32_t>();
    im.height = get<int32_t>();
    im.rgb = floats();
    im.se = floats();
    return im;
  }
  analysis::TechniqueImages images() {
    analysis::TechniqueImages im;
    im.name = text();
    im.convention = static_cast<bssrdf::ExitConvention>(get<int32_t>());
    im.radiance = image();
    im.exitance = image();
    return im;
  }

 private:
  size_t size(size_t unit) {
    const auto n = get<uint64_t>();
    if (n > (b_.size() - pos_) / unit) throw std::runtime_error("technique result truncated");
    return static_cast<size_t>(n);
  }
  void read(void* p, size_t n) {
    if (n > b_.size() - pos_) throw std::runtime_error("technique result truncated");
    if (n) std::memcpy(p, b_.data() + pos_, n);
    pos_ += n;
  }
  std::string b_;
  size_t pos_ = 0;
};

std::string encode(const WorkerResult& w) {
  Bytes b;
  b.put(w.gpu);
  b.put(w.error);
  b.put<uint64_t>(w.parameters.size());
  for (const auto& [k, v] : w.parameters) { b.put(k); b.put(v); }
  b.put(w.render.images);
  b.put<uint64_t>(w.render.passes.size());
  for (const PassStat& p : w.render.passes) {
    b.put(p.name);
    b.put<int32_t>(p.depth);
    b.put(p.median_ms);
    b.put(p.min_ms);
    b.put(p.max_ms);
  }
  b.put(w.render.frame_ms);
  b.put<uint64_t>(w.render.notes.size());
  for (const std::string& n : w.render.notes) b.put(n);
  b.put<uint64_t>(w.sweep_notes.size());
  for (const std::string& n : w.sweep_notes) b.put(n);
  b.put<uint64_t>(w.sweep.size());
  for (const SweepRender& r : w.sweep) {
    b.put(r.parameter);
    b.put(r.value);
    b.put(r.failure);
    b.put(r.frame_ms);
    b.put(r.images);
  }
  return b.str();
}

WorkerResult decode(std::string bytes) {
  Bytes b(std::move(bytes));
  WorkerResult w;
  w.gpu = b.text();
  w.error = b.text();
  for (auto n = b.get<uint64_t>(); n--;) {
    std::string k = b.text();
    w.parameters.emplace_back(std::move(k), b.text());
  }
  w.render.images = b.images();
  for (auto n = b.get<uint64_t>(); n--;) {
    PassStat p;
    p.name = b.text();
    p.depth = b.get<int32_t>();
    p.median_ms = b.get<double>();
    p.min_ms = b.get<double>();
    p.max_ms = b.get<double>();
    w.render.passes.push_back(std::move(p));
  }
  w.render.frame_ms = b.get<double>();
  for (auto n = b.get<uint64_t>(); n--;) w.render.notes.push_back(b.text());
  for (auto n = b.get<uint64_t>(); n--;) w.sweep_notes.push_back(b.text());
  for (auto n = b.get<uint64_t>(); n--;) {
    SweepRender r;
    r.parameter = b.text();
    r.value = b.get<double>();
    r.failure = b.text();
    r.frame_ms = b.get<double>();
    r.images = b.images();
    w.sweep.push_back(std::move(r));
  }
  return w;
}

// The child's work: a context, the technique prepared for the scene, its timed render and (with
// --sweep) its quality parameters over their sweep values.
WorkerResult renderTechnique(const std::string& name, const scene::Scene& s, int warmup,
                             int frames, bool sweep) {
  WorkerResult w;
  gpu::Context gl;
  w.gpu = fmt::format("{} ({})", gl.info().renderer, gl.info().version);
  std::unique_ptr<techniques::Technique> t;
  try {
    // The scene's settings belong to the scene's technique; the others run at their defaults;
    // then a variant's own settings.
    t = makeTechniqueSpec(name, &s);
    printStderr("{}: preparing on {}\n", name, w.gpu);
    t->prepare(s, gl);
    w.render = renderTimed(*t, name, s, warmup, frames);
    printStderr("  frame {:.3f} ms (median of {}), L by the {} convention{}\n", w.render.frame_ms,
                frames, toString(w.render.images.convention),
                w.render.images.exitance.empty() ? ", no exitance" : "");
    for (const auto& p : t->parameters())
      w.parameters.emplace_back(p.name, techniques::toString(t->parameter(p.name)));
  } catch (const std::exception& e) {
    w.error = e.what();
    if (t)
      for (const auto& p : t->parameters())
        w.parameters.emplace_back(p.name, techniques::toString(t->parameter(p.name)));
    return w;
  }
  if (!sweep) return w;
  // The sweep: each quality parameter over its values (the others as above), then restored. A
  // value that fails ends that parameter's sweep with a note; the technique's own result stands.
  // A sweep measures the real-time image at each value: a technique that accumulates frames into
  // a converged image (tsis) would give every sample count the same converged error, so its
  // accumulation is off during the sweep.
  for (const auto& p : t->parameters())
    if (p.name == "accumulate" && p.type == techniques::ParameterType::Bool) {
      t->setParameter(p.name, false);
      w.sweep_notes.push_back("sweep: accumulate false (real-time frames)");
    }
  for (const auto& p : t->parameters()) {
    if (p.sweep.empty()) continue;
    const techniques::ParameterValue keep = t->parameter(p.name);
    for (double v : p.sweep) {
      SweepRender r;
      r.parameter = p.name;
      r.value = v;
      try {
        t->setParameter(p.name, v);
        analysis::TimedRender sr = renderTimed(*t, name, s, warmup, frames);
        printStderr("  sweep {} = {:g}: {:.3f} ms\n", p.name, v, sr.frame_ms);
        r.frame_ms = sr.frame_ms;
        r.images = std::move(sr.images);
        w.sweep.push_back(std::move(r));
      } catch (const std::exception& e) {
        r.failure = fmt::format("sweep {} = {:g} failed, sweep of {} stopped: {}", p.name, v,
                                p.name, e.what());
        printStderr("  {}\n", r.failure);
        w.sweep.push_back(std::move(r));
        break;
      }
    }
    t->setParameter(p.name, keep);
  }
  return w;
}

// How a technique's process ended.
struct Isolated {
  enum class End { Done, OverBudget, Stopped, Crashed } end = End::Done;
  WorkerResult result;  // when Done
  double seconds = 0.0;
  std::string why;      // when Crashed
};

// A temporary file that is removed when it goes out of scope.
struct TempFile {
  std::string path;
  explicit TempFile(const char* suffix) {
    // In the system's temporary folder ($TMPDIR), named by mkstemps: its template ends in six
    // 'X' before the suffix.
    std::string t = (fs::temp_directory_path() / "translucent-technique-").string() +
                    std::string(6, 'X') + suffix;
    const int fd = mkstemps(t.data(), static_cast<int>(std::strlen(suffix)));
    if (fd < 0)
      throw std::runtime_error(fmt::format("cannot create a temporary file: {}", std::strerror(errno)));
    ::close(fd);
    path = t;
  }
  ~TempFile() { ::unlink(path.c_str()); }
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;
};

// Runs renderTechnique in a worker process (`translucent compare-worker`, a fresh program: not a
// fork of this one, whose threads, locks and GL driver a forked child would inherit half-way:
// oneTBB and the sanitizers' allocators do not survive that, and a driver the parent started
// cannot be used in a forked child), ended after `budget` seconds (0: none) or when a signal asks
// the run to stop. The worker reads the scene from a temporary JSON file (scene::toJson round
// trips) and writes its result to another; it runs in a process group of its own, so Ctrl-C in
// the terminal reaches only compare, which ends the worker.
Isolated runIsolated(const std::string& name, const scene::Scene& s, const CompareArgs& a,
                     bool watchSignal) {
  const TempFile scene_file(".json"), result(".bin");
  scene::saveScene(s, scene_file.path);
  std::vector<std::string> args = {"translucent", "compare-worker", "--scene", scene_file.path,
                                   "--technique", name, "--warmup", std::to_string(a.warmup),
                                   "--frames", std::to_string(a.frames), "--result", result.path};
  if (a.sweep && !InterruptGuard::interrupted()) args.push_back("--sweep");
  std::vector<char*> argv;
  for (std::string& arg : args) argv.push_back(arg.data());
  argv.push_back(nullptr);
  std::fflush(stdout);
  std::fflush(stderr);
  posix_spawnattr_t attr;
  posix_spawnattr_init(&attr);
  posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETPGROUP);
  posix_spawnattr_setpgroup(&attr, 0);
  const auto t0 = std::chrono::steady_clock::now();
  pid_t pid = 0;
  const int spawned = posix_spawn(&pid, "/proc/self/exe", nullptr, &attr, argv.data(), environ);
  posix_spawnattr_destroy(&attr);
  if (spawned != 0)
    throw std::runtime_error(fmt::format("cannot start the technique's process: {}", std::strerror(spawned)));
  Isolated out;
  int status = 0;
  double nextLine = 10.0;
  for (;;) {
    const pid_t r = ::waitpid(pid, &status, WNOHANG);
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (r == pid) break;
    if (r < 0 && errno != EINTR) throw std::runtime_error(fmt::format("waitpid: {}", std::strerror(errno)));
    if (out.end == Isolated::End::Done) {
      if (watchSignal && InterruptGuard::interrupted()) {
        out.end = Isolated::End::Stopped;
        ::kill(pid, SIGKILL);
      } else if (a.budget > 0.0 && out.seconds > a.budget) {
        out.end = Isolated::End::OverBudget;
        ::kill(pid, SIGKILL);
      } else if (out.seconds >= nextLine) {
        printStderr("compare: {}: running for {}{}\n", name, clockText(out.seconds),
                    a.budget > 0.0 ? fmt::format(" of its budget of {}", clockText(a.budget)) : "");
        nextLine += 10.0;
      }
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  if (out.end != Isolated::End::Done) return out;
  if (watchSignal && InterruptGuard::interrupted() &&
      !(WIFEXITED(status) && WEXITSTATUS(status) == 0)) {
    out.end = Isolated::End::Stopped;
    return out;
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    out.end = Isolated::End::Crashed;
    out.why = WIFSIGNALED(status)
                  ? fmt::format("its process ended by signal {} ({})", WTERMSIG(status),
                                strsignal(WTERMSIG(status)))
                  : fmt::format("its process exited with status {}", WEXITSTATUS(status));
    return out;
  }
  std::ifstream f(result.path, std::ios::binary | std::ios::ate);
  const std::streamoff size = f ? static_cast<std::streamoff>(f.tellg()) : -1;
  if (size < 0) throw std::runtime_error(fmt::format("cannot read the result of {}", name));
  std::string bytes(static_cast<size_t>(size), '\0');
  f.seekg(0);
  f.read(bytes.data(), size);
  if (!f) throw std::runtime_error(fmt::format("cannot read the result of {}", name));
  out.result = decode(std::move(bytes));
  return out;
}

// The options that apply to every scene, checked once (before a suite's first scene).
struct Parsed {
  std::vector<std::string> names;
  std::vector<analysis::ReferenceKind> kinds;
  uint64_t photons = 0, samples = 0;
  uint64_t physicalSamples = 0;  // --physical-samples (camera method)
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
  p.physicalSamples = parseCount(a.physical_samples, "--physical-samples");
  if (a.physical_method == "camera" && !a.reference_from.empty())
    throw ParameterError("--reference-from: the runs of `pathtrace mesh` it reads are the light "
                         "method's; not with --physical-method camera");
  if (a.subpixels < 1 || a.subpixels > 16)
    throw ParameterError(fmt::format("--subpixels {}: expected 1 to 16", a.subpixels));
  if (a.frames < 1) throw ParameterError(fmt::format("--frames {}: expected at least 1", a.frames));
  if (a.warmup < 0) throw ParameterError(fmt::format("--warmup {}: expected 0 or more", a.warmup));
  if (a.threads < 0) throw ParameterError(fmt::format("--threads {}: expected >= 0", a.threads));
  if (!std::isfinite(a.budget) || a.budget < 0.0 || a.budget > 1e9)
    throw ParameterError(fmt::format("--budget {}: expected seconds in [0, 1e9] (0: no limit)", a.budget));
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
  std::vector<std::string> over_budget;         // stopped by --budget (not an error)
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
  cmd += fmt::format(" --budget {:g}", a.budget);
  cmd += a.material.commandLine();
  for (const std::string& f : a.reference_from) cmd += " --reference-from " + quoted(f);
  if (a.reference_device != "cpu") cmd += " --reference-device " + a.reference_device;
  if (a.physical_method != "light")
    cmd += fmt::format(" --physical-method {} --physical-samples {}", a.physical_method,
                       parsed.physicalSamples);
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
                     {"physical_method", a.physical_method},
                     {"physical_samples", std::to_string(parsed.physicalSamples)},
                     {"seed", std::to_string(a.seed)},
                     {"threads", std::to_string(a.threads)},
                     {"width", std::to_string(s.camera.width)},
                     {"height", std::to_string(s.camera.height)},
                     {"frames", std::to_string(a.frames)},
                     {"warmup", std::to_string(a.warmup)},
                     {"budget", fmt::format("{:g}", a.budget)},
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
    const bool camera = physical && a.physical_method == "camera";
    if (camera) {
      req.method = "camera";
      req.count = parsed.physicalSamples;
    }
    const char* unit = camera ? "camera paths per pixel and channel"
                              : physical ? "photons per channel" : "surface samples";
    ProgressBar bar(fmt::format("compare: {} reference", toString(kind)),
                    camera ? "paths" : physical ? "photons" : "pixels",
                    a.budget > 0.0 ? std::optional<double>(a.budget) : std::nullopt);
    printStderr("{} reference ({} {}):\n", toString(kind), req.count, unit);
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
    if (ref.partial && !InterruptGuard::interrupted()) {
      // Stopped by --budget: the reference is what it traced so far (fewer photons or samples).
      const std::string over = fmt::format(
          "{} reference over budget: stopped after --budget {:g} s with {} of {} {} (partial)",
          toString(kind), a.budget, ref.count_done, req.count, unit);
      printStderr("{}\n", over);
      report.notes.push_back(over);
    }
    const std::string what = analysis::referenceOrigin(ref);
    printStderr("{} reference: {}\n", toString(kind), what);
    report.notes.push_back(fmt::format("{} reference: {}", toString(kind), what));
    report.partial = report.partial || ref.partial;
    report.references.push_back(std::move(ref));
  }
  std::span<const float> coverage;
  for (const auto& r : report.references)
    if (r.kind == analysis::ReferenceKind::Model) coverage = r.coverage;
  report.masks = analysis::compareMasks(s, mesh, coverage,
                                        analysis::physicalConeAngle(report.references));
  // With both references the report says where each technique's error is (diagnosis.h).
  report.regions = analysis::reportRegions(s, mesh, report.references, report.masks.interior);
  const double eta = s.medium.eta;
  analysis::MetricOptions display;
  display.exposure = s.exposure;
  display.gamma = s.gamma;

  // ---- Techniques --------------------------------------------------------------------------
  // Each in a process of its own (runIsolated), stopped after --budget; the report is written
  // after each one, so that a stop, a budget or a crash keeps the techniques done.
  std::set<bssrdf::ExitConvention> conventions;
  std::vector<plot::XySeries> sweepSeries;
  const auto techniquesStarted = std::chrono::steady_clock::now();
  double finishedSeconds = 0.0;
  size_t finished = 0;
  // A stop during the references leaves them partial and the techniques still render (each
  // within --budget); a stop during the techniques ends the one running and skips the rest.
  const bool stoppedBefore = InterruptGuard::interrupted();
  // Writes the report as it stands: the model's rows under the conventions seen so far.
  const auto writeNow = [&](const analysis::CompareReport& r, bool inProgress) {
    analysis::CompareReport copy = r;
    std::set<bssrdf::ExitConvention> convs = conventions;
    if (convs.empty()) convs.insert(bssrdf::ExitConvention::Jensen);
    for (const auto conv : convs) {
      const auto rows = analysis::modelMetrics(copy.references, conv, eta, copy.masks, display);
      copy.metrics.insert(copy.metrics.end(), rows.begin(), rows.end());
    }
    if (inProgress) {
      copy.partial = true;
      copy.notes.push_back(fmt::format("in progress: {} of {} techniques done", r.techniques.size(),
                                       names.size()));
    }
    return analysis::writeReport(out, copy);
  };
  for (size_t i = 0; i < names.size(); ++i) {
    const std::string& name = names[i];
    if (!stoppedBefore && InterruptGuard::interrupted()) {
      report.notes.push_back(fmt::format("{} not run (stopped by {})", name, stopSignalName()));
      report.partial = true;
      continue;
    }
    {
      const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() -
                                                           techniquesStarted).count();
      const double perTechnique = finished ? finishedSeconds / double(finished) : -1.0;
      const double remaining = static_cast<double>(names.size() - i);
      const double etaSeconds = perTechnique >= 0.0 ? perTechnique * remaining : -1.0;
      printStderr("compare: technique {}/{}: {} (elapsed {}, ETA {}{})\n", i + 1, names.size(),
                  name, clockText(elapsed), clockText(etaSeconds),
                  a.budget > 0.0 ? fmt::format(", at most {}", clockText(a.budget * remaining)) : "");
    }
    analysis::TechniqueRun run;
    run.images.name = name;
    run.description = techniques::description(parseTechniqueSpec(name).base);
    const Isolated iso = runIsolated(name, s, a, !stoppedBefore);
    if (iso.end == Isolated::End::Stopped) {
      const std::string what = fmt::format("{} stopped by {} after {:.1f} s: not in the report",
                                           name, stopSignalName(), iso.seconds);
      printStderr("compare: {}\n", what);
      report.notes.push_back(what);
      report.partial = true;
      continue;
    }
    ++finished;
    finishedSeconds += iso.seconds;
    if (iso.end == Isolated::End::OverBudget) {
      run.over_budget = true;
      run.error = fmt::format("over budget: stopped after {:.1f} s (--budget {:g} s)", iso.seconds,
                              a.budget);
    } else if (iso.end == Isolated::End::Crashed) {
      run.error = iso.why;
    } else {
      const WorkerResult& w = iso.result;
      if (report.gpu.empty()) report.gpu = w.gpu;
      run.parameters = w.parameters;
      run.error = w.error;
    }
    if (run.failed()) {
      printStderr("{}: {}{}\n", name, run.over_budget ? "" : "failed: ", run.error);
      report.techniques.push_back(std::move(run));
      writeNow(report, i + 1 < names.size());
      continue;
    }
    analysis::TimedRender r = iso.result.render;
    const std::vector<PairMetrics> rows =
        analysis::techniqueMetrics(r.images, report.references, eta, report.masks, display);
    run.passes = r.passes;
    run.frame_ms = r.frame_ms;
    run.timed_frames = a.frames;
    run.warmup_frames = a.warmup;
    run.notes = r.notes;
    run.images = std::move(r.images);
    conventions.insert(run.images.convention);
    report.metrics.insert(report.metrics.end(), rows.begin(), rows.end());
    run.notes.insert(run.notes.end(), iso.result.sweep_notes.begin(), iso.result.sweep_notes.end());
    // The sweep's points, one series per parameter and reference.
    std::string parameter;
    std::map<std::string, plot::XySeries> series;  // per reference
    const auto flush = [&] {
      for (auto& [ref, xy] : series) sweepSeries.push_back(std::move(xy));
      series.clear();
    };
    for (const SweepRender& sr : iso.result.sweep) {
      if (sr.parameter != parameter) flush();
      parameter = sr.parameter;
      if (!sr.failure.empty()) {
        run.notes.push_back(sr.failure);
        continue;
      }
      analysis::SweepPoint point{name, sr.parameter, sr.value, sr.frame_ms,
                                 analysis::techniqueMetrics(sr.images, report.references, eta,
                                                            report.masks, display)};
      for (const PairMetrics& m : point.metrics) {
        if (m.quantity != "radiance") continue;
        auto& xy = series[m.reference];
        xy.label = fmt::format("{} {} vs {}", name, sr.parameter, m.reference);
        xy.x.push_back(sr.frame_ms);
        xy.y.push_back(100.0 * m.metrics.rel_rmse);
      }
      report.sweep.push_back(std::move(point));
    }
    flush();
    printStderr("compare: {} done in {:.1f} s\n", name, iso.seconds);
    report.techniques.push_back(std::move(run));
    writeNow(report, i + 1 < names.size());
  }
  if (a.sweep && InterruptGuard::interrupted())
    report.notes.push_back(fmt::format("sweep skipped (stopped by {})", stopSignalName()));
  if (conventions.empty()) conventions.insert(bssrdf::ExitConvention::Jensen);
  for (const auto conv : conventions) {
    const auto rows = analysis::modelMetrics(report.references, conv, eta, report.masks, display);
    report.metrics.insert(report.metrics.end(), rows.begin(), rows.end());
  }

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
    if (t.over_budget) {
      fmt::print("{:<12} {}\n", t.images.name, t.error);
      outcome.over_budget.push_back(t.images.name);
      continue;
    }
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
  cmd += fmt::format(" --budget {:g}", a.budget);
  cmd += a.material.commandLine();
  for (const std::string& f : a.reference_from) cmd += " --reference-from " + quoted(f);
  if (a.reference_device != "cpu") cmd += " --reference-device " + a.reference_device;
  if (a.physical_method != "light")
    cmd += fmt::format(" --physical-method {} --physical-samples {}", a.physical_method,
                       o.physicalSamples);
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

namespace {

// `translucent compare-worker`: runIsolated's worker (hidden from --help: not for users).
void addCompareWorkerCommand(CLI::App& app) {
  struct WorkerArgs {
    std::string scene, technique, result;
    int warmup = 0, frames = 1;
    bool sweep = false;
  };
  auto w = std::make_shared<WorkerArgs>();
  auto* cmd = app.add_subcommand("compare-worker", "");
  cmd->group("");  // hidden
  cmd->add_option("--scene", w->scene)->required();
  cmd->add_option("--technique", w->technique)->required();
  cmd->add_option("--warmup", w->warmup);
  cmd->add_option("--frames", w->frames);
  cmd->add_flag("--sweep", w->sweep);
  cmd->add_option("--result", w->result)->required();
  cmd->callback([w] {
    if (!beginWork()) return;
    std::signal(SIGINT, SIG_IGN);  // compare watches the signals and ends this process
    // The scene's file names are as compare resolved them: absolute or relative to the working
    // directory, which this process shares (not relative to the temporary file's folder).
    std::ifstream in(w->scene, std::ios::binary);
    std::stringstream text;
    text << in.rdbuf();
    if (!in) throw std::runtime_error(fmt::format("cannot read '{}'", w->scene));
    const scene::Scene s = scene::parseScene(text.str(), fs::current_path(), "compare's scene");
    const std::string bytes = encode(renderTechnique(w->technique, s, w->warmup, w->frames, w->sweep));
    std::ofstream f(w->result, std::ios::binary | std::ios::trunc);
    f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    f.close();
    if (!f) throw std::runtime_error(fmt::format("cannot write '{}'", w->result));
  });
}

}  // namespace

void addCompareCommand(CLI::App& app) {
  addCompareWorkerCommand(app);
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
                              "all,tsis:mode=hybrid:samples=900), its row named so; none: only "
                              "the references (the model against the physical truth)",
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
  cmd->add_option("--physical-method", a->physical_method,
                  "Physical reference: light (photons from the lights; its true radiance a cone "
                  "average, its L the diffusion radiance Ft·B/π) or camera (paths from the "
                  "camera: the true radiance per pixel, against which the leaderboard then ranks; "
                  "slower to converge on backlit, low-absorption scenes)")
      ->check(CLI::IsMember({"light", "camera"}))
      ->capture_default_str();
  cmd->add_option("--physical-samples", a->physical_samples,
                  "Physical reference with --physical-method camera: camera paths per pixel and "
                  "channel (e.g. 256)")
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
  cmd->add_option("--budget", a->budget,
                  fmt::format("Seconds each technique and each reference may take (0: no limit). A "
                              "technique still running then is stopped and listed as over budget "
                              "(the others continue; not an error); a reference still running "
                              "keeps the photons or samples done (partial). Every finished "
                              "technique is written to the report at once. With the defaults a "
                              "run takes at most {} techniques x {:g} s plus 2 references x {:g} "
                              "s (about {:.0f} min), whatever the renderer (a software one, "
                              "llvmpipe, included)",
                              techniques::names().size(), kDefaultBudget, kDefaultBudget,
                              (double(techniques::names().size()) + 2.0) * kDefaultBudget / 60.0))
      ->capture_default_str();
  cmd->callback([a] { runCompare(*a); });
}

}  // namespace translucent::cli
