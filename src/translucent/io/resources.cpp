// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/io/resources.h"

#include <dlfcn.h>
#include <fmt/format.h>

#include <cstdlib>
#include <stdexcept>
#include <system_error>

#ifndef TRANSLUCENT_SOURCE_SHARE_DIR
#error "TRANSLUCENT_SOURCE_SHARE_DIR must be defined by the build (the repository's root folder)"
#endif

namespace translucent::io {
namespace {

// Where a prefix keeps our files, seen from the folder of a binary inside it.
void addBinaryRelative(const std::filesystem::path& binary,
                       std::vector<std::filesystem::path>& out) {
  if (binary.empty()) return;
  const std::filesystem::path dir = binary.parent_path();
  out.push_back((dir / ".." / "share" / "translucent").lexically_normal());
  out.push_back((dir / "share" / "translucent").lexically_normal());
}

std::filesystem::path runningExecutable() {
  std::error_code ec;
  auto p = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::filesystem::path() : p;
}

}  // namespace

std::filesystem::path binaryOfThisCode() {
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&binaryOfThisCode), &info) == 0 || info.dli_fname == nullptr)
    return {};
  std::error_code ec;
  auto p = std::filesystem::canonical(info.dli_fname, ec);
  return ec ? std::filesystem::path() : p;
}

std::vector<std::filesystem::path> shareDirectoryCandidates() {
  std::vector<std::filesystem::path> out;
  if (const char* env = std::getenv("TRANSLUCENT_SHARE_DIR"); env != nullptr && *env != '\0')
    out.emplace_back(env);
  addBinaryRelative(binaryOfThisCode(), out);
  addBinaryRelative(runningExecutable(), out);
  out.emplace_back(TRANSLUCENT_SOURCE_SHARE_DIR);
  return out;
}

std::filesystem::path shareDirectory() {
  const auto candidates = shareDirectoryCandidates();
  std::error_code ec;
  // An explicit override is taken as given: a wrong one should fail loudly, naming it.
  if (const char* env = std::getenv("TRANSLUCENT_SHARE_DIR"); env != nullptr && *env != '\0') {
    if (!std::filesystem::is_directory(std::filesystem::path(env) / "shaders", ec))
      throw std::runtime_error(fmt::format(
          "TRANSLUCENT_SHARE_DIR='{}' holds no shaders/ folder (expected the folder that "
          "`cmake --install` writes as <prefix>/share/translucent)",
          env));
    return env;
  }
  for (const auto& c : candidates)
    if (std::filesystem::is_directory(c / "shaders", ec)) return c;
  std::string tried;
  for (const auto& c : candidates) tried += "\n  " + c.string();
  throw std::runtime_error(fmt::format(
      "cannot find Translucent's shaders and data; looked for a shaders/ folder in:{}\n"
      "(set TRANSLUCENT_SHARE_DIR to the installed share/translucent folder)",
      tried));
}

}  // namespace translucent::io
