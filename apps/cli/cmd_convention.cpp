// SPDX-License-Identifier: GPL-3.0-or-later
// translucent convention-study: measures the two exit-radiance conventions of seed Eq. 2.16
// (bssrdf/exit_radiance.h: Jensen Ft B/π, normalized Ft B/(π 4Cφ(1/η))) against the path
// tracer's true (cone-averaged) radiance, and writes the tables as Markdown
// (docs/radiance-convention.md is its output with the defaults).
//
// Scenes: the lit sphere (reference/sphere.h: radius 1, light along (1,1,1), orthographic view
// along +z), the glmark2 bunny scene (data/scenes/bunny.json, its two lights and pinhole camera,
// at a lower resolution), and the bunny with only its lights on the camera's side, each with
// every material of --materials at its preset η.
// Per scene, material and channel: the ratio cone radiance / prediction over the image interior
// and in bins of n·v (analysis/exit_convention_study.h explains the pixels, the cone correction
// and the errors). Photon counts are fixed per material (high-albedo materials walk longer) and
// scaled by --photon-scale; the same seed gives the same tables on any thread count.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include "safe_print.h"
#include "translucent/analysis/exit_convention_study.h"
#include "translucent/bssrdf/exit_radiance.h"
#include "commands.h"
#include "output_guard.h"
#include "translucent/optics/presets.h"
#include "options.h"
#include "translucent/reference/mesh_tracer.h"
#include "translucent/reference/sphere.h"
#include "translucent/scene/scene.h"

#include <algorithm>
#include <variant>

#include <glm/geometric.hpp>

