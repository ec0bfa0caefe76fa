// SPDX-License-Identifier: GPL-3.0-or-later
// The files a run writes, checked against each other and against the files the run reads before
// any work is done (issue #15, "Outputs"): a typo or a copied command line must never destroy a
// scene, a mesh or an environment map, nor let one output silently replace another.
//
// Writing goes through OutputFiles: every output of a run is written to a temporary file first,
// and all of them are put in place together, only once every one of them was written (all or
// nothing): a failing or interrupted run leaves no file behind, never truncates an existing one
// and never leaves the first of its outputs replaced when a later one fails. A target that exists
// and is not a regular file (/dev/stdout, /dev/full, a FIFO) is written in place when the run
// commits, since renaming over a device would replace it; those writes are checked too, so
// /dev/full fails loudly (and before any other output of the run is renamed into place).
#pragma once

#include <CLI/CLI.hpp>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "translucent/io/output_guard.h"

namespace translucent::scene {
struct Scene;
}

namespace translucent::cli {

// '-' as an output writes to stdout (for CSV and JSON outputs); /dev/stdout is the same (written
// through the process's stdout, also where the shell redirected it to a regular file).
bool isStdoutPath(const std::string& path);

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

// The outputs of one run, written all or nothing (issue #15 §2). text() and file() write an
// output now, to a temporary file: beside its target and hidden (`.NAME.tmp-PID-N.EXT`, the
// target's extension kept, since some writers choose the format by it), or for a device in the
// system's temporary folder. commit() then puts every one in place: first it keeps each existing
// target as a hard link (or a copy) beside it, then it writes the devices' bytes into them, then
// it renames the temporaries over their targets; when any of that fails it renames the kept
// targets back, removes the new ones and every temporary, and throws ParameterError naming the
// option and the path. A set destroyed without commit() (a later output or the work after the
// first write failed) removes its temporaries: no target is created, replaced or truncated.
// Messages saying "wrote ..." belong after commit().
class OutputFiles {
 public:
  OutputFiles() = default;
  OutputFiles(const OutputFiles&) = delete;
  OutputFiles& operator=(const OutputFiles&) = delete;
  ~OutputFiles();

  // `text` as the output `path` of `option` ("--json"); every write and the close are checked.
  void text(const std::string& option, const std::string& path, std::string_view text);
  // A library writer that takes a path (`write(tmp)`: an image, a plot, a CSV, a Markdown report;
  // it must throw when a write fails) run on the temporary file of the output `path`. Its error
  // message names `path`, not the temporary file.
  void file(const std::string& option, const std::string& path,
            const std::function<void(const std::string&)>& write);
  // Puts every output written so far in place (see above); the set is empty afterwards and may
  // be used again (a progressive run commits its outputs after every pass).
  void commit();
  // Outputs written and not yet committed.
  size_t size() const { return staged_.size(); }

 private:
  struct Staged {
    std::string option, path, tmp;
    bool device = false;  // written in place at commit()
    std::string backup;   // the previous target, kept during commit() ("" : none)
  };
  Staged stage(const std::string& option, const std::string& path);
  void discard() noexcept;
  std::vector<Staged> staged_;
};

// One output alone, committed at once: OutputFiles with a single text() or file().
void writeTextOutput(const std::string& option, const std::string& path, std::string_view text);
void writeOutput(const std::string& option, const std::string& path,
                 const std::function<void(const std::string&)>& write);

}  // namespace translucent::cli
