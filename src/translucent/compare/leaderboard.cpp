// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/compare/leaderboard.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>

#include "translucent/compare/report.h"
#include "translucent/compare/report_text.h"
#include "translucent/geometry/atomic_file.h"
#include "translucent/io/json.h"
#include "translucent/optics/medium.h"  // ParameterError

namespace translucent::analysis {
namespace fs = std::filesystem;
using nlohmann::json;
using text::html, text::number, text::num, text::pct, text::spct;

namespace {

constexpr const char* kSuiteGenerator = "translucent compare --suite";
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();


// A relative link to a file inside OUT: every byte outside [A-Za-z0-9._-] percent-encoded, so a
// scene named "a b#c" still links to its own folder.
std::string urlPart(const std::string& s) {
  std::string out;
  for (unsigned char c : s) {
    if (std::isalnum(c) || c == '.' || c == '_' || c == '-') out += static_cast<char>(c);
    else out += fmt::format("%{:02X}", c);
  }
  return out;
}

// Markdown table cells: '|' would end the cell, newlines the row.
std::string mdCell(std::string s) {
  std::string out;
  for (char c : s) {
    if (c == '|') out += "\\|";
    else if (c == '\n' || c == '\r') out += ' ';
    else out += c;
  }
  return out;
}

double value(const json& j) { return j.is_number() ? j.get<double>() : kNaN; }

// The metrics object of a report.json row, or nothing.
const json* findMetrics(const json& report, const std::string& test, const std::string& reference,
                        const std::string& quantity, const std::string& convention) {
  for (const json& m : report.at("metrics"))
    if (m.at("test") == test && m.at("reference") == reference && m.at("quantity") == quantity &&
        (convention.empty() || m.at("convention") == convention))
      return &m.at("metrics");
  return nullptr;
}

// A scene that failed has a row with `error` and no technique; a technique that failed on a
// scene whose report was written has a row with both (and no numbers).
struct Row {
  std::string scene, technique, convention, error;
  std::string report;  // link to the scene's index.html ("" when there is none)
  double vs_model_rmse = kNaN, vs_model_bias = kNaN;
  double vs_physical_rmse = kNaN, vs_physical_bias = kNaN, vs_physical_flip = kNaN;
  double model_vs_physical_rmse = kNaN, model_vs_physical_bias = kNaN;
  double frame_ms = kNaN;
  bool partial = false;
  bool over_budget = false;  // the technique was stopped by compare's --budget (error says so)
};

double metric(const json* m, const char* key) { return m ? value(m->at(key)) : kNaN; }

std::vector<Row> sceneRows(const fs::path& dir, const SuiteScene& s) {
  using Status = SuiteScene::Status;
  if (s.status == Status::Failed || s.status == Status::NotRun) {
    Row r;
    r.scene = s.name;
    r.error = s.error.empty() ? toString(s.status) : s.error;
    return {r};
  }
  const fs::path file = dir / s.name / "report.json";
  json report;
  try {
    report = io::readJsonFile(file);
  } catch (const std::exception& e) {
    Row r;
    r.scene = s.name;
    r.error = fmt::format("cannot read '{}': {}", file.string(), e.what());
    return {r};
  }
  std::vector<Row> rows;
  for (const json& t : report.at("techniques")) {
    Row r;
    r.scene = s.name;
    r.report = urlPart(s.name) + "/index.html";
    r.technique = t.at("name");
    r.partial = report.at("partial").get<bool>();
    if (t.contains("status") && (t.at("status") == "failed" || t.at("status") == "over budget")) {
      r.error = t.at("error");
      r.over_budget = t.at("status") == "over budget";
      rows.push_back(r);
      continue;
    }
    r.convention = t.at("convention");
    r.frame_ms = value(t.at("frame_ms"));
    // Against a physical reference from the camera method, the true radiance (its cone
    // radiance at half-angle 0); from the light method, the diffusion radiance Ft·B/π (its cone
    // average is photon speckle at suite photon counts).
    std::string truth = "radiance";
    if (report.contains("references"))
      for (const json& ref : report.at("references"))
        if (ref.contains("method") && ref.at("method").is_string() &&
            ref.at("method").get<std::string>() == "camera")
          truth = "cone_radiance";
    const json* vm = findMetrics(report, r.technique, "model", "radiance", "");
    const json* vp = findMetrics(report, r.technique, "physical", truth, "");
    const json* mp = findMetrics(report, "model", "physical", truth, r.convention);
    r.vs_model_rmse = metric(vm, "rel_rmse");
    r.vs_model_bias = metric(vm, "bias");
    r.vs_physical_rmse = metric(vp, "rel_rmse");
    r.vs_physical_bias = metric(vp, "bias");
    r.vs_physical_flip = metric(vp, "flip");
    r.model_vs_physical_rmse = metric(mp, "rel_rmse");
    r.model_vs_physical_bias = metric(mp, "bias");
    rows.push_back(r);
  }
  return rows;
}

double mean(const std::vector<double>& v) {
  if (v.empty()) return kNaN;
  double s = 0.0;
  for (double x : v) s += x;
  return s / static_cast<double>(v.size());
}
double median(std::vector<double> v) {
  if (v.empty()) return kNaN;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

struct Summary {
  std::string technique;
  std::vector<double> vs_model, vs_physical, frame_ms;
  int wins = 0;
  int failed = 0;  // scenes where it failed: in no mean, median or ranking
};

std::vector<Summary> summarize(const std::vector<Row>& rows) {
  std::vector<Summary> out;
  auto find = [&](const std::string& t) -> Summary& {
    for (Summary& s : out)
      if (s.technique == t) return s;
    out.push_back({t, {}, {}, {}, 0, 0});
    return out.back();
  };
  std::map<std::string, double> best;  // per scene: the lowest total error
  for (const Row& r : rows) {
    if (r.technique.empty()) continue;
    Summary& s = find(r.technique);
    if (!r.error.empty()) {
      ++s.failed;
      continue;
    }
    if (std::isfinite(r.vs_model_rmse)) s.vs_model.push_back(r.vs_model_rmse);
    if (std::isfinite(r.vs_physical_rmse)) {
      s.vs_physical.push_back(r.vs_physical_rmse);
      auto [it, fresh] = best.try_emplace(r.scene, r.vs_physical_rmse);
      if (!fresh) it->second = std::min(it->second, r.vs_physical_rmse);
    }
    if (std::isfinite(r.frame_ms)) s.frame_ms.push_back(r.frame_ms);
  }
  for (const Row& r : rows)
    if (!r.technique.empty() && r.error.empty() && std::isfinite(r.vs_physical_rmse) &&
        r.vs_physical_rmse == best.at(r.scene))
      find(r.technique).wins++;
  return out;
}

// Temporary file and rename (geometry/atomic_file.h): a failing write never truncates a page.
void writeText(const fs::path& path, const std::string& text) {
  const std::string why = geometry::writeFileAtomically(path, text);
  if (!why.empty())
    throw ParameterError(fmt::format("--out: cannot write '{}': {}", path.string(), why));
}

}  // namespace

const char* toString(SuiteScene::Status status) {
  switch (status) {
    case SuiteScene::Status::Done: return "done";
    case SuiteScene::Status::Partial: return "partial";
    case SuiteScene::Status::Failed: return "failed";
    case SuiteScene::Status::NotRun: return "not run";
  }
  return "?";
}

std::vector<fs::path> suiteSceneFiles(const fs::path& dir, const std::string& option) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw ParameterError(fmt::format("{} '{}': not a folder", option, dir.string()));
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    // (The error_code form: a link that loops threw "filesystem error: status: Too many levels
    // of symbolic links" out of the whole suite; it is kept, and its scene fails naming it.)
    std::error_code entry;
    if (e.path().extension() == ".json" && !e.is_directory(entry)) files.push_back(e.path());
  }
  if (ec)
    throw ParameterError(fmt::format("{} '{}': cannot list the folder: {}", option, dir.string(),
                                     ec.message()));
  if (files.empty())
    throw ParameterError(fmt::format("{} '{}': holds no scene files (*.json)", option, dir.string()));
  std::sort(files.begin(), files.end(),
            [](const fs::path& a, const fs::path& b) { return a.filename() < b.filename(); });
  return files;
}

