// SPDX-License-Identifier: GPL-3.0-or-later
// Where the files a scene names (mesh, filter textures, environment maps) are found, after
// Mitsuba 3's FileResolver: a relative name is looked up first beside the scene file, then in
// each folder of the data search path, so that scenes can name shared data ("cgal/head.off",
// extracted by scripts/install-test-data) without absolute paths:
//   1. the scene file's folder (for text without a file: the base folder the caller gives)
//   2. each folder of $TRANSLUCENT_DATA, colon-separated, in order (empty entries skipped)
//   3. ${XDG_CACHE_HOME:-$HOME/.cache}/translucent/data (where scripts/install-test-data puts
//      the CGAL meshes; not $TRANSLUCENT_CACHE_DIR, which only holds caches that can be rebuilt)
// An absolute name is used as it is. The first existing file wins.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace translucent::scene {

// Steps 2 and 3 above, in order.
std::vector<std::filesystem::path> dataSearchPath();

struct ResolvedFile {
  std::filesystem::path path;  // where it was found
  bool on_search_path = false; // found in a data folder (steps 2-3), not beside the scene
};

// Finds `name` as above. Throws ParameterError naming `what` (the scene file), `key` (e.g.
// "mesh.file"), the name and every place tried (and, for names under cgal/, the script that
// installs them) when it is nowhere.
ResolvedFile resolveSceneFile(const std::string& name, const std::filesystem::path& base_dir,
                              const std::string& what, const std::string& key);

}  // namespace translucent::scene
