// SPDX-License-Identifier: GPL-3.0-or-later
// The plug-in modules (io/plugins.h) that bring OpenImageIO and OpenVDB: the folders looked in and
// their order, the build tree's modules loading with their ABI version, and the error for a
// module that is nowhere naming every path tried and what to set.
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include "translucent/io/oiio_plugin.h"
#include "translucent/io/plugins.h"
#include "translucent/material/voxels_openvdb_plugin.h"

namespace translucent::io {
namespace {

// Sets an environment variable for one scope.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const char* value) : name_(name) {
    if (const char* old = std::getenv(name)) {
      old_ = old;
      had_ = true;
    }
    ::setenv(name, value, 1);
  }
  ~ScopedEnv() {
    if (had_)
      ::setenv(name_, old_.c_str(), 1);
    else
      ::unsetenv(name_);
  }
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;

 private:
  const char* name_;
  std::string old_;
  bool had_ = false;
};

TEST(ImagePlugins, TheVariableComesFirstAndTheBuildTreeBeforeTheInstallPath) {
  const ScopedEnv env("TRANSLUCENT_PLUGIN_DIR", "/nowhere/plugins");
  const auto dirs = pluginDirectoryCandidates();
  ASSERT_GE(dirs.size(), 3u);
  EXPECT_EQ(dirs.front(), "/nowhere/plugins");
  // The last two: the build tree's module folder, then the compiled-in install path.
  EXPECT_EQ(dirs[dirs.size() - 2].filename(), "translucent");
  EXPECT_EQ(dirs.back().filename(), "translucent");
  EXPECT_EQ(dirs[dirs.size() - 2].parent_path().filename(), "lib");
}

TEST(ImagePlugins, BothModulesLoadWithTheirAbiVersionAndStayLoaded) {
  // A folder without modules first: the lookup goes on to the build tree's.
  const ScopedEnv env("TRANSLUCENT_PLUGIN_DIR", "/nowhere/plugins");
  const auto& oiio = plugin<OiioApi>("oiio");
  EXPECT_EQ(oiio.header.abi_version, OiioApi::kAbiVersion);
  EXPECT_NE(oiio.encode, nullptr);
  EXPECT_EQ(&plugin<OiioApi>("oiio"), &oiio);
  const auto& vdb = plugin<material::VdbApi>("openvdb");
  EXPECT_EQ(vdb.header.abi_version, material::VdbApi::kAbiVersion);
  EXPECT_NE(vdb.read_grid, nullptr);
}

TEST(ImagePlugins, AModuleFoundNowhereIsAnErrorNamingEveryPathTried) {
  const ScopedEnv env("TRANSLUCENT_PLUGIN_DIR", "/nowhere/plugins");
  try {
    (void)loadPlugin("no_such_module", 1);
    FAIL() << "loaded a module that does not exist";
  } catch (const PluginError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("libtranslucent_no_such_module.so"), std::string::npos) << message;
    for (const auto& dir : pluginDirectoryCandidates())
      EXPECT_NE(message.find(dir.string()), std::string::npos) << dir << " in " << message;
    EXPECT_NE(message.find("TRANSLUCENT_PLUGIN_DIR"), std::string::npos) << message;
  }
}

}  // namespace
}  // namespace translucent::io
