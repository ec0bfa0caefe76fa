// SPDX-License-Identifier: GPL-3.0-or-later
// Subcommands of the `translucent` command line; each file adds one (main.cpp lists them).
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>

namespace translucent::cli {

void addPresetsCommand(CLI::App& app);
void addInvertCommand(CLI::App& app);
void addProfileCommand(CLI::App& app);
void addPathtraceCommand(CLI::App& app);
void addRenderReferenceCommands(CLI::App& app);  // pathtrace sphere|mesh, integrate sphere|mesh
void addRenderCommand(CLI::App& app);            // render (real-time techniques, GPU)
void addTechniquesCommand(CLI::App& app);        // techniques [NAME] (and their parameters)
void addCompareCommand(CLI::App& app);           // compare (techniques vs references, report)
void addConventionStudyCommand(CLI::App& app);   // convention-study (exit-radiance conventions)
void addAtlasCommand(CLI::App& app);             // atlas (surface parameterisation, statistics)
void addPointCloudCommand(CLI::App& app);        // pointcloud (surface samples as PLY)
void addMergeCommand(CLI::App& app);             // merge (the shards of a path-traced run)
void addFitCommand(CLI::App& app);               // fit (a technique's parameters to a reference)

// Every subcommand above, on a new app (main(), `merge` when it runs a recorded command, and the
// fuzz_cli target).
void addAllCommands(CLI::App& app);

// Each subcommand's callback does two things in order: its checks, then its work. The checks read
// and validate every option (numbers and their ranges, lists, names of models, presets and
// techniques), the files the command reads (a scene file is parsed, a mesh only named), and its
// outputs against each other and against those inputs (OutputSet::check, which creates nothing);
// they never write a file, make a GL context or trace. The work is everything after: loading
// meshes, GL, tracing, rendering, writing the outputs. beginWork() is the seam between the two:
// every callback calls it where its checks end, and returns when it says false.
//
// In check-only mode (CheckOnly, held while a command line is parsed: the fuzz_cli target, issue
// #15 §7) beginWork() returns false, so a parse runs the real CLI11 parser and every check of the
// subcommand given, with the same messages, and stops before the work.
[[nodiscard]] bool beginWork();
// Whether a command's checks passed and its work began (beginWork() returned true): an error
// before then is a usage error (exit status 2), after it a runtime error (1).
bool workBegun();

class CheckOnly {
 public:
  CheckOnly();
  ~CheckOnly();
  CheckOnly(const CheckOnly&) = delete;
  CheckOnly& operator=(const CheckOnly&) = delete;
  // How many commands reached beginWork() (their checks passed) while one was held.
  static uint64_t checked();

 private:
  bool previous_;
};

}  // namespace translucent::cli
