// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/io/plugins.h"

#include <dlfcn.h>
#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>
#include <map>
#include <mutex>
#include <system_error>

#include "translucent/io/resources.h"

#if !defined(TRANSLUCENT_PLUGIN_LIBDIR) || !defined(TRANSLUCENT_PLUGIN_BUILD_DIR) || \
    !defined(TRANSLUCENT_PLUGIN_INSTALL_DIR)
#error "the build defines TRANSLUCENT_PLUGIN_LIBDIR, _BUILD_DIR and _INSTALL_DIR (io/CMakeLists.txt)"
#endif

namespace translucent::io {
namespace {

namespace fs = std::filesystem;

// What each module needs, for the error message.
std::string whatToInstall(const std::string& name) {
  if (name == "oiio") return "OpenImageIO (Debian: libopenimageio2.4)";
  if (name == "openvdb") return "OpenVDB (Debian: libopenvdb10.0)";
  return "its libraries";
}

struct Loaded {
  const PluginHeader* table = nullptr;
};

std::mutex& mutex() {
  static std::mutex m;
  return m;
}
std::map<std::string, Loaded>& loaded() {
  static std::map<std::string, Loaded> m;
  return m;
}

}  // namespace

std::vector<fs::path> pluginDirectoryCandidates() {
  const fs::path libdir = TRANSLUCENT_PLUGIN_LIBDIR;
  std::vector<fs::path> out;
  if (const char* env = std::getenv("TRANSLUCENT_PLUGIN_DIR"); env != nullptr && *env != '\0')
    out.emplace_back(env);
  try {
    out.push_back((shareDirectory() / ".." / ".." / libdir / "translucent").lexically_normal());
  } catch (const std::exception&) {
    // No share folder found: the other places may still hold the module.
  }
  if (const fs::path binary = binaryOfThisCode(); !binary.empty()) {
    const fs::path dir = binary.parent_path();
    out.push_back((dir / ".." / libdir / "translucent").lexically_normal());
    out.push_back((dir / ".." / ".." / ".." / ".." / libdir / "translucent").lexically_normal());
  }
  out.emplace_back(TRANSLUCENT_PLUGIN_BUILD_DIR);
  out.emplace_back(TRANSLUCENT_PLUGIN_INSTALL_DIR);
  std::vector<fs::path> unique;
  for (const auto& p : out)
    if (std::find(unique.begin(), unique.end(), p) == unique.end()) unique.push_back(p);
  return unique;
}

const PluginHeader& loadPlugin(const std::string& name, uint32_t abi_version) {
  std::lock_guard lock(mutex());
  if (auto it = loaded().find(name); it != loaded().end()) return *it->second.table;
  const std::string file = "libtranslucent_" + name + ".so";
  const std::string entry = "translucent_" + name + "_plugin";
  std::string tried;
  for (const fs::path& dir : pluginDirectoryCandidates()) {
    const fs::path path = dir / file;
    std::error_code ec;
    if (!fs::exists(path, ec)) {
      tried += fmt::format("\n  {}: no such file", path.string());
      continue;
    }
    // RTLD_LOCAL: the module's libraries (OpenImageIO's, OpenVDB's) do not resolve symbols of
    // anything loaded later; RTLD_NOW: a missing library or symbol fails here, not mid-run.
    void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (handle == nullptr) {
      const char* why = dlerror();
      tried += fmt::format("\n  {}: {}", path.string(), why != nullptr ? why : "dlopen failed");
      continue;
    }
    using Entry = const void* (*)();
    dlerror();
    void* symbol = dlsym(handle, entry.c_str());
    if (symbol == nullptr) {
      const char* why = dlerror();
      tried += fmt::format("\n  {}: no {}(): {}", path.string(), entry, why != nullptr ? why : "");
      dlclose(handle);
      continue;
    }
    const auto* table = static_cast<const PluginHeader*>(reinterpret_cast<Entry>(symbol)());
    if (table == nullptr || table->abi_version != abi_version) {
      tried += fmt::format("\n  {}: ABI version {}, expected {} (a module of another build)",
                           path.string(), table != nullptr ? table->abi_version : 0, abi_version);
      dlclose(handle);
      continue;
    }
    // Never closed: the tables and the libraries' static state live as long as the process.
    loaded()[name].table = table;
    return *table;
  }
  throw PluginError(fmt::format(
      "cannot load Translucent's {} plug-in module {}; tried:{}\n(install Translucent's modules "
      "into <prefix>/{}/translucent with `cmake --install` or the .deb, and {}; or set "
      "TRANSLUCENT_PLUGIN_DIR to the folder that holds {})",
      name, file, tried, TRANSLUCENT_PLUGIN_LIBDIR, whatToInstall(name), file));
}

}  // namespace translucent::io
