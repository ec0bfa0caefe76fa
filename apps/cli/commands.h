// Subcommands of the `translucent` command line; each file adds one (main.cpp lists them).
#pragma once

#include <CLI/CLI.hpp>

namespace translucent::cli {

void addPresetsCommand(CLI::App& app);
void addInvertCommand(CLI::App& app);
void addProfileCommand(CLI::App& app);
void addPathtraceCommand(CLI::App& app);
void addRenderReferenceCommands(CLI::App& app);  // pathtrace sphere|mesh, integrate sphere|mesh
void addRenderCommand(CLI::App& app);            // render (real-time techniques, GPU)
void addCompareCommand(CLI::App& app);           // compare (techniques vs references, report)
void addConventionStudyCommand(CLI::App& app);   // convention-study (exit-radiance conventions)
void addAtlasCommand(CLI::App& app);             // atlas (surface parameterisation, statistics)
void addPointCloudCommand(CLI::App& app);        // pointcloud (surface samples as PLY)
void addMergeCommand(CLI::App& app);             // merge (the shards of a path-traced run)

// Every subcommand above, on a new app (main(), and `merge` when it runs a recorded command).
void addAllCommands(CLI::App& app);

}  // namespace translucent::cli
