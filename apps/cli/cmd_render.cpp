// translucent render: a scene (JSON, scene/scene.h; the built-in bunny when none is given) with a
// real-time technique (techniques/registry.h) on the GPU through a headless OpenGL 4.5 context,
// written as PNG (tone mapped: exposure, gamma) and/or OpenEXR (linear radiance, plus the radiant
// exitance B in the layer "exitance"). Prints the GPU time of every pass.
//
// Every parameter of every registered technique is an option (--points, --epsilon,
// --shadow-map-size, ...; `--help` lists them with their ranges); options override the scene's
// "technique" settings. Progressive work (occluded environment lighting) is finished in each
// frame (FrameRequest::converge).
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <vector>

#include "analysis/image_io.h"
#include "commands.h"
#include "output_guard.h"
#include "gpu/context.h"
#include "scene/scene.h"
#include "techniques/registry.h"

namespace translucent::cli {
namespace {

struct RenderArgs {
  std::string scene;
  std::optional<std::string> technique;
  std::optional<int> width, height;
  std::optional<std::string> model;
  std::string out, exr;
  std::string debug_dir;  // every frame layer as <layer>.exr (linear) and <layer>.png (scaled),
                          // every view as view-<name>.exr/.png
  std::optional<double> exposure, gamma;
  int frames = 1;
  std::map<std::string, std::string> settings;  // technique parameter -> value as typed
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

void runRender(const RenderArgs& a) {
  if (a.frames < 1) throw ParameterError(fmt::format("--frames {}: expected at least 1", a.frames));
  if (!a.out.empty()) {
    auto ext = std::filesystem::path(a.out).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    if (ext != ".png") throw ParameterError(fmt::format("--out '{}': expected a .png file", a.out));
  }

  // Scene, with the command line's overrides.
  scene::Scene s = a.scene.empty() ? scene::defaultScene() : scene::loadScene(a.scene);
  if (a.technique) s.technique = *a.technique;
  if (a.width) s.camera.width = *a.width;
  if (a.height) s.camera.height = *a.height;
  if (a.model) s.model = *a.model;
  if (a.exposure) s.exposure = *a.exposure;
  if (a.gamma) s.gamma = *a.gamma;
  s.camera.validate();
  if (!(s.gamma > 0.0) || !std::isfinite(s.gamma) || !std::isfinite(s.exposure))
    throw ParameterError(fmt::format("--gamma {} / --exposure {}: expected a finite gamma > 0 and a "
                                     "finite exposure", s.gamma, s.exposure));
  // The outputs against each other and against every file the run reads, before the GPU work;
  // nothing is created until a file is complete (written via a temporary file and renamed).
  OutputSet outputs;
  outputs.output("--exr", a.exr);
  outputs.output("--out", a.out);
  outputs.sceneInputs(a.scene, s);
  outputs.check();
  // A camera or light inside the object renders nothing meaningful: refuse it (the mesh is
  // loaded once more for this, about 0.1 s for the bunny).
  scene::requireOutsideMesh(s, scene::loadSceneMesh(s));

  // The context first: the technique's GL objects must be deleted while it is alive.
  gpu::Context gl;
  std::unique_ptr<techniques::Technique> t = techniques::make(s.technique);
  techniques::applySettings(*t, s);
  for (const auto& [name, value] : a.settings) {
    try {
      t->setParameter(name, value);
    } catch (const ParameterError& e) {
      throw ParameterError(fmt::format("{}: {}", optionName(name), e.what()));
    }
  }

  fmt::print("render: {} on {} ({}), {}x{}, scene: {}\n", s.technique, gl.info().renderer,
             gl.info().version, s.camera.width, s.camera.height,
             a.scene.empty() ? "built-in bunny" : a.scene);
  t->prepare(s, gl);

  // Frames: the last one is kept; each one finishes the progressive work (converge).
  techniques::Frame frame;
  int rendered = 0;
  for (;;) {
    techniques::FrameRequest request;
    request.converge = true;
    request.views = !a.debug_dir.empty();
    frame = t->render(request);
    ++rendered;
    for (const auto& note : frame.notes) fmt::print("  {}\n", note);
    if (rendered >= a.frames && frame.converged) break;
    if (rendered >= 100000) break;
  }

  fmt::print("GPU times of frame {}{}:\n", rendered, frame.converged ? "" : " (not converged)");
  for (const auto& p : frame.passes)
    fmt::print("  {:<{}}{:<22} {:9.3f} ms\n", "", 2 * p.depth, p.name, p.ms);
  fmt::print("  {:<22} {:9.3f} ms\n", "total", frame.totalMs());

  // The debug files are known only now: checked like the other outputs before any file is
  // written (a scene file, its mesh or environment map in the debug folder must not be replaced
  // by a layer of that name).
  if (!a.debug_dir.empty()) {
    std::error_code ec;
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
    const std::pair<std::string, std::string> attrs[] = {
        {"translucent:quantity", quantity},
        {"translucent:layers", "exitance: radiant exitance B (RGB)"},
        {"translucent:technique", s.technique},
        {"translucent:source", what}};
    analysis::writeExr(a.exr, frame.width, frame.height, frame.rgb, layers, attrs);
    fmt::print("wrote {}: {}\n", a.exr, quantity);
  }
  if (!a.out.empty()) {
    analysis::writePng(a.out, frame.width, frame.height, frame.rgb, {s.exposure, s.gamma});
    fmt::print("wrote {}\n", a.out);
  }
  if (!a.debug_dir.empty()) {
    if (frame.layers.empty() && frame.views.empty())
      fmt::print("--debug-dir: technique {} has no debug layers\n", s.technique);
    // The technique's inspection views: display-ready [0, 1], written as they are.
    for (const auto& [name, view] : frame.views) {
      const std::filesystem::path base = std::filesystem::path(a.debug_dir) / ("view-" + name);
      analysis::writeExr(base.string() + ".exr", view.width, view.height, view.rgb);
      analysis::writePng(base.string() + ".png", view.width, view.height, view.rgb, {0.0, 1.0});
      fmt::print("wrote {}.exr/.png: {}\n", base.string(), view.description);
    }
    for (const auto& [name, data] : frame.layers) {
      const std::filesystem::path base = std::filesystem::path(a.debug_dir) / name;
      analysis::writeExr(base.string() + ".exr", frame.width, frame.height, data);
      // PNG for viewing: linear, scaled so that the layer's largest value is white.
      float peak = 0.0f;
      for (float v : data)
        if (std::isfinite(v)) peak = std::max(peak, v);
      std::vector<float> scaled(data.size());
      for (size_t i = 0; i < data.size(); ++i) scaled[i] = peak > 0.0f ? data[i] / peak : 0.0f;
      analysis::writePng(base.string() + ".png", frame.width, frame.height, scaled, {0.0, 1.0});
      fmt::print("wrote {}.exr/.png (PNG scaled by 1/{:.6g})\n", base.string(), peak);
    }
  }
}

}  // namespace

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
  cmd->add_option("--model", a->model, "BSSRDF model name or .bssrdf file (default: the scene's)");
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
  cmd->add_option("--frames", a->frames, "Frames to render (times are the last frame's; every frame is converged)")
      ->capture_default_str();
  // One option per technique parameter (the union over the registered techniques).
  std::map<std::string, std::string> seen;
  for (const std::string& name : techniques::names()) {
    const auto t = techniques::make(name);
    for (const auto& p : t->parameters()) {
      if (seen.contains(p.name)) continue;
      seen[p.name] = name;
      const std::string param = p.name;
      cmd->add_option_function<std::string>(
          optionName(p.name), [a, param](const std::string& v) { a->settings[param] = v; },
          fmt::format("{}: {}", name, describe(p)));
    }
  }
  cmd->callback([a] {
    RenderArgs args = *a;
    // The default output is a convenience for a first try, so it never replaces a file the user
    // did not name: an existing translucent.png is replaced only by an explicit --out.
    if (args.out.empty() && args.exr.empty()) {
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
