// SPDX-License-Identifier: GPL-3.0-or-later
// libFuzzer target for the command line (issue #15 §7): the parsing and the checks of every
// subcommand of `translucent`.
//
// The input is a command line, its arguments separated by newline or NUL bytes, the subcommand
// first ("pathtrace\nslab\n--photons\n1e6\n--json\nout.json"). It is parsed by the real CLI11 app
// (addAllCommands, as main() builds it) in check-only mode (apps/cli/commands.h, CheckOnly): the
// subcommand checks its options, reads the scene files it names and checks its outputs, and stops
// where its work would begin, so nothing is traced, rendered, loaded on a GPU or written.
//
// Each input runs in a scratch folder holding the files the seeds name: scene.json (the cube
// scene), cube.obj, layers.json (pathtrace slab --layers), model.bssrdf, table.csv (a tabulated
// profile), a folder sub/ and an existing output old.png. An argument that could leave the
// folder (an absolute path, "..", a '/' after '=' or ',') makes the input uninteresting: the
// fuzzer must not read a device that never ends (/dev/zero) or the user's files, and nothing in
// the checks depends on where a folder is.
//
// Expected outcomes, as main() handles them: a CLI::ParseError (a usage error, --help, --version;
// formatted by app.exit into a string), a ParameterError (our checks) and the registries' errors
// for a name they do not have (bssrdf::UnknownModelError, techniques::UnknownTechniqueError, which
// list the valid names). Anything else is a
// finding: a crash, a sanitizer report, a hang, another exception (std::out_of_range from a
// conversion, a JSON library error, std::bad_alloc: messages that would not name the option), or
// a file created, changed or removed in the scratch folder.
#include <fcntl.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cctype>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <typeinfo>
#include <vector>

#include "translucent/bssrdf/registry.h"  // UnknownModelError
#include "commands.h"
#include "translucent/optics/medium.h"  // ParameterError
#include "translucent/techniques/registry.h"  // UnknownTechniqueError

namespace {
namespace fs = std::filesystem;

const char* const kScene = R"({
  "mesh": {"file": "cube.obj"},
  "material": {"preset": "Marble", "scale": 10.0},
  "lights": [
    {"type": "directional", "direction": [-0.4, 1.0, 0.6], "irradiance": 1.0},
    {"type": "point", "position": [1.5, 0.3, 1.2], "intensity": 0.3, "color": [1.0, 0.8, 0.6]}
  ],
  "camera": {"type": "pinhole", "position": [1.8, 1.4, 2.4], "look_at": [0, 0, 0],
             "up": [0, 1, 0], "fov": 40, "width": 16, "height": 12},
  "cone_angle": 5.0
}
)";

const char* const kCube =
    "v -0.5 -0.5 -0.5\nv 0.5 -0.5 -0.5\nv 0.5 0.5 -0.5\nv -0.5 0.5 -0.5\n"
    "v -0.5 -0.5 0.5\nv 0.5 -0.5 0.5\nv 0.5 0.5 0.5\nv -0.5 0.5 0.5\n"
    "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";

const char* const kLayers =
    R"([{"thickness": 0.5, "sigma_a": 0.1, "sigma_s": 10, "g": 0.9},)"
    R"( {"thickness": null, "sigma_a": 0.01, "sigma_s": 1, "g": 0}])";

// Not compiled in check-only mode (the GPU does that): a file that exists is all it takes.
const char* const kBssrdf = "analytic radial\n";

const char* const kTable = "# units: mm\nr,R_r,R_g,R_b\n0.1,1,1,1\n0.5,0.5,0.5,0.5\n2,0.01,0.01,0.01\n";

// What the scratch folder holds: path -> size and modification time.
std::map<std::string, std::pair<uintmax_t, int64_t>> listing(const fs::path& dir) {
  std::map<std::string, std::pair<uintmax_t, int64_t>> out;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    std::error_code ec;
    const uintmax_t size = e.is_regular_file(ec) ? e.file_size(ec) : 0;
    const int64_t time = e.last_write_time(ec).time_since_epoch().count();
    out[fs::relative(e.path(), dir).string()] = {size, time};
  }
  return out;
}

