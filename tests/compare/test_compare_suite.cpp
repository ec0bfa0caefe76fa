// `translucent compare --suite` through the real binary: a temporary suite of two tiny cube
// scenes (32x24, few photons and samples, 2000 points as in test_compare_cli.cpp) around a broken
// one. The leaderboard lists every scene x technique with exactly the numbers of each scene's
// report.json, the broken scene is a row with its error while the scenes after it still run,
// every link of OUT/index.html resolves, and OUT follows the report's folder rules.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>
#include <sstream>

namespace {
namespace fs = std::filesystem;
using nlohmann::json;

const fs::path kRoot = fs::temp_directory_path() /
                       ("translucent_test_compare_suite_" + std::to_string(::getpid()));

std::string readText(const fs::path& p) {
  std::ifstream f(p);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

json readJson(const fs::path& p) {
  std::ifstream f(p);
  return json::parse(f);
}

struct CliRun {
  int status = -1;
  std::string output;
};

CliRun run(const std::string& args, const std::string& tag) {
  const fs::path log = kRoot / (tag + ".log");
  const std::string cmd = "TRANSLUCENT_CACHE_DIR='" + (kRoot / "technique-cache").string() + "' '" +
                          TRANSLUCENT_CLI + "' compare " + args + " > '" + log.string() + "' 2>&1";
  CliRun r;
  const int rc = std::system(cmd.c_str());
  r.status = WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
  r.output = readText(log);
  return r;
}

std::string suiteArgs(const fs::path& out) {
  return "--suite '" + (kRoot / "suite").string() + "' --width 32 --height 24 --photons 20000 "
         "--samples 4000 --frames 1 --warmup 0 --threads 2 --cache '" + (kRoot / "cache").string() +
         "' --out '" + out.string() + "'";
}

// data/scenes/cube.json with its mesh by absolute path, the light's irradiance as given and a
// 2000-point cloud (llvmpipe renders the default 100000 at ~1 s a frame).
void writeScene(const fs::path& path, const std::string& irradiance) {
  std::string text = readText(TRANSLUCENT_CUBE_SCENE);
  const std::string from = "\"irradiance\": 1.0";
  text.replace(text.find(from), from.size(), "\"irradiance\": " + irradiance);
  const std::string mesh = "\"../meshes/cube.obj\"";
  // Built with += : GCC 12 warns (-Wrestrict, a false positive) on the chained operator+.
  std::string absolute = "\"";
  absolute += (fs::path(TRANSLUCENT_CUBE_SCENE).parent_path() / "../meshes/cube.obj").string();
  absolute += "\"";
  text.replace(text.find(mesh), mesh.size(), absolute);
  const std::string last = "\"cone_angle\": 5.0";
  text.replace(text.find(last), last.size(),
               last + ",\n  \"technique\": {\"name\": \"pointcloud\", \"points\": 2000}");
  std::ofstream(path) << text;
}

const std::vector<std::string> kGood = {"a-cube", "c-cube-brighter"};
const std::vector<std::string> kTechniques = {"pointcloud", "empirical"};

class CompareSuite : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    fs::remove_all(kRoot);
    fs::create_directories(kRoot / "suite");
    writeScene(kRoot / "suite" / "a-cube.json", "1.0");
    // Sorted between the two good scenes: the one after it must still run.
    std::ofstream(kRoot / "suite" / "b-broken.json") << R"({"mesh": {"file": "/nonexistent.obj"}})";
    writeScene(kRoot / "suite" / "c-cube-brighter.json", "1.5");
    std::ofstream(kRoot / "suite" / "notes.txt") << "not a scene: ignored";
    first_ = new CliRun(run(suiteArgs(kRoot / "out"), "first"));
  }
  static void TearDownTestSuite() {
    delete first_;
    std::error_code ec;
    fs::remove_all(kRoot, ec);
  }
  static CliRun* first_;
};
CliRun* CompareSuite::first_ = nullptr;

