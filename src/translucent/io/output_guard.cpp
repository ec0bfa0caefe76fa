// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/io/output_guard.h"

#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <system_error>
#include <unordered_map>

namespace translucent::io {
namespace fs = std::filesystem;

namespace {

// The process's run inputs (ScopedRunInputs), last added last.
std::vector<std::pair<std::string, fs::path>>& runInputs() {
  static std::vector<std::pair<std::string, fs::path>> inputs;
  return inputs;
}

}  // namespace

// The device and inode of an existing file (so hard links and links to it too), else the
// absolute path with "./", "a/../" and the links of its existing parents resolved
// (weakly_canonical; absolute first, since it leaves a relative path whose first part does not
// exist relative: "x.json" and "./x.json" would differ). One key per path keeps the checks of a
// run with many outputs (the frames of an animation) linear.
std::string fileKey(const fs::path& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0) return fmt::format("inode {}:{}", st.st_dev, st.st_ino);
  std::error_code ec;
  const fs::path c = fs::weakly_canonical(fs::absolute(path, ec), ec);
  return "path " + (ec ? path.lexically_normal().string() : c.string());
}

size_t maxFileNameLength(const fs::path& folder) {
  errno = 0;
  const long n = ::pathconf(folder.empty() ? "." : folder.c_str(), _PC_NAME_MAX);
  return n > 0 ? static_cast<size_t>(n) : 255;
}

std::string temporaryBeside(const fs::path& target, const std::string& tag) {
  const std::string name = target.filename().string(), ext = target.extension().string();
  const fs::path dir = target.parent_path();
  const size_t limit = maxFileNameLength(dir.empty() ? fs::path(".") : dir);
  // "." + name + tag + ext; when too long, NAME loses its end (bytes; a cut UTF-8 character in
  // a hidden temporary's name is harmless).
  const size_t fixed = 1 + tag.size() + ext.size();
  const std::string kept = fixed + name.size() <= limit
                               ? name
                               : name.substr(0, limit > fixed ? limit - fixed : 1);
  return (dir / ("." + kept + tag + ext)).string();
}

void OutputSet::output(std::string option, std::string path) {
  if (!path.empty()) outputs_.emplace_back(std::move(option), std::move(path));
}

void OutputSet::input(std::string what, const fs::path& path) {
  std::error_code ec;
  if (!path.empty() && fs::exists(path, ec)) inputs_.emplace_back(std::move(what), path);
}

void OutputSet::check() const {
  std::vector<std::pair<std::string, fs::path>> all = inputs_;
  for (const auto& [what, path] : runInputs()) {
    std::error_code ec;
    if (fs::exists(path, ec)) all.emplace_back(what, path);
  }
  std::unordered_map<std::string, size_t> inputKeys, outputKeys;  // key -> first index
  for (size_t k = 0; k < all.size(); ++k) inputKeys.emplace(fileKey(all[k].second), k);
  for (size_t i = 0; i < outputs_.size(); ++i) {
    const auto& [option, path] = outputs_[i];
    std::error_code ec;
    if (fs::is_directory(path, ec))
      throw OutputError(fmt::format("{} '{}': is a folder: expected a file name", option, path));
    const fs::path dir = fs::path(path).parent_path().empty() ? fs::path(".")
                                                                : fs::path(path).parent_path();
    // ENAMETOOLONG would otherwise come only when the output is written, after the work.
    const std::string name = fs::path(path).filename().string();
    if (const size_t limit = maxFileNameLength(dir); name.size() > limit)
      throw OutputError(fmt::format("{} '{}': cannot write: the file name is {} bytes long, and "
                                    "the folder's file system takes at most {}",
                                    option, path, name.size(), limit));
    if (const size_t whole = fs::absolute(path, ec).string().size(); whole >= PATH_MAX)
      throw OutputError(fmt::format("{} '{}': cannot write: the path is {} bytes long, and the "
                                    "system takes at most {}", option, path, whole, PATH_MAX - 1));
    if (!fs::is_directory(dir, ec))
      throw OutputError(fmt::format("{} '{}': cannot write: folder '{}' does not exist",
                                    option, path, dir.string()));
    // The temporary file is created in the folder, so the folder must be writable even when the
    // target itself is (a device is written directly and needs only its own permission).
    const bool special = fs::exists(path, ec) && !fs::is_regular_file(path, ec);
    if (special ? ::access(path.c_str(), W_OK) != 0 : ::access(dir.c_str(), W_OK) != 0)
      throw OutputError(fmt::format("{} '{}': cannot write: {} is not writable", option, path,
                                    special ? "the file" : fmt::format("folder '{}'", dir.string())));
    const std::string key = fileKey(path);
    if (const auto in = inputKeys.find(key); in != inputKeys.end()) {
      const auto& [what, file] = all[in->second];
      throw OutputError(fmt::format("{} '{}': is {} of this run ('{}'): refusing to "
                                    "overwrite an input; choose another output file",
                                    option, path, what, file.string()));
    }
    const auto [first, added] = outputKeys.emplace(key, i);
    if (!added && !special)
      throw OutputError(fmt::format("{} '{}' and {} '{}' are the same file: each output "
                                    "needs its own file",
                                    outputs_[first->second].first, outputs_[first->second].second,
                                    option, path));
  }
}

ScopedRunInputs::ScopedRunInputs(std::vector<std::pair<std::string, fs::path>> inputs)
    : count_(inputs.size()) {
  auto& all = runInputs();
  all.insert(all.end(), std::make_move_iterator(inputs.begin()),
             std::make_move_iterator(inputs.end()));
}

ScopedRunInputs::~ScopedRunInputs() {
  auto& all = runInputs();
  all.resize(all.size() - std::min(count_, all.size()));
}

}  // namespace translucent::io