struct Scratch {
  fs::path dir;
  std::map<std::string, std::pair<uintmax_t, int64_t>> files;

  Scratch() {
    dir = fs::temp_directory_path() / ("translucent_fuzz_cli_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir / "sub");
    const std::pair<const char*, const char*> contents[] = {
        {"scene.json", kScene},     {"cube.obj", kCube},   {"layers.json", kLayers},
        {"model.bssrdf", kBssrdf},  {"table.csv", kTable}, {"old.png", "not a PNG"}};
    for (const auto& [name, text] : contents) std::ofstream(dir / name) << text;
    files = listing(dir);
    // Caches the checks might name stay inside (none is created in check-only mode).
    ::setenv("TRANSLUCENT_CACHE_DIR", (dir / "cache").c_str(), 1);
    ::setenv("XDG_CACHE_HOME", (dir / "cache").c_str(), 1);
    ::setenv("HOME", dir.c_str(), 1);
  }
  ~Scratch() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
};

// An argument that might name something outside the scratch folder.
bool leavesScratch(const std::string& arg) {
  if (arg.find("..") != std::string::npos || (!arg.empty() && arg[0] == '~')) return true;
  for (size_t i = 0; i < arg.size(); ++i) {
    if (arg[i] != '/') continue;
    if (i == 0) return true;
    const unsigned char before = static_cast<unsigned char>(arg[i - 1]);
    if (!(std::isalnum(before) || before == '_' || before == '-' || before == '.')) return true;
  }
  return false;
}

[[noreturn]] void finding(const std::string& what, const std::vector<std::string>& args) {
  std::string line;
  for (const auto& a : args) line += " '" + a + "'";
  std::fprintf(stderr, "fuzz_cli: %s\n  translucent%s\n", what.c_str(), line.c_str());
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const Scratch scratch;
  std::vector<std::string> args;
  {
    std::string arg;
    for (size_t i = 0; i < size; ++i) {
      const char c = static_cast<char>(data[i]);
      if (c == '\n' || c == '\0') {
        args.push_back(arg);
        arg.clear();
      } else {
        arg += c;
      }
    }
    if (size > 0 && data[size - 1] != '\n' && data[size - 1] != '\0') args.push_back(arg);
  }
  for (const auto& a : args)
    if (leavesScratch(a)) return -1;  // not added to the corpus

  // Relative paths resolve in the scratch folder; the fuzzer's own folder is back before
  // libFuzzer writes anything.
  const int home = ::open(".", O_RDONLY | O_DIRECTORY);
  if (home < 0 || ::chdir(scratch.dir.c_str()) != 0) finding("cannot enter the scratch folder", args);
  std::string unexpected;
  {
    translucent::cli::CheckOnly checkOnly;
    CLI::App app{"translucent (fuzz_cli)"};
    translucent::cli::addAllCommands(app);
    std::vector<std::string> reversed(args.rbegin(), args.rend());  // CLI11 takes them reversed
    try {
      app.parse(reversed);
    } catch (const CLI::ParseError& e) {
      std::ostringstream out, err;
      (void)app.exit(e, out, err);
    } catch (const translucent::ParameterError&) {
    } catch (const translucent::bssrdf::UnknownModelError&) {
    } catch (const translucent::techniques::UnknownTechniqueError&) {
    } catch (const std::exception& e) {
      unexpected = std::string("unexpected exception (") + typeid(e).name() + "): " + e.what();
    } catch (...) {
      unexpected = "unexpected exception that is not a std::exception";
    }
  }
  if (::fchdir(home) != 0) finding("cannot leave the scratch folder", args);
  ::close(home);
  if (!unexpected.empty()) finding(unexpected, args);
  if (listing(scratch.dir) != scratch.files)
    finding("the scratch folder changed: check-only mode wrote, moved or removed a file", args);
  return 0;
}