TEST_F(CompareSuite, BrokenSceneIsARowWithItsErrorAndTheOthersRun) {
  // Nonzero: a scene failed; but every file is written.
  EXPECT_NE(first_->status, 0) << first_->output;
  EXPECT_NE(first_->output.find("1 of 3 scenes failed"), std::string::npos) << first_->output;
  const json lb = readJson(kRoot / "out" / "leaderboard.json");
  EXPECT_EQ(lb.at("generator"), "translucent compare --suite");
  EXPECT_FALSE(lb.at("partial").get<bool>());
  ASSERT_EQ(lb.at("scenes").size(), 3u);
  EXPECT_EQ(lb.at("scenes")[0].at("status"), "done");
  EXPECT_EQ(lb.at("scenes")[1].at("name"), "b-broken");
  EXPECT_EQ(lb.at("scenes")[1].at("status"), "failed");
  EXPECT_EQ(lb.at("scenes")[2].at("status"), "done");
  int errorRows = 0;
  for (const json& r : lb.at("rows"))
    if (r.contains("error")) {
      ++errorRows;
      EXPECT_EQ(r.at("scene"), "b-broken");
      EXPECT_NE(r.at("error").get<std::string>().find("b-broken.json"), std::string::npos) << r;
    }
  EXPECT_EQ(errorRows, 1);
  const std::string md = readText(kRoot / "out" / "leaderboard.md");
  EXPECT_NE(md.find("| b-broken | **error: "), std::string::npos) << md;
  EXPECT_NE(readText(kRoot / "out" / "index.html").find("b-broken.json"), std::string::npos);
}

TEST_F(CompareSuite, LeaderboardHasEverySceneAndTechniqueWithTheReportsNumbers) {
  const json lb = readJson(kRoot / "out" / "leaderboard.json");
  const std::string md = readText(kRoot / "out" / "leaderboard.md");
  std::set<std::string> seen;
  for (const json& row : lb.at("rows")) {
    if (row.contains("error")) continue;
    const std::string scene = row.at("scene"), tech = row.at("technique");
    seen.insert(scene + "/" + tech);
    EXPECT_NE(md.find("| " + scene + " | " + tech + " |"), std::string::npos) << scene << tech;
    // The same numbers as the scene's own report, looked up here independently (exact: the
    // leaderboard copies them, it does not recompute them).
    const json report = readJson(kRoot / "out" / scene / "report.json");
    auto metrics = [&](const std::string& test, const std::string& ref, const std::string& conv) {
      for (const json& m : report.at("metrics"))
        if (m.at("test") == test && m.at("reference") == ref && m.at("quantity") == "radiance" &&
            (conv.empty() || m.at("convention") == conv))
          return m.at("metrics");
      ADD_FAILURE() << "no " << test << " vs " << ref << " in " << scene;
      return json();
    };
    const json vm = metrics(tech, "model", ""), vp = metrics(tech, "physical", "");
    const json mp = metrics("model", "physical", row.at("convention"));
    EXPECT_EQ(row.at("vs_model").at("rel_rmse"), vm.at("rel_rmse")) << scene << tech;
    EXPECT_EQ(row.at("vs_model").at("bias"), vm.at("bias")) << scene << tech;
    EXPECT_EQ(row.at("vs_physical").at("rel_rmse"), vp.at("rel_rmse")) << scene << tech;
    EXPECT_EQ(row.at("vs_physical").at("bias"), vp.at("bias")) << scene << tech;
    EXPECT_EQ(row.at("vs_physical").at("flip"), vp.at("flip")) << scene << tech;
    EXPECT_EQ(row.at("model_vs_physical").at("rel_rmse"), mp.at("rel_rmse")) << scene << tech;
    EXPECT_TRUE(row.at("vs_physical").at("rel_rmse").is_number()) << row;
    for (const json& t : report.at("techniques"))
      if (t.at("name") == tech) {
        EXPECT_EQ(row.at("frame_ms"), t.at("frame_ms")) << scene << tech;
        EXPECT_GT(t.at("frame_ms").get<double>(), 0.0);
      }
  }
  for (const std::string& s : kGood)
    for (const std::string& t : kTechniques) EXPECT_TRUE(seen.contains(s + "/" + t)) << s << t;
  EXPECT_EQ(seen.size(), kGood.size() * kTechniques.size());

  // The summary: each technique over both scenes; the wins add up to one per scene (or more on
  // an exact tie).
  ASSERT_EQ(lb.at("summary").size(), kTechniques.size());
  int wins = 0;
  for (const json& s : lb.at("summary")) {
    EXPECT_EQ(s.at("scenes"), kGood.size()) << s;
    wins += s.at("wins").get<int>();
    double sum = 0.0;
    for (const json& row : lb.at("rows"))
      if (!row.contains("error") && row.at("technique") == s.at("technique"))
        sum += row.at("vs_physical").at("rel_rmse").get<double>();
    EXPECT_NEAR(s.at("vs_physical_rel_rmse_mean").get<double>(), sum / 2.0, 1e-12) << s;
  }
  EXPECT_GE(wins, static_cast<int>(kGood.size()));
}

