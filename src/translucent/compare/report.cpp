// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/compare/report.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <span>

#include "translucent/analysis/colormap.h"
#include "translucent/io/image_io.h"
#include "translucent/compare/report_text.h"
#include "translucent/geometry/atomic_file.h"
#include "translucent/io/json.h"
#include "viewer_assets.h"  // generated: viewer/viewer.js and viewer.css (CMakeLists.txt)

namespace translucent::analysis {
namespace fs = std::filesystem;
using nlohmann::json;
using text::html, text::number, text::num, text::pct, text::spct;

namespace {

// "failed: ERROR", or for a technique stopped by compare's --budget its error ("over budget: ...").
std::string failureText(const TechniqueRun& t) {
  return t.over_budget ? t.error : "failed: " + t.error;
}

constexpr const char* kGenerator = "translucent compare";
constexpr double kPi = 3.14159265358979323846;

json metricsJson(const Metrics& m) {
  return {{"pixels", m.pixels},
          {"mean_reference", number(m.mean_reference)},
          {"mean_test", number(m.mean_test)},
          {"rel_rmse", number(m.rel_rmse)},
          {"rel_rmse_raw", number(m.rel_rmse_raw)},
          {"noise_mse", number(m.noise_mse)},
          {"noise_mse_stderr", number(m.noise_mse_stderr)},
          {"noise_variance", number(m.noise_variance)},
          {"bias", number(m.bias)},
          {"bias_stderr", number(m.bias_stderr)},
          {"ssim", number(m.ssim)},
          {"flip", number(m.flip)},
          {"mean_abs_z", number(m.mean_abs_z)},
          {"fraction_abs_z_above_3", number(m.fraction_abs_z_above_3)},
          {"z_pixels", m.z_pixels}};
}

json pairJson(const PairMetrics& p) {
  json j = {{"test", p.test},         {"reference", p.reference}, {"quantity", p.quantity},
            {"convention", p.convention}, {"mask", p.mask}};
  j["metrics"] = metricsJson(p.metrics);
  return j;
}

// A technique's row name as a file name: a variant "tsis:mode=hybrid:samples=900" (cmd_compare)
// holds ':' and '=', which a relative URL would read as a scheme; letters, digits, '.', '-' and
// '_' are kept, '=' becomes '-', anything else '_'.
std::string fileStem(const std::string& name) {
  std::string out = name;
  for (char& c : out) {
    const auto u = static_cast<unsigned char>(c);
    if (std::isalnum(u) || c == '.' || c == '-' || c == '_') continue;
    c = c == '=' ? '-' : '_';
  }
  return out;
}

std::string pairStem(const PairMetrics& p) {
  return fmt::format("err-{}-vs-{}-{}{}", fileStem(p.test), p.reference, p.quantity,
                     p.convention.empty() ? "" : "-" + p.convention);
}

int modelSubpixels(const CompareReport& r) {
  for (const Reference& ref : r.references)
    if (ref.kind == ReferenceKind::Model) return ref.request.subpixels;
  return 0;
}

const Reference* findReference(const CompareReport& r, const std::string& kind) {
  for (const Reference& ref : r.references)
    if (toString(ref.kind) == kind) return &ref;
  return nullptr;
}

// The two images and the mask a row of the metrics compared.
struct PairImages {
  CompareImage test, reference;
  const std::vector<uint8_t>* mask = nullptr;
};

PairImages pairImages(const CompareReport& r, const PairMetrics& p) {
  const double eta = r.scene.medium.eta;
  const bssrdf::ExitConvention conv =
      p.convention.empty() ? bssrdf::ExitConvention::Jensen : bssrdf::parseExitConvention(p.convention);
  PairImages out;
  out.mask = p.mask == "interior_cone" ? &r.masks.cone : &r.masks.interior;
  if (p.test == "model") {
    const Reference* m = findReference(r, "model");
    out.test = p.quantity == "exitance" ? m->exitance : m->radianceFor(conv, eta);
  } else {
    for (const TechniqueRun& t : r.techniques)
      if (t.images.name == p.test)
        out.test = p.quantity == "exitance" ? t.images.exitance : t.images.radiance;
  }
  const Reference* ref = findReference(r, p.reference);
  out.reference = p.quantity == "exitance"        ? ref->exitance
                  : p.quantity == "cone_radiance" ? ref->cone_radiance
                                                  : ref->radianceFor(conv, eta);
  return out;
}

class Writer {
 public:
  Writer(fs::path dir, const CompareReport& r) : dir_(std::move(dir)), r_(r) {}

  std::string file(const std::string& name) {
    files_.push_back(name);
    return (dir_ / name).string();
  }
  // Tone-mapped PNG: radiance at the scene's exposure, exitance at exposure - log2 π (B/π, the
  // radiance of a white Lambertian exit) so that the two look alike.
  std::string png(const std::string& name, const CompareImage& img, bool exitance) {
    const ToneMap tm{r_.scene.exposure - (exitance ? std::log2(kPi) : 0.0), r_.scene.gamma};
    writePng(file(name), img.width, img.height, img.rgb, tm);
    return name;
  }
  std::string map(const std::string& name, std::span<const float> values, ColorMap cmap,
                  double lo, double hi) {
    const int w = r_.scene.camera.width, h = r_.scene.camera.height;
    writePng8(file(name), w, h, falseColor(values, w, h, cmap, lo, hi));
    return name;
  }
  std::string map8(const std::string& name, const std::vector<uint8_t>& rgb) {
    writePng8(file(name), r_.scene.camera.width, r_.scene.camera.height, rgb);
    return name;
  }
  std::string bar(const std::string& name, ColorMap cmap, double lo, double hi) {
    const int w = 320, h = 40;  // colorBar needs >= 24 rows for its labels
    writePng8(file(name), w, h, colorBar(w, h, cmap, lo, hi));
    return name;
  }
  std::string text(const std::string& name, const std::string& content) {
    // Temporary file and rename: an interrupted or failing write never leaves half a page.
    const std::string why = geometry::writeFileAtomically(file(name), content);
    if (!why.empty())
      throw ImageError(fmt::format("cannot write '{}': {}", (dir_ / name).string(), why));
    return name;
  }
  const std::vector<std::string>& files() const { return files_; }
  void addExisting(const std::string& name) { files_.push_back(name); }

