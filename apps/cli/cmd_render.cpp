// SPDX-License-Identifier: GPL-3.0-or-later
// translucent render: a scene (JSON, scene/scene.h; the built-in bunny when none is given) with a
// real-time technique (techniques/registry.h) on the GPU through a headless OpenGL 4.5 context,
// written as PNG (tone mapped: exposure, gamma) and/or OpenEXR (linear radiance, plus the radiant
// exitance B in the layer "exitance"). Prints the GPU time of every pass.
//
// Every parameter of every registered technique is an option (--points, --epsilon,
// --shadow-map-size, ...; `--help` lists them with their ranges); options override the scene's
// "technique" settings. Progressive work (occluded environment lighting) is finished in each
// frame (FrameRequest::converge).
//
// Animation (mesh.deform, scene.h): --time T renders the scene at time T (default: the scene's
// "time"); --frames N renders N frames at T + i/F (--fps F, default 24) into numbered files
// (--out frame_%04d.png: one printf conversion %d or %0Nd, the frame index from 0), with a
// progress bar and ETA; --video out.mp4 also encodes them with ffmpeg (Debian's, found on PATH;
// a clear error before any rendering when it is missing). Every file goes through a temporary
// file and a rename (output_guard.h) and is checked against the inputs first.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <vector>

#include "translucent/io/image_io.h"
#include "commands.h"
#include "options.h"
#include "plot/frame_plot.h"
#include "output_guard.h"
#include "progress.h"
#include "safe_print.h"
#include "translucent/gpu/context.h"
#include "translucent/scene/scene.h"
#include "translucent/techniques/registry.h"

namespace translucent::cli {
namespace {

constexpr int kMaxFrames = 100000;  // over an hour at 24 fps

struct RenderArgs {
  std::string scene;
  std::optional<std::string> technique;
  std::optional<int> width, height;
  MediumOptions material;  // over the scene's material (options.h)
  std::string out, exr;
  std::string debug_dir;  // every frame layer as <layer>.exr (linear) and <layer>.png (scaled),
                          // every view as view-<name>.exr/.png
  std::optional<double> exposure, gamma, key;
  std::string tonemap;
  int frames = 1;
  std::optional<double> time;  // of the first frame (default: the scene's)
  double fps = 24.0;
  std::string video;  // encoded from the PNG frames by ffmpeg
  std::map<std::string, std::string> settings;  // technique parameter -> value as typed
  std::map<std::string, std::string> spelling;  // technique parameter -> the option that set it
};

std::string optionName(const std::string& parameter) {
  std::string s = parameter;
  std::replace(s.begin(), s.end(), '_', '-');
  return "--" + s;
}

std::string describe(const techniques::ParameterInfo& p) {
  std::string range;
  switch (p.type) {
    case techniques::ParameterType::Float:
    case techniques::ParameterType::Int:
      range = fmt::format(" [{}, {}]{}", p.min, p.max, p.unit.empty() ? "" : " " + p.unit);
      break;
    case techniques::ParameterType::Bool: range = " (true/false)"; break;
    case techniques::ParameterType::Enum: range = fmt::format(" ({})", fmt::join(p.choices, "|")); break;
  }
  return fmt::format("{}{}, default {}", p.help, range, techniques::toString(p.value));
}

// A frame-file pattern: the position and width of its one %d / %0Nd conversion ("%%" is a
// literal %). Throws ParameterError naming the option for anything else.
struct FramePattern {
  std::string text;
  size_t at = std::string::npos, length = 0;  // the conversion (npos: none)
  int width = 0;

