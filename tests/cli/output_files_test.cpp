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

// A writer's error that does not name the file ("No space left on device") is reported with
// the option and the target, never the temporary file.
TEST_F(OutputFilesTest, WriterErrorsNameTheOutput) {
  OutputFiles out;
  try {
    out.file("--out", path("plot.png"),
             [](const std::string&) { throw std::runtime_error("No space left on device"); });
    FAIL() << "a failing writer succeeded";
  } catch (const ParameterError& e) {
    EXPECT_EQ(std::string(e.what()),
              "--out '" + path("plot.png") + "': write failed: No space left on device");
  }
  EXPECT_TRUE(entries().empty());
}

// A name that fits the folder's file system writes, though its hidden temporary
// (".NAME.tmp-PID-N.EXT") would be longer than the longest name: the temporary is shortened.
TEST_F(OutputFilesTest, LongestNameThatFitsIsWritten) {
  const std::string name = std::string(251, 'n') + ".csv";  // 255 bytes
  OutputFiles out;
  out.text("--csv", path(name), "a,b\n");
  out.file("--out", path(std::string(250, 'p') + ".json"),
           [](const std::string& tmp) { std::ofstream(tmp) << "{}"; });
  out.commit();
  EXPECT_EQ(read(path(name)), "a,b\n");
  EXPECT_EQ(entries().size(), 2u);
}

// A name longer than the file system takes is refused by the check before the work, naming the
// option, the length and the limit (it used to fail after the work as "disk full").
TEST_F(OutputFilesTest, TooLongNameIsRefusedBeforeTheWork) {
  translucent::cli::OutputSet outputs;
  const std::string name = std::string(300, 'x') + ".csv";
  outputs.output("--csv", path(name));
  try {
    outputs.check();
    FAIL() << "a 304-byte file name passed the check";
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("--csv '"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("the file name is 304 bytes long"), std::string::npos)
        << e.what();
  }
}

}  // namespace
