// SPDX-License-Identifier: GPL-3.0-or-later
// `translucent compare --suite` through the real binary: a temporary suite of two tiny cube
// scenes (32x24, few photons and samples, 2000 points as in test_compare_cli.cpp) around two that
// fail as a whole (a scene file naming a missing mesh; a light the path tracer refuses, so there
// is no physical reference), and a cube whose point light is inside the bounding sphere, which the
// point cloud refuses while the empirical technique and both references still run. The
// leaderboard lists every scene x technique with exactly the numbers of each scene's report.json,
// a failed scene is a row with its error while the scenes after it still run, a failed technique
// is a row with its reason and is in no average or ranking, every link of OUT/index.html resolves,
// and OUT follows the report's folder rules. A single compare of the point-light scene writes its
// report and exits 1 with a final line naming the failed technique.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <map>
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

// The suite's failure handling is tested with two techniques: the point cloud (which refuses the
// point light inside the bounding sphere) and the empirical shader (which renders it); the
// registry's other techniques would only add rows.
const std::string kTechniqueArg = "--techniques pointcloud,empirical";

std::string suiteArgs(const fs::path& out) {
  return "--suite '" + (kRoot / "suite").string() + "' --width 32 --height 24 --photons 20000 "
         "--samples 4000 --frames 1 --warmup 0 --threads 2 " + kTechniqueArg + " --cache '" +
         (kRoot / "cache").string() +
         "' --out '" + out.string() + "'";
}

