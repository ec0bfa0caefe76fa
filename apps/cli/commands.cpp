// SPDX-License-Identifier: GPL-3.0-or-later
// The list of subcommands and the seam between each one's checks and its work (commands.h).
#include "commands.h"

#include <fmt/format.h>

#include <exception>
#include <string>

#include "translucent/io/resources.h"

namespace translucent::cli {
namespace {
bool gCheckOnly = false;
uint64_t gChecked = 0;

bool gWorkBegun = false;
}  // namespace

bool beginWork() {
  if (!gCheckOnly) return gWorkBegun = true;
  ++gChecked;
  return false;
}

bool workBegun() { return gWorkBegun; }

CheckOnly::CheckOnly() : previous_(gCheckOnly) { gCheckOnly = true; }
CheckOnly::~CheckOnly() { gCheckOnly = previous_; }
uint64_t CheckOnly::checked() { return gChecked; }

void addAllCommands(CLI::App& app) {
  app.require_subcommand(1);
  // --version: the release, and where this binary takes its shaders and data from (an installed
  // prefix's share/translucent, or the source tree for a build-tree run).
  app.set_version_flag("--version", [] {
    std::string where;
    try {
      where = io::shareDirectory().string();
    } catch (const std::exception& e) {
      where = e.what();
    }
    return fmt::format("translucent {}\nshaders and data: {}", TRANSLUCENT_VERSION, where);
  });
  addPresetsCommand(app);
  addInvertCommand(app);
  addProfileCommand(app);
  addPathtraceCommand(app);
  addRenderReferenceCommands(app);  // after pathtrace: adds to it
  addRenderCommand(app);
  addTechniquesCommand(app);
  addCompareCommand(app);
  addConventionStudyCommand(app);
  addAtlasCommand(app);
  addPointCloudCommand(app);
  addMergeCommand(app);
  addFitCommand(app);
}

}  // namespace translucent::cli
