// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/scene/data_path.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cstdlib>

#include "translucent/optics/medium.h"  // ParameterError

namespace translucent::scene {
namespace fs = std::filesystem;

std::vector<fs::path> dataSearchPath() {
  std::vector<fs::path> dirs;
  if (const char* list = std::getenv("TRANSLUCENT_DATA"); list != nullptr) {
    std::string_view rest(list);
    while (!rest.empty()) {
      const size_t colon = rest.find(':');
      const std::string_view dir = rest.substr(0, colon);
      if (!dir.empty()) dirs.emplace_back(dir);
      if (colon == std::string_view::npos) break;
      rest.remove_prefix(colon + 1);
    }
  }
  // The XDG base-directory spec ignores relative paths.
  if (const char* xdg = std::getenv("XDG_CACHE_HOME");
      xdg != nullptr && *xdg != '\0' && fs::path(xdg).is_absolute())
    dirs.push_back(fs::path(xdg) / "translucent" / "data");
  else if (const char* home = std::getenv("HOME"); home != nullptr && *home != '\0')
    dirs.push_back(fs::path(home) / ".cache" / "translucent" / "data");
  return dirs;
}

ResolvedFile resolveSceneFile(const std::string& name, const fs::path& base_dir,
                              const std::string& what, const std::string& key) {
  const fs::path given(name);
  std::vector<fs::path> tried;
  std::error_code ec;
  // Existence, not readability: a file that is there but unreadable should fail where it is
  // read, with that error, rather than be passed over for another of the same name.
  auto exists = [&](const fs::path& p) { return fs::exists(p, ec) && !fs::is_directory(p, ec); };
  if (given.is_absolute()) {
    if (exists(given)) return {given, false};
    tried.push_back(given);
  } else {
    const fs::path beside = base_dir.empty() ? given : base_dir / given;
    if (exists(beside)) return {beside, false};
    tried.push_back(beside);
    for (const fs::path& dir : dataSearchPath()) {
      const fs::path candidate = dir / given;
      if (exists(candidate)) return {candidate, true};
      tried.push_back(candidate);
    }
  }
  // A folder of that name is not the file, and "not found" would send the user looking for it.
  for (const fs::path& p : tried)
    if (fs::is_directory(p, ec))
      throw ParameterError(fmt::format("{}: {}: '{}' is a directory: expected a file", what, key,
                                       p.string()));
  std::vector<std::string> places;
  for (const fs::path& p : tried) places.push_back(fmt::format("'{}'", p.string()));
  std::string message = fmt::format(
      "{}: {}: file '{}' not found; looked in {} (relative names: beside the scene file, then "
      "each folder of $TRANSLUCENT_DATA, then ${{XDG_CACHE_HOME:-$HOME/.cache}}/translucent/data)",
      what, key, name, fmt::join(places, ", "));
  if (given.begin() != given.end() && *given.begin() == "cgal")
    message += "; the cgal/ meshes are extracted there by scripts/install-test-data";
  throw ParameterError(message);
}

}  // namespace translucent::scene
