// SPDX-License-Identifier: GPL-3.0-or-later
// Where the files that ship with Translucent are found at run time: the GLSL shaders and the data
// (built-in .bssrdf models, scenes, meshes, compare suites). An installed binary finds them
// relative to itself, so a prefix can be moved and nothing depends on the build path:
//   1. $TRANSLUCENT_SHARE_DIR, when set (a folder holding shaders/ and data/);
//   2. relative to the binary that holds this code (the executable, or the Python extension
//      module): <bin>/../share/translucent (cmake --install, the .deb) or <dir>/share/translucent
//      (the Python package, whose module sits beside its share/ folder);
//   3. relative to the running executable (/proc/self/exe), the same two places;
//   4. the source tree the binary was built from (a build-tree run).
// The first that holds a shaders/ folder wins.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace translucent::io {

// The folder that holds shaders/ and data/. Throws std::runtime_error listing every place looked
// in when none holds them.
std::filesystem::path shareDirectory();

// The places shareDirectory() looks in, in order (for error messages and `translucent --version`).
std::vector<std::filesystem::path> shareDirectoryCandidates();

// The file of the executable or shared object that holds the io layer's code (for the Python
// module, the module's file, not the interpreter's), canonical; empty when dladdr cannot tell.
// Installed files (share/translucent, the plug-in modules) are found relative to it.
std::filesystem::path binaryOfThisCode();

}  // namespace translucent::io