 private:
  fs::path dir_;
  const CompareReport& r_;
  std::vector<std::string> files_;
};

std::string maskPng(Writer& w, const std::string& name, const std::vector<uint8_t>& mask, int width,
                    int height) {
  CompareImage m{width, height, {}, {}};
  for (uint8_t v : mask) m.rgb.insert(m.rgb.end(), 3, v ? 1.0f : 0.0f);
  const std::string path = name;
  writePng(w.file(path), width, height, m.rgb, {0.0, 1.0});
  return path;
}

std::string sceneSummary(const scene::Scene& s) {
  return fmt::format("{} ({}x{}), medium{} σa = ({:.4g}, {:.4g}, {:.4g}), σs = ({:.4g}, {:.4g}, "
                     "{:.4g}) per medium unit, {} medium units per scene unit, g = {}, η = {}, "
                     "model {}",
                     s.mesh_file.string(), s.camera.width, s.camera.height,
                     s.preset.empty() ? "" : " " + s.preset, s.medium.sigma_a[0],
                     s.medium.sigma_a[1], s.medium.sigma_a[2], s.medium.sigma_s[0],
                     s.medium.sigma_s[1], s.medium.sigma_s[2], s.medium.scale, s.medium.g,
                     s.medium.eta, s.model);
}


// ---- Summary ---------------------------------------------------------------------------------

// The metrics row of (test, reference, quantity), or nullptr.
const PairMetrics* findPair(const CompareReport& r, const std::string& test,
                            const std::string& reference, const std::string& quantity) {
  for (const PairMetrics& p : r.metrics)
    if (p.test == test && p.reference == reference && p.quantity == quantity) return &p;
  return nullptr;
}

double relRmse(const PairMetrics* p) {
  return p ? p->metrics.rel_rmse : std::numeric_limits<double>::quiet_NaN();
}

// The leaderboard of this scene (report.json "summary", and the first table of index.html, which
// is written from this JSON so that the page and the file cannot disagree): per technique the
// noise-aware relative RMSE of its radiance L against each reference (the quantity the suite's
// leaderboard ranks by), its median frame time and its status; ranked by the error against the
// physical reference where there is one, else against the model; failed and over-budget
// techniques last, in the order they were run, each with its reason.
json summaryJson(const CompareReport& r) {
  struct Row {
    json j;
    double key1, key2;  // vs physical, vs model (NaN sorts last)
    size_t order;
  };
  std::vector<Row> done, failedRows;
  for (size_t i = 0; i < r.techniques.size(); ++i) {
    const TechniqueRun& t = r.techniques[i];
    const std::string& n = t.images.name;
    if (t.failed()) {
      failedRows.push_back({{{"technique", n},
                             {"status", t.over_budget ? "over budget" : "failed"},
                             {"reason", failureText(t)}},
                            0.0, 0.0, i});
      continue;
    }
    const double vm = relRmse(findPair(r, n, "model", "radiance"));
    const double vp = relRmse(findPair(r, n, "physical", "radiance"));
    done.push_back({{{"technique", n},
                     {"status", "done"},
                     {"vs_model_rel_rmse", number(vm)},
                     {"vs_physical_rel_rmse", number(vp)},
                     {"frame_ms", number(t.frame_ms)}},
                    vp, vm, i});
  }
  auto less = [](double a, double b) {  // finite before NaN
    if (std::isfinite(a) != std::isfinite(b)) return std::isfinite(a);
    return std::isfinite(a) && a < b;
  };
  std::stable_sort(done.begin(), done.end(), [&](const Row& a, const Row& b) {
    if (less(a.key1, b.key1) || less(b.key1, a.key1)) return less(a.key1, b.key1);
    return less(a.key2, b.key2);
  });
  json rows = json::array();
  for (const Row& row : done) rows.push_back(row.j);
  for (const Row& row : failedRows) rows.push_back(row.j);
  json out = {{"quantity", "radiance L over the interior mask; rel_rmse noise-aware, as in "
                           "metrics (report.json); frame_ms the median GPU time of a frame"},
              {"ranked_by", findReference(r, "physical") ? "vs_physical_rel_rmse"
                                                          : "vs_model_rel_rmse"},
              {"rows", rows}};
  out["model_vs_physical_rel_rmse"] = number(relRmse(findPair(r, "model", "physical", "radiance")));
  return out;
}

double jsonNumber(const json& j, const char* key) {
  return j.contains(key) && j.at(key).is_number() ? j.at(key).get<double>()
                                                  : std::numeric_limits<double>::quiet_NaN();
}

// index.html's first table, from summaryJson.
std::string summaryHtml(const json& summary) {
  std::string h =
      "<h2 id=\"summary-heading\">Summary</h2>\n<table id=\"summary\" class=\"summary\"><tr>"
      "<th>rank</th><th class=\"l\">technique</th><th>error vs model</th>"
      "<th>error vs physical</th><th>GPU time [ms]</th><th class=\"l\">status</th></tr>\n";
  int rank = 0;
  std::vector<const json*> failures;
  for (const json& row : summary.at("rows")) {
    const std::string status = row.at("status").get<std::string>();
    if (status != "done") {
      failures.push_back(&row);
      continue;
    }
    h += fmt::format("<tr data-technique=\"{}\"><td>{}</td><td class=\"l\">{}</td><td>{}</td>"
                     "<td>{}</td><td>{}</td><td class=\"l\">{}</td></tr>\n",
                     html(row.at("technique").get<std::string>()), ++rank,
                     html(row.at("technique").get<std::string>()),
                     pct(jsonNumber(row, "vs_model_rel_rmse")),
                     pct(jsonNumber(row, "vs_physical_rel_rmse")), num(jsonNumber(row, "frame_ms")),
                     html(status));
  }
  if (summary.at("rows").empty())
    h += "<tr><td class=\"l\" colspan=\"6\">no technique was run (the references only)</td></tr>\n";
  for (const json* row : failures)
    h += fmt::format("<tr data-technique=\"{}\"><td>–</td><td class=\"l\">{}</td>"
                     "<td class=\"l warn\" colspan=\"3\">{}</td><td class=\"l warn\">{}</td></tr>\n",
                     html(row->at("technique").get<std::string>()),
                     html(row->at("technique").get<std::string>()),
                     html(row->at("reason").get<std::string>()),
                     html(row->at("status").get<std::string>()));
  h += "</table>\n<p class=\"note\">Error: noise-aware relative RMSE of the radiance L over the "
       "interior mask (the Errors table below has every quantity and metric); ranked by the "
       "error vs " +
       std::string(summary.at("ranked_by") == "vs_physical_rel_rmse" ? "physical" : "model") +
       ". GPU time: the median frame.";
  const double mp = jsonNumber(summary, "model_vs_physical_rel_rmse");
  if (std::isfinite(mp)) h += " The model itself vs physical: " + pct(mp) + ".";
  h += "</p>\n";
  if (!failures.empty()) {
    const size_t total = summary.at("rows").size();
    h += fmt::format("<p class=\"warn\">{} of {} techniques failed or ran over budget on this "
                     "scene (no images or metrics; the others and the references are complete):"
                     "</p>\n<ul class=\"failures\">\n", failures.size(), total);
    for (const json* row : failures)
      h += "<li class=\"warn\">" + html(row->at("technique").get<std::string>()) + ": " +
           html(row->at("reason").get<std::string>()) + "</li>\n";
    h += "</ul>\n";
  }
  return h;
}

// ---- Viewer data -------------------------------------------------------------------------------

std::string base64(std::span<const unsigned char> bytes) {
  static constexpr char kAlphabet[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const uint32_t v = (uint32_t{bytes[i]} << 16) | (uint32_t{bytes[i + 1]} << 8) | bytes[i + 2];
    for (int k = 18; k >= 0; k -= 6) out += kAlphabet[(v >> k) & 63];
  }
  if (i < bytes.size()) {
    uint32_t v = uint32_t{bytes[i]} << 16;
    if (i + 1 < bytes.size()) v |= uint32_t{bytes[i + 1]} << 8;
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += i + 1 < bytes.size() ? kAlphabet[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

// Linear RGB as little-endian IEEE float32, base64.
std::string floatsBase64(std::span<const float> values) {
  std::vector<unsigned char> bytes(values.size() * 4);
  for (size_t i = 0; i < values.size(); ++i) {
    uint32_t u = 0;
    static_assert(sizeof(float) == 4);
    std::memcpy(&u, &values[i], 4);
    for (int b = 0; b < 4; ++b) bytes[4 * i + static_cast<size_t>(b)] = static_cast<unsigned char>(u >> (8 * b));
  }
  return base64(bytes);
}

const char* kStyle = R"(body{font-family:sans-serif;margin:1.5em;max-width:1400px;color:#222}
table{border-collapse:collapse;margin:0.5em 0 1.5em}td,th{border:1px solid #bbb;padding:3px 7px;
text-align:right;font-size:13px}th{background:#eee}td.l,th.l{text-align:left}
figure{display:inline-block;margin:4px;text-align:center;font-size:12px;vertical-align:top}
figure img{image-rendering:pixelated;border:1px solid #888;width:240px}
figure img.bar{width:320px;height:40px;image-rendering:auto;border:none}
pre{background:#f4f4f4;padding:8px;white-space:pre-wrap;word-break:break-all}
.warn{color:#a00;font-weight:bold}.plot{width:800px;border:1px solid #ccc})";

}  // namespace

void prepareOwnedFolder(const fs::path& dir, bool force, const fs::path& ignore,
                        const std::string& option, const std::string& manifest,
                        const std::string& generator, const std::string& what) {
  std::error_code ec;
  if (!fs::exists(dir, ec)) {
    fs::create_directories(dir, ec);
    if (ec)
      throw ParameterError(fmt::format("{} '{}': cannot create the folder: {}", option,
                                       dir.string(), ec.message()));
    return;
  }
  if (!fs::is_directory(dir, ec))
    throw ParameterError(fmt::format("{} '{}': exists and is not a folder", option, dir.string()));
  // The previous run's files, if there is one.
  std::set<std::string> ours;
  const fs::path previous = dir / manifest;
  if (fs::exists(previous, ec)) {
    try {
      const json j = io::readJsonFile(previous);
      if (j.value("generator", "") == generator) {
        ours.insert(manifest);
        for (const auto& name : j.at("files")) ours.insert(name.get<std::string>());
      }
    } catch (const std::exception&) {
      ours.clear();  // not one of ours
    }
  }
  std::vector<fs::path> remove;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (!ignore.empty() && fs::equivalent(entry.path(), ignore, ec)) continue;
    if (ours.contains(name) && entry.is_regular_file()) {
      remove.push_back(entry.path());
    } else if (!force) {
      throw ParameterError(fmt::format(
          "{} '{}': the folder holds '{}', which is not part of {}; choose an empty or new "
          "folder, or pass --force to write into it anyway",
          option, dir.string(), name, what));
    }
  }
  for (const auto& p : remove) fs::remove(p, ec);
}

void prepareReportDirectory(const fs::path& dir, bool force, const fs::path& ignore,
                            const std::string& option) {
  prepareOwnedFolder(dir, force, ignore, option, "report.json", kGenerator,
                     "a previous compare report");
}

namespace {

// The half-angle of the physical reference's cone radiance (0: the camera method's true radiance;
// the scene's cone_angle for the light method, or when there is no physical reference).
double physicalConeAngle(const CompareReport& r) {
  return analysis::physicalConeAngle(r.references).value_or(r.scene.cone_angle);
}

// "Where the error is": per technique the split of its radiance error against the physical
// reference into its own part (vs the model reference) and the model's (model vs physical), per
// region, with a map; report.json "diagnosis". Nothing without both references or regions.
std::string diagnosisSection(Writer& w, const CompareReport& r, json& j) {
  const Reference* model = findReference(r, "model");
  const Reference* physical = findReference(r, "physical");
  if (model == nullptr || physical == nullptr || r.regions.names.empty()) return {};
  const double eta = r.scene.medium.eta;
  std::string h =
      "<h2>Where the error is</h2>\n<p>Each technique's radiance error against the physical "
      "reference P, split into the technique's part (against the model reference M: what the "
      "technique adds to its model) and the model's part (M against P: what the model itself "
      "misses on this mesh), as relative RMSE with the noise taken out, per region of the "
      "picture. Regions (they overlap): " + html(r.regions.definition) + ".</p>\n";
  w.map8("regions.png", regionMap(r.regions, r.masks.interior));
  h += "<figure><img src=\"regions.png\" alt=\"regions\"><figcaption>Regions: silhouettes red, "
       "thin parts green, shadow boundaries blue (mixed where they overlap), elsewhere grey."
       "</figcaption></figure>\n";
  json dj = {{"regions", r.regions.names}, {"definition", r.regions.definition},
             {"thin_threshold", r.regions.thin_threshold}, {"techniques", json::object()}};
  for (size_t k = 0; k < r.regions.names.size(); ++k) {
    uint64_t count = 0;
    for (uint8_t v : r.regions.masks[k]) count += v != 0;
    dj["pixels"][r.regions.names[k]] = count;
  }
  std::string table = "<table><tr><th class=\"l\">technique</th><th class=\"l\">region</th>"
                      "<th>pixels</th><th>vs physical</th><th>technique's part</th>"
                      "<th>model's part</th></tr>\n";
  std::string maps;
  for (const TechniqueRun& t : r.techniques) {
    if (t.failed() || t.images.radiance.empty()) continue;
    const CompareImage m = model->radianceFor(t.images.convention, eta);
    const CompareImage p = physical->radianceFor(t.images.convention, eta);
    std::vector<RegionSplit> rows;
    try {
      rows = splitError(t.images.radiance, m, p, r.regions, r.masks.interior);
    } catch (const ParameterError& e) {  // (sizes that differ: the metrics table says so too)
      table += "<tr><td class=\"l\">" + html(t.images.name) + "</td><td class=\"l warn\" "
               "colspan=\"5\">" + html(e.what()) + "</td></tr>\n";
      continue;
    }
    const std::string file = "split-" + fileStem(t.images.name) + ".png";
    w.map8(file, splitMap(t.images.radiance, m, p, r.masks.interior));
    maps += "<figure><img src=\"" + html(file) + "\" alt=\"" + html(t.images.name) +
            "\"><figcaption>" + html(t.images.name) + "</figcaption></figure>\n";
    json tj = json::array();
    for (const RegionSplit& s : rows) {
      table += fmt::format("<tr><td class=\"l\">{}</td><td class=\"l\">{}</td><td>{}</td>"
                           "<td>{}</td><td>{}</td><td>{}</td></tr>\n", html(t.images.name),
                           html(s.region), s.pixels, pct(s.vs_physical), pct(s.technique_part),
                           pct(s.model_part));
      tj.push_back({{"region", s.region}, {"pixels", s.pixels}, {"vs_physical", number(s.vs_physical)},
                    {"technique_part", number(s.technique_part)},
                    {"model_part", number(s.model_part)}});
    }
    dj["techniques"][t.images.name] = tj;
  }
  j["diagnosis"] = dj;
  h += table + "</table>\n<p>Maps: brightness |T − P| / P (full at 50%), hue the larger part: "
       "orange the technique's, blue the model's.</p>\n" + maps + "\n";
  return h;
}

}  // namespace

std::vector<std::string> writeReport(const fs::path& dir, const CompareReport& r) {
  Writer w(dir, r);
  const int width = r.scene.camera.width, height = r.scene.camera.height;
  const double eta = r.scene.medium.eta;
  // The references' L is shown under the first technique's convention that rendered.
  bssrdf::ExitConvention shown = bssrdf::ExitConvention::Jensen;
  for (auto t = r.techniques.rbegin(); t != r.techniques.rend(); ++t)
    if (!t->failed()) shown = t->images.convention;
  std::vector<const TechniqueRun*> failed;
  for (const TechniqueRun& t : r.techniques)
    if (t.failed()) failed.push_back(&t);
  json j;
  j["generator"] = kGenerator;
  j["version"] = r.version;
  j["versions"] = {{"translucent", r.version}, {"gl", r.gpu},
                   {"compiler", __VERSION__},
                   {"reference_code_version", kReferenceCodeVersion}};
  for (const auto& [k, v] : r.settings) j["settings"][k] = v;
  j["created"] = r.created;
  j["command"] = r.command;
  j["scene_file"] = r.scene_file;
  j["scene"] = json::parse(scene::toJson(r.scene));
  j["gpu"] = r.gpu;
  j["partial"] = r.partial;
  j["notes"] = r.notes;
  j["material"] = {{"kind", r.material.kind},
                   {"physical_reference", r.material.physical},
                   {"references", r.material.text}};
  j["cache_dir"] = r.cache_dir.string();
  j["masks"] = {{"interior_pixels", r.masks.interiorPixels()},
                {"interior_cone_pixels", r.masks.conePixels()},
                {"pixels", static_cast<uint64_t>(width) * static_cast<uint64_t>(height)},
                {"interior", "every ray of a 4x4 grid per pixel hits the mesh, and the model "
                             "reference's coverage is 1 where it was computed"},
                {"interior_cone", fmt::format("interior, and |n·v| >= sin θc (θc = {} degrees) "
                                              "for every ray of the grid: the cone radiance is "
                                              "biased low within θc of silhouettes",
                                              physicalConeAngle(r))}};

  // ---- Images ----------------------------------------------------------------------------
  struct Shown { std::string label, exitance, radiance, cone; };
  std::vector<Shown> shownRows;
  json techniques = json::array();
  for (const TechniqueRun& t : r.techniques) {
    const std::string n = t.images.name;
    if (t.failed()) {
      json tj = {{"name", n}, {"description", t.description}, {"status", t.over_budget ? "over budget" : "failed"},
                 {"error", t.error}, {"notes", t.notes}};
      for (const auto& [k, v] : t.parameters) tj["parameters"][k] = v;
      techniques.push_back(tj);
      continue;
    }
    Shown s{n, "", "", ""};
    std::vector<ExrLayer> layers;
    if (!t.images.exitance.empty()) layers.push_back({"exitance", t.images.exitance.rgb});
    const std::pair<std::string, std::string> attrs[] = {
        {"translucent:quantity",
         fmt::format("radiance L ({} convention); layer exitance: B", toString(t.images.convention))},
        {"translucent:technique", n}};
    const std::string f = fileStem(n);
    writeExr(w.file(f + ".exr"), width, height, t.images.radiance.rgb, layers, attrs);
    s.radiance = w.png(f + "-radiance.png", t.images.radiance, false);
    if (!t.images.exitance.empty()) s.exitance = w.png(f + "-exitance.png", t.images.exitance, true);
    shownRows.push_back(s);
    json tj = {{"name", n}, {"description", t.description}, {"status", "done"},
               {"convention", toString(t.images.convention)},
               {"frame_ms", t.frame_ms}, {"timed_frames", t.timed_frames},
               {"warmup_frames", t.warmup_frames}, {"notes", t.notes},
               {"has_exitance", !t.images.exitance.empty()}, {"exr", f + ".exr"}};
    for (const auto& [k, v] : t.parameters) tj["parameters"][k] = v;
    for (const PassStat& p : t.passes)
      tj["passes"].push_back({{"name", p.name}, {"depth", p.depth}, {"median_ms", p.median_ms},
                              {"min_ms", p.min_ms}, {"max_ms", p.max_ms}});
    techniques.push_back(tj);
  }
  j["techniques"] = techniques;
  json references = json::array();
  for (const Reference& ref : r.references) {
    const std::string n = toString(ref.kind);
    writeReferenceExr(w.file(n + ".exr"), ref, "translucent compare: " + r.command);
    Shown s{n + " reference", "", "", ""};
    s.exitance = w.png(n + "-exitance.png", ref.exitance, true);
    s.radiance = w.png(n + "-radiance.png", ref.radianceFor(shown, eta), false);
    if (!ref.cone_radiance.empty()) s.cone = w.png(n + "-cone_radiance.png", ref.cone_radiance, false);
    shownRows.push_back(s);
    references.push_back({{"kind", n}, {"count", ref.request.count},
                          {"method", ref.kind == ReferenceKind::Physical ? json(ref.request.method)
                                                                         : json(nullptr)},
                          {"cone_angle", ref.kind == ReferenceKind::Physical
                                             ? json(ref.cone_angle.value_or(r.scene.cone_angle))
                                             : json(nullptr)},
                          {"count_unit", ref.kind != ReferenceKind::Physical ? "samples"
                                         : ref.request.method == "camera"
                                             ? "camera paths per pixel and channel"
                                             : "photons per channel"},
                          {"count_done", ref.count_done}, {"seed", ref.request.seed},
                          {"subpixels", ref.kind == ReferenceKind::Model ? json(ref.request.subpixels)
                                                                         : json(nullptr)},
                          {"seconds", ref.seconds}, {"partial", ref.partial},
                          {"from_cache", ref.from_cache}, {"key", ref.key},
                          {"cache_file", ref.cache_file.string()}, {"cache_note", ref.cache_note},
                          {"exr", n + ".exr"}, {"stored_convention", "jensen"}});
  }
  j["references"] = references;
  const std::string maskInterior = maskPng(w, "mask-interior.png", r.masks.interior, width, height);
  const std::string maskCone = maskPng(w, "mask-interior_cone.png", r.masks.cone, width, height);

  // ---- Metrics and error maps ------------------------------------------------------------
  const std::string barRel = w.bar("bar-relative.png", ColorMap::Diverging, -kRelativeRange, kRelativeRange);
  const std::string barZ = w.bar("bar-z.png", ColorMap::Diverging, -kZRange, kZRange);
  const std::string barFlip = w.bar("bar-flip.png", ColorMap::Magma, 0.0, 1.0);
  json metrics = json::array();
  struct Maps { std::string rel, z, flip; };
  std::vector<Maps> maps;
  // The viewer's linear pixels: one script per image (px-KEY.js, each image once however many
  // pairs show it) that hands its float32 RGB to viewer.js. A script rather than a .bin beside
  // the PNGs because a page opened from file:// may not fetch() or XHR the files beside it in
  // Chromium (nor Firefox by default), while <script src> loads them; base64 rather than a JSON
  // number list so that every float arrives bit-exact, at 16 bytes a pixel (4/3 of the raw
  // floats). The viewer loads an image's script when a pair first shows it.
  json viewerImages = json::object();
  json viewerPairs = json::array();
  auto viewerImage = [&](const std::string& key, const std::string& label,
                         const std::string& quantity, const CompareImage& img) {
    if (viewerImages.contains(key)) return key;
    const std::string file = "px-" + key + ".js";
    w.text(file, fmt::format("translucentViewerPixels(\"{}\", {}, {}, \"{}\");\n", key, img.width,
                             img.height, floatsBase64(img.rgb)));
    viewerImages[key] = {{"file", file}, {"label", label}, {"quantity", quantity},
                         {"width", img.width}, {"height", img.height},
                         {"exposure", r.scene.exposure - (quantity == "exitance" ? std::log2(kPi) : 0.0)},
                         {"encoding", "RGB float32 little-endian, rows from the top, base64"}};
    return key;
  };
  for (const PairMetrics& p : r.metrics) {
    const PairImages im = pairImages(r, p);
    const std::string stem = pairStem(p);
    MetricOptions o;
    o.mask = *im.mask;
    o.exposure = r.scene.exposure;
    o.gamma = r.scene.gamma;
    Maps m;
    m.rel = w.map(stem + "-rel.png", relativeDifferenceMap(im.test.ref(), im.reference.ref(), *im.mask),
                  ColorMap::Diverging, -kRelativeRange, kRelativeRange);
    m.z = w.map(stem + "-z.png", zScoreMap(im.test.ref(), im.reference.ref(), *im.mask),
                ColorMap::Diverging, -kZRange, kZRange);
    // FLIP is computed on the whole image (its filters see the neighbours); shown, like the
    // other maps, where it is averaged: grey outside the mask.
    std::vector<float> flip = flipMap(im.test.ref(), im.reference.ref(), o);
    for (size_t i = 0; i < flip.size() && i < im.mask->size(); ++i)
      if (!(*im.mask)[i]) flip[i] = std::numeric_limits<float>::quiet_NaN();
    m.flip = w.map(stem + "-flip.png", flip, ColorMap::Magma, 0.0, 1.0);
    maps.push_back(m);
    {
      const std::string conv = p.convention.empty() ? "jensen" : p.convention;
      const std::string testQuantity = p.quantity == "exitance" ? "exitance" : "radiance";
      const std::string left =
          p.test == "model"
              ? viewerImage(fileStem("ref-model-" + testQuantity +
                                     (testQuantity == "radiance" ? "-" + conv : "")),
                            "model reference " + testQuantity + (testQuantity == "radiance" ? " (" + conv + ")" : ""),
                            testQuantity, im.test)
              : viewerImage(fileStem("tech-" + p.test + "-" + testQuantity), p.test + " " + testQuantity,
                            testQuantity, im.test);
      const std::string right = viewerImage(
          fileStem("ref-" + p.reference + "-" + p.quantity + (p.quantity == "radiance" ? "-" + conv : "")),
          p.reference + " reference " + p.quantity + (p.quantity == "radiance" ? " (" + conv + ")" : ""),
          p.quantity, im.reference);
      viewerPairs.push_back({{"test", p.test}, {"reference", p.reference}, {"quantity", p.quantity},
                             {"convention", p.convention}, {"mask", p.mask}, {"left", left},
                             {"right", right},
                             {"maps", {{"relative", m.rel}, {"z", m.z}, {"flip", m.flip}}}});
    }
    json pj = pairJson(p);
    pj["maps"] = {{"relative", m.rel}, {"z", m.z}, {"flip", m.flip}};
    metrics.push_back(pj);
  }
  j["metrics"] = metrics;
  j["summary"] = summaryJson(r);
  // What viewer.js shows: every metrics pair with its two images and error maps; the tests in the
  // summary's order, then the model. viewer-data.js holds the same and the masks.
  {
    json tests = json::array();
    for (const json& row : j["summary"]["rows"])
      if (row.at("status") == "done") tests.push_back(row.at("technique"));
    if (findPair(r, "model", "physical", "radiance")) tests.push_back("model");
    j["viewer"] = {{"width", width}, {"height", height}, {"gamma", r.scene.gamma},
                   {"tests", tests}, {"images", viewerImages}, {"pairs", viewerPairs},
                   {"bars", {{"relative", barRel}, {"z", barZ}, {"flip", barFlip}}},
                   {"ranges", {{"relative", kRelativeRange}, {"z", kZRange}, {"flip", 1.0}}},
                   {"script", "viewer.js"}, {"style", "viewer.css"}, {"data", "viewer-data.js"}};
    json data = j["viewer"];
    auto maskBase64 = [](const std::vector<uint8_t>& mask) {
      return base64(std::span<const unsigned char>(mask.data(), mask.size()));
    };
    data["masks"] = {{"interior", maskBase64(r.masks.interior)},
                     {"interior_cone", maskBase64(r.masks.cone)}};
    w.text("viewer-data.js", "// Written by translucent compare: what viewer.js shows (report.json \"viewer\").\n"
                             "window.translucentViewerData = " + data.dump() + ";\n");
    w.text("viewer.js", std::string(viewer::kScript));
    w.text("viewer.css", std::string(viewer::kStyle));
  }
  json sweep = json::array();
  for (const SweepPoint& s : r.sweep) {
    json sj = {{"technique", s.technique}, {"parameter", s.parameter}, {"value", s.value},
               {"frame_ms", s.frame_ms}};
    for (const PairMetrics& p : s.metrics) sj["metrics"].push_back(pairJson(p));
    sweep.push_back(sj);
  }
  j["sweep"] = sweep;
  for (const Figure& f : r.figures) {
    w.addExisting(f.file);
    j["figures"].push_back({{"file", f.file}, {"caption", f.caption}});
  }

  // ---- index.html ------------------------------------------------------------------------
  std::string h;
  h += "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>translucent compare: " +
       html(r.scene_file.empty() ? "built-in bunny" : r.scene_file) + "</title><style>" + kStyle +
       "</style><link rel=\"stylesheet\" href=\"viewer.css\"></head><body>\n";
  h += "<h1>translucent compare</h1>\n";
  if (r.partial)
    h += "<p class=\"warn\">Partial report: stopped early (Ctrl-C); a reference is partial or "
         "missing and its numbers are from fewer samples than requested.</p>\n";
  h += "<p>Scene: <b>" + html(r.scene_file.empty() ? "built-in bunny" : r.scene_file) + "</b>: " +
       html(sceneSummary(r.scene)) + ". GPU: " + html(r.gpu) + ". " + html(r.version) +
       ", created " + html(r.created) + ".</p>\n";
  // The summary first, then the viewer; the details follow.
  h += summaryHtml(j["summary"]);
  h += "<h2 id=\"viewer-heading\">Viewer</h2>\n<div id=\"viewer\" class=\"viewer\"><noscript>The "
       "viewer needs JavaScript; every image is also in the tables below.</noscript></div>\n";
  h += "<p>Reproduce:</p><pre>" + html(r.command) + "</pre>\n";
  if (!r.material.text.empty()) h += "<p>References: " + html(r.material.text) + "</p>\n";
  for (const std::string& n : r.notes) h += "<p>" + html(n) + "</p>\n";

  h += "<h2>Images</h2>\n<p>Tone mapped with exposure " + num(r.scene.exposure) + " stops, gamma " +
       num(r.scene.gamma) + "; exitance B shown as B/π (exposure − log2 π). Radiance L by the " +
       toString(shown) + " convention (Eq. 2.16); the physical reference's radiance L is Ft·B/π, "
       "the diffusion convention, and its cone radiance the true radiance towards the camera " +
       (physicalConeAngle(r) == 0.0 ? std::string("(the camera method: cone half-angle 0)")
                                   : "(the light method's cone average, half-angle " +
                                         num(physicalConeAngle(r)) + "°)") +
       ". Linear EXRs: the links.</p>\n<table><tr><th class=\"l\">source</th><th>exitance B</th>"
       "<th>radiance L</th><th>true radiance (cone)</th></tr>\n";
  auto figure = [](const std::string& src, const std::string& caption, const char* cls) {
    return "<figure><img" + std::string(cls) + " src=\"" + html(src) + "\" alt=\"" +
           html(caption) + "\"><figcaption>" + html(caption) + "</figcaption></figure>";
  };
  auto cell = [&](const std::string& src, const std::string& caption) {
    return src.empty() ? std::string("<td>–</td>") : "<td>" + figure(src, caption, "") + "</td>";
  };
  for (const TechniqueRun* t : failed)
    h += "<tr><td class=\"l\">" + html(t->images.name) + "</td><td class=\"l warn\" colspan=\"3\">"
         + html(failureText(*t)) + "</td></tr>\n";
  for (const Shown& s : shownRows) {
    const std::string exr = (s.label.ends_with(" reference") ? s.label.substr(0, s.label.size() - 10)
                                                             : s.label) + ".exr";
    h += "<tr><td class=\"l\">" + html(s.label) + "<br><a href=\"" + html(exr) + "\">" + html(exr) +
         "</a></td>" + cell(s.exitance, s.label + " B") + cell(s.radiance, s.label + " L") +
         cell(s.cone, s.label + " cone L") + "</tr>\n";
  }
  h += "</table>\n";
  h += "<p>Masks (white: compared): " + figure(maskInterior, fmt::format("interior, {} pixels",
                                                                      r.masks.interiorPixels()), "") +
       figure(maskCone, fmt::format("interior, away from silhouettes (cone), {} pixels",
                                  r.masks.conePixels()), "") +
       "</p>\n<p>" + html(j["masks"]["interior"].get<std::string>()) + "; for the cone radiance: " +
       html(j["masks"]["interior_cone"].get<std::string>()) + ".</p>\n";

  h += "<h2>Errors</h2>\n<p>Technique vs model: the technique's own error; model vs physical: the "
       "model's error; technique vs physical: the total. rel. RMSE: noise-aware (the reference "
       "noise removed: sqrt(max(0, MSE − noise MSE)) / mean reference); raw: without; bias: "
       "mean(test − reference) / mean reference ± its standard error; |z|: per pixel and channel "
       "|test − reference| / combined standard error (≈ 0.8 for agreement within noise); FLIP "
       "and SSIM of the tone-mapped images over the mask.</p>\n<p>Caveats: standard errors "
       "are per pixel and channel and the aggregate ones assume independent pixels and channels. "
       "The model reference's pixels and channels share its surface samples, so for pairs with "
       "the model reference the bias ± stderr and z understate the uncertainty (per pixel, up to "
       "√3 in z). A pixel that no photon reached has a standard error of 0: at low photon counts "
       "(the cone radiance needs about 1/sin²θc times more photons than B) z and the noise-aware "
       "RMSE are unreliable; raise --photons until they settle. Pixel filters: the techniques "
       "shade the pixel centre; the model reference traces " + (modelSubpixels(r) > 0 ? fmt::format("{0}x{0}", modelSubpixels(r)) : std::string("(none here)")) +
       " rays per pixel (1x1: the centre, so technique vs model has no filter difference); the "
       "physical reference is a pixel average (box filter), so pairs with it include the "
       "difference between point and box sampling, which grows with the detail per pixel.</p>\n";
  h += "<table><tr><th class=\"l\">test</th><th class=\"l\">reference</th><th class=\"l\">quantity"
       "</th><th class=\"l\">L convention</th><th>pixels</th><th>mean ref.</th><th>mean test</th>"
       "<th>rel. RMSE</th><th>rel. RMSE raw</th><th>bias</th><th>± stderr</th><th>SSIM</th>"
       "<th>FLIP</th><th>mean |z|</th><th>|z| &gt; 3</th></tr>\n";
  for (const PairMetrics& p : r.metrics) {
    const Metrics& m = p.metrics;
    h += fmt::format("<tr><td class=\"l\">{}</td><td class=\"l\">{}</td><td class=\"l\">{}</td>"
                     "<td class=\"l\">{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td>"
                     "<td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
                     html(p.test), html(p.reference), html(p.quantity),
                     p.convention.empty() ? "–" : html(p.convention), m.pixels,
                     num(m.mean_reference), num(m.mean_test), pct(m.rel_rmse), pct(m.rel_rmse_raw),
                     spct(m.bias), pct(m.bias_stderr), num(m.ssim), num(m.flip), num(m.mean_abs_z),
                     pct(m.fraction_abs_z_above_3));
  }
  // A failed technique is a row with its reason, never blank or zero numbers.
  for (const TechniqueRun* t : failed)
    h += "<tr><td class=\"l\">" + html(t->images.name) + "</td><td class=\"l warn\" "
         "colspan=\"14\">" + html(failureText(*t)) + "</td></tr>\n";
  h += "</table>\n<h3>Error maps</h3>\n<p>Relative difference (test − reference) / reference: " +
       figure(barRel, fmt::format("−{0:g}% … +{0:g}%", 100 * kRelativeRange), " class=\"bar\"") +
       " z-score: " + figure(barZ, fmt::format("−{0:g} … +{0:g}", kZRange), " class=\"bar\"") +
       " FLIP: " + figure(barFlip, "0 … 1", " class=\"bar\"") +
       "</p>\n<table><tr><th class=\"l\">pair</th><th>relative difference</th><th>z-score</th>"
       "<th>FLIP</th></tr>\n";
  for (size_t i = 0; i < r.metrics.size(); ++i) {
    const PairMetrics& p = r.metrics[i];
    const std::string label = fmt::format("{} vs {}: {}{}", p.test, p.reference, p.quantity,
                                          p.convention.empty() ? "" : " (" + p.convention + ")");
    h += "<tr><td class=\"l\">" + html(label) + "</td>" + cell(maps[i].rel, "relative") +
         cell(maps[i].z, "z") + cell(maps[i].flip, "FLIP") + "</tr>\n";
  }
  h += "</table>\n";

  h += diagnosisSection(w, r, j);

  h += "<h2>Time</h2>\n<table><tr><th class=\"l\">technique</th><th class=\"l\">pass</th>"
       "<th>median [ms]</th><th>min [ms]</th><th>max [ms]</th></tr>\n";
  for (const TechniqueRun& t : r.techniques) {
    if (t.failed()) {
      h += "<tr><th class=\"l\">" + html(t.images.name) + "</th><td class=\"l warn\" colspan=\"4\">"
           + html(failureText(t)) + "</td></tr>\n";
      continue;
    }
    for (const PassStat& p : t.passes)
      h += fmt::format("<tr><td class=\"l\">{}</td><td class=\"l\">{}{}</td><td>{}</td><td>{}</td>"
                       "<td>{}</td></tr>\n", html(t.images.name),
                       std::string(static_cast<size_t>(4 * p.depth), '.'), html(p.name),
                       num(p.median_ms), num(p.min_ms), num(p.max_ms));
    h += fmt::format("<tr><th class=\"l\">{}</th><th class=\"l\">frame (median of {} after {} "
                     "warm-up)</th><th>{}</th><th></th><th></th></tr>\n", html(t.images.name),
                     t.timed_frames, t.warmup_frames, num(t.frame_ms));
  }
  h += "</table>\n<table><tr><th class=\"l\">reference</th><th>count</th><th>seed</th>"
       "<th>seconds</th><th class=\"l\">cache</th></tr>\n";
  for (const Reference& ref : r.references)
    h += fmt::format("<tr><td class=\"l\">{}{}</td><td>{} {}</td><td>{}</td><td>{}</td>"
                     "<td class=\"l\">{}</td></tr>\n", toString(ref.kind),
                     ref.partial ? " <span class=\"warn\">(partial)</span>" : "", ref.count_done,
                     ref.kind == ReferenceKind::Physical ? "photons/channel" : "samples",
                     ref.request.seed, num(ref.seconds),
                     html(ref.from_cache ? "reused from " + ref.cache_file.string()
                                         : ref.cache_file.empty() ? ref.cache_note
                                                                  : "stored as " + ref.cache_file.string()));
  h += "</table>\n<h3>Technique settings</h3>\n";
  for (const TechniqueRun& t : r.techniques) {
    h += "<p><b>" + html(t.images.name) + "</b> (" + html(t.description) + ")" +
         (t.failed() ? " <span class=\"warn\">" + html(failureText(t)) + "</span>" : "") + ": ";
    for (size_t i = 0; i < t.parameters.size(); ++i)
      h += (i ? ", " : "") + html(t.parameters[i].first) + " = " + html(t.parameters[i].second);
    for (const std::string& n : t.notes) h += "<br>" + html(n);
    h += "</p>\n";
  }

  if (!r.sweep.empty() || !r.figures.empty()) {
    h += "<h2>Sweep: error against time</h2>\n";
    for (const Figure& f : r.figures)
      h += "<figure><img class=\"plot\" src=\"" + html(f.file) + "\" alt=\"" + html(f.caption) +
           "\"><figcaption>" + html(f.caption) + "</figcaption></figure>\n";
    h += "<table><tr><th class=\"l\">technique</th><th class=\"l\">parameter</th><th>value</th>"
         "<th>frame [ms]</th><th class=\"l\">rel. RMSE (noise-aware)</th></tr>\n";
    for (const SweepPoint& s : r.sweep) {
      std::string errs;
      for (const PairMetrics& p : s.metrics)
        errs += fmt::format("{}{} vs {}: {}", errs.empty() ? "" : "; ", p.quantity, p.reference,
                            pct(p.metrics.rel_rmse));
      h += fmt::format("<tr><td class=\"l\">{}</td><td class=\"l\">{}</td><td>{}</td><td>{}</td>"
                       "<td class=\"l\">{}</td></tr>\n", html(s.technique), html(s.parameter),
                       num(s.value), num(s.frame_ms), html(errs));
    }
    h += "</table>\n";
  }
  h += "<h2>Files</h2>\n<p><a href=\"report.json\">report.json</a> (every number)</p>\n"
       "<script src=\"viewer-data.js\"></script>\n<script src=\"viewer.js\"></script>\n"
       "</body></html>\n";
  w.text("index.html", h);
  std::vector<std::string> files = w.files();
  files.push_back("report.json");
  j["files"] = files;
  if (const std::string why = geometry::writeFileAtomically(dir / "report.json", j.dump(2) + "\n");
      !why.empty())
    throw ImageError(fmt::format("cannot write '{}': {}", (dir / "report.json").string(), why));
  return files;
}

}  // namespace translucent::analysis
