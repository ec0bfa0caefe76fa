// SPDX-License-Identifier: GPL-3.0-or-later
// The list of subcommands and the seam between each one's checks and its work (commands.h).
#include "commands.h"

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
  app.set_version_flag("--version", "translucent 0.1.0");
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
}

}  // namespace translucent::cli