  static FramePattern parse(const std::string& option, const std::string& text) {
    FramePattern p{text};
    for (size_t i = 0; i < text.size(); ++i) {
      if (text[i] != '%') continue;
      if (i + 1 < text.size() && text[i + 1] == '%') {
        ++i;
        continue;
      }
      size_t j = i + 1;
      int width = 0;
      while (j < text.size() && std::isdigit(static_cast<unsigned char>(text[j])) && j - i < 4)
        width = width * 10 + (text[j++] - '0');
      if (j >= text.size() || text[j] != 'd' || p.at != std::string::npos)
        throw ParameterError(fmt::format(
            "{} '{}': expected at most one frame-number conversion %d or %0Nd (N < 1000; %% for "
            "a literal %)", option, text));
      p.at = i;
      p.length = j + 1 - i;
      p.width = width;
      i = j;
    }
    return p;
  }
  bool numbered() const { return at != std::string::npos; }
  // The file of frame i (the pattern with %% as %).
  std::string file(int i) const {
    std::string out;
    for (size_t k = 0; k < text.size(); ++k) {
      if (numbered() && k == at) {
        out += fmt::format("{:0{}d}", i, width);
        k += length - 1;
      } else if (text[k] == '%' && k + 1 < text.size() && text[k + 1] == '%') {
        out += '%';
        ++k;
      } else {
        out += text[k];
      }
    }
    return out;
  }
};

// The executable `name` in a folder of $PATH, or "" when there is none.
std::string findOnPath(const std::string& name) {
  const char* path = std::getenv("PATH");
  if (!path) return {};
  std::string dirs = path;
  size_t start = 0;
  while (start <= dirs.size()) {
    const size_t end = std::min(dirs.find(':', start), dirs.size());
    const std::filesystem::path candidate =
        std::filesystem::path(end > start ? dirs.substr(start, end - start) : ".") / name;
    if (access(candidate.c_str(), X_OK) == 0 && std::filesystem::is_regular_file(candidate))
      return candidate.string();
    start = end + 1;
  }
  return {};
}

// Runs argv[0] (an absolute path) with its arguments, no shell; its exit status (-1: not started).
int runProgram(const std::vector<std::string>& argv) {
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  pid_t pid = 0;
  if (posix_spawn(&pid, args[0], nullptr, nullptr, args.data(), environ) != 0) return -1;
  int status = 0;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

void runRender(const RenderArgs& a) {
  if (a.frames < 1) throw ParameterError(fmt::format("--frames {}: expected at least 1", a.frames));
  // Each frame is an output checked and named before the work: a limit keeps a typo from
  // spending minutes (and gigabytes) on the names alone.
  if (a.frames > kMaxFrames)
    throw ParameterError(fmt::format("--frames {}: expected at most {} (render a longer animation "
                                     "in parts, each from its own --time)", a.frames, kMaxFrames));
  if (!(std::isfinite(a.fps) && a.fps >= 1e-3 && a.fps <= 1e4))
    throw ParameterError(fmt::format("--fps {}: expected frames per second in [0.001, 10000]",
                                     a.fps));
  if (a.time && !std::isfinite(*a.time))
    throw ParameterError(fmt::format("--time {}: expected a finite time", *a.time));
  if (!a.out.empty()) {
    auto ext = std::filesystem::path(a.out).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    if (ext != ".png") throw ParameterError(fmt::format("--out '{}': expected a .png file", a.out));
  }
  const bool animation = a.frames > 1 || !a.video.empty();
  const FramePattern outPattern = FramePattern::parse("--out", a.out);
  const FramePattern exrPattern = FramePattern::parse("--exr", a.exr);
  for (const FramePattern* p : {&outPattern, &exrPattern})
    if (a.frames > 1 && !p->text.empty() && !p->numbered())
      throw ParameterError(fmt::format(
          "{} '{}' with --frames {}: expected a pattern with the frame number, e.g. "
          "frame_%04d{}", p == &outPattern ? "--out" : "--exr", p->text, a.frames,
          p == &outPattern ? ".png" : ".exr"));
  if (animation && !a.debug_dir.empty())
    throw ParameterError("--debug-dir: for one frame only (without --frames > 1 and --video)");
  // --video: ffmpeg first (a missing encoder is an error before minutes of rendering).
  std::string ffmpeg;
  if (!a.video.empty()) {
    ffmpeg = findOnPath("ffmpeg");
    if (ffmpeg.empty())
      throw ParameterError(fmt::format(
          "--video '{}': ffmpeg is not on PATH: expected Debian's ffmpeg (apt-get install "
          "ffmpeg), or --out frame_%04d.png for the frames alone", a.video));
  }
  // --video: ffmpeg's PNG frames go to a temporary folder beside the video (the --out frames are
  // outputs, which appear only once the whole run has succeeded). A '%' of the video's name is
  // written "%%" in the pattern, for FramePattern and ffmpeg alike.
  std::filesystem::path frameDir;
  FramePattern framePattern;
  if (!a.video.empty()) {
    const std::filesystem::path v(a.video);
    frameDir = v.parent_path() / fmt::format(".{}.frames-{}", v.filename().string(), getpid());
    std::string dir = frameDir.string();
    for (size_t at = dir.find('%'); at != std::string::npos; at = dir.find('%', at + 2))
      dir.insert(at, "%");
    framePattern = FramePattern::parse("--video", dir + "/frame_%06d.png");
  }

  // Scene, with the command line's overrides.
  scene::Scene s = a.scene.empty() ? scene::defaultScene() : scene::loadScene(a.scene);
  if (a.technique) {
    // The scene's technique settings belong to the scene's technique: another one named on the
    // command line starts from its own defaults (its options still apply).
    if (*a.technique != s.technique) s.settings.clear();
    s.technique = *a.technique;
  }
  if (a.width) s.camera.width = *a.width;
  if (a.height) s.camera.height = *a.height;
  a.material.apply(s);
  if (a.exposure) s.exposure = *a.exposure;
  if (a.gamma) s.gamma = *a.gamma;
  if (!a.tonemap.empty()) {
    if (a.tonemap != "clamp" && a.tonemap != "reinhard")
      throw ParameterError(fmt::format("--tonemap '{}': expected clamp or reinhard", a.tonemap));
    s.tonemap = analysis::parseToneOperator(a.tonemap, "--tonemap");
  }
  if (a.key) s.tonemap_key = *a.key;
  if (!(s.tonemap_key > 0.0 && s.tonemap_key <= 100.0))
    throw ParameterError(fmt::format("--key is {}: expected a tone map key in (0, 100]", s.tonemap_key));
  if (a.time) s.time = *a.time;
  const double time0 = s.time;
  auto frameTime = [&](int i) { return time0 + i / a.fps; };
  s.camera.validate();
  // Tone mapping: x -> (2^exposure x)^(1/gamma). A gamma of 1e-300 or an exposure of 1e6 is a
  // legal number that maps every pixel to black or white; the ranges below hold every useful one.
  constexpr double kMinGamma = 0.01, kMaxGamma = 100.0, kMaxExposure = 64.0;
  if (!(s.gamma >= kMinGamma && s.gamma <= kMaxGamma))
    throw ParameterError(fmt::format("--gamma is {}{}: expected a display gamma in [{}, {}]",
                                     s.gamma, a.gamma ? "" : " (the scene's display.gamma)",
                                     kMinGamma, kMaxGamma));
  if (!(std::fabs(s.exposure) <= kMaxExposure))
    throw ParameterError(fmt::format("--exposure is {}{}: expected stops in [-{}, {}]", s.exposure,
                                     a.exposure ? "" : " (the scene's display.exposure)",
                                     kMaxExposure, kMaxExposure));
  // The outputs against each other and against every file the run reads, before the GPU work;
  // nothing is created until a file is complete (written via a temporary file and renamed).
  OutputSet outputs;
  for (int i = 0; i < a.frames; ++i) {
    if (!exrPattern.text.empty()) outputs.output("--exr", exrPattern.file(i));
    if (!a.out.empty()) outputs.output("--out", outPattern.file(i));
  }
  outputs.output("--video", a.video);
  outputs.sceneInputs(a.scene, s);
  outputs.check();
  // The technique with the scene's settings and the command line's (no GL yet): checked here on
  // a technique made for it, and made again after the context below.
  auto makeTechnique = [&] {
    std::unique_ptr<techniques::Technique> t = techniques::make(s.technique);
    techniques::applySettings(*t, s);
    for (const auto& [name, value] : a.settings) {
      try {
        t->setParameter(name, value);
      } catch (const ParameterError& e) {
        const auto it = a.spelling.find(name);
        throw ParameterError(fmt::format(
            "{}: {}", it != a.spelling.end() ? it->second : optionName(name), e.what()));
      }
    }
    return t;
  };
  (void)makeTechnique();
  if (!beginWork()) return;
  // A camera or light inside the object renders nothing meaningful: refuse it (the mesh is
  // loaded once more for this, about 0.1 s for the bunny; for an animation at every frame's
  // time, since a deformation may move the surface over the camera).
  scene::requireOutsideMesh(s, scene::loadSceneMesh(s));

  // The context first: the technique's GL objects must be deleted while it is alive.
  gpu::Context gl;
  std::unique_ptr<techniques::Technique> t = makeTechnique();

  fmt::print("render: {} on {} ({}), {}x{}, scene: {}{}\n", s.technique, gl.info().renderer,
             gl.info().version, s.camera.width, s.camera.height,
             a.scene.empty() ? "built-in bunny" : a.scene,
             animation ? fmt::format(", {} frames at {} fps from time {}", a.frames, a.fps, time0)
                       : s.time != 0.0 ? fmt::format(", time {}", s.time) : std::string());
  if (!frameDir.empty()) {
    std::error_code ec;
    std::filesystem::create_directory(frameDir, ec);
    if (ec)
      throw ParameterError(fmt::format("--video '{}': cannot create the frame folder '{}': {}",
                                       a.video, frameDir.string(), ec.message()));
  }
  // The temporary frame folder goes whatever happens.
  struct RemoveFolder {
    std::filesystem::path dir;
    ~RemoveFolder() {
      std::error_code ec;
      if (!dir.empty()) std::filesystem::remove_all(dir, ec);
    }
  } removeFrames{frameDir};

  // One frame at the scene's time: render until converged (each render finishes the progressive
  // work, FrameRequest::converge).
  auto renderFrame = [&]() {
    techniques::Frame f;
    for (int tries = 0; tries < 100000; ++tries) {
      techniques::FrameRequest request;
      request.converge = true;
      request.views = !a.debug_dir.empty();
      f = t->render(request);
      if (f.converged) break;
    }
    return f;
  };
  // A debug folder this run creates goes again when the run fails (once the
  // temporary files in it are gone: declared before them).
  struct RemoveEmptyFolder {
    std::filesystem::path dir;
    ~RemoveEmptyFolder() {
      std::error_code ec;
      if (!dir.empty()) std::filesystem::remove(dir, ec);  // removes an empty folder only
    }
  } removeDebugDir;
  // Every output of the run, put in place together at the end (all or nothing); the messages
  // saying what was written follow.
  OutputFiles out;
  std::vector<std::string> wrote;
  auto writeFrame = [&](const techniques::Frame& f, int i) {
    if (!outPattern.text.empty())
      out.file("--out", outPattern.file(i), [&](const std::string& p) {
        analysis::writePng(p, f.width, f.height, f.rgb, scene::displayToneMap(s));
      });
    if (!framePattern.text.empty())  // ffmpeg's input
      analysis::writePng(framePattern.file(i), f.width, f.height, f.rgb, scene::displayToneMap(s));
    if (!exrPattern.text.empty()) {
      std::vector<analysis::ExrLayer> layers;
      for (const auto& [name, data] : f.layers) layers.push_back({name, data});
      const std::pair<std::string, std::string> attrs[] = {
          {"translucent:technique", s.technique},
          {"translucent:time", fmt::format("{}", s.time)}};
      out.file("--exr", exrPattern.file(i), [&](const std::string& p) {
        analysis::writeExr(p, f.width, f.height, f.rgb, layers, attrs);
      });
    }
  };

  techniques::Frame frame;
  if (animation) {
    // Frame i at time T0 + i/F; the technique is prepared again for each time (GPU techniques
    // deform their rest mesh on the GPU, the others re-prepare: techniques/common/gl_resources.h
    // ClosedMeshState).
    // SIGINT/SIGTERM stop after the frame under way: the frames rendered so far (and the video
    // of them) are written, and the exit status says which signal stopped the run (progress.h).
    InterruptGuard guard;
    ProgressBar bar("render", "frames");
    const auto start = std::chrono::steady_clock::now();
    int done = a.frames;
    for (int i = 0; i < a.frames; ++i) {
      s.time = frameTime(i);
      if (i > 0 && !s.mesh_deform.empty()) scene::requireOutsideMesh(s, scene::loadSceneMesh(s));
      t->prepare(s, gl);
      frame = renderFrame();
      writeFrame(frame, i);
      const double seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      if (!bar.update(uint64_t(i + 1), uint64_t(a.frames), seconds) && i + 1 < a.frames) {
        bar.end();  // throws when the run was refused for its projected time
        done = i + 1;
        printStderr("render: {}{} of {} frames\n", stoppedEarly(true), done, a.frames);
        break;
      }
    }
    bar.end();
    if (!a.out.empty())
      wrote.push_back(fmt::format("wrote {} frames {} .. {}\n", done, outPattern.file(0),
                                  outPattern.file(done - 1)));
    if (!exrPattern.text.empty())
      wrote.push_back(fmt::format("wrote {} frames {} .. {}\n", done, exrPattern.file(0),
                                  exrPattern.file(done - 1)));
    if (!a.video.empty()) {
      out.file("--video", a.video, [&](const std::string& tmp) {
        const std::vector<std::string> argv = {
            ffmpeg, "-nostdin", "-loglevel", "error", "-y", "-framerate", fmt::format("{}", a.fps),
            "-i", framePattern.text, "-pix_fmt", "yuv420p",
            // yuv420p needs even sizes: pad by one pixel where odd.
            "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", tmp};
        const int rc = runProgram(argv);
        if (rc != 0)
          throw ParameterError(fmt::format("--video '{}': ffmpeg ({}) failed{}", a.video, ffmpeg,
                                           rc < 0 ? " to start" : fmt::format(" with status {}", rc)));
      });
      wrote.push_back(fmt::format("wrote {} ({} frames at {} fps, ffmpeg)\n", a.video, done,
                                  a.fps));
    }
    out.commit();
    for (const std::string& line : wrote) fmt::print("{}", line);
    fmt::print("GPU times of the last frame (time {}):\n", s.time);
    for (const auto& p : frame.passes)
      fmt::print("  {:<{}}{:<22} {:9.3f} ms\n", "", 2 * p.depth, p.name, p.ms);
    fmt::print("  {:<22} {:9.3f} ms\n", "total", frame.totalMs());
    return;
  }
  t->prepare(s, gl);
  frame = renderFrame();
  for (const auto& note : frame.notes) fmt::print("  {}\n", note);

  fmt::print("GPU times{}:\n", frame.converged ? "" : " (not converged)");
  for (const auto& p : frame.passes)
    fmt::print("  {:<{}}{:<22} {:9.3f} ms\n", "", 2 * p.depth, p.name, p.ms);
  fmt::print("  {:<22} {:9.3f} ms\n", "total", frame.totalMs());

  // The debug files are known only now: checked like the other outputs before any file is
  // written (a scene file, its mesh or environment map in the debug folder must not be replaced
  // by a layer of that name).
  if (!a.debug_dir.empty()) {
    std::error_code ec;
    if (!std::filesystem::exists(a.debug_dir, ec)) removeDebugDir.dir = a.debug_dir;
    std::filesystem::create_directories(a.debug_dir, ec);
    if (ec)
      throw ParameterError(fmt::format("--debug-dir '{}': cannot create the folder: {}",
                                       a.debug_dir, ec.message()));
    const std::filesystem::path dir(a.debug_dir);
    for (const auto& [name, view] : frame.views)
      for (const char* ext : {".exr", ".png"})
        outputs.output("--debug-dir", (dir / ("view-" + name + ext)).string());
    for (const auto& [name, data] : frame.layers)
      for (const char* ext : {".exr", ".png"})
        outputs.output("--debug-dir", (dir / (name + ext)).string());
    outputs.check();
  }

  const std::string what = fmt::format("translucent render{}", a.scene.empty() ? "" : " " + a.scene);
  // A pattern names frame 0 (--frames 1 --out frame_%04d.png writes frame_0000.png).
  const std::string exrFile = exrPattern.file(0), outFile = outPattern.file(0);
  if (!a.exr.empty()) {
    std::vector<analysis::ExrLayer> layers;
    for (const auto& [name, data] : frame.layers) layers.push_back({name, data});
    // What the pixels are depends on the technique's exit-radiance convention (seed Eq. 2.16).
    std::string quantity = "the technique's colour (RGB), not derived from an exitance";
    for (const auto& p : t->parameters())
      if (p.name == "radiance_convention") {
        // A copy: parameter() returns the value, and a reference into it would dangle.
        const std::string c = std::get<std::string>(t->parameter(p.name));
        quantity = fmt::format("radiance {} (RGB, radiance_convention {}), per unit light flux",
                               c == "jensen" ? "Ft(eta, w_o) B / pi"
                                             : "Ft(eta, w_o) B / (pi 4 C_phi(1/eta))",
                               c);
      }
    // transfer's scattering: single scattering is a true radiance, added per pixel.
    for (const auto& p : t->parameters())
      if (p.name == "scattering") {
        const std::string m = std::get<std::string>(t->parameter(p.name));
        if (m == "single")
          quantity = "single-scattering radiance L1 (RGB, per pixel along the view ray), per unit light flux";
        else if (m != "operator")
          quantity += fmt::format(", plus single scattering's radiance per pixel (scattering {})", m);
      }
    const std::pair<std::string, std::string> attrs[] = {
        {"translucent:quantity", quantity},
        {"translucent:layers", "exitance: radiant exitance B (RGB)"},
        {"translucent:technique", s.technique},
        {"translucent:source", what}};
    out.file("--exr", exrFile, [&](const std::string& p) {
      analysis::writeExr(p, frame.width, frame.height, frame.rgb, layers, attrs);
    });
    wrote.push_back(fmt::format("wrote {}: {}\n", exrFile, quantity));
  }
  if (!a.out.empty()) {
    out.file("--out", outFile, [&](const std::string& p) {
      analysis::writePng(p, frame.width, frame.height, frame.rgb, scene::displayToneMap(s));
    });
    wrote.push_back(fmt::format("wrote {}\n", outFile));
  }
  if (!a.debug_dir.empty()) {
    if (frame.layers.empty() && frame.views.empty() && frame.plots.empty())
      wrote.push_back(fmt::format("--debug-dir: technique {} has no debug layers\n", s.technique));
    // The technique's inspection views: display-ready [0, 1], written as they are.
    // (Named references, not structured bindings: clang 14 cannot capture those in the lambdas.)
    for (const auto& entry : frame.views) {
      const std::string& name = entry.first;
      const auto& view = entry.second;
      const std::string base = (std::filesystem::path(a.debug_dir) / ("view-" + name)).string();
      out.file("--debug-dir", base + ".exr", [&](const std::string& p) {
        analysis::writeExr(p, view.width, view.height, view.rgb);
      });
      out.file("--debug-dir", base + ".png", [&](const std::string& p) {
        analysis::writePng(p, view.width, view.height, view.rgb, {0.0, 1.0});
      });
      wrote.push_back(fmt::format("wrote {}.exr/.png: {}\n", base, view.description));
    }
    // The technique's plots: SVG and CSV (series, x, y).
    for (const auto& entry : frame.plots) {
      const std::string& name = entry.first;
      const techniques::FramePlot& fp = entry.second;
      const std::string base = (std::filesystem::path(a.debug_dir) / ("plot-" + name)).string();
      const plot::FrameXyPlot xy = plot::xyPlotOf(fp);
      out.file("--debug-dir", base + ".svg",
               [&](const std::string& p) { plot::writeXyPlot(p, xy.series, xy.options); });
      out.file("--debug-dir", base + ".csv", [&](const std::string& p) {
        std::ofstream f(p);
        f << "series,x,y\n";
        f.precision(9);
        for (const auto& sr : fp.series)
          for (size_t i = 0; i < sr.x.size() && i < sr.y.size(); ++i)
            f << '"' << sr.label << "\"," << sr.x[i] << ',' << sr.y[i] << '\n';
        if (!f) throw std::runtime_error(fmt::format("cannot write '{}'", p));
      });
      wrote.push_back(fmt::format("wrote {}.svg/.csv: {}\n", base, fp.title));
    }
    for (const auto& entry : frame.layers) {
      const std::string& name = entry.first;
      const auto& data = entry.second;
      const std::string base = (std::filesystem::path(a.debug_dir) / name).string();
      out.file("--debug-dir", base + ".exr", [&](const std::string& p) {
        analysis::writeExr(p, frame.width, frame.height, data);
      });
      // PNG for viewing: linear, scaled so that the layer's largest value is white.
      float peak = 0.0f;
      for (float v : data)
        if (std::isfinite(v)) peak = std::max(peak, v);
      std::vector<float> scaled(data.size());
      for (size_t i = 0; i < data.size(); ++i) scaled[i] = peak > 0.0f ? data[i] / peak : 0.0f;
      out.file("--debug-dir", base + ".png", [&](const std::string& p) {
        analysis::writePng(p, frame.width, frame.height, scaled, {0.0, 1.0});
      });
      wrote.push_back(fmt::format("wrote {}.exr/.png (PNG scaled by 1/{:.6g})\n", base, peak));
    }
  }
  out.commit();
  removeDebugDir.dir.clear();
  for (const std::string& line : wrote) fmt::print("{}", line);
}

}  // namespace

void addTechniquesCommand(CLI::App& app) {
  auto name = std::make_shared<std::string>();
  auto* cmd = app.add_subcommand(
      "techniques", "The real-time techniques (`render --technique`), or one technique's "
                    "parameters (`render --param NAME=VALUE`) with their types, ranges and units");
  cmd->add_option("name", *name, "Technique: " + fmt::format("{}", fmt::join(techniques::names(), ", ")));
  cmd->callback([name] {
    if (name->empty()) {
      if (!beginWork()) return;
      for (const std::string& n : techniques::names())
        fmt::print("{:<12} {}\n", n, techniques::make(n)->description());
      return;
    }
    const auto t = techniques::make(*name);  // ParameterError listing the valid names
    if (!beginWork()) return;
    fmt::print("{}: {}\nparameters (render --technique {} --param NAME=VALUE):\n", t->name(),
               t->description(), t->name());
    for (const auto& p : t->parameters())
      fmt::print("  {:<24} {:<5} {}\n", p.name, techniques::toString(p.type), describe(p));
  });
}

void addRenderCommand(CLI::App& app) {
  auto a = std::make_shared<RenderArgs>();
  auto* cmd = app.add_subcommand(
      "render", "Render a scene (JSON; default: the built-in bunny) with a real-time technique on "
                "the GPU; writes PNG/EXR and prints the GPU time of every pass");
  cmd->add_option("scene", a->scene, "Scene file (JSON, see README); omitted: the built-in bunny");
  cmd->add_option("--technique", a->technique,
                  fmt::format("Technique: {} (default: the scene's, else pointcloud)",
                              fmt::join(techniques::names(), ", ")));
  cmd->add_option("--width", a->width, "Image width [pixels] (default: the scene camera's)");
  cmd->add_option("--height", a->height, "Image height [pixels] (default: the scene camera's)");
  a->material.addOverrides(*cmd);
  cmd->add_option_function<std::vector<std::string>>(
         "-p,--param",
         [a](const std::vector<std::string>& values) {
           for (const std::string& v : values) {
             const auto [name, value] = parseParam(v, "--param");
             a->settings[name] = value;
             a->spelling[name] = fmt::format("--param {}", v);
           }
         },
         "NAME=VALUE: a parameter of the technique (repeatable; `translucent techniques NAME` "
         "lists them with their types and ranges); overrides the scene's technique settings")
      ->allow_extra_args(false);
  outputOption(cmd->add_option(
      "--out", a->out,
      "PNG output (tone mapped with --exposure and --gamma); without --out and --exr: "
      "translucent.png, only where no such file exists"));
  outputOption(cmd->add_option("--exr", a->exr, "OpenEXR output (linear radiance; layer 'exitance': B)"));
  cmd->add_option("--debug-dir", a->debug_dir,
                  "Folder for the technique's debug layers (empirical: front_depth, back_depth, "
                  "thickness, ao): <layer>.exr linear, <layer>.png scaled to the layer's maximum");
  cmd->add_option("--exposure", a->exposure, "PNG exposure in stops (default: the scene's, 0)");
  cmd->add_option("--gamma", a->gamma, "PNG display gamma (default: the scene's, 2.2)");
  cmd->add_option("--tonemap", a->tonemap,
                  "PNG tone map: clamp (x 2^exposure, clamped) or reinhard (s/(1+s), s = key x "
                  "2^exposure / the rendered pixels' average; Reinhard et al. 2002) (default: the "
                  "scene's, clamp)");
  cmd->add_option("--key", a->key,
                  "reinhard tone map: the rendered pixels' average maps to key/(1+key) (default: "
                  "the scene's, 1)");
  cmd->add_option("--frames", a->frames,
                  "Frames of an animation, frame i at time --time + i/--fps (--out and --exr then "
                  "take a pattern such as frame_%04d.png)")
      ->capture_default_str();
  cmd->add_option("--time", a->time,
                  "Time of the (first) frame, for the mesh's deformations (mesh.deform; default: "
                  "the scene's \"time\", 0)");
  cmd->add_option("--fps", a->fps, "Frames per unit of time of an animation (--frames)")
      ->capture_default_str();
  outputOption(cmd->add_option("--video", a->video,
                               "Also encode the frames as a video (ffmpeg on PATH; e.g. out.mp4)"));
  // One option per technique parameter (the union over the registered techniques), but for the
  // empirical technique's `preset` and `sigma`: as options they read as the material options of
  // every other command (--material, --sigma-a/--sigma-s), so they are --param preset=… and
  // --param sigma=… now, and --preset/--sigma work one more release with a warning.
  std::map<std::string, std::string> seen;
  for (const char* renamed : {"preset", "sigma"}) {
    const std::string param = renamed;
    cmd->add_option_function<std::string>(
        optionName(param),
        [a, param](const std::string& v) {
          warnDeprecated("render", optionName(param),
                         fmt::format("use --param {}={} (the empirical technique's {}; "
                                     "--material names the material)", param, v,
                                     param == "preset" ? "survey preset" : "smoothing σ"));
          a->settings[param] = v;
          a->spelling[param] = fmt::format("{} {}", optionName(param), v);
        },
        "Deprecated: --param " + param + "=VALUE")
        ->group("");
    seen[param] = "empirical";
  }
  for (const std::string& name : techniques::names()) {
    const auto t = techniques::make(name);
    for (const auto& p : t->parameters()) {
      if (seen.contains(p.name)) continue;
      seen[p.name] = name;
      const std::string param = p.name;
      // Accepted as --NAME VALUE too, but not listed: --help would otherwise list every
      // technique's parameters in one flat list (`translucent techniques NAME` shows them with
      // their types, ranges and defaults, grouped by technique).
      cmd->add_option_function<std::string>(
             optionName(p.name), [a, param](const std::string& v) { a->settings[param] = v; },
             fmt::format("{}: {}", name, describe(p)))
          ->group("");
    }
  }
  cmd->footer("Technique parameters: --param NAME=VALUE (also accepted as --NAME VALUE). "
              "`translucent techniques` lists the techniques, `translucent techniques NAME` the "
              "parameters of one, with their types, ranges and defaults.");
  cmd->callback([a] {
    RenderArgs args = *a;
    // The default output is a convenience for a first try, so it never replaces a file the user
    // did not name: an existing translucent.png is replaced only by an explicit --out.
    if (args.out.empty() && args.exr.empty() && args.video.empty()) {
      if (args.frames > 1)
        throw ParameterError(fmt::format("--frames {}: expected --out frame_%04d.png, --exr "
                                         "frame_%04d.exr or --video FILE", args.frames));
      std::error_code ec;
      if (std::filesystem::exists("translucent.png", ec))
        throw ParameterError(
            "no --out or --exr given, and the default output translucent.png exists already: "
            "give --out FILE.png (--out translucent.png replaces it) or --exr FILE.exr");
      args.out = "translucent.png";
    }
    runRender(args);
  });
}

}  // namespace translucent::cli
