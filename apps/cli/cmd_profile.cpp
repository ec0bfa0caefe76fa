// SPDX-License-Identifier: GPL-3.0-or-later
// translucent profile: radial diffuse reflectance profiles of models as CSV, PNG or SVG
// (seed 3.6.3, the pencil plot).
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <filesystem>
#include <memory>

#include "safe_print.h"
#include "translucent/analysis/model_study.h"
#include "translucent/analysis/pencil_reference.h"
#include "translucent/bssrdf/profile_curves.h"
#include "bssrdf_models.h"
#include "translucent/bssrdf/registry.h"
#include "translucent/bssrdf/tabulated.h"
#include "commands.h"
#include "output_guard.h"
#include "translucent/gpu/bssrdf_profiles.h"
#include "options.h"
#include "plot/profile_plot.h"
#include "progress.h"
#include "translucent/reference/gpu/device.h"
#include "translucent/reference/slab.h"

namespace translucent::cli {
namespace {

constexpr const char* kDefaultPreset = "Marble";
// Radii per curve: each curve holds them all, and --save-profile tallies 32 times as many annuli
// per channel (at most 2^24, the tally's limit); far beyond any plot's resolution.
constexpr int kMaxPoints = 500'000;

struct ProfileArgs {
  std::string models = "all";
  std::vector<std::string> params;  // NAME=VALUE for .bssrdf models
  MediumOptions medium;
  std::optional<double> r_max;
  int points = 200;
  std::string channel = "luminance";
  std::string y = "log";
  bool times_r = false;
  std::string out;
  std::string save_profile;  // the reference as a tabulated model (bssrdf/tabulated.h)
  int width = plot::PlotOptions{}.width;
  int height = plot::PlotOptions{}.height;
  std::string title;
  bool reference = false;
  std::string scattering = "all";  // --scattering: all | single | multiple | split
  bool study = false;
  std::string csv, json;
  std::vector<std::string> study_presets;
  double photons = 1e6;
  uint64_t seed = 1;
  int threads = 0;
  std::string device = "auto";  // of the reference: cpu | gpu | auto (reference/gpu/device.h)
  double theta = 0.0;  // incidence of the pencil beam [degrees]
};

// --model ",,," (or ""): a list that names nothing would write a file without a curve.
std::string noModelNamed(const std::string& models) {
  return fmt::format("--model '{}': names no model: expected comma-separated model names, .bssrdf "
                     "or .csv files, or 'all'", models);
}

std::string extensionOf(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (auto& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return ext;
}

// Unit of r in scene units: the medium's coefficients are per mm, and one scene unit spans
// `scale` mm (seed 3.6.1).
std::string lengthUnit(double scale) {
  if (scale == 1.0) return "mm";
  if (scale == 10.0) return "cm";
  if (scale == 1000.0) return "m";
  if (scale == 0.001) return "µm";
  return fmt::format("{:g} mm", scale);
}

std::string defaultTitle(const ProfileArgs& a) {
  const std::string material =
      !a.medium.sigma_a.empty() ? std::string("Custom medium")
                                : (a.medium.preset.empty() ? kDefaultPreset : a.medium.preset);
  if (a.theta != 0.0)
    return fmt::format("{}: diffuse reflectance around a pencil beam at {:g}°", material, a.theta);
  return fmt::format("{}: diffuse reflectance around a pencil beam", material);
}

// The path-traced reference (seed 3.6.3): a pencil beam at normal incidence (or --theta) on a
// semi-infinite slab of the medium, Rd(r) tallied in annuli on [0, r_max] (annulus centres as radii). The
// models' R(r) is per unit flux *entering* the medium (Eq. 2.16 applies Ft(ωi) separately), so
// the tally per incident photon is divided by 1 - Rsp, the exact entry transmittance. Channels
// use independent seeds so the luminance error combines in quadrature.
std::array<reference::SlabResult, 3> traceReference(const Medium& medium,
                                                    const std::array<bool, 3>& needed,
                                                    double r_max, int bins,
                                                    const ProfileArgs& a) {
  std::array<reference::SlabResult, 3> results;
  const reference::TraceDevice device = reference::openTraceDevice(a.device);
  for (size_t c = 0; c < 3; ++c) {
    if (!needed[c]) continue;
    const ScalarMedium m = medium.channel(static_cast<int>(c));
    if (m.sigma_a <= 0.0)
      throw ParameterError(fmt::format(
          "--reference: sigma_a ({} channel) is 0: a non-absorbing semi-infinite medium never "
          "lets every photon go; the path-traced reference needs absorption",
          kChannelNames[c]));
    reference::TraceOptions o;
    o.photons = static_cast<uint64_t>(a.photons);
    o.seed = a.seed + c;
    o.threads = a.threads;
    o.radial_bins = bins;
    o.radial_max = r_max;
    InterruptGuard guard;
    ProgressBar bar(fmt::format("reference ({})", kChannelNames[c]), "photons");
    reference::SlabSetup setup = reference::SlabSetup::semiInfinite(m);
    setup.theta = a.theta * std::numbers::pi / 180.0;
    results[c] = reference::traceSlab(device, setup, o,
                                      [&](const reference::TraceProgress& p) { return bar(p); });
    bar.end();
    if (results[c].partial) printStderr("profile: reference stopped early, partial\n");
  }
  return results;
}

// The reference curves of channel `ch` that --scattering asks for: all orders (the seed's "multi
// + single scattering"), single or multiple scattering alone, or all three.
std::vector<analysis::Curve> referenceCurves(const std::array<reference::SlabResult, 3>& results,
                                             const std::array<bool, 3>& traced,
                                             analysis::Channel ch, const ProfileArgs& a) {
  const auto ptr = [&](size_t c) { return traced[c] ? &results[c] : nullptr; };
  const std::array<const reference::SlabResult*, 3> r{ptr(0), ptr(1), ptr(2)};
  std::vector<analysis::Curve> out;
  for (const auto& order : analysis::scatteringSelection(a.scattering))
    out.push_back(analysis::pencilReferenceCurve(r, ch, a.times_r, order));
  return out;
}

// Diffuse reflectance per unit flux entering the medium, as the models' Rd (pencil_reference.h).
double enteringRd(const reference::SlabResult& r) {
  return r.diffuse_reflectance.value / (1.0 - r.specular_reflectance.value);
}

// --save-profile: the path-traced R(r) of the three channels as a tabulated model in
// millimetres (r_mm = r · scale, R_mm = R / scale², the medium's units being mm). The tally's
// annuli are kFineBins times finer than --points asks, then merged (area-weighted, so each merged
// annulus keeps its energy exactly) into annuli no wider than 5% of their radius and no wider than
// the --points spacing: the steep R(r) near the source (single scattering, ~1/r) is resolved
// where the table's interpolation between annulus centres would otherwise lose energy (with
// --points 200 alone Skin1's blue Rd came out 10% low), and the tail keeps --points' noise level.
constexpr int kFineBins = 32;

std::string saveReferenceProfile(OutputFiles& out, const std::string& path, const Medium& medium,
                                 double r_max, const ProfileArgs& a) {
  const auto res = traceReference(medium, {true, true, true}, r_max, a.points * kFineBins, a);
  bssrdf::ProfileSamples t;
  t.eta = medium.eta;
  std::array<analysis::Curve, 3> rgb;
  for (size_t c = 0; c < 3; ++c) {
    std::array<const reference::SlabResult*, 3> one{nullptr, nullptr, nullptr};
    one[c] = &res[c];
    rgb[c] = analysis::pencilReferenceCurve(one, static_cast<analysis::Channel>(c), false);
  }
  const size_t n = rgb[0].r.size();
  const double dr = r_max / static_cast<double>(n);
  for (size_t i = 0; i < n;) {
    const double ra = dr * static_cast<double>(i);
    const size_t width = std::clamp<size_t>(static_cast<size_t>(0.05 * ra / dr), 1, kFineBins);
    const size_t j = std::min(n, i + width);
    const double rb = dr * static_cast<double>(j);
    std::array<double, 3> energy{};
    for (size_t k = i; k < j; ++k) {
      const double area = (2.0 * static_cast<double>(k) + 1.0) * dr * dr;  // / π, as below
      for (size_t c = 0; c < 3; ++c) energy[c] += std::max(0.0, rgb[c].value[k]) * area;
    }
    const double area = rb * rb - ra * ra;
    t.r_mm.push_back(0.5 * (ra + rb) * medium.scale);
    for (size_t c = 0; c < 3; ++c) t.R_mm[c].push_back(energy[c] / area / (medium.scale * medium.scale));
    i = j;
  }
  std::vector<std::string> comment{
      "tabulated profile: path-traced pencil beam on a semi-infinite slab (translucent profile "
      "--reference --save-profile)",
      fmt::format("medium: sigma_a {} sigma_s {} [1/mm] g {} eta {}",
                  fmt::join(medium.sigma_a, ","), fmt::join(medium.sigma_s, ","), medium.g,
                  medium.eta),
      fmt::format("photons per channel: {}, seed {}; R on [0, {:.6g}] mm, {} annuli (centres)",
                  res[0].photons, a.seed, r_max * medium.scale, t.r_mm.size()),
      fmt::format("traced Rd per unit flux entering (as the table's R; incl. beyond the table): "
                  "{:.6g}, {:.6g}, {:.6g}", enteringRd(res[0]), enteringRd(res[1]),
                  enteringRd(res[2]))};
  out.file("--save-profile", path, [&](const std::string& p) { bssrdf::writeProfileSamples(p, t, comment); });
  return fmt::format("wrote {} (tabulated profile, {} radii per channel)\n", path, t.r_mm.size());
}

// --study: every model against the path-traced reference for every traceable preset and RGB
// channel (analysis/model_study.h), written as Markdown (--out), CSV and JSON.
void runStudy(const ProfileArgs& a, const std::string& command) {
  if (a.out.empty() && a.csv.empty() && a.json.empty())
    throw ParameterError("--study: give at least one of --out FILE.md, --csv FILE, --json FILE");
  if (!a.out.empty() && extensionOf(a.out) != ".md")
    throw ParameterError(fmt::format("--study --out '{}': expected a Markdown file (.md)", a.out));
  if (!(a.photons >= 1000.0 && a.photons <= 1e12))
    throw ParameterError(
        fmt::format("--photons is {}: expected between 1e3 and 1e12 per channel", a.photons));
  if (a.models != "all" && splitList(a.models).empty()) throw ParameterError(noModelNamed(a.models));
  OutputSet outputs;
  outputs.output("--out", a.out);
  outputs.output("--csv", a.csv);
  outputs.output("--json", a.json);
  if (a.models != "all")
    for (const auto& m : splitList(a.models)) outputs.input("a BSSRDF model file (--model)", m);
  outputs.check();
  if (!beginWork()) return;
  analysis::ModelStudyOptions o;
  if (a.models != "all") o.models = splitList(a.models);
  o.presets = a.study_presets;
  o.photons = static_cast<uint64_t>(a.photons);
  o.seed = a.seed;
  o.threads = a.threads;
  InterruptGuard guard;
  std::unique_ptr<ProgressBar> bar;
  size_t current = static_cast<size_t>(-1);
  const analysis::ModelStudy study = analysis::runModelStudy(o, [&](const analysis::StudyProgress& p) {
    if (p.index != current) {
      if (bar) bar->end();
      current = p.index;
      bar = std::make_unique<ProgressBar>(
          fmt::format("study {} {} ({}/{})", p.preset, kChannelNames[p.channel], p.index + 1,
                      p.total),
          "photons");
    }
    return (*bar)(p.trace);
  });
  if (bar) bar->end();
  if (study.partial) printStderr("profile --study: stopped early, the outputs are partial\n");
  OutputFiles out;  // all or nothing
  if (!a.out.empty())
    out.file("--out", a.out, [&](const std::string& p) { analysis::writeModelStudyMarkdown(p, study, command); });
  if (!a.csv.empty()) out.file("--csv", a.csv, [&](const std::string& p) { analysis::writeModelStudyCsv(p, study); });
  if (!a.json.empty()) out.file("--json", a.json, [&](const std::string& p) { analysis::writeModelStudyJson(p, study); });
  out.commit();
  printStderr("profile --study: {} models x {} channels in {:.0f} s\n", study.models.size(),
             study.references.size(), study.seconds);
  fmt::print("{}", analysis::modelStudySummaryMarkdown(study));
}

void runProfile(const ProfileArgs& a) {
  const std::string ext = isStdoutPath(a.out) ? ".csv" : extensionOf(a.out);  // '-': CSV on stdout
  if (!a.save_profile.empty()) {
    if (!a.reference)
      throw ParameterError("--save-profile: needs --reference (it saves the path-traced profile)");
    if (extensionOf(a.save_profile) != ".csv")
      throw ParameterError(fmt::format("--save-profile '{}': expected a .csv file",
                                       a.save_profile));
  }
  if (!a.out.empty() && ext != ".csv" && ext != ".png" && ext != ".svg" && ext != ".pdf")
    throw ParameterError(
        fmt::format("--out '{}': expected a file ending in .csv, .png, .svg or .pdf", a.out));
  const Medium medium = a.medium.medium();
  const std::vector<std::string> entries =
      a.models == "all" ? bssrdf::modelNames() : splitList(a.models);
  if (entries.empty()) throw ParameterError(noModelNamed(a.models));
  std::vector<std::string> models, files;  // registered models, .bssrdf files
  for (const auto& m : entries) (isBssrdfFile(m) ? files : models).push_back(m);
  OutputSet outputs;
  outputs.output("--out", a.out);
  outputs.output("--save-profile", a.save_profile);
  for (const auto& f : files) outputs.input("a BSSRDF model file (--model)", f);
  for (const auto& m : models)
    if (bssrdf::isTabulatedFile(m)) outputs.input("a tabulated profile (--model)", m);
  outputs.check();
  for (const auto& m : models) (void)bssrdf::model(m);  // unknown names fail before any work
  for (const auto& f : files)
    if (!std::filesystem::is_regular_file(f))
      throw ParameterError(fmt::format("--model {}: no such .bssrdf file", f));
  if (files.empty()) checkParamsUsed(a.params, {});  // --param without a .bssrdf model
  // The options' values, before any GPU work.
  std::vector<analysis::Channel> channels;
  if (a.channel == "all")
    channels = {analysis::Channel::Red, analysis::Channel::Green, analysis::Channel::Blue};
  else
    channels = {analysis::parseChannel(a.channel)};
  if (a.r_max && !(*a.r_max > 0.0 && std::isfinite(*a.r_max)))
    throw ParameterError(fmt::format("--rmax is {}: expected a positive finite radius", *a.r_max));
  if (a.points < 2 || a.points > kMaxPoints)
    throw ParameterError(fmt::format("--points is {}: expected 2 to {} radii per curve", a.points,
                                     kMaxPoints));
  analysis::CurveOptions opts{a.r_max, a.points, a.times_r};
  if (!(a.theta >= 0.0 && a.theta < 90.0))
    throw ParameterError(fmt::format("--theta is {}: expected a polar angle in [0, 90) degrees", a.theta));
  if (a.theta != 0.0 && !a.save_profile.empty())
    throw ParameterError("--save-profile with --theta: a tabulated model is a normal-incidence "
                         "profile; trace it without --theta");
  if (a.scattering != "all" && !a.reference)
    throw ParameterError(fmt::format(
        "--scattering {}: needs --reference (it selects the path-traced reference's light)",
        a.scattering));
  if (a.reference && !(a.photons >= 1000.0 && a.photons <= 1e12))
    throw ParameterError(
        fmt::format("--photons is {}: expected between 1e3 and 1e12 per channel", a.photons));
  // The plot's name and size, before the curves and the reference are computed.
  if (!a.out.empty() && ext != ".csv") {
    try {
      plot::checkPlotOutput(a.out, a.width, a.height);
    } catch (const ParameterError& e) {
      throw ParameterError(fmt::format("--width {} --height {}: {}", a.width, a.height, e.what()));
    }
  }
  if (!beginWork()) return;
  // .bssrdf files: evaluated on the GPU; the context exists only when one is requested.
  std::unique_ptr<gpu::Context> gl;
  std::vector<std::unique_ptr<gpu::BssrdfEvaluator>> evaluators;
  std::vector<const gpu::BssrdfEvaluator*> loaded;
  if (!files.empty()) {
    gl = bssrdfContext("--model " + files.front());
    for (const auto& f : files) {
      evaluators.push_back(loadBssrdfModel(f, a.params));
      loaded.push_back(evaluators.back().get());
      // A directional file's R(r) is its normal-incidence restriction (gpu/bssrdf_profiles.h),
      // as for the registered directional-dipole.
      if (!evaluators.back()->file().attributes.radial)
        printStderr("profile: {} is directional (line 1 lacks `radial`): plotted at normal "
                    "incidence\n", f);
    }
  }
  checkParamsUsed(a.params, loaded);
  opts.incidence = a.theta * std::numbers::pi / 180.0;
  if (a.theta != 0.0) {
    std::vector<std::string> radial;
    for (const auto& m : models)
      if (bssrdf::model(m).tabulated() || !bssrdf::model(m).directional(medium.channel(0)))
        radial.push_back(m);
    if (!radial.empty())
      printStderr("profile: {} {} radial: plotted for normal incidence whatever --theta (only a "
                  "directional model and the reference see the incidence)\n",
                  fmt::join(radial, ", "), radial.size() == 1 ? "is" : "are");
  }
  double rMax = 0.0;
  if (a.r_max) {
    rMax = *a.r_max;
  } else {
    if (!models.empty()) rMax = analysis::defaultRadius(models, medium);
    for (auto& e : evaluators) {
      const Rgb r95 = gpu::bssrdfRadiusForFraction(*e, medium, 0.95).radius;
      rMax = std::max({rMax, r95[0], r95[1], r95[2]});
    }
  }
  opts.r_max = rMax;
  std::vector<analysis::Curve> curves;
  for (const auto& entry : entries) {
    if (!isBssrdfFile(entry)) {
      auto c = analysis::profileCurves({entry}, medium, channels, opts);
      curves.insert(curves.end(), c.begin(), c.end());
      continue;
    }
    auto& e = *evaluators[static_cast<size_t>(
        std::find(files.begin(), files.end(), entry) - files.begin())];
    // Labelled with the file stem, or the file name where the stem is also a plotted model's.
    std::string label = e.file().stem();
    if (std::find(models.begin(), models.end(), label) != models.end()) label += ".bssrdf";
    auto c = gpu::bssrdfCurves(e, label, medium, channels, analysis::radiusGrid(rMax, a.points),
                               a.times_r);
    curves.insert(curves.end(), c.begin(), c.end());
  }
  for (auto& c : curves)  // a tabulated profile's curves are labelled with its file's stem
    if (bssrdf::isTabulatedFile(c.model)) c.model = std::filesystem::path(c.model).stem().string();
  if (a.reference && !a.out.empty()) {
    std::array<bool, 3> needed{};
    for (analysis::Channel ch : channels)
      for (size_t c = 0; c < 3; ++c)
        if (ch == analysis::Channel::Luminance || static_cast<size_t>(ch) == c) needed[c] = true;
    const auto results = traceReference(medium, needed, rMax, a.points, a);
    for (analysis::Channel ch : channels)
      for (auto& c : referenceCurves(results, needed, ch, a)) curves.push_back(std::move(c));
  }
  // The saved model should hold (nearly) all of the energy: without --rmax its table reaches
  // 3x the plotted default (the 95% radius), where ~0.1% of Rd is left for the fitted tail.
  OutputFiles out;  // all or nothing: --save-profile and --out
  std::string saved;
  if (!a.save_profile.empty())
    saved = saveReferenceProfile(out, a.save_profile, medium, a.r_max ? rMax : 3.0 * rMax, a);
  if (a.out.empty()) {
    out.commit();
    printStderr("{}", saved);
    return;
  }
  if (ext == ".csv") {
    out.file("--out", a.out, [&](const std::string& p) { analysis::writeCurvesCsv(p, curves); });
  } else {
    plot::PlotOptions po;
    po.title = a.title.empty() ? defaultTitle(a) : a.title;
    po.y_scale = plot::parseYScale(a.y);
    po.times_r = a.times_r;
    po.length_unit = lengthUnit(medium.scale);
    po.width = a.width;
    po.height = a.height;
    out.file("--out", a.out, [&](const std::string& p) { plot::writeProfilePlot(p, curves, po); });
  }
  out.commit();
  printStderr("{}wrote {} ({} curves x {} points)\n", saved, a.out, curves.size(), a.points);
}

}  // namespace

void addProfileCommand(CLI::App& app) {
  auto args = std::make_shared<ProfileArgs>();
  auto* cmd = app.add_subcommand(
      "profile", "Radial diffuse reflectance profiles R(r) of BSSRDF models (pencil beam on a "
                 "semi-infinite slab), as CSV, PNG or SVG");
  cmd->add_option("--model", args->models,
                  "Comma-separated model names, .bssrdf files (evaluated on the GPU) or .csv "
                  "tabulated profiles (r,R_r,R_g,R_b with a '# units: mm' line), or 'all': " +
                      fmt::format("{}", fmt::join(bssrdf::modelNames(), ", ")))
      ->capture_default_str();
  cmd->add_option("--param", args->params,
                  "NAME=VALUE for a parameter of a .bssrdf model (repeatable; default: the "
                  "file's)");
  args->medium.add(*cmd, kDefaultPreset);
  cmd->add_option("--rmax", args->r_max,
                  "Largest radius plotted [scene units] (default: largest 95% energy radius)");
  cmd->add_option("--points", args->points, "Radii sampled per curve")->capture_default_str();
  cmd->add_option("--channel", args->channel, "r, g, b, luminance, or all")->capture_default_str();
  cmd->add_option("--y", args->y, "Y axis of plots: lin, log or sqrt")
      ->check(CLI::IsMember({"lin", "log", "sqrt"}))
      ->capture_default_str();
  cmd->add_flag("--times-r", args->times_r, "Plot r·R(r) instead of R(r)");
  outputOption(cmd->add_option("--out", args->out,
                  "Output file: .csv (model,channel,r,value; '-': CSV on stdout), .png, .svg or .pdf; "
                  "with --study a .md report"));
  outputOption(cmd->add_option(
      "--save-profile", args->save_profile,
      "With --reference: save the path-traced R(r) of the three channels as a tabulated model "
      "(.csv, r in mm), usable as --model FILE.csv"));
  cmd->add_option("--width", args->width, "Plot width [pixels] (.png/.svg/.pdf)")->capture_default_str();
  cmd->add_option("--height", args->height, "Plot height [pixels] (.png/.svg/.pdf)")
      ->capture_default_str();
  cmd->add_option("--title", args->title, "Plot title (default: material and what is plotted)");
  cmd->add_flag("--reference", args->reference,
                "Add the path-traced reference (pencil beam on a semi-infinite slab) with error "
                "bars");
  cmd->add_option("--photons", args->photons, "Reference photons per channel")
      ->capture_default_str();
  cmd->add_option("--scattering", args->scattering,
                  "Which light of the reference: all (multi + single scattering), single, "
                  "multiple, or split (the three curves; Bitterli 2013, Eq. 2.13, Fig. 3.6)")
      ->check(CLI::IsMember(std::vector<std::string>(analysis::kScatteringSelections.begin(),
                                                     analysis::kScatteringSelections.end())))
      ->capture_default_str();
  cmd->add_flag("--study", args->study,
                "Error study: every model (or --model list) against the path-traced reference for "
                "every traceable preset and RGB channel: L1 of 2πrR(r), Rd error, R95 ratio "
                "(Markdown --out, --csv, --json)");
  outputOption(cmd->add_option("--csv", args->csv, "With --study: per model and channel results as CSV"));
  outputOption(cmd->add_option("--json", args->json, "With --study: the full study as JSON"));
  cmd->add_option("--study-presets", args->study_presets,
                  "With --study: comma-separated presets (default: every traceable one)")
      ->delimiter(',');
  cmd->add_option("--theta", args->theta,
                  "Polar angle of the pencil beam [degrees, outside]: the reference is traced at "
                  "it and directional models are averaged over the azimuth at it (radial models "
                  "assume normal incidence)")
      ->capture_default_str();
  cmd->add_option("--seed", args->seed, "Reference random seed")->capture_default_str();
  cmd->add_option("--threads", args->threads, "Reference threads (0: all)")->capture_default_str();
  cmd->add_option("--device", args->device,
                  "Where --reference is traced: cpu, gpu (GL compute shaders), or auto (the GPU "
                  "on a hardware GPU, else the CPU)")
      ->check(CLI::IsMember({"cpu", "gpu", "auto"}))
      ->capture_default_str();
  cmd->callback([args, cmd] {
    if (args->study) {
      // The study's references come from analysis::runModelStudy (CPU threads, with its cache).
      if (args->device == "gpu")
        throw ParameterError("--device gpu: the --study references are traced on the CPU; "
                             "--device applies to --reference");
      std::string command = "translucent profile --study";
      for (const auto& opt : cmd->get_options())
        if (opt->count() > 0 && opt->get_name() != "--study" && opt->get_name() != "--help")
          command += " " + opt->get_name() + " " + fmt::format("{}", fmt::join(opt->results(), ","));
      runStudy(*args, command);
      return;
    }
    if (!args->csv.empty() || !args->json.empty() || !args->study_presets.empty())
      throw ParameterError("--csv, --json and --study-presets need --study");
    if (args->out.empty() && args->save_profile.empty())
      throw ParameterError("--out is required (or --save-profile with --reference)");
    runProfile(*args);
  });
}

}  // namespace translucent::cli
