// SPDX-License-Identifier: GPL-3.0-or-later
// The check every writer of a run makes before it writes (the CLI's commands, `translucent
// merge`, the explorer's --screenshot): an output must not be a folder, must lie in a writable
// folder, must not be one of the files the run reads, and two outputs must not be one file.
// Files are compared by device and inode when they exist (a hard link or a symbolic link to an
// input is that input), else by their absolute path with the links of its folders resolved.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace translucent::io {

// Thrown by OutputSet::check; the message names the option and the path.
class OutputError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

// A key two names of one file share (device and inode, else the resolved absolute path).
std::string fileKey(const std::filesystem::path& path);

// A hidden temporary file beside `target`, for writing it whole before a rename:
// `.NAME<tag>EXT` (the extension kept, since some writers choose the format by it), with NAME
// shortened so that the name fits the folder's longest file name (a target whose own name fits
// always gets a temporary that fits too).
std::string temporaryBeside(const std::filesystem::path& target, const std::string& tag);

// The longest file name (bytes) the folder's file system takes (pathconf _PC_NAME_MAX; 255 when
// it does not say).
size_t maxFileNameLength(const std::filesystem::path& folder);

class OutputSet {
 public:
  // An output of the run; `option` names it in messages ("--json"). Empty paths are skipped.
  void output(std::string option, std::string path);
  // A file the run reads; `what` names it in messages ("scene", "environment map"). Names that
  // are not files (a registered model name, "checker") are skipped.
  void input(std::string what, const std::filesystem::path& path);
  // Throws OutputError when an output is a folder, its name is longer than its folder's file
  // system takes (or the whole path than the system's), its folder does not exist or is not
  // writable, it is one of the inputs (those given here and the process's run inputs, below),
  // or two outputs are the same file. Call it before any long work.
  void check() const;
  const std::vector<std::pair<std::string, std::filesystem::path>>& inputs() const {
    return inputs_;
  }

 private:
  std::vector<std::pair<std::string, std::string>> outputs_;
  std::vector<std::pair<std::string, std::filesystem::path>> inputs_;
};

// Inputs of the whole process that every OutputSet::check() of it treats as its own while this
// object lives: the partial files `translucent merge` reads while it runs the recorded command,
// whose own outputs know nothing of them.
class ScopedRunInputs {
 public:
  explicit ScopedRunInputs(std::vector<std::pair<std::string, std::filesystem::path>> inputs);
  ~ScopedRunInputs();
  ScopedRunInputs(const ScopedRunInputs&) = delete;
  ScopedRunInputs& operator=(const ScopedRunInputs&) = delete;

 private:
  size_t count_ = 0;
};

}  // namespace translucent::io
