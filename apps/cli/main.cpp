// `translucent`: the batch front end. Each subcommand lives in its own cmd_*.cpp.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>

#include "safe_print.h"
#include "commands.h"

int main(int argc, char** argv) {
  CLI::App app{
      "Translucent: render, compare and validate translucent (subsurface-scattering) materials."};
  app.require_subcommand(1);
  app.set_version_flag("--version", "translucent 0.1.0");
  translucent::cli::addPresetsCommand(app);
  translucent::cli::addInvertCommand(app);
  translucent::cli::addProfileCommand(app);
  translucent::cli::addPathtraceCommand(app);
  translucent::cli::addRenderReferenceCommands(app);  // after pathtrace: adds to it
  translucent::cli::addRenderCommand(app);
  translucent::cli::addCompareCommand(app);
  translucent::cli::addConventionStudyCommand(app);
  translucent::cli::addAtlasCommand(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const std::exception& e) {
    // What the command printed first: the error is the last line even when stdout (buffered) and
    // stderr go to one file, as a report's summary followed by what failed in it.
    std::fflush(stdout);
    translucent::cli::printStderr("translucent: error: {}\n", e.what());
    return 1;
  }
  return 0;
}