TEST_F(CompareSuite, EveryLinkOfTheIndexResolves) {
  const fs::path dir = kRoot / "out";
  const std::string html = readText(dir / "index.html");
  const std::regex ref(R"re((?:src|href)="([^"]*)")re");
  std::set<std::string> targets;
  for (auto it = std::sregex_iterator(html.begin(), html.end(), ref); it != std::sregex_iterator(); ++it) {
    const std::string target = (*it)[1];
    EXPECT_FALSE(fs::path(target).is_absolute()) << target;
    EXPECT_EQ(target.find(".."), std::string::npos) << target;
    EXPECT_TRUE(fs::is_regular_file(dir / target)) << target;
    targets.insert(target);
  }
  for (const std::string& s : kGood) EXPECT_TRUE(targets.contains(s + "/index.html")) << s;
  EXPECT_TRUE(targets.contains("leaderboard.json"));
  // Each scene's folder is a complete report, the same as a single compare writes.
  for (const std::string& s : kGood)
    for (const json& f : readJson(dir / s / "report.json").at("files"))
      EXPECT_TRUE(fs::is_regular_file(dir / s / f.get<std::string>())) << s << " " << f;
  EXPECT_FALSE(fs::exists(dir / "b-broken" / "report.json"));
}

TEST_F(CompareSuite, RerunReplacesThePreviousSuiteAndUserFilesAreRefused) {
  ASSERT_TRUE(fs::exists(kRoot / "out" / "leaderboard.json")) << first_->output;
  // Rerun into the same folder (a previous suite): allowed, the references come from the cache.
  const CliRun again = run(suiteArgs(kRoot / "out"), "again");
  EXPECT_NE(again.output.find("physical reference: reused from the cache"), std::string::npos)
      << again.output;
  EXPECT_NE(again.output.find("1 of 3 scenes failed"), std::string::npos) << again.output;
  EXPECT_EQ(readJson(kRoot / "out" / "leaderboard.json").at("rows").size(), 5u);

  const fs::path mine = kRoot / "mine";
  fs::create_directories(mine);
  std::ofstream(mine / "thesis.tex") << "my work";
  const CliRun r = run(suiteArgs(mine), "refused");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("thesis.tex"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("--force"), std::string::npos) << r.output;
  EXPECT_EQ(readText(mine / "thesis.tex"), "my work");
  EXPECT_FALSE(fs::exists(mine / "leaderboard.json"));

  std::string args = "'";
  args += (kRoot / "suite" / "a-cube.json").string();
  args += "' ";
  args += suiteArgs(kRoot / "both");
  const CliRun both = run(args, "both");
  EXPECT_NE(both.status, 0);
  EXPECT_NE(both.output.find("expected one of them"), std::string::npos) << both.output;
}

}  // namespace
