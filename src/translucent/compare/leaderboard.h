// SPDX-License-Identifier: GPL-3.0-or-later
// The leaderboard of `translucent compare --suite DIR --out OUT`: every scene of the suite is a
// complete compare report in OUT/<scene>/ (analysis/report.h), and the leaderboard gathers, for
// the radiance L, one row per scene x technique:
//   vs model          the technique's own error (noise-aware relative RMSE, bias)
//   vs physical       the total error (relative RMSE, bias, FLIP)
//   model vs physical the model's error (under the technique's radiance convention)
//   frame_ms          the median GPU time per frame
// and a per-technique summary across the scenes (mean and median of the relative RMSEs; wins:
// scenes where the technique has the lowest total error, ties counting for each; failed: scenes
// where it could not run). A technique that failed on a scene is a row with its error (from the
// scene's report.json), never numbers, and is left out of the means, medians and wins; a scene
// that failed as a whole (its scene file, mesh or a reference) is a row with its error.
//
// The numbers are read back from each scene's report.json, never recomputed, so the leaderboard
// and the reports agree exactly. OUT follows the report's folder rules: it is only written when
// empty, missing or a previous suite (its leaderboard.json lists its files and scene folders).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace translucent::analysis {

struct SuiteScene {
  std::string name;                  // the scene file's stem: its folder in OUT
  std::filesystem::path scene_file;  // as found in DIR
  enum class Status { Done, Partial, Failed, NotRun } status = Status::NotRun;
  std::string error;                 // Failed: what went wrong; NotRun: why
  double seconds = 0.0;              // wall time of the scene's compare
};
const char* toString(SuiteScene::Status status);  // "done", "partial", "failed", "not run"

struct SuiteInfo {
  std::string command;  // reproduces the suite
  std::string version;
  std::string created;  // UTC time
  std::filesystem::path suite_dir;
  bool partial = false;  // stopped early (Ctrl-C)
  double seconds = 0.0;  // wall time of the whole suite
};

// The suite's *.json scene files, sorted by name; ParameterError naming `option` when the folder
// cannot be read or holds none.
std::vector<std::filesystem::path> suiteSceneFiles(const std::filesystem::path& dir,
                                                   const std::string& option);

// As prepareReportDirectory for the suite folder: removes a previous suite's leaderboard files and
// the reports of its scene folders that `scenes` no longer has (those still in `scenes` are left to
// prepareReportDirectory); refuses anything else unless `force`. `ignore` is left alone.
void prepareSuiteDirectory(const std::filesystem::path& dir, bool force,
                           const std::filesystem::path& ignore,
                           const std::vector<std::string>& scenes, const std::string& option);

// Writes OUT/leaderboard.json, leaderboard.md and index.html from the scenes' report.json files
// (Done and Partial scenes; Failed and NotRun ones give a row with their error). Returns the
// files written, relative to `dir`.
std::vector<std::string> writeLeaderboard(const std::filesystem::path& dir, const SuiteInfo& info,
                                          const std::vector<SuiteScene>& scenes);

}  // namespace translucent::analysis
