// SPDX-License-Identifier: GPL-3.0-or-later
// `translucent`: the batch front end. Each subcommand lives in its own cmd_*.cpp.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <regex>
#include <set>
#include <sstream>
#include <string>

#include "safe_print.h"
#include "commands.h"
#include "progress.h"

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

// Exit statuses: 0 success, 1 a runtime error (the work failed), 2 a usage error (the command line
// could not be parsed, or the checks before any work refused it: commands.h), 130/143 after
// SIGINT/SIGTERM stopped long work whose partial outputs were written (progress.h).
constexpr int kRuntimeError = 1;
constexpr int kUsageError = 2;

// The subcommand being parsed when CLI11 stopped ("pathtrace slab"; "" for none) and that App.
std::pair<std::string, CLI::App*> deepestCommand(CLI::App& app) {
  std::string path;
  CLI::App* at = &app;
  for (;;) {
    const auto subs = at->get_subcommands();
    if (subs.empty()) break;
    at = subs.back();
    path += (path.empty() ? "" : " ") + at->get_name();
  }
  return {path, at};
}

// What an option's value must be, from CLI11's type name.
std::string expectedValue(const std::string& type) {
  if (type == "INT") return "a whole number";
  if (type == "UINT") return "a whole number >= 0";
  if (type == "FLOAT") return "a number";
  if (type == "BOOLEAN") return "true or false";
  return "a value of type " + type;
}

// CLI11's parse errors in our own words: "translucent: error: <what> (<command> --help ...)",
// naming the option and what was expected.
std::string usageMessage(const CLI::ParseError& e, CLI::App& app) {
  const auto [command, sub] = deepestCommand(app);
  std::string what = e.what();
  std::smatch m;
  if (std::regex_match(what, m, std::regex("Could not convert: (\\S+) = (.*)"))) {
    const CLI::Option* opt = sub->get_option_no_throw(m[1].str());
    what = fmt::format("{} '{}': expected {}", m[1].str(), m[2].str(),
                       opt ? expectedValue(opt->get_type_name()) : "another value");
  } else if (std::regex_match(what, m, std::regex("The value (.*) is not an allowed value for (\\S+)"))) {
    what = fmt::format("{} '{}': not an allowed value", m[2].str(), m[1].str());
  } else if (std::regex_match(what, m, std::regex("The following arguments? w(?:as|ere) not expected: (.*)"))) {
    // CLI11 lists them last first ("1 --bogus"): name the option where there is one.
    std::string extra = m[1].str();
    std::istringstream words(m[1].str());
    for (std::string w; words >> w;)
      if (w.size() > 1 && w[0] == '-') extra = w;
    what = extra.rfind('-', 0) == 0
               ? fmt::format("unknown option '{}'{}", extra,
                             command.empty() ? "" : " for '" + command + "'")
               : fmt::format("unexpected argument '{}'{}", extra,
                             command.empty() ? " (expected a command)" : " for '" + command + "'");
  } else if (std::regex_match(what, m, std::regex("Requires at least 1 subcommands?|A subcommand is required"))) {
    std::string names;
    for (const CLI::App* c : sub->get_subcommands([](const CLI::App*) { return true; }))
      names += (names.empty() ? "" : ", ") + c->get_name();
    what = fmt::format("expected a command{}: {}", command.empty() ? "" : " after '" + command + "'",
                       names);
  } else if (std::regex_match(what, m, std::regex("(\\S+): (\\d+) required (\\S+) missing"))) {
    what = fmt::format("{}: expected {} after it", m[1].str(), expectedValue(m[3].str()));
  } else if (!what.empty()) {
    what[0] = static_cast<char>(std::tolower(static_cast<unsigned char>(what[0])));
  }
  return fmt::format("translucent: error: {}\nRun 'translucent{}{} --help' for the options.\n",
                     what, command.empty() ? "" : " ", command);
}

// CLI11 converts an empty value of a number option to 0 (`--points ''`) or leaves an optional
// one unset (`--rmax ''`, `--thickness ''`: a semi-infinite slab; `--layers ''`: no layers file,
// then a message about the medium), silently: every option of every command that takes a value
// refuses an empty one instead, naming itself and what it expected.
void refuseEmptyValues(CLI::App& app) {
  static const std::set<std::string> numbers = {"FLOAT", "INT", "UINT", "NUMBER", "INT64", "UINT64"};
  for (CLI::Option* opt : app.get_options()) {
    if (opt->get_expected_min() < 1) continue;
    const std::string expected = numbers.contains(opt->get_type_name()) ? "a number" : "a value";
    opt->check(CLI::Validator(
        [expected](std::string& value) {
          return value.empty() ? "empty value '': expected " + expected : std::string();
        },
        "", ""));
  }
  for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) refuseEmptyValues(*sub);
}

int run(int argc, char** argv) {
  CLI::App app{
      "Translucent: render, compare and validate translucent (subsurface-scattering) materials."};
  translucent::cli::addAllCommands(app);
  refuseEmptyValues(app);
  translucent::cli::setCommandLine(argc, argv);
  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {
    return app.exit(e);  // --help, --version
  } catch (const CLI::ParseError& e) {
    std::fflush(stdout);
    translucent::cli::printStderr("{}", usageMessage(e, app));
    return kUsageError;
  } catch (const std::exception& e) {
    // What the command printed first: the error is the last line even when stdout (buffered) and
    // stderr go to one file, as a report's summary followed by what failed in it.
    std::fflush(stdout);
    translucent::cli::printStderr("translucent: error: {}\n", e.what());
    if (const int stopped = translucent::cli::stopExitStatus()) return stopped;
    return translucent::cli::workBegun() ? kRuntimeError : kUsageError;
  }
  std::fflush(stdout);
  return translucent::cli::stopExitStatus();  // 0, or 130/143 after a signal stopped the work
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