void prepareSuiteDirectory(const fs::path& dir, bool force, const fs::path& ignore,
                           const std::vector<std::string>& scenes, const std::string& option) {
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
  std::set<std::string> files, folders(scenes.begin(), scenes.end()), stale;
  const fs::path previous = dir / "leaderboard.json";
  if (fs::exists(previous, ec)) {
    try {
      const json j = io::readJsonFile(previous);
      // Not j.value(...): GCC 12 sees a possible null dereference inlined there (-Werror).
      const auto g = j.find("generator");
      if (g != j.end() && *g == kSuiteGenerator) {
        for (const auto& n : j.at("files")) files.insert(n.get<std::string>());
        for (const auto& s : j.at("scenes")) {
          const std::string n = s.at("name");
          if (!folders.contains(n)) stale.insert(n);
        }
      }
    } catch (const std::exception&) {
      files.clear();  // not a suite of ours
      stale.clear();
    }
  }
  std::vector<fs::path> remove;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (!ignore.empty() && fs::equivalent(entry.path(), ignore, ec)) continue;
    // A scene folder of this suite: its own report rules apply when the scene is written.
    if (folders.contains(name) && entry.is_directory()) continue;
    if ((files.contains(name) && entry.is_regular_file()) ||
        (stale.contains(name) && entry.is_directory())) {
      remove.push_back(entry.path());
    } else if (!force) {
      throw ParameterError(fmt::format(
          "{} '{}': the folder holds '{}', which is not part of a previous compare suite; "
          "choose an empty or new folder, or pass --force to write into it anyway",
          option, dir.string(), name));
    }
  }
  for (const auto& p : remove) {
    if (fs::is_directory(p, ec)) {
      // A scene the suite no longer has: only its report's files go, and the folder if then empty.
      prepareReportDirectory(p, force, ignore, option);
      fs::remove(p, ec);
    } else {
      fs::remove(p, ec);
    }
  }
}