namespace translucent::cli {
namespace {

using bssrdf::ExitConvention;

struct StudyArgs {
  std::string out = "docs/radiance-convention.md";
  std::string bunny = "data/scenes/bunny.json";
  std::string materials = "Marble,Potato,Skin2,Skin1,Ketchup";
  double photon_scale = 1.0;
  double cone_angle = 15.0;
  uint64_t seed = 1;
  int threads = 0;
  int sphere_size = 96;
  int bunny_width = 160, bunny_height = 120;
};

// Photons per channel at --photon-scale 1, for each scene: 175 s of CPU time in all for the
// default materials and scenes (10 minutes wall on a loaded 2-core share); walk lengths grow with
// the albedo: a Marble photon costs ~15 times a Ketchup one.
uint64_t basePhotons(const std::string& material) {
  static const std::map<std::string, uint64_t> counts = {
      {"marble", 1'500'000}, {"potato", 3'000'000}, {"skin2", 3'000'000},
      {"skin1", 4'000'000},  {"ketchup", 6'000'000}};
  std::string key = material;
  for (char& ch : key) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  const auto it = counts.find(key);
  return it != counts.end() ? it->second : 4'000'000;
}

struct Run {
  std::string scene, material;
  Medium medium;
  uint64_t photons = 0;
  double seconds = 0.0;
  std::vector<analysis::ChannelStudy> channels;
};

std::string ratio(const analysis::ConventionRatio& r) {
  if (!(r.value > 0.0)) return "–";
  return fmt::format("{:.3f} ± {:.3f}", r.value, r.std_error);
}

// Weighted least-squares slope of the Jensen ratio over the bins' centres (bins with a ratio).
std::string slope(const analysis::ChannelStudy& ch) {
  double sw = 0.0, sx = 0.0, sy = 0.0;
  int n = 0;
  for (const auto& b : ch.bins) {
    const auto& r = b.ratio[0];
    if (!(r.value > 0.0 && r.std_error > 0.0)) continue;
    const double w = 1.0 / (r.std_error * r.std_error), x = 0.5 * (b.cos_lo + b.cos_hi);
    sw += w;
    sx += w * x;
    sy += w * r.value;
    ++n;
  }
  if (n < 3) return "–";
  const double xm = sx / sw, ym = sy / sw;
  double sxx = 0.0, sxy = 0.0;
  for (const auto& b : ch.bins) {
    const auto& r = b.ratio[0];
    if (!(r.value > 0.0 && r.std_error > 0.0)) continue;
    const double w = 1.0 / (r.std_error * r.std_error), x = 0.5 * (b.cos_lo + b.cos_hi) - xm;
    sxx += w * x * x;
    sxy += w * x * (r.value - ym);
  }
  return fmt::format("{:+.3f} ± {:.3f}", sxy / sxx, 1.0 / std::sqrt(sxx));
}

std::vector<double> etasOf(const Medium& m) {
  std::vector<double> e;
  for (int c = 0; c < 3; ++c) e.push_back(m.channel(c).eta);
  return e;
}

Run runSphere(const StudyArgs& a, const std::string& material) {
  Run run{"sphere", material, preset(material).medium(10.0), 0, 0.0, {}};
  reference::SphereScene s;
  s.width = s.height = a.sphere_size;
  s.cone_half_angle = a.cone_angle;
  s.validate();
  run.photons = static_cast<uint64_t>(std::llround(a.photon_scale * double(basePhotons(material))));
  reference::SpherePathTracer tracer(s, run.medium, {a.seed, a.threads});
  tracer.addPass(run.photons);
  run.photons = tracer.stats().photons[0];
  run.seconds = tracer.stats().seconds;
  const auto etas = etasOf(run.medium);
  run.channels = analysis::studyExitConventions(tracer.images(), tracer.body(), tracer.camera(),
                                                etas, a.cone_angle);
  return run;
}

// frontOnly: keep only the lights on the camera's side of the object (directional lights whose
// direction, point lights whose position, makes a positive dot product with the direction from
// the look-at point to the camera). Without the lights behind it, no light crosses thin parts
// (ears) straight towards the camera, which separates the exit law from that transmission.
Run runBunny(const StudyArgs& a, const std::string& material, bool frontOnly) {
  scene::Scene s = scene::loadScene(a.bunny);
  if (frontOnly) {
    const glm::dvec3 toCamera = s.camera.position - s.camera.look_at;
    std::vector<scene::Light> front;
    for (const auto& l : s.lights) {
      bool keep = false;
      if (const auto* d = std::get_if<reference::DirectionalLight>(&l.emitter))
        keep = glm::dot(d->direction, toCamera) > 0.0;
      else if (const auto* pt = std::get_if<reference::PointLight>(&l.emitter))
        keep = glm::dot(pt->position - s.camera.look_at, toCamera) > 0.0;
      if (keep) front.push_back(l);
    }
    if (front.empty())
      throw ParameterError(fmt::format("--bunny '{}': no directional or point light on the camera's "
                                       "side for the front-lit run", a.bunny));
    s.lights = front;
  }
  s.preset = material;
  s.medium = preset(material).medium(s.medium.scale);
  s.camera.width = a.bunny_width;
  s.camera.height = a.bunny_height;
  s.cone_angle = a.cone_angle;
  Run run{frontOnly ? "bunny, front light" : "bunny", material, s.medium, 0, 0.0, {}};
  const geometry::TriangleMesh mesh = scene::loadSceneMesh(s);
  run.photons = static_cast<uint64_t>(std::llround(a.photon_scale * double(basePhotons(material))));
  reference::MeshPathTracer tracer(mesh, s.medium, scene::referenceLights(s), s.camera,
                                   s.cone_angle, {a.seed, a.threads});
  tracer.addPass(run.photons);
  run.photons = tracer.stats().photons[0];
  run.seconds = tracer.stats().seconds;
  const auto etas = etasOf(run.medium);
  run.channels = analysis::studyExitConventions(tracer.images(), tracer.body(), tracer.camera(),
                                                etas, a.cone_angle);
  return run;
}

std::string markdown(const StudyArgs& a, const std::vector<Run>& runs, const std::string& command) {
  std::ostringstream md;
  const double eta = runs.empty() ? 1.3 : runs.front().medium.eta;
  const double norm = bssrdf::diffuseTransmittanceFromOutside(eta);
  md << "# Radiance from exitance: Jensen or normalized? (measured)\n\n";
  md << "Generated by `" << command << "` (apps/cli/cmd_convention.cpp); do not edit by hand.\n\n";
  md << "Both conventions of Eq. 2.16 of Bitterli 2013 (BSSRDF Explorer) turn the radiant exitance B into an exit radiance with "
        "the same angular shape Ft(η, ω_o) and differ by a constant:\n\n"
        "- **jensen**: L = Ft(η, ω_o) B / π (Jensen et al. 2001)\n"
        "- **normalized**: L = Ft(η, ω_o) B / (π · 4Cφ(1/η)), 4Cφ(1/η) = 1 − 2C1_ext(η) = "
     << fmt::format("{:.4f}", norm) << " at η = " << eta
     << " (carries out exactly B)\n\n"
        "The path tracer scores, from the same photons, B, the Jensen radiance (per photon, with "
        "its exit cosine) and the true radiance towards the camera averaged over a cone of "
        "half-angle θc = "
     << a.cone_angle
     << "° (reference/camera.h). Each table gives **cone radiance / prediction** (1 = the "
        "convention is right): the prediction is the tracer's own Jensen radiance times the "
        "cone's average of the exit law (so the cone's finite size is not an error of either "
        "convention) times 1 or 1/(1 − 2C1_ext). Only the exit law is tested; no diffusion "
        "profile is involved.\n\n"
        "Scenes (all media at their preset η):\n\n"
        "- **sphere**: radius 1 at medium scale 10 (a 10 mm sphere), directional light of unit "
        "irradiance along (1, 1, 1), orthographic view along +z, "
     << a.sphere_size << "×" << a.sphere_size
     << " pixels (reference/sphere.h);\n"
        "- **bunny**: `" << a.bunny << "` with its two lights (a key light from above and behind, a "
        "weak fill from the camera's side) and its camera at "
     << a.bunny_width << "×" << a.bunny_height
     << " pixels, medium scale as in the scene;\n"
        "- **bunny, front light**: the same with only the lights on the camera's side. Under the "
        "key light from behind, light crosses thin parts (the ears) towards the camera with "
        "little or no scattering and leaves in the light's direction, outside the cone: it is "
        "exitance but not diffuse radiance, and no exit law of the form Ft B/π can describe it "
        "(both conventions fail there alike, most for the low-albedo channels). The front-lit "
        "run separates that from the exit law.\n\n"
        "Pixels: interior only — five camera rays per pixel must hit the body at one depth "
        "(no silhouette or depth step inside the pixel) with n·v > "
     << analysis::ExitConventionStudyOptions{}.cos_edges.front()
     << " at every sample (60° from the normal), binned by n·v at the pixel centre. "
        "± is one standard error (photons shared by all pixels; the cone and Jensen images are "
        "positively correlated and their covariance is left out, which overstates the ratio's "
        "error slightly). α' is the channel's reduced albedo.\n\n";

  // Summary over the interior. Since L_normalized = L_jensen · norm, normalized is the closer
  // to the truth exactly when cone / L_jensen > 2 / (1 + norm) (the midpoint of the two
  // predictions); "closer" is called only when the ratio is two standard errors from it.
  const double midpoint = 2.0 / (1.0 + norm);
  const char* names[3] = {"R", "G", "B"};
  struct Case {
    const Run* run;
    size_t channel;
    double albedo;
    std::string closer;
  };
  std::vector<Case> cases;
  for (const Run& r : runs)
    for (size_t c = 0; c < r.channels.size(); ++c) {
      const auto& j = r.channels[c].all.ratio[0];
      std::string closer = "–";
      if (j.value > 0.0 && j.std_error > 0.0) {
        const double z = (j.value - midpoint) / j.std_error;
        closer = z > 2.0 ? "normalized" : z < -2.0 ? "jensen" : "neither (< 2σ)";
      }
      cases.push_back({&r, c, r.medium.channel(int(c)).reducedAlbedo(), closer});
    }
  auto row = [&](const Case& k) {
    const auto& ch = k.run->channels[k.channel];
    return fmt::format("| {} | {} | {} | {:.4f} | {} | {} | {} | {} | {} |\n", k.run->scene,
                       k.run->material, names[k.channel], k.albedo, ch.all.pixels,
                       ratio(ch.all.ratio[0]), ratio(ch.all.ratio[1]), k.closer, slope(ch));
  };
  const std::string header =
      "| scene | material | channel | α' | pixels | cone / L_jensen | cone / L_normalized | closer "
      "| slope |\n|---|---|---|---|---|---|---|---|---|\n";
  md << "## Interior of the image (n·v > 0.5)\n\n";
  md << "\"slope\": d(cone / L_jensen) / d(n·v) by a weighted least-squares line through the n·v "
        "bins below (± its standard error): 0 when the angular shape is Ft's; negative when the "
        "true radiance falls off towards the normal faster than Ft B/π, i.e. relatively more "
        "light leaves at grazing angles.\n\n";
  md << fmt::format("\"closer\": normalized when cone / L_jensen exceeds 2/(1 + {:.4f}) = {:.4f} "
                    "(the midpoint of the two predictions) by more than two standard errors, "
                    "jensen when it falls short of it by as much.\n\n", norm, midpoint);
  md << header;
  for (const Case& k : cases) md << row(k);
  md << "\n";
  for (const std::string scene : {"sphere", "bunny", "bunny, front light"}) {
    int n = 0, closerN = 0, closerJ = 0;
    double dev[2] = {0.0, 0.0};
    for (const Case& k : cases) {
      if (k.run->scene != scene || !(k.run->channels[k.channel].all.ratio[0].value > 0.0)) continue;
      ++n;
      for (size_t c = 0; c < 2; ++c) dev[c] += std::abs(k.run->channels[k.channel].all.ratio[c].value - 1.0);
      closerN += k.closer == "normalized";
      closerJ += k.closer == "jensen";
    }
    if (n > 0)
      md << fmt::format("- {}: mean |ratio − 1| over its {} material channels is {:.3f} (jensen), "
                        "{:.3f} (normalized); normalized closer in {}, jensen in {}, neither in {}.\n",
                        scene, n, dev[0] / n, dev[1] / n, closerN, closerJ, n - closerN - closerJ);
  }
  {
    int n = 0, closerN = 0, closerJ = 0;
    double dev[2] = {0.0, 0.0};
    for (const Case& k : cases) {
      if (k.run->scene == "bunny" || !(k.run->channels[k.channel].all.ratio[0].value > 0.0)) continue;
      ++n;
      for (size_t c = 0; c < 2; ++c) dev[c] += std::abs(k.run->channels[k.channel].all.ratio[c].value - 1.0);
      closerN += k.closer == "normalized";
      closerJ += k.closer == "jensen";
    }
    if (n > 0)
      md << fmt::format("- sphere and front-lit bunny together (the exitance is diffusely "
                        "scattered light): mean |ratio − 1| over {} channels is {:.3f} (jensen), "
                        "{:.3f} (normalized); normalized closer in {}, jensen in {}, neither in {}.\n",
                        n, dev[0] / n, dev[1] / n, closerN, closerJ, n - closerN - closerJ);
  }
  md << "\n";

  // By albedo: the scenes where the exitance is diffuse light (not the bunny under its back light,
  // whose thin parts let light cross towards the camera in directions outside the cone).
  md << "### By reduced albedo (sphere and front-lit bunny)\n\n";
  std::vector<Case> sorted;
  for (const Case& k : cases)
    if (k.run->scene != "bunny") sorted.push_back(k);
  std::stable_sort(sorted.begin(), sorted.end(),
                   [](const Case& x, const Case& y) { return x.albedo > y.albedo; });
  md << header;
  for (const Case& k : sorted) md << row(k);
  md << "\n";

  // Angular dependence.
  md << "## Dependence on the view angle (bins of n·v at the pixel centre)\n\n";
  md << "A trend over the bins means the true angular shape differs from Ft(η, ω_o); an offset "
        "common to all bins is the normalisation. normalized = jensen × "
     << fmt::format("{:.4f}", norm) << " in every bin.\n\n";
  for (const Run& r : runs) {
    md << "### " << r.scene << ", " << r.material << fmt::format(" ({} photons per channel, {:.1f} s)\n\n", r.photons, r.seconds);
    md << "| n·v | pixels |";
    for (size_t c = 0; c < r.channels.size(); ++c)
      md << " " << names[c] << ": cone / L_jensen | " << names[c] << ": cone / L_normalized |";
    md << "\n|---|---|";
    for (size_t c = 0; c < r.channels.size(); ++c) md << "---|---|";
    md << "\n";
    const size_t nb = r.channels.front().bins.size();
    for (size_t b = 0; b <= nb; ++b) {
      const auto& first = b < nb ? r.channels.front().bins[b] : r.channels.front().all;
      md << fmt::format("| {} | {} |", b < nb ? fmt::format("{:.1f}–{:.1f}", first.cos_lo, first.cos_hi)
                                               : std::string("all"),
                        first.pixels);
      for (const auto& ch : r.channels) {
        const auto& bin = b < nb ? ch.bins[b] : ch.all;
        md << " " << ratio(bin.ratio[0]) << " | " << ratio(bin.ratio[1]) << " |";
      }
      md << "\n";
    }
    md << "\n";
  }
  return md.str();
}

void runStudy(const StudyArgs& a) {
  if (!(a.photon_scale > 0.0 && a.photon_scale <= 1000.0))
    throw ParameterError(fmt::format("--photon-scale is {}: expected a value in (0, 1000]", a.photon_scale));
  if (!(a.cone_angle > 0.0 && a.cone_angle <= 30.0))
    throw ParameterError(fmt::format("--cone-angle is {}: expected degrees in (0, 30] (the bins "
                                     "start at 60° from the normal)", a.cone_angle));
  if (a.threads < 0) throw ParameterError(fmt::format("--threads is {}: expected >= 0", a.threads));
  if (a.sphere_size < 8 || a.bunny_width < 8 || a.bunny_height < 8)
    throw ParameterError("--sphere-size, --bunny-width, --bunny-height: expected at least 8 pixels");
  const auto materials = splitList(a.materials);
  if (materials.empty()) throw ParameterError("--materials: expected at least one preset name");
  for (const auto& m : materials) (void)preset(m);  // ParameterError listing the valid names
  // The report must be writable and must not be the bunny scene or one of its files; checked
  // before the minutes of tracing, without creating anything (written via temporary + rename).
  {
    OutputSet outputs;
    outputs.output("--out", a.out);
    outputs.sceneInputs(a.bunny, scene::loadScene(a.bunny));
    outputs.check();
  }
  if (!beginWork()) return;
  std::vector<Run> runs;
  for (const auto& m : materials) {
    runs.push_back(runSphere(a, m));
    printStderr("convention-study: sphere {}: {} photons per channel, {:.1f} s\n", m,
               runs.back().photons, runs.back().seconds);
  }
  for (bool front : {false, true})
    for (const auto& m : materials) {
      runs.push_back(runBunny(a, m, front));
      printStderr("convention-study: {} {}: {} photons per channel, {:.1f} s\n",
                 runs.back().scene, m, runs.back().photons, runs.back().seconds);
    }
  std::string command = "translucent convention-study";
  if (a.photon_scale != 1.0) command += fmt::format(" --photon-scale {}", a.photon_scale);
  if (a.cone_angle != 15.0) command += fmt::format(" --cone-angle {}", a.cone_angle);
  if (a.materials != StudyArgs{}.materials) command += " --materials " + a.materials;
  if (a.seed != 1) command += fmt::format(" --seed {}", a.seed);
  const StudyArgs defaults;
  if (a.bunny != defaults.bunny) command += " --bunny " + a.bunny;
  if (a.sphere_size != defaults.sphere_size) command += fmt::format(" --sphere-size {}", a.sphere_size);
  if (a.bunny_width != defaults.bunny_width || a.bunny_height != defaults.bunny_height)
    command += fmt::format(" --bunny-width {} --bunny-height {}", a.bunny_width, a.bunny_height);
  command += " --out " + a.out;
  const std::string text = markdown(a, runs, command);
  writeTextOutput("--out", a.out, text);
  fmt::print("wrote {}\n", a.out);
}

}  // namespace

void addConventionStudyCommand(CLI::App& app) {
  auto a = std::make_shared<StudyArgs>();
  auto* cmd = app.add_subcommand(
      "convention-study",
      "Measure the exit-radiance conventions (jensen, normalized; Bitterli 2013, Eq. 2.16) against the path "
      "tracer's true radiance on the lit sphere and the bunny; writes a Markdown report");
  outputOption(cmd->add_option("--out", a->out, "Markdown output"))->capture_default_str();
  cmd->add_option("--bunny", a->bunny, "Bunny scene file (JSON)")->capture_default_str();
  cmd->add_option("--materials", a->materials, "Presets, comma-separated")->capture_default_str();
  cmd->add_option("--photon-scale", a->photon_scale,
                  "Factor on the photon counts (1: ~3 CPU-minutes)")->capture_default_str();
  cmd->add_option("--cone-angle", a->cone_angle, "Cone half-angle of the true radiance [degrees]")
      ->capture_default_str();
  cmd->add_option("--seed", a->seed, "Random seed")->capture_default_str();
  cmd->add_option("--threads", a->threads, "Worker threads (0: all cores)")->capture_default_str();
  cmd->add_option("--sphere-size", a->sphere_size, "Sphere image size [pixels]")->capture_default_str();
  cmd->add_option("--bunny-width", a->bunny_width, "Bunny image width [pixels]")->capture_default_str();
  cmd->add_option("--bunny-height", a->bunny_height, "Bunny image height [pixels]")->capture_default_str();
  cmd->callback([a] { runStudy(*a); });
}

}  // namespace translucent::cli
