// SPDX-License-Identifier: GPL-3.0-or-later
#include "output_guard.h"

#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <system_error>
#include <unordered_map>
#include <variant>

#include "translucent/io/image_io.h"
#include "translucent/optics/medium.h"
#include "translucent/scene/scene.h"

namespace translucent::cli {
namespace fs = std::filesystem;

bool isStdoutPath(const std::string& path) {
  return path == "-" || path == "/dev/stdout" || path == "/proc/self/fd/1";
}

CLI::Option* outputOption(CLI::Option* option) {
  return option->check(CLI::Validator(
      [](std::string& value) -> std::string {
        return value.empty() ? "empty path: expected a file name" : "";
      },
      "FILE"));
}

void OutputSet::output(std::string option, std::string path) {
  if (!path.empty()) outputs_.emplace_back(std::move(option), std::move(path));
}

void OutputSet::input(std::string what, const fs::path& path) {
  std::error_code ec;
  if (!path.empty() && fs::exists(path, ec)) inputs_.emplace_back(std::move(what), path);
}

void OutputSet::sceneInputs(const fs::path& scene_file, const scene::Scene& s) {
  if (!scene_file.empty()) input("the scene", scene_file);
  for (const auto& [what, path] : scene::inputFiles(s)) input(what, path);  // material files too
}

void OutputSet::check() const {
  // The library's check (translucent/io/output_guard.h: folders, permissions, inputs by device
  // and inode, the process's run inputs such as merge's parts, outputs that are one file), for
  // every output but stdout.
  io::OutputSet files;
  for (const auto& [what, path] : inputs_) files.input(what, path);
  const std::pair<std::string, std::string>* toStdout = nullptr;  // the output given as '-'
  for (size_t i = 0; i < outputs_.size(); ++i) {
    const auto& [option, path] = outputs_[i];
    if (isStdoutPath(path)) {
      if (toStdout)
        throw ParameterError(fmt::format("{} '{}' and {} '{}' both write to stdout: at most one "
                                         "output can be '-'", toStdout->first, toStdout->second,
                                         option, path));
      toStdout = &outputs_[i];
      continue;
    }
    files.output(option, path);
  }
  try {
    files.check();
  } catch (const io::OutputError& e) {
    throw ParameterError(e.what());
  }
}

namespace {

// A device or FIFO: an existing target that is neither a regular file nor a folder (links
// followed, so a link to /dev/full is one).
bool isDevice(const std::string& path) {
  std::error_code ec;
  return fs::exists(path, ec) && !fs::is_regular_file(path, ec) && !fs::is_directory(path, ec);
}


bool readBytes(const std::string& file, std::string& bytes) {
  std::FILE* f = std::fopen(file.c_str(), "rb");
  if (!f) return false;
  char buffer[1 << 16];
  size_t n = 0;
  while ((n = std::fread(buffer, 1, sizeof buffer, f)) > 0) bytes.append(buffer, n);
  const bool ok = std::ferror(f) == 0;
  std::fclose(f);
  return ok;
}

// '-' (and /dev/stdout, which may be a regular file the shell redirected): the bytes on the
// process's stdout, after what the command printed there so far.
bool writeStdout(const std::string& bytes) {
  std::fflush(stdout);
  const bool ok = std::fwrite(bytes.data(), 1, bytes.size(), stdout) == bytes.size();
  return std::fflush(stdout) == 0 && ok;
}

std::string replaceAll(std::string text, const std::string& from, const std::string& to) {
  if (from.empty()) return text;
  for (size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size()))
    text.replace(at, from.size(), to);
  return text;
}

int nextNumber() {
  static int counter = 0;
  return counter++;
}

}  // namespace

OutputFiles::~OutputFiles() { discard(); }

void OutputFiles::discard() noexcept {
  for (const Staged& s : staged_) {
    std::error_code ec;
    fs::remove(s.tmp, ec);
    if (!s.backup.empty()) fs::remove(s.backup, ec);
  }
  staged_.clear();
}

OutputFiles::Staged OutputFiles::stage(const std::string& option, const std::string& path) {
  Staged s{option, path, "", isStdoutPath(path) || isDevice(path), ""};
  const fs::path p(path);
  const std::string tag = fmt::format(".tmp-{}-{}", ::getpid(), nextNumber());
  std::error_code ec;
  // A device's temporary does not take its name (/dev/stdout is short, a FIFO's name may not be).
  s.tmp = s.device ? (fs::temp_directory_path(ec) /
                      ("translucent-output" + tag + p.extension().string()))
                         .string()
                   : io::temporaryBeside(p, tag);
  return s;
}

