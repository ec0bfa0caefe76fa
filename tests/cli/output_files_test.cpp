// SPDX-License-Identifier: GPL-3.0-or-later
// OutputFiles (apps/cli/output_guard.h): the outputs of a run are put in place all or nothing.
// The CLI tests (outputs.cmake, all_or_nothing) fail a run on a full device; these cases reach
// what a command line cannot: a rename that fails after another output was renamed, which must
// put the earlier target back.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "translucent/optics/medium.h"  // ParameterError
#include "output_guard.h"

namespace fs = std::filesystem;
using translucent::ParameterError;
using translucent::cli::OutputFiles;

namespace {

struct OutputFilesTest : ::testing::Test {
  fs::path dir;
  void SetUp() override {
    dir = fs::temp_directory_path() /
          ("translucent_output_files_" +
           std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir);
    fs::create_directories(dir);
  }
  void TearDown() override { fs::remove_all(dir); }
  std::string path(const std::string& name) const { return (dir / name).string(); }
  static std::string read(const std::string& file) {
    std::ifstream in(file, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
  }
  static void write(const std::string& file, const std::string& text) {
    std::ofstream(file, std::ios::binary) << text;
  }
  // Every entry of the folder, hidden temporaries and kept targets included.
  std::vector<std::string> entries() const {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
  }
};

TEST_F(OutputFilesTest, NothingAppearsBeforeCommit) {
  OutputFiles out;
  out.text("--json", path("a.json"), "{}\n");
  out.file("--csv", path("b.csv"), [](const std::string& p) { write(p, "r,value\n"); });
  EXPECT_FALSE(fs::exists(path("a.json")));
  EXPECT_FALSE(fs::exists(path("b.csv")));
  EXPECT_EQ(out.size(), 2u);
  out.commit();
  EXPECT_EQ(read(path("a.json")), "{}\n");
  EXPECT_EQ(read(path("b.csv")), "r,value\n");
  EXPECT_EQ(entries(), (std::vector<std::string>{"a.json", "b.csv"}));
}

TEST_F(OutputFilesTest, DestroyedWithoutCommitLeavesNothing) {
  write(path("a.json"), "old");
  {
    OutputFiles out;
    out.text("--json", path("a.json"), "new");
    out.text("--csv", path("b.csv"), "new");
  }
  EXPECT_EQ(read(path("a.json")), "old");
  EXPECT_EQ(entries(), (std::vector<std::string>{"a.json"}));
}

TEST_F(OutputFilesTest, WriterErrorNamesTheTargetAndLeavesNothing) {
  write(path("a.json"), "old");
  OutputFiles out;
  out.text("--json", path("a.json"), "new");
  try {
    out.file("--png", path("b.png"), [](const std::string& p) {
      write(p, "partial");
      throw std::runtime_error("cannot write '" + p + "': encoder failed");
    });
    FAIL() << "the writer's error was swallowed";
  } catch (const ParameterError& e) {
    EXPECT_EQ(std::string(e.what()), "cannot write '" + path("b.png") + "': encoder failed");
  }
  EXPECT_EQ(out.size(), 1u);
}

// The second rename fails (its target is a folder that is not empty): the first target, already
// replaced, is put back byte for byte, a new first target is removed, and nothing else is left.
TEST_F(OutputFilesTest, FailedRenamePutsEarlierTargetsBack) {
  write(path("a.json"), "previous a");
  fs::create_directories(dir / "b.csv" / "inside");
  OutputFiles out;
  out.text("--json", path("a.json"), "new a");
  out.text("--new", path("new.txt"), "new file");
  out.text("--csv", path("b.csv"), "new b");
  try {
    out.commit();
    FAIL() << "renaming over a folder that is not empty succeeded";
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("--csv '" + path("b.csv") + "': write failed"),
              std::string::npos)
        << e.what();
  }
  EXPECT_EQ(read(path("a.json")), "previous a");
  EXPECT_EQ(entries(), (std::vector<std::string>{"a.json", "b.csv"}));
  EXPECT_EQ(out.size(), 0u);
}

TEST_F(OutputFilesTest, ReplacesExistingTargetsAndKeepsNoCopy) {
  write(path("a.json"), "old");
  fs::create_hard_link(path("a.json"), path("link.json"));
  OutputFiles out;
  out.text("--json", path("a.json"), "new");
  out.commit();
  EXPECT_EQ(read(path("a.json")), "new");
  EXPECT_EQ(read(path("link.json")), "old");  // the target is replaced, not written through
  EXPECT_EQ(entries(), (std::vector<std::string>{"a.json", "link.json"}));
  // The set can be used again (a progressive run commits after each pass).
  out.text("--json", path("a.json"), "newer");
  out.commit();
  EXPECT_EQ(read(path("a.json")), "newer");
}

}  // namespace