// data/scenes/cube.json with its mesh by absolute path, the light's irradiance as given, the
// point light at `point` when given, and a 2000-point cloud (llvmpipe renders the default 100000
// at ~1 s a frame).
void writeScene(const fs::path& path, const std::string& irradiance, const std::string& point = "") {
  std::string text = readText(TRANSLUCENT_CUBE_SCENE);
  const std::string from = "\"irradiance\": 1.0";
  text.replace(text.find(from), from.size(), "\"irradiance\": " + irradiance);
  const std::string position = "\"position\": [1.5, 0.3, 1.2]";
  if (!point.empty()) text.replace(text.find(position), position.size(), "\"position\": " + point);
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
// The cube is [-0.5, 0.5]^3 (bounding sphere radius 0.866); this point is outside the cube, 0.834
// from its centre: inside the sphere the point cloud's shadow map needs the light outside of.
const std::string kInsidePoint = "[0.55, 0.3, 0.55]";
const std::string kPointLightScene = "d-cube-point-light-inside";

class CompareSuite : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    fs::remove_all(kRoot);
    fs::create_directories(kRoot / "suite");
    writeScene(kRoot / "suite" / "a-cube.json", "1.0");
    // Sorted between the two good scenes: the one after it must still run.
    std::ofstream(kRoot / "suite" / "b-broken.json") << R"({"mesh": {"file": "/nonexistent.obj"}})";
    // A filtered directional light: the techniques could, the path tracer cannot.
    std::string noReference = readText(kRoot / "suite" / "a-cube.json");
    const std::string light = R"({"type": "directional", "direction": [-0.4, 1.0, 0.6], "irradiance": 1.0})";
    noReference.replace(noReference.find(light), light.size(),
                        R"({"type": "filtered_directional", "direction": [-0.4, 1.0, 0.6], "texture": "checker"})");
    std::ofstream(kRoot / "suite" / "b2-no-reference.json") << noReference;
    writeScene(kRoot / "suite" / "c-cube-brighter.json", "1.5");
    writeScene(kRoot / "suite" / (kPointLightScene + ".json"), "1.0", kInsidePoint);
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

TEST_F(CompareSuite, FailedScenesAreRowsWithTheirErrorsAndTheOthersRun) {
  // Nonzero: scenes and a technique failed; but every file is written, and the last line says so.
  EXPECT_EQ(first_->status, 1) << first_->output;
  EXPECT_NE(first_->output.find("2 of 5 scenes failed, 1 technique run failed in 1 scene"),
            std::string::npos) << first_->output;
  const json lb = readJson(kRoot / "out" / "leaderboard.json");
  EXPECT_EQ(lb.at("generator"), "translucent compare --suite");
  EXPECT_FALSE(lb.at("partial").get<bool>());
  ASSERT_EQ(lb.at("scenes").size(), 5u);
  const std::vector<std::pair<std::string, std::string>> expected = {
      {"a-cube", "done"}, {"b-broken", "failed"}, {"b2-no-reference", "failed"},
      {"c-cube-brighter", "done"}, {kPointLightScene, "done"}};
  for (size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(lb.at("scenes")[i].at("name"), expected[i].first);
    EXPECT_EQ(lb.at("scenes")[i].at("status"), expected[i].second) << expected[i].first;
  }
  std::map<std::string, std::string> sceneErrors;
  for (const json& r : lb.at("rows"))
    if (r.contains("error") && !r.contains("technique")) sceneErrors[r.at("scene")] = r.at("error");
  ASSERT_EQ(sceneErrors.size(), 2u);
  EXPECT_NE(sceneErrors["b-broken"].find("b-broken.json"), std::string::npos);
  EXPECT_NE(sceneErrors["b-broken"].find("mesh.file"), std::string::npos);
  // No ground truth: the scene fails, named by the reference that could not be computed.
  EXPECT_NE(sceneErrors["b2-no-reference"].find("physical reference: lights[0]: filtered_directional"),
            std::string::npos) << sceneErrors["b2-no-reference"];
  const std::string md = readText(kRoot / "out" / "leaderboard.md");
  EXPECT_NE(md.find("| b-broken | **error: "), std::string::npos) << md;
  EXPECT_NE(md.find("| b2-no-reference | **error: "), std::string::npos) << md;
  EXPECT_NE(readText(kRoot / "out" / "index.html").find("b-broken.json"), std::string::npos);
}

TEST_F(CompareSuite, FailedTechniqueIsARowWithItsReasonInNoAverage) {
  const json lb = readJson(kRoot / "out" / "leaderboard.json");
  const json *failed = nullptr, *other = nullptr;
  for (const json& r : lb.at("rows"))
    if (r.at("scene") == kPointLightScene)
      (r.at("technique") == "pointcloud" ? failed : other) = &r;
  ASSERT_TRUE(failed && other) << lb.at("rows");
  EXPECT_EQ(failed->at("status"), "failed");
  const std::string why = failed->at("error");
  EXPECT_NE(why.find("the point light lies inside the mesh's bounding sphere"), std::string::npos)
      << why;
  EXPECT_FALSE(failed->contains("vs_physical")) << "a failed technique has no numbers, not zeros";
  EXPECT_TRUE(other->at("vs_physical").at("rel_rmse").is_number()) << *other;
  EXPECT_TRUE(other->at("vs_model").at("rel_rmse").is_number()) << *other;
  const std::string md = readText(kRoot / "out" / "leaderboard.md");
  EXPECT_NE(md.find("| " + kPointLightScene + " | pointcloud | **failed: lights[1]: the point light"),
            std::string::npos) << md;
  EXPECT_NE(readText(kRoot / "out" / "index.html").find("failed: lights[1]: the point light"),
            std::string::npos);
  for (const json& s : lb.at("summary")) {
    if (s.at("technique") == "pointcloud") {
      EXPECT_EQ(s.at("scenes"), 2u) << s;  // a-cube and c-cube-brighter only
      EXPECT_EQ(s.at("failed"), 1) << s;
    } else {
      EXPECT_EQ(s.at("scenes"), 3u) << s;
      EXPECT_EQ(s.at("failed"), 0) << s;
    }
  }

  // The scene's own report: the technique listed with its reason, the others complete.
  const fs::path dir = kRoot / "out" / kPointLightScene;
  const json report = readJson(dir / "report.json");
  ASSERT_EQ(report.at("techniques").size(), 2u);
  for (const json& t : report.at("techniques")) {
    if (t.at("name") == "pointcloud") {
      EXPECT_EQ(t.at("status"), "failed");
      EXPECT_EQ(t.at("error"), why);
      EXPECT_FALSE(t.contains("exr"));
    } else {
      EXPECT_EQ(t.at("status"), "done");
      EXPECT_TRUE(fs::is_regular_file(dir / t.at("exr").get<std::string>()));
    }
  }
  EXPECT_EQ(report.at("references").size(), 2u);
  std::set<std::string> tested;
  for (const json& m : report.at("metrics")) tested.insert(m.at("test").get<std::string>() + "/" +
                                                           m.at("reference").get<std::string>());
  EXPECT_EQ(tested, (std::set<std::string>{"empirical/model", "empirical/physical",
                                           "model/physical"}));
  const std::string html = readText(dir / "index.html");
  EXPECT_NE(html.find("1 of 2 techniques failed"), std::string::npos);
  EXPECT_NE(html.find("failed: lights[1]: the point light lies inside"), std::string::npos);
  EXPECT_FALSE(fs::exists(dir / "pointcloud.exr"));
  // The text summary names it too.
  EXPECT_NE(first_->output.find("pointcloud   failed: lights[1]"), std::string::npos) << first_->output;
}

TEST_F(CompareSuite, SingleCompareWithAFailedTechniqueWritesTheReportAndExitsOne) {
  const fs::path out = kRoot / "single";
  std::string args = "'";
  args += (kRoot / "suite" / (kPointLightScene + ".json")).string();
  args += "' --width 32 --height 24 --photons 20000 --samples 4000 --frames 1 --warmup 0 "
          "--threads 2 " + kTechniqueArg + " --cache '";
  args += (kRoot / "cache").string();
  args += "' --out '";
  args += out.string();
  args += "'";
  const CliRun r = run(args, "single");
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_TRUE(fs::is_regular_file(out / "index.html")) << r.output;
  EXPECT_TRUE(fs::is_regular_file(out / "empirical.exr")) << r.output;
  // The final line says what failed and where the rest is.
  std::string last = r.output.substr(0, r.output.find_last_not_of('\n') + 1);
  last = last.substr(last.find_last_of('\n') + 1);
  EXPECT_EQ(last, "translucent: error: compare: 1 of 2 techniques failed (pointcloud); the report "
                  "has the others: " + (out / "index.html").string()) << r.output;
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
  EXPECT_TRUE(seen.contains(kPointLightScene + "/empirical"));
  EXPECT_EQ(seen.size(), kGood.size() * kTechniques.size() + 1);

  // The summary: each technique over the scenes it ran on (failed runs are in no mean); the wins
  // add up to one per scene with numbers (or more on an exact tie).
  ASSERT_EQ(lb.at("summary").size(), kTechniques.size());
  int wins = 0;
  for (const json& s : lb.at("summary")) {
    wins += s.at("wins").get<int>();
    double sum = 0.0;
    int n = 0;
    for (const json& row : lb.at("rows"))
      if (!row.contains("error") && row.at("technique") == s.at("technique")) {
        sum += row.at("vs_physical").at("rel_rmse").get<double>();
        ++n;
      }
    EXPECT_EQ(s.at("scenes"), n) << s;
    EXPECT_NEAR(s.at("vs_physical_rel_rmse_mean").get<double>(), sum / n, 1e-12) << s;
  }
  EXPECT_GE(wins, static_cast<int>(kGood.size()) + 1);
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
  for (const std::string& s : kGood) {
    const json report = readJson(dir / s / "report.json");  // outlives the loop over its files
    for (const json& f : report.at("files"))
      EXPECT_TRUE(fs::is_regular_file(dir / s / f.get<std::string>())) << s << " " << f;
  }
  EXPECT_FALSE(fs::exists(dir / "b-broken" / "report.json"));
}

TEST_F(CompareSuite, RerunReplacesThePreviousSuiteAndUserFilesAreRefused) {
  ASSERT_TRUE(fs::exists(kRoot / "out" / "leaderboard.json")) << first_->output;
  // Rerun into the same folder (a previous suite): allowed, the references come from the cache.
  const CliRun again = run(suiteArgs(kRoot / "out"), "again");
  EXPECT_NE(again.output.find("physical reference: reused from the cache"), std::string::npos)
      << again.output;
  EXPECT_NE(again.output.find("2 of 5 scenes failed"), std::string::npos) << again.output;
  EXPECT_EQ(readJson(kRoot / "out" / "leaderboard.json").at("rows").size(), 8u);

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
