// The files a run writes, checked against each other and against the files the run reads before
// any work is done (issue #15, "Outputs"): a typo or a copied command line must never destroy a
// scene, a mesh or an environment map, nor let one output silently replace another.
//
// Writing itself goes through a temporary file beside the target that is renamed over it only
// when every write and the close succeeded (analysis::writeExr/writePng do that for images,
// writeTextOutput below for text): a failing or interrupted run leaves no file behind and never
// truncates an existing one. A target that exists and is not a regular file (/dev/stdout,
// /dev/full, a FIFO) is written directly, since renaming over a device would replace it; those
// writes are checked too, so /dev/full fails loudly.
#pragma once

#include <CLI/CLI.hpp>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace translucent::scene {
struct Scene;
}

namespace translucent::cli {

// Adds a check to an output option: an empty value (`--out ""`) is an error instead of being
// taken as "not given" (which used to fall back to a default file name and overwrite it).
CLI::Option* outputOption(CLI::Option* option);

class OutputSet {
 public:
  // An output of the run; `option` names it in messages ("--exr"). Empty paths are skipped (the
  // option was not given; outputOption refuses an explicitly empty one at parse time).
  void output(std::string option, std::string path);
  // A file the run reads; `what` names it in messages ("scene", "environment map"). Names that
  // are not files (a registered model name, "checker") are skipped.
  void input(std::string what, const std::filesystem::path& path);
  // The scene file and every file it names: mesh, filter textures, environment maps, .bssrdf.
  void sceneInputs(const std::filesystem::path& scene_file, const scene::Scene& s);
  // Throws ParameterError when an output is a directory, its folder does not exist or is not
  // writable, it is one of the inputs, or two outputs are the same file (naming both options
  // and the path). Call it before any long work.
  void check() const;
  // The inputs given so far (what they are, their paths).
  const std::vector<std::pair<std::string, std::filesystem::path>>& inputs() const {
    return inputs_;
  }

 private:
  std::vector<std::pair<std::string, std::string>> outputs_;
  std::vector<std::pair<std::string, std::filesystem::path>> inputs_;
};

// Writes `text` to the output `path` of `option` through a temporary file (see above); throws
// ParameterError naming the option and the path when a write, the close or the rename fails.
void writeTextOutput(const std::string& option, const std::string& path, std::string_view text);

// Runs a library writer that takes a path (`write(path)`: a plot, a CSV, a Markdown report; it
// must throw when a write fails) on a temporary file beside `path` with the same extension (some
// writers choose the format by it), and renames that over `path` when it returned. A writer that
// throws leaves no temporary file and the target untouched. Devices are written in place.
void writeOutput(const std::string& path, const std::function<void(const std::string&)>& write);

}  // namespace translucent::cli