std::vector<std::string> writeLeaderboard(const fs::path& dir, const SuiteInfo& info,
                                          const std::vector<SuiteScene>& scenes) {
  std::vector<Row> rows;
  for (const SuiteScene& s : scenes) {
    const auto r = sceneRows(dir, s);
    rows.insert(rows.end(), r.begin(), r.end());
  }
  const std::vector<Summary> summary = summarize(rows);
  const std::vector<std::string> files = {"leaderboard.json", "leaderboard.md", "index.html"};

  // ---- leaderboard.json ------------------------------------------------------------------
  json j;
  j["generator"] = kSuiteGenerator;
  j["version"] = info.version;
  j["created"] = info.created;
  j["command"] = info.command;
  j["suite_dir"] = info.suite_dir.string();
  j["partial"] = info.partial;
  j["seconds"] = info.seconds;
  j["files"] = files;
  j["quantity"] = "radiance L over the interior mask; rel_rmse noise-aware (report.json)";
  j["scenes"] = json::array();
  for (const SuiteScene& s : scenes)
    j["scenes"].push_back({{"name", s.name}, {"scene_file", s.scene_file.string()},
                           {"status", toString(s.status)}, {"error", s.error},
                           {"seconds", s.seconds},
                           {"report", s.status == SuiteScene::Status::Done ||
                                              s.status == SuiteScene::Status::Partial
                                          ? json(s.name + "/report.json")
                                          : json(nullptr)}});
  j["rows"] = json::array();
  for (const Row& r : rows) {
    json row = {{"scene", r.scene}};
    if (!r.error.empty()) {
      // A failed technique keeps its name (status "failed"); a failed scene has none.
      if (!r.technique.empty()) {
        row["technique"] = r.technique;
        row["status"] = r.over_budget ? "over budget" : "failed";
        row["partial"] = r.partial;
      }
      row["error"] = r.error;
    } else {
      row["technique"] = r.technique;
      row["convention"] = r.convention;
      row["partial"] = r.partial;
      row["vs_model"] = {{"rel_rmse", number(r.vs_model_rmse)}, {"bias", number(r.vs_model_bias)}};
      row["vs_physical"] = {{"rel_rmse", number(r.vs_physical_rmse)},
                            {"bias", number(r.vs_physical_bias)},
                            {"flip", number(r.vs_physical_flip)}};
      row["model_vs_physical"] = {{"rel_rmse", number(r.model_vs_physical_rmse)},
                                  {"bias", number(r.model_vs_physical_bias)}};
      row["frame_ms"] = number(r.frame_ms);
    }
    j["rows"].push_back(row);
  }
  j["summary"] = json::array();
  for (const Summary& s : summary)
    j["summary"].push_back({{"technique", s.technique},
                            {"scenes", s.vs_physical.size()},
                            {"vs_model_rel_rmse_mean", number(mean(s.vs_model))},
                            {"vs_model_rel_rmse_median", number(median(s.vs_model))},
                            {"vs_physical_rel_rmse_mean", number(mean(s.vs_physical))},
                            {"vs_physical_rel_rmse_median", number(median(s.vs_physical))},
                            {"frame_ms_median", number(median(s.frame_ms))},
                            {"wins", s.wins},
                            {"failed", s.failed}});
  writeText(dir / "leaderboard.json", j.dump(2) + "\n");

  // ---- leaderboard.md --------------------------------------------------------------------
  std::string md = "# translucent compare: suite leaderboard\n\n";
  if (info.partial) md += "**Partial: stopped early (Ctrl-C); the scenes not run are listed.**\n\n";
  md += fmt::format("Suite `{}`, {} scenes, created {} in {:.0f} s by\n\n```\n{}\n```\n\n",
                    info.suite_dir.string(), scenes.size(), info.created, info.seconds,
                    info.command);
  md += "Radiance L over each scene's interior mask. rel. RMSE: noise-aware relative RMSE; vs "
        "model: the technique's own error; vs physical: the total error (against the true "
        "radiance where the physical reference is from the camera method, else against the "
        "diffusion radiance Ft·B/π of the light method); model vs physical: the BSSRDF model's "
        "error; FLIP against the physical reference; GPU: median ms per frame.\n\n";
  md += "## Per technique\n\n| technique | scenes | vs model mean | vs model median | vs physical "
        "mean | vs physical median | GPU ms (median) | wins | failed |\n|---|---:|---:|---:|---:|"
        "---:|---:|---:|---:|\n";
  for (const Summary& s : summary)
    md += fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} | {} |\n", mdCell(s.technique),
                      s.vs_physical.size(), pct(mean(s.vs_model)), pct(median(s.vs_model)),
                      pct(mean(s.vs_physical)), pct(median(s.vs_physical)),
                      num(median(s.frame_ms)), s.wins, s.failed);
  md += "\nwins: scenes where the technique has the lowest rel. RMSE vs physical. failed: scenes "
        "where it could not run (listed below with the reason; in no mean, median or win).\n\n"
        "## Per scene\n\n| scene | technique | vs model rel. RMSE | vs model bias | vs physical "
        "rel. RMSE | vs physical bias | model vs physical rel. RMSE | FLIP vs physical | GPU ms |"
        "\n|---|---|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const Row& r : rows) {
    if (!r.error.empty() && !r.technique.empty()) {
      md += fmt::format("| {}{} | {} | **{}** |  |  |  |  |  |  |\n", mdCell(r.scene),
                        r.partial ? " (partial)" : "", mdCell(r.technique),
                        mdCell((r.over_budget ? "" : "failed: ") + r.error));
      continue;
    }
    if (!r.error.empty()) {
      md += fmt::format("| {} | **{}** |  |  |  |  |  |  |  |\n", mdCell(r.scene),
                        mdCell("error: " + r.error));
      continue;
    }
    md += fmt::format("| {}{} | {} | {} | {} | {} | {} | {} | {} | {} |\n", mdCell(r.scene),
                      r.partial ? " (partial)" : "", mdCell(r.technique), pct(r.vs_model_rmse),
                      spct(r.vs_model_bias), pct(r.vs_physical_rmse), spct(r.vs_physical_bias),
                      pct(r.model_vs_physical_rmse), num(r.vs_physical_flip), num(r.frame_ms));
  }
  writeText(dir / "leaderboard.md", md);

  // ---- index.html ------------------------------------------------------------------------
  std::string h = "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>translucent "
                  "compare suite</title>\n<style>body{font-family:sans-serif;margin:1.5em;color:"
                  "#222}table{border-collapse:collapse;margin:0.5em 0 1.5em}td,th{border:1px solid"
                  " #bbb;padding:3px 7px;text-align:right;font-size:13px}th{background:#eee}td.l,"
                  "th.l{text-align:left}pre{background:#f4f4f4;padding:8px;white-space:pre-wrap}"
                  ".warn{color:#a00;font-weight:bold}</style></head><body>\n"
                  "<h1>translucent compare: suite leaderboard</h1>\n";
  if (info.partial) h += "<p class=\"warn\">Partial: stopped early (Ctrl-C).</p>\n";
  h += fmt::format("<p>Suite {} ({} scenes), {} in {:.0f} s.</p>\n<pre>{}</pre>\n",
                   html(info.suite_dir.string()), scenes.size(), html(info.created), info.seconds,
                   html(info.command));
  h += "<p>Radiance L over each scene's interior mask; rel. RMSE noise-aware. vs model: the "
       "technique's own error; vs physical: the total; model vs physical: the BSSRDF model's.</p>\n"
       "<h2>Per technique</h2>\n<table><tr><th class=\"l\">technique</th><th>scenes</th><th>vs "
       "model mean</th><th>vs model median</th><th>vs physical mean</th><th>vs physical median"
       "</th><th>GPU ms (median)</th><th>wins</th><th>failed</th></tr>\n";
  for (const Summary& s : summary)
    h += fmt::format("<tr><td class=\"l\">{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td>"
                     "<td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n", html(s.technique),
                     s.vs_physical.size(), pct(mean(s.vs_model)), pct(median(s.vs_model)),
                     pct(mean(s.vs_physical)), pct(median(s.vs_physical)),
                     num(median(s.frame_ms)), s.wins, s.failed);
  h += "</table>\n<h2>Per scene</h2>\n<table><tr><th class=\"l\">scene</th><th class=\"l\">"
       "technique</th><th>vs model rel. RMSE</th><th>vs model bias</th><th>vs physical rel. "
       "RMSE</th><th>vs physical bias</th><th>model vs physical</th><th>FLIP vs physical</th>"
       "<th>GPU ms</th></tr>\n";
  for (const Row& r : rows) {
    if (!r.error.empty() && !r.technique.empty()) {
      h += fmt::format("<tr><td class=\"l\"><a href=\"{}\">{}</a>{}</td><td class=\"l\">{}</td>"
                       "<td class=\"l warn\" colspan=\"7\">{}{}</td></tr>\n", html(r.report),
                       html(r.scene), r.partial ? " <span class=\"warn\">(partial)</span>" : "",
                       html(r.technique), r.over_budget ? "" : "failed: ", html(r.error));
      continue;
    }
    if (!r.error.empty()) {
      h += fmt::format("<tr><td class=\"l\">{}</td><td class=\"l warn\" colspan=\"8\">error: {}"
                       "</td></tr>\n", html(r.scene), html(r.error));
      continue;
    }
    h += fmt::format("<tr><td class=\"l\"><a href=\"{}\">{}</a>{}</td><td class=\"l\">{}</td>"
                     "<td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}"
                     "</td></tr>\n", html(r.report), html(r.scene),
                     r.partial ? " <span class=\"warn\">(partial)</span>" : "",
                     html(r.technique), pct(r.vs_model_rmse), spct(r.vs_model_bias),
                     pct(r.vs_physical_rmse), spct(r.vs_physical_bias),
                     pct(r.model_vs_physical_rmse), num(r.vs_physical_flip), num(r.frame_ms));
  }
  h += "</table>\n<p><a href=\"leaderboard.json\">leaderboard.json</a> (every number), <a "
       "href=\"leaderboard.md\">leaderboard.md</a></p>\n</body></html>\n";
  writeText(dir / "index.html", h);
  return files;
}

}  // namespace translucent::analysis