void OutputFiles::text(const std::string& option, const std::string& path, std::string_view text) {
  Staged s = stage(option, path);
  if (!analysis::writeBytes(s.tmp, text)) {
    const std::string why = analysis::writeErrorText();
    std::error_code ec;
    fs::remove(s.tmp, ec);
    throw ParameterError(fmt::format("{} '{}': write failed: {}", option, path, why));
  }
  staged_.push_back(std::move(s));
}

void OutputFiles::file(const std::string& option, const std::string& path,
                       const std::function<void(const std::string&)>& write) {
  Staged s = stage(option, path);
  try {
    write(s.tmp);
  } catch (const std::exception& e) {
    std::error_code ec;
    fs::remove(s.tmp, ec);
    // Every message names the file: a writer's own ("cannot write 'x.png': ...") with the
    // target for its temporary, else the option and the target before it ("No space left on
    // device" alone says nothing of which output failed).
    const std::string message = replaceAll(e.what(), s.tmp, path);
    throw ParameterError(message.find(path) != std::string::npos
                             ? message
                             : fmt::format("{} '{}': write failed: {}", option, path, message));
  } catch (...) {
    std::error_code ec;
    fs::remove(s.tmp, ec);
    throw;
  }
  staged_.push_back(std::move(s));
}

void OutputFiles::commit() {
  // 1. Keep every existing regular target, so that a failure below can put it back.
  for (Staged& s : staged_) {
    std::error_code ec;
    const fs::file_status st = fs::symlink_status(s.path, ec);
    if (s.device || !(fs::is_regular_file(st) || fs::is_symlink(st))) continue;
    const fs::path p(s.path);
    const std::string backup =
        (p.parent_path() /
         fmt::format(".{}.bak-{}-{}", p.filename().string(), ::getpid(), nextNumber()))
            .string();
    fs::create_hard_link(s.path, backup, ec);
    if (ec) {
      ec.clear();
      fs::copy(s.path, backup, fs::copy_options::copy_symlinks, ec);
    }
    if (ec) {
      const std::string why = ec.message();
      discard();
      throw ParameterError(fmt::format("{} '{}': cannot keep the previous file while the outputs "
                                       "are replaced: {}", s.option, s.path, why));
    }
    s.backup = backup;
  }
  // 2. Devices: their bytes, in place (nothing renamed yet, so a full device leaves every file
  // as it was).
  for (const Staged& s : staged_) {
    if (!s.device) continue;
    std::string bytes;
    const bool written =
        readBytes(s.tmp, bytes) &&
        (isStdoutPath(s.path) ? writeStdout(bytes) : analysis::writeBytes(s.path, bytes));
    if (!written) {
      const std::string why = analysis::writeErrorText();
      discard();
      throw ParameterError(fmt::format("{} '{}': write failed: {}", s.option, s.path, why));
    }
  }
  // 3. The renames; a failed one undoes those before it.
  for (size_t i = 0; i < staged_.size(); ++i) {
    if (staged_[i].device) continue;
    std::error_code ec;
    fs::rename(staged_[i].tmp, staged_[i].path, ec);
    if (!ec) continue;
    const std::string why = ec.message();
    for (size_t j = 0; j < i; ++j) {
      Staged& done = staged_[j];
      if (done.device) continue;
      std::error_code ignored;
      if (done.backup.empty()) {
        fs::remove(done.path, ignored);
      } else {
        fs::rename(done.backup, done.path, ignored);
        if (!ignored) done.backup.clear();
      }
    }
    const Staged failed = staged_[i];
    discard();
    throw ParameterError(fmt::format("{} '{}': write failed: {}", failed.option, failed.path, why));
  }
  // 4. Done: the kept targets and the devices' temporaries go.
  for (const Staged& s : staged_) {
    std::error_code ec;
    if (s.device) fs::remove(s.tmp, ec);
    if (!s.backup.empty()) fs::remove(s.backup, ec);
  }
  staged_.clear();
}

void writeTextOutput(const std::string& option, const std::string& path, std::string_view text) {
  OutputFiles out;
  out.text(option, path, text);
  out.commit();
}

void writeOutput(const std::string& option, const std::string& path,
                 const std::function<void(const std::string&)>& write) {
  OutputFiles out;
  out.file(option, path, write);
  out.commit();
}

}  // namespace translucent::cli
