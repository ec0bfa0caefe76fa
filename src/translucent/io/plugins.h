// SPDX-License-Identifier: GPL-3.0-or-later
// Plug-in modules: the code that needs a large third-party library only for some runs (OpenImageIO
// for image files, OpenVDB for .vdb grids) lives in a shared module loaded with dlopen on first
// use, so that a process that never reads or writes an image or a grid does not map those
// libraries and their ~260-library dependency closure (about 100 MiB of resident memory at
// start-up, 25 MiB of it OpenImageIO's static initialisers).
//
// A module libtranslucent_<name>.so exports one C function, translucent_<name>_plugin(), that
// returns a pointer to a table of function pointers whose first member is the ABI version
// (PluginHeader). The functions never throw: they report errors as text. The tables use standard
// library types (std::string, std::vector) by reference: the modules are built in the same build,
// with the same compiler and flags, as the binaries that load them, and the version number
// changes with any change of a table.
//
// The module is looked for, in order, in:
//   1. $TRANSLUCENT_PLUGIN_DIR, when set;
//   2. <prefix>/<libdir>/translucent, where <prefix> is io::shareDirectory()/../.. (an installed
//      tree, also when it has been moved);
//   3. relative to the binary that holds this code: <dir>/../<libdir>/translucent (an executable
//      in <prefix>/bin) and <dir>/../../../../<libdir>/translucent (the Python module in
//      <prefix>/lib/python3/dist-packages/translucent);
//   4. the build tree's module folder (<build>/lib/translucent, for binaries run from the build);
//   5. the install path compiled in (<CMAKE_INSTALL_PREFIX>/<libdir>/translucent).
// The first file that loads and has the expected ABI version wins; it stays loaded.
#pragma once

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

namespace translucent::io {

// The first member of every module's table.
struct PluginHeader {
  uint32_t abi_version;
};

// Thrown when no candidate loads; the message names every path tried and why each failed, and
// says which package to install or which variable to set.
class PluginError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The table of module `name` (e.g. "oiio": libtranslucent_oiio.so, entry translucent_oiio_plugin),
// loaded on the first call (thread-safe) and cached for the life of the process. Throws
// PluginError.
const PluginHeader& loadPlugin(const std::string& name, uint32_t abi_version);

template <typename Api>
const Api& plugin(const std::string& name) {
  return reinterpret_cast<const Api&>(loadPlugin(name, Api::kAbiVersion));
}

// The folders loadPlugin() looks in, in order (duplicates removed).
std::vector<std::filesystem::path> pluginDirectoryCandidates();

}  // namespace translucent::io
