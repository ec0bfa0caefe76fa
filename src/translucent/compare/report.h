// SPDX-License-Identifier: GPL-3.0-or-later
// The report of `translucent compare`: a self-contained folder
//   index.html     first the summary (the leaderboard of the scene: per technique the error of
//                  its radiance against each reference, its GPU time and status; failed and
//                  over-budget techniques one line each with the reason), then the viewer, then
//                  the images side by side (tone-mapped PNGs), false-colour error maps (relative
//                  difference, z-score, FLIP) with their colour bars, the metric and timing
//                  tables, the plots, and the command that reproduces the report
//   report.json    every number, the scene, the settings, versions and times, the list of files;
//                  "summary" is what the first table of index.html shows, "viewer" what the
//                  viewer shows
//   *.exr          every image, linear, the references with their standard errors as layers
//   *.png          what index.html shows
//   viewer.js, viewer.css, viewer-data.js, px-*.js
//                  the interactive viewer (viewer/viewer.js in the source tree): a technique
//                  against a reference by flip, slider or error map, zoom and pan, and the linear
//                  values under the cursor, which px-KEY.js holds per image (float32, base64:
//                  16 bytes a pixel per image; a page opened from file:// can load scripts beside
//                  it but not fetch files)
// Nothing outside the folder is referenced, and nothing on the network.
//
// A technique that failed on the scene (TechniqueRun::error) is listed with its message in
// index.html (images, errors and time tables) and in report.json (techniques[].status "failed",
// techniques[].error); it has no images and no rows in metrics.
//
// A folder is only ever written when it is empty, missing, or holds a previous report (its
// report.json says generator "translucent compare" and lists its files): a rerun first removes
// the files the previous report listed, and refuses (without --force) when anything else is
// there, so a user's own files are never overwritten.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "translucent/compare/compare.h"
#include "translucent/compare/diagnosis.h"

namespace translucent::analysis {

// The median GPU time of one pass over the timed frames.
struct PassStat {
  std::string name;
  int depth = 0;
  double median_ms = 0.0, min_ms = 0.0, max_ms = 0.0;
};

struct TechniqueRun {
  TechniqueImages images;  // a failed run has only images.name
  std::string error;       // why the technique failed on this scene ("" when it ran): a row of
                           // the report with this message, no images and no metrics
  bool over_budget = false;  // stopped by compare's --budget (error says after how long):
                            // report.json status "over budget"
  std::string description;
  std::vector<std::pair<std::string, std::string>> parameters;  // every value as rendered
  std::vector<PassStat> passes;  // depth-0 and nested, in frame order
  double frame_ms = 0.0;         // median over the timed frames of the depth-0 total
  int timed_frames = 0, warmup_frames = 0;
  std::vector<std::string> notes;

  bool failed() const { return !error.empty(); }
};

// One rendering of a technique's sweep (its quality parameter at one value).
struct SweepPoint {
  std::string technique, parameter;
  double value = 0.0;
  double frame_ms = 0.0;
  std::vector<PairMetrics> metrics;
};

struct Figure {
  std::string file;     // inside the report folder
  std::string caption;
};

struct CompareReport {
  std::string command;     // reproduces the report
  std::string scene_file;  // as given ("" for the built-in bunny)
  scene::Scene scene;      // as compared (overrides applied)
  std::string gpu;         // renderer and GL version
  std::string version;     // translucent version
  std::string created;     // UTC time
  std::vector<std::pair<std::string, std::string>> settings;  // the command's options, as used
  std::vector<TechniqueRun> techniques;  // failed ones included, in the order they were run
  std::vector<Reference> references;
  std::vector<PairMetrics> metrics;
  std::vector<SweepPoint> sweep;
  std::vector<Figure> figures;  // written by the caller into the folder before writeReport
  Masks masks;
  // Where the error is (diagnosis.h): with a model and a physical reference, index.html and
  // report.json split each technique's error against the physical reference into its own and
  // the model's part per region. Empty (no names): no such section.
  ErrorRegions regions;
  std::filesystem::path cache_dir;  // "" when caching is off
  bool partial = false;             // stopped early: some reference is partial or missing
  std::vector<std::string> notes;   // what the user should know (cache hits, skipped parts)
  // The material and which reference is physical for it (materialReferences: report.json
  // "material", a paragraph of index.html).
  MaterialReferences material{"homogeneous", true, ""};
};

// A folder a command writes its files into: created when missing; otherwise it may hold only
// the files that its `manifest` (a JSON file in it whose "generator" is `generator`) lists, which
// are removed, and `ignore`; anything else is refused naming `option`, the folder and the file
// ("not part of <what>") unless `force`, so that a user's files are never overwritten.
void prepareOwnedFolder(const std::filesystem::path& dir, bool force,
                        const std::filesystem::path& ignore, const std::string& option,
                        const std::string& manifest, const std::string& generator,
                        const std::string& what);

// Checks `dir` and removes a previous report's files (see the header comment). `ignore` (e.g.
// a cache folder inside `dir`) is left alone. Throws ParameterError naming `option`, the folder and
// the first file that is not ours unless `force`.
void prepareReportDirectory(const std::filesystem::path& dir, bool force,
                            const std::filesystem::path& ignore, const std::string& option);

// Writes the whole folder; returns the files written (relative to `dir`), figures included.
std::vector<std::string> writeReport(const std::filesystem::path& dir, const CompareReport& report);

// Bounds of the error maps: relative difference ±kRelativeRange, z-score ±kZRange, FLIP [0, 1].
inline constexpr double kRelativeRange = 0.5;
inline constexpr double kZRange = 5.0;

}  // namespace translucent::analysis
