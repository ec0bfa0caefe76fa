// SPDX-License-Identifier: GPL-3.0-or-later
// `translucent`: the batch front end. Each subcommand lives in its own cmd_*.cpp.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>

#include "safe_print.h"
#include "commands.h"

#include "shard.h"

#if defined(__SANITIZE_ADDRESS__)
#define TRANSLUCENT_HAS_LSAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define TRANSLUCENT_HAS_LSAN 1
#endif
#endif
#ifdef TRANSLUCENT_HAS_LSAN
#include <sanitizer/lsan_interface.h>
#endif


namespace {
int run(int argc, char** argv) {
  CLI::App app{
      "Translucent: render, compare and validate translucent (subsurface-scattering) materials."};
  translucent::cli::addAllCommands(app);
  translucent::cli::setCommandLine(argc, argv);
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
}  // namespace

int main(int argc, char** argv) {
  const int status = run(argc, argv);
#ifdef TRANSLUCENT_HAS_LSAN
  // Under ASan, the leak check runs before exit, not from LSan's atexit handler while the system
  // libraries' static destructors tear down their thread pools (a thread exiting during the
  // check faults LSan's tracer: tests/support/gtest_main.cpp has the story).
  std::fflush(stdout);
  __lsan_do_leak_check();
#endif
  return status;
}
