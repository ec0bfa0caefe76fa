// SPDX-License-Identifier: GPL-3.0-or-later
// Scene files (scene/scene.h): every key parses, the scene round-trips through toJson, bad input
// names the key, and meshes are normalised and placed as documented.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <numbers>
#include <optional>

#include <unistd.h>

#include <glm/geometric.hpp>

#include "translucent/io/image_io.h"
#include "translucent/io/json.h"
#include "translucent/scene/data_path.h"
#include "translucent/geometry/icosphere.h"
#include "translucent/geometry/point_cloud.h"
#include "translucent/geometry/ray_scene.h"
#include "translucent/scene/scene.h"

namespace translucent::scene {
namespace {

class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = std::filesystem::temp_directory_path() /
            (std::string("translucent-scene-") + info->name() + "-" + std::to_string(::getpid()));
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  std::filesystem::path write(const std::string& name, const std::string& text) const {
    std::ofstream(path_ / name, std::ios::binary) << text;
    return path_ / name;
  }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

const char* kFull = R"({
  "mesh": {"file": "box.obj", "normalize": false, "rotate": [10, 20, 30], "scale": 2.5,
           "translate": [1, 2, 3]},
  "material": {"sigma_a": [0.1, 0.2, 0.3], "sigma_s": 4, "g": 0.25, "eta": 1.4, "scale": 7,
               "model": "better-dipole"},
  "lights": [
    {"type": "directional", "direction": [0, 3, 4], "irradiance": 2, "color": [1, 0.5, 0.25]},
    {"type": "point", "position": [0, 0, 5], "intensity": 3},
    {"type": "beam", "origin": [0, 0, 9], "direction": [0, 0, -1], "radius": 0.1, "power": 4},
    {"type": "filtered_directional", "direction": [1, 1, 0], "irradiance": 5, "texture": "checker",
     "texture_size": 0.5},
    {"type": "environment", "file": "sky.exr", "intensity": 0.5, "rotate": 90, "occlusion": true}
  ],
  "camera": {"type": "pinhole", "position": [0, 1, 4], "look_at": [0, 0.5, 0], "up": [0, 1, 0],
             "fov": 30, "width": 64, "height": 48, "near": 0.5, "far": 20},
  "technique": {"name": "pointcloud", "points": 5000, "epsilon": 0.05, "specular": true,
                "criterion": "centroid"},
  "display": {"exposure": -1, "gamma": 2.0, "tonemap": "reinhard", "key": 0.18},
  "cone_angle": 4
})";

// kFull in `dir` with the files it names (parsing requires that they exist).
Scene loadFull(const TempDir& dir) {
  dir.write("box.obj", "");
  dir.write("sky.exr", "");
  return loadScene(dir.write("scene.json", kFull));
}

TEST(Scene, ParsesEveryKey) {
  TempDir dir;
  const Scene s = loadFull(dir);
  EXPECT_EQ(s.mesh_file, dir.path() / "box.obj");
  EXPECT_FALSE(s.mesh_normalize);
  EXPECT_FALSE(s.mesh_fill_holes);  // the default
  EXPECT_TRUE(s.data_names.empty());  // everything beside the scene file
  EXPECT_EQ(s.mesh_rotate, glm::dvec3(10, 20, 30));
  EXPECT_EQ(s.mesh_scale, 2.5);
  EXPECT_EQ(s.mesh_translate, glm::dvec3(1, 2, 3));
  EXPECT_TRUE(s.preset.empty());
  EXPECT_EQ(s.medium.sigma_a[2], 0.3);
  EXPECT_EQ(s.medium.sigma_s[1], 4.0);
  EXPECT_EQ(s.medium.g, 0.25);
  EXPECT_EQ(s.medium.eta, 1.4);
  EXPECT_EQ(s.medium.scale, 7.0);
  EXPECT_EQ(s.model, "better-dipole");
  ASSERT_EQ(s.lights.size(), 5u);
  const auto& d = std::get<reference::DirectionalLight>(s.lights[0].emitter);
  EXPECT_NEAR(d.direction.y, 0.6, 1e-15);  // normalised
  EXPECT_NEAR(d.direction.z, 0.8, 1e-15);
  EXPECT_EQ(s.lights[0].color[2], 0.25);
  EXPECT_EQ(std::get<reference::PointLight>(s.lights[1].emitter).intensity, 3.0);
  EXPECT_EQ(std::get<reference::BeamLight>(s.lights[2].emitter).radius, 0.1);
  const auto& f = std::get<FilteredDirectionalLight>(s.lights[3].emitter);
  EXPECT_EQ(f.texture, "checker");  // built-in: not resolved against the scene folder
  EXPECT_EQ(f.texture_size, 0.5);
  const auto& e = std::get<EnvironmentLight>(s.lights[4].emitter);
  EXPECT_EQ(e.file, dir.path() / "sky.exr");
  EXPECT_TRUE(e.occlusion);
  EXPECT_EQ(e.rotate, 90.0);
  EXPECT_EQ(s.camera.height, 48);
  EXPECT_EQ(s.clip_near, 0.5);
  EXPECT_EQ(s.clip_far, 20.0);
  EXPECT_EQ(s.technique, "pointcloud");
  EXPECT_EQ(std::get<double>(s.settings.at("points")), 5000.0);
  EXPECT_EQ(std::get<bool>(s.settings.at("specular")), true);
  EXPECT_EQ(std::get<std::string>(s.settings.at("criterion")), "centroid");
  EXPECT_EQ(s.exposure, -1.0);
  EXPECT_EQ(s.gamma, 2.0);
  EXPECT_EQ(s.tonemap, analysis::ToneOperator::Reinhard);
  EXPECT_EQ(s.tonemap_key, 0.18);
  EXPECT_EQ(s.cone_angle, 4.0);
}

TEST(Scene, RoundTripsThroughJson) {
  TempDir dir;
  const Scene s = loadFull(dir);
  const std::string once = toJson(s);
  const Scene again = parseScene(once, "", "round trip");  // paths are stored resolved
  EXPECT_EQ(toJson(again), once);
  // Every field survives, not only the text: spot checks of each kind of value.
  EXPECT_EQ(again.mesh_file, s.mesh_file);
  EXPECT_EQ(again.mesh_rotate, s.mesh_rotate);
  EXPECT_EQ(again.medium.sigma_a, s.medium.sigma_a);
  EXPECT_EQ(again.lights.size(), s.lights.size());
  EXPECT_EQ(std::get<EnvironmentLight>(again.lights[4].emitter).file,
            std::get<EnvironmentLight>(s.lights[4].emitter).file);
  EXPECT_EQ(again.settings, s.settings);
  EXPECT_EQ(again.clip_far, s.clip_far);
  // A preset scene and the built-in default scene round-trip too (via a file).
  for (const Scene& original : {defaultScene(), loadScene(std::string(TRANSLUCENT_DATA_DIR) + "/scenes/cube.json")}) {
    const auto file = dir.path() / "saved.json";
    saveScene(original, file);
    EXPECT_EQ(toJson(loadScene(file)), toJson(original));
  }
}

// Parsed against a folder holding m.obj, the mesh the scenes below name.
std::string parseError(const std::string& json) {
  static const std::filesystem::path dir = [] {
    const auto d = std::filesystem::temp_directory_path() /
                   ("translucent-scene-errors-" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    std::ofstream(d / "m.obj") << "";
    return d;
  }();
  try {
    (void)parseScene(json, dir, "scene");
  } catch (const ParameterError& e) {
    return e.what();
  }
  return "no error";
}

TEST(Scene, RejectsBadInputNamingTheKey) {
  const std::string mesh = R"("mesh": {"file": "m.obj"})";
  const std::string mat = R"("material": {"preset": "Marble"})";
  const std::string cam = R"("camera": {"position": [0, 0, 5]})";
  const std::string light = R"("lights": [{"type": "directional", "direction": [0, 0, 1]}])";
  auto scene = [&](const std::string& m, const std::string& ma, const std::string& l,
                   const std::string& c, const std::string& extra = "") {
    return "{" + m + "," + ma + "," + l + "," + c + extra + "}";
  };
  EXPECT_EQ(parseError(scene(mesh, mat, light, cam)), "no error");  // the base scene is valid
  EXPECT_NE(parseError(scene(R"("mesh": {"file": "m.obj", "scale": -1})", mat, light, cam)).find("mesh.scale"),
            std::string::npos);
  EXPECT_NE(parseError(scene(R"("mesh": {"file": "m.obj", "fill_holes": 1})", mat, light, cam))
                .find("mesh.fill_holes: number 1: expected true or false"),
            std::string::npos);
  // mesh.wrap (geometry/alpha_wrap.h): a bool or {alpha, offset} in [1e-4, 1], not with fill_holes.
  EXPECT_EQ(parseError(scene(R"("mesh": {"file": "m.obj", "wrap": {"alpha": 0.01}})", mat, light, cam)),
            "no error");
  EXPECT_NE(parseError(scene(R"("mesh": {"file": "m.obj", "wrap": {"alpha": 0}})", mat, light, cam))
                .find("mesh.wrap.alpha: 0: expected a fraction of the bounding-box diagonal in [1e-4, 1]"),
            std::string::npos);
  EXPECT_NE(parseError(scene(R"("mesh": {"file": "m.obj", "wrap": {"ofset": 0.1}})", mat, light, cam))
                .find("ofset"),
            std::string::npos);
  EXPECT_NE(parseError(scene(R"("mesh": {"file": "m.obj", "wrap": "yes"})", mat, light, cam))
                .find("mesh.wrap: string \"yes\": expected true, false or an object"),
            std::string::npos);
  EXPECT_NE(parseError(scene(R"("mesh": {"file": "m.obj", "wrap": true, "fill_holes": true})", mat, light, cam))
                .find("mesh.wrap: given with mesh.fill_holes"),
            std::string::npos);
  EXPECT_NE(parseError(scene(mesh, R"("material": {"preset": "Jelly"})", light, cam)).find("material.preset"),
            std::string::npos);
  EXPECT_NE(parseError(scene(mesh, R"("material": {"preset": "Marble", "eta": -2})", light, cam))
                .find("material"),
            std::string::npos);
  EXPECT_NE(parseError(scene(mesh, mat, R"("lights": [{"type": "environment"}])", cam)).find("lights[0].file"),
            std::string::npos);
  EXPECT_NE(parseError(scene(mesh, mat, R"("lights": [{"type": "filtered_directional", "direction": [0,0,1], "texture": "checker", "texture_size": 0}])", cam))
                .find("lights[0].texture_size"),
            std::string::npos);
  EXPECT_NE(parseError(scene(mesh, mat, R"("lights": [{"type": "point", "position": [0,0,1], "color": [1,-1,1]}])", cam))
                .find("lights[0].color"),
            std::string::npos);
  EXPECT_NE(parseError(scene(mesh, mat, light, R"("camera": {"position": [0, 0, 5], "near": 2, "far": 1})"))
                .find("near"),
            std::string::npos);
  EXPECT_NE(parseError(scene(mesh, mat, light, R"("camera": {"position": [0, 0, 0]})")).find("look_at"),
            std::string::npos);
  EXPECT_NE(parseError(scene(mesh, mat, light, cam, R"(, "technique": {"points": [1, 2]})"))
                .find("technique.points"),
            std::string::npos);
  EXPECT_NE(parseError(scene(mesh, mat, light, cam, R"(, "display": {"gamma": 0})")).find("display.gamma"),
            std::string::npos);
  EXPECT_NE(parseError(scene(mesh, mat, light, cam, R"(, "display": {"tonemap": "aces"})"))
                .find("display.tonemap"),
            std::string::npos);
  EXPECT_NE(parseError(scene(mesh, mat, light, cam, R"(, "display": {"key": 0})")).find("display.key"),
            std::string::npos);
  EXPECT_NE(parseError(scene(mesh, mat, light, cam, R"(, "displya": {})")).find("valid keys"),
            std::string::npos);
  EXPECT_NE(parseError("{ not json").find("not valid JSON"), std::string::npos);
  // Numbers too large for a double are rejected by the JSON reader.
  EXPECT_NE(parseError(scene(R"("mesh": {"file": "m.obj", "scale": 1e999})", mat, light, cam)).find("not valid JSON"),
            std::string::npos);
  // Integers are range-checked before narrowing (4294967360 used to read as 64), and finite
  // numbers too large for the float pipeline are refused (1e308 irradiance gave inf pixels).
  EXPECT_NE(parseError(scene(mesh, mat, light, R"("camera": {"position": [0, 0, 5], "width": 4294967360})"))
                .find("camera.width: is 4294967360: expected a whole number in [1, 16384]"),
            std::string::npos);
  EXPECT_NE(parseError(scene(mesh, mat, light, R"("camera": {"position": [0, 0, 5], "height": -3})"))
                .find("camera.height: is -3: expected a whole number in [1, 16384]"),
            std::string::npos);
  EXPECT_NE(parseError(scene(mesh, mat, R"("lights": [{"type": "directional", "direction": [0,0,1], "irradiance": 1e308}])", cam))
                .find("lights[0].irradiance: is 1e+308: expected a finite number of magnitude at most 1e+15"),
            std::string::npos);
}

TEST(Scene, PlacesMeshesAsDocumented) {
  // A box 4 x 2 x 1 centred at (10, 0, 0): normalised to 1 x 0.5 x 0.25 about the origin, then
  // rotated 90 degrees about z (x -> y), scaled by 3 and moved by (0, 0, 1).
  geometry::TriangleMesh box = geometry::makeBox({8.0, -1.0, -0.5}, {12.0, 1.0, 0.5});
  Scene s;
  s.mesh_rotate = {0.0, 0.0, 90.0};
  s.mesh_scale = 3.0;
  s.mesh_translate = {0.0, 0.0, 1.0};
  placeMesh(s, box);
  const geometry::Bounds b = box.bounds();
  EXPECT_NEAR(b.lower.x, -0.75, 1e-12);
  EXPECT_NEAR(b.upper.x, 0.75, 1e-12);
  EXPECT_NEAR(b.lower.y, -1.5, 1e-12);
  EXPECT_NEAR(b.upper.y, 1.5, 1e-12);
  EXPECT_NEAR(b.lower.z, 1.0 - 0.375, 1e-12);
  EXPECT_NEAR(b.upper.z, 1.0 + 0.375, 1e-12);
  EXPECT_NEAR(box.area(), 9.0 * 2.0 * (0.5 + 0.25 + 0.125), 1e-12);
  // Without normalisation only the rotation, scale and translation apply.
  geometry::TriangleMesh raw = geometry::makeBox({0.0, 0.0, 0.0}, {2.0, 1.0, 1.0});
  Scene t;
  t.mesh_normalize = false;
  t.mesh_scale = 2.0;
  placeMesh(t, raw);
  EXPECT_NEAR(raw.bounds().upper.x, 4.0, 1e-12);
}

TEST(Scene, DefaultSceneLoadsTheBunny) {
  const Scene s = defaultScene();
  EXPECT_EQ(s.mesh_file, kDefaultBunny);
  EXPECT_EQ(s.preset, "Marble");
  EXPECT_NO_THROW(s.medium.validate());
  EXPECT_NO_THROW(s.camera.validate());
  ASSERT_FALSE(s.lights.empty());
  // The key light comes from behind (away from the camera) and above.
  const auto& key = std::get<reference::DirectionalLight>(s.lights[0].emitter);
  EXPECT_LT(glm::dot(key.direction, s.camera.position - s.camera.look_at), 0.0);
  EXPECT_GT(key.direction.y, 0.0);
  if (std::filesystem::exists(kDefaultBunny)) {
    const geometry::TriangleMesh m = loadSceneMesh(s);
    const geometry::Bounds b = m.bounds();
    const glm::dvec3 e = b.upper - b.lower;
    EXPECT_NEAR(std::max({e.x, e.y, e.z}), 1.0, 1e-12);  // normalised (scale 1)
    EXPECT_NEAR(glm::length(b.center()), 0.0, 1e-12);
    EXPECT_EQ(m.openEdgeCount(), 0u);
  }
}

TEST(Scene, ReferenceLightsLoadEnvironmentMapsAndRejectFilteredLights) {
  // An environment light reaches the references with its map loaded and one sampler per channel
  // that has radiance; a missing map is named; a filtered light is refused by type.
  TempDir dir;
  Scene s = defaultScene();
  EXPECT_EQ(referenceLights(s).size(), s.lights.size());
  std::vector<float> sky(8 * 4 * 3, 0.0f);
  for (size_t i = 0; i < sky.size(); i += 3) sky[i] = 2.0f, sky[i + 1] = 1.0f;  // no blue
  analysis::writeExr((dir.path() / "sky.exr").string(), 8, 4, sky);
  Light env;
  env.emitter = EnvironmentLight{dir.path() / "sky.exr", 3.0, 45.0, false};
  s.lights.push_back(env);
  const auto lights = referenceLights(s);
  ASSERT_EQ(lights.size(), s.lights.size());
  const auto* e = std::get_if<reference::EnvironmentLight>(&lights.back().emitter);
  ASSERT_NE(e, nullptr);
  EXPECT_EQ(e->map->width, 8);
  EXPECT_EQ(e->intensity, 3.0);
  EXPECT_EQ(e->rotate, 45.0);
  ASSERT_TRUE(e->samplers[0] && e->samplers[1]);
  EXPECT_FALSE(e->samplers[2]);
  EXPECT_NEAR(e->samplers[0]->integral(), 2.0 * 4.0 * std::numbers::pi, 1e-5);

  s.lights.back().emitter = EnvironmentLight{dir.path() / "missing.exr", 1.0, 0.0, false};
  try {
    (void)referenceLights(s);
    FAIL() << "expected an error";
  } catch (const ParameterError& err) {
    EXPECT_NE(std::string(err.what()).find("missing.exr"), std::string::npos) << err.what();
  }
  s.lights.back().emitter = FilteredDirectionalLight{};
  try {
    (void)referenceLights(s);
    FAIL() << "expected an error";
  } catch (const ParameterError& err) {
    EXPECT_NE(std::string(err.what()).find("filtered_directional"), std::string::npos) << err.what();
  }
}

TEST(Scene, MissingFileIsNamed) {
  try {
    (void)loadScene("/nonexistent/scene.json");
    FAIL() << "expected an error";
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/scene.json"), std::string::npos);
  }
}

// ---- Data search path (scene/data_path.h) ------------------------------------------------

// Sets (or, with nullopt, removes) an environment variable for one test and restores it (or its
// absence) afterwards.
class EnvVar {
 public:
  EnvVar(const char* name, const std::optional<std::string>& value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    if (value) ::setenv(name, value->c_str(), 1);
    else ::unsetenv(name);
  }
  ~EnvVar() {
    if (old_) ::setenv(name_, old_->c_str(), 1);
    else ::unsetenv(name_);
  }
  EnvVar(const EnvVar&) = delete;
  EnvVar& operator=(const EnvVar&) = delete;

 private:
  const char* name_;
  std::optional<std::string> old_;
};

std::string meshScene(const std::string& file, const std::string& extra = "") {
  return R"({"mesh": {"file": ")" + file + R"(")" + extra + R"(}, "material": {"preset": "Marble"},
    "lights": [{"type": "directional", "direction": [0, 0, 1]}],
    "camera": {"position": [0, 0, 5]}})";
}

TEST(SceneDataPath, TheSceneFolderFirstThenEachDataFolderInOrderThenTheXdgCache) {
  TempDir dir;
  const auto scenes = dir.path() / "scenes", a = dir.path() / "a", b = dir.path() / "b",
             xdg = dir.path() / "xdg";
  for (const auto& d : {scenes, a / "sub", b / "sub", xdg / "translucent" / "data" / "sub"})
    std::filesystem::create_directories(d);
  std::ofstream(b / "sub" / "m.obj") << "";
  std::ofstream(xdg / "translucent" / "data" / "sub" / "m.obj") << "";
  std::ofstream(xdg / "translucent" / "data" / "sub" / "only-xdg.obj") << "";
  // An empty entry (the "::") is skipped, not taken as the working directory.
  const EnvVar data("TRANSLUCENT_DATA", a.string() + "::" + b.string());
  const EnvVar cache("XDG_CACHE_HOME", xdg.string());
  ASSERT_EQ(dataSearchPath(), (std::vector<std::filesystem::path>{
                                  a, b, xdg / "translucent" / "data"}));

  std::ofstream(scenes / "s.json") << meshScene("sub/m.obj");
  // Not beside the scene, not in a: b, the first data folder that has it.
  Scene s = loadScene(scenes / "s.json");
  EXPECT_EQ(s.mesh_file, b / "sub" / "m.obj");
  std::ofstream(a / "sub" / "m.obj") << "";
  EXPECT_EQ(loadScene(scenes / "s.json").mesh_file, a / "sub" / "m.obj");
  // Beside the scene file wins over every data folder.
  std::filesystem::create_directories(scenes / "sub");
  std::ofstream(scenes / "sub" / "m.obj") << "";
  s = loadScene(scenes / "s.json");
  EXPECT_EQ(s.mesh_file, scenes / "sub" / "m.obj");
  EXPECT_TRUE(s.data_names.empty());
  // The XDG cache folder comes last.
  std::ofstream(scenes / "x.json") << meshScene("sub/only-xdg.obj");
  EXPECT_EQ(loadScene(scenes / "x.json").mesh_file,
            xdg / "translucent" / "data" / "sub" / "only-xdg.obj");
}

TEST(SceneDataPath, WithoutXdgCacheHomeTheDataFolderIsUnderHome) {
  TempDir dir;
  const EnvVar home("HOME", dir.path().string());
  const EnvVar data("TRANSLUCENT_DATA", std::nullopt);
  const EnvVar xdg("XDG_CACHE_HOME", std::nullopt);
  EXPECT_EQ(dataSearchPath(),
            std::vector<std::filesystem::path>{dir.path() / ".cache" / "translucent" / "data"});
}

TEST(SceneDataPath, FilesFromTheDataFoldersAreWrittenBackByTheirGivenNames) {
  TempDir dir;
  const auto data = dir.path() / "data";
  std::filesystem::create_directories(data / "cgal");
  std::ofstream(data / "cgal" / "thing.off") << "";
  std::ofstream(data / "stained.png") << "";
  std::ofstream(data / "sky.exr") << "";
  const EnvVar env("TRANSLUCENT_DATA", data.string());
  const std::string text = R"({"mesh": {"file": "cgal/thing.off", "fill_holes": true},
    "material": {"preset": "Marble"},
    "lights": [{"type": "filtered_directional", "direction": [0, 0, 1], "texture": "stained.png"},
               {"type": "environment", "file": "sky.exr"}],
    "camera": {"position": [0, 0, 5]}})";
  const Scene s = parseScene(text, dir.path() / "elsewhere", "scene");
  EXPECT_EQ(s.mesh_file, data / "cgal" / "thing.off");
  EXPECT_EQ(std::get<FilteredDirectionalLight>(s.lights[0].emitter).texture, data / "stained.png");
  EXPECT_EQ(std::get<EnvironmentLight>(s.lights[1].emitter).file, data / "sky.exr");
  const std::string once = toJson(s);
  EXPECT_NE(once.find(R"("file": "cgal/thing.off")"), std::string::npos) << once;
  EXPECT_NE(once.find(R"("texture": "stained.png")"), std::string::npos) << once;
  EXPECT_NE(once.find(R"("file": "sky.exr")"), std::string::npos) << once;
  EXPECT_EQ(once.find(data.string()), std::string::npos) << "no machine-specific path: " << once;
  // Read back from any folder it is the same scene (the names are found on the path again).
  const Scene again = parseScene(once, dir.path() / "another", "round trip");
  EXPECT_EQ(again.mesh_file, s.mesh_file);
  EXPECT_TRUE(again.mesh_fill_holes);
  EXPECT_EQ(toJson(again), once);
  // A path changed after parsing is written as it is, not by the old name.
  Scene moved = s;
  moved.mesh_file = dir.path() / "other.obj";
  EXPECT_NE(toJson(moved).find((dir.path() / "other.obj").string()), std::string::npos);
}

TEST(SceneDataPath, AFileThatIsNowhereNamesTheSceneTheKeyAndEveryPlaceTried) {
  TempDir dir;
  const auto a = dir.path() / "a", b = dir.path() / "b", xdg = dir.path() / "xdg";
  const EnvVar data("TRANSLUCENT_DATA", a.string() + ":" + b.string());
  const EnvVar cache("XDG_CACHE_HOME", xdg.string());
  auto error = [&](const std::string& text) -> std::string {
    try {
      (void)loadScene(dir.write("s.json", text));
    } catch (const ParameterError& e) {
      return e.what();
    }
    return "no error";
  };
  const std::string m = error(meshScene("cgal/head.off"));
  for (const std::string& part :
       {(dir.path() / "s.json").string(), std::string("mesh.file"), std::string("cgal/head.off"),
        (dir.path() / "cgal" / "head.off").string(), (a / "cgal" / "head.off").string(),
        (b / "cgal" / "head.off").string(), (xdg / "translucent" / "data" / "cgal" / "head.off").string(),
        std::string("scripts/install-test-data")})
    EXPECT_NE(m.find(part), std::string::npos) << part << " not in: " << m;
  // Not a cgal/ name: no hint about the script.
  EXPECT_EQ(error(meshScene("mine.obj")).find("install-test-data"), std::string::npos);
  // An absolute name is only looked for where it says.
  const std::string abs = error(meshScene((dir.path() / "nowhere.obj").string()));
  EXPECT_NE(abs.find((dir.path() / "nowhere.obj").string()), std::string::npos) << abs;
  EXPECT_EQ(abs.find((a / "nowhere.obj").string()), std::string::npos) << abs;
  // Lights' files are found the same way and named by their key.
  dir.write("m.obj", "");
  const std::string env = error(R"({"mesh": {"file": "m.obj"}, "material": {"preset": "Marble"},
    "lights": [{"type": "directional", "direction": [0, 0, 1]},
               {"type": "environment", "file": "sky.exr"}],
    "camera": {"position": [0, 0, 5]}})");
  EXPECT_NE(env.find("lights[1].file: file 'sky.exr' not found"), std::string::npos) << env;
  const std::string tex = error(R"({"mesh": {"file": "m.obj"}, "material": {"preset": "Marble"},
    "lights": [{"type": "filtered_directional", "direction": [0, 0, 1], "texture": "glass.png"}],
    "camera": {"position": [0, 0, 5]}})");
  EXPECT_NE(tex.find("lights[0].texture: file 'glass.png' not found"), std::string::npos) << tex;
}

// ---- mesh.fill_holes on CGAL's open head ---------------------------------------------------

TEST(SceneFillHoles, ClosesTheHeadAtLoadTimeAndIsPartOfTheMeshKey) {
  TempDir dir;
  const std::string text = meshScene("cgal/head.off", R"(, "fill_holes": true)");
  Scene filled;
  try {
    filled = loadScene(dir.write("head.json", text));
  } catch (const ParameterError& e) {
    FAIL() << e.what();  // names scripts/install-test-data when the mesh is missing
  }
  Scene open = filled;
  open.mesh_fill_holes = false;
  EXPECT_NE(meshKey(filled), meshKey(open));  // techniques reload, caches miss

  geometry::HoleFillStats st;
  const geometry::TriangleMesh closed = loadSceneMesh(filled, &st);
  EXPECT_EQ(st.holes, 3u);  // head.off: the neck and two small openings
  EXPECT_EQ(st.filled(), 3u);
  EXPECT_EQ(closed.openEdgeCount(), 0u);
  EXPECT_NO_THROW(closed.requireClosed("head"));
  // Filled before the placement: still normalised to a longest axis of 1 about the origin.
  const geometry::Bounds b = closed.bounds();
  const glm::dvec3 e = b.upper - b.lower;
  EXPECT_NEAR(std::max({e.x, e.y, e.z}), 1.0, 1e-12);
  EXPECT_NEAR(glm::length(b.center()), 0.0, 1e-12);
  EXPECT_NE(describeHoleFill(st).find("3 holes filled"), std::string::npos) << describeHoleFill(st);

  EXPECT_EQ(loadSceneMesh(open).openEdgeCount(), 58u);  // as distributed
}

// ---- The standing compare suite (data/compare) ---------------------------------------------

// Every scene of the suite parses and gives the closed mesh both references require (the head
// scenes through mesh.fill_holes; their mesh comes from the data search path, so this fails with
// the scene's own message naming scripts/install-test-data when it is not installed).
TEST(StandingSuite, EverySceneParsesAndItsMeshIsClosed) {
  const std::filesystem::path dir = std::filesystem::path(TRANSLUCENT_DATA_DIR) / "compare";
  int scenes = 0, heads = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    if (e.path().extension() != ".json") continue;
    ++scenes;
    SCOPED_TRACE(e.path().string());
    try {
      const Scene s = loadScene(e.path());
      const geometry::TriangleMesh m = loadSceneMesh(s);
      EXPECT_NO_THROW(m.requireClosed(e.path().string()));
      if (e.path().filename().string().starts_with("head-")) {
        ++heads;
        EXPECT_TRUE(s.mesh_fill_holes);
        EXPECT_NE(toJson(s).find(R"("file": "cgal/head.off")"), std::string::npos);
      }
    } catch (const std::exception& x) {
      ADD_FAILURE() << x.what();
    }
  }
  EXPECT_EQ(scenes, 10);
  EXPECT_EQ(heads, 6);  // 10 and 40 mm x skim milk, marble, skin
}

// ---- data/scenes ---------------------------------------------------------------------------

// Every scene of data/scenes parses, round-trips through toJson, loads its mesh and builds its
// material (the heterogeneous ones included: layers from the surface build their distance
// structure over the placed head). The dragon comes from npm (scripts/install-test-data, which
// ./test runs).
TEST(DataScenes, EverySceneParsesRoundTripsAndBuildsItsMaterial) {
  const std::filesystem::path dir = std::filesystem::path(TRANSLUCENT_DATA_DIR) / "scenes";
  int scenes = 0, heterogeneous = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    if (e.path().extension() != ".json") continue;
    SCOPED_TRACE(e.path().string());
    Scene s;
    try {
      s = loadScene(e.path());
    } catch (const ParameterError& x) {
      ADD_FAILURE() << x.what();
      continue;
    }
    ++scenes;
    try {
      const std::string once = toJson(s);
      EXPECT_EQ(toJson(parseScene(once, "", "round trip")), once);
      const geometry::TriangleMesh mesh = loadSceneMesh(s);
      if (s.mesh_fill_holes) {
        EXPECT_NO_THROW(mesh.requireClosed(e.path().string()));
      }
      const material::Material m = sceneMaterial(s, mesh);
      EXPECT_EQ(m.heterogeneous(), !s.material.homogeneous());
      if (m.heterogeneous()) {
        ++heterogeneous;
        // The material answers at a surface point (the volume's average below it, or the map).
        const glm::dvec3 n = mesh.normals.empty() ? glm::dvec3(0, 0, 1) : glm::normalize(mesh.normals[0]);
        EXPECT_NO_THROW(Medium(m.surfaceMedium(mesh.positions[0], n, {0.5, 0.5})
                                   .medium(s.medium.eta, s.medium.scale)).validate());
      }
    } catch (const std::exception& x) {
      ADD_FAILURE() << x.what();
    }
  }
  EXPECT_GE(scenes, 7);
  EXPECT_GE(heterogeneous, 4);  // veins, chessboard, layered head, wax dragon
}

}  // namespace
}  // namespace translucent::scene

namespace translucent::scene {
namespace {

// requireOutsideMesh (issue 15): a camera, point light or beam origin inside the closed mesh is
// an error naming the key; outside (also inside the bounding box, between the box's corner and
// the sphere) it is not; an open mesh has no inside and is not checked.
TEST(Scene, CameraAndLightsInsideTheMeshAreRefused) {
  const geometry::TriangleMesh sphere = geometry::makeIcosphere(3, 1.0);
  Scene s;
  s.mesh_file = "sphere.obj";
  s.camera.position = {0.0, 0.0, 5.0};
  s.lights = {Light{reference::PointLight{{0.0, 3.0, 0.0}, 1.0}, {1.0, 1.0, 1.0}},
              Light{reference::BeamLight{{0.0, 0.0, 4.0}, {0.0, 0.0, -1.0}, 0.0, 1.0}, {1.0, 1.0, 1.0}}};
  EXPECT_NO_THROW(requireOutsideMesh(s, sphere));
  s.camera.position = {0.9, 0.9, 0.9};  // in the bounding box, outside the sphere
  EXPECT_NO_THROW(requireOutsideMesh(s, sphere));

  auto message = [&](const Scene& scene) {
    try {
      requireOutsideMesh(scene, sphere);
    } catch (const ParameterError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  Scene inside = s;
  inside.camera.position = {0.1, -0.2, 0.3};
  EXPECT_NE(message(inside).find("camera.position [0.1, -0.2, 0.3] is inside the mesh 'sphere.obj'"),
            std::string::npos) << message(inside);
  inside = s;
  std::get<reference::PointLight>(inside.lights[0].emitter).position = {0.0, 0.5, 0.0};
  EXPECT_NE(message(inside).find("lights[0].position"), std::string::npos) << message(inside);
  inside = s;
  std::get<reference::BeamLight>(inside.lights[1].emitter).origin = {0.0, 0.0, 0.0};
  EXPECT_NE(message(inside).find("lights[1].origin"), std::string::npos) << message(inside);

  // Open: one triangle fewer; the same camera position is not judged.
  geometry::TriangleMesh open = sphere;
  open.triangles.pop_back();
  inside = s;
  inside.camera.position = {0.1, -0.2, 0.3};
  EXPECT_NO_THROW(requireOutsideMesh(inside, open));
}

// The parity test agrees with the analytic inside of a sphere at random points away from its
// surface (a polyhedron within 1% of the radius: points within 2% are skipped).
TEST(Scene, InsideClosedMeshMatchesTheSphere) {
  const geometry::TriangleMesh sphere = geometry::makeIcosphere(3, 1.0);
  const geometry::RayScene rays(sphere, "sphere");
  uint64_t state = 12345;
  auto next = [&] {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<double>(state >> 11) * 0x1.0p-53 * 3.0 - 1.5;
  };
  int checked = 0;
  for (int i = 0; i < 2000; ++i) {
    const glm::dvec3 p{next(), next(), next()};
    const double r = glm::length(p);
    if (std::abs(r - 1.0) < 0.02) continue;
    EXPECT_EQ(geometry::insideClosedMesh(rays, p), r < 1.0) << p.x << " " << p.y << " " << p.z;
    ++checked;
  }
  EXPECT_GT(checked, 1800);
}

}  // namespace
}  // namespace translucent::scene

namespace translucent::scene {
namespace {

// mesh.deform (geometry/deform.h): parsed as one object or an array, every key checked, written
// back, applied by loadSceneMesh after the placement at the scene's time, part of meshKey (not of
// restMeshKey), and carried by the material frame so that materials follow the surface.
const char* kDeformed = R"({
  "mesh": {"file": "/usr/share/glmark2/models/bunny.obj", "rotate": [0, 30, 0], "scale": 1.5,
           "deform": [{"type": "twist", "amount": 90, "period": 2},
                      {"type": "bend", "amount": 40, "origin": [0, -0.2, 0], "axis": [0, 1, 0],
                       "direction": [0, 0, 1]},
                      {"type": "wave", "amount": 0.02, "period": 0.5, "wavelength": 0.25,
                       "axis": [1, 0, 0], "direction": [0, 1, 0]}]},
  "time": 0.3,
  "material": {"preset": "Marble"},
  "lights": [{"type": "directional", "direction": [0, 0, 1]}],
  "camera": {"position": [0, 0, 5]}
})";

TEST(SceneDeform, ParsesRoundTripsAndEntersTheMeshKey) {
  const Scene s = parseScene(kDeformed, "", "deformed");
  ASSERT_EQ(s.mesh_deform.size(), 3u);
  EXPECT_EQ(s.mesh_deform[0].type, geometry::Deformation::Type::Twist);
  EXPECT_EQ(s.mesh_deform[1].direction, glm::dvec3(0, 0, 1));
  EXPECT_EQ(s.mesh_deform[2].wavelength, 0.25);
  EXPECT_EQ(s.time, 0.3);
  const std::string once = toJson(s);
  const Scene again = parseScene(once, "", "round trip");
  EXPECT_EQ(toJson(again), once);
  EXPECT_EQ(again.mesh_deform, s.mesh_deform);
  EXPECT_EQ(again.time, s.time);
  // One object is a chain of one.
  const Scene one = parseScene(R"({"mesh": {"file": "/usr/share/glmark2/models/bunny.obj",
      "deform": {"type": "twist", "amount": 10}}, "material": {"preset": "Marble"},
      "lights": [{"type": "directional", "direction": [0, 0, 1]}], "camera": {"position": [0, 0, 5]}})",
                               "", "one");
  ASSERT_EQ(one.mesh_deform.size(), 1u);
  EXPECT_EQ(one.mesh_deform[0].amount, 10.0);
  // Keys: the time and the deformation enter meshKey, not restMeshKey.
  Scene later = s;
  later.time = 0.4;
  EXPECT_NE(meshKey(later), meshKey(s));
  EXPECT_EQ(restMeshKey(later), restMeshKey(s));
  Scene plain = s;
  plain.mesh_deform.clear();
  EXPECT_EQ(meshKey(plain), restMeshKey(s));
  // At time 0 every periodic deformation is the identity, but the bend (period 0) is not.
  Scene atZero = s;
  atZero.time = 0.0;
  EXPECT_NE(meshKey(atZero), restMeshKey(s));
  atZero.mesh_deform.erase(atZero.mesh_deform.begin() + 1);
  EXPECT_EQ(meshKey(atZero), restMeshKey(s));
}

TEST(SceneDeform, BadDeformationsNameTheKey) {
  auto scene = [](const std::string& deform) {
    return R"({"mesh": {"file": "m.obj", "deform": )" + deform +
           R"(}, "material": {"preset": "Marble"}, "lights": [{"type": "directional", "direction": [0, 0, 1]}], "camera": {"position": [0, 0, 5]}})";
  };
  auto has = [](const std::string& error, const std::string& text) {
    return error.find(text) != std::string::npos;
  };
  EXPECT_EQ(parseError(scene(R"([{"type": "wave", "amount": 0.1}])")), "no error");
  EXPECT_PRED2(has, parseError(scene(R"({"type": "squash"})")),
               "mesh.deform.type: 'squash': expected twist, bend or wave");
  EXPECT_PRED2(has, parseError(scene(R"([{"amount": 1}])")), "mesh.deform[0].type: required");
  EXPECT_PRED2(has, parseError(scene(R"([{"type": "twist"}, {"type": "twist", "wavelength": 1}])")),
               "mesh.deform[1].wavelength: unknown key");
  EXPECT_PRED2(has, parseError(scene(R"({"type": "twist", "direction": [1, 0, 0]})")),
               "mesh.deform.direction: unknown key");
  EXPECT_PRED2(has, parseError(scene(R"({"type": "bend", "period": -1})")),
               "mesh.deform.period: is -1: expected 0 (constant) or a period > 0");
  EXPECT_PRED2(has, parseError(scene(R"({"type": "bend", "axis": [0, 0, 0]})")),
               "mesh.deform.axis");
  EXPECT_PRED2(has, parseError(scene(R"({"type": "bend", "axis": [1, 1, 0]})")),
               "mesh.deform.direction: [1, 0, 0] is not perpendicular");
  EXPECT_PRED2(has, parseError(scene(R"({"type": "wave", "wavelength": 0})")),
               "mesh.deform.wavelength: is 0: expected a finite value > 0");
  EXPECT_PRED2(has, parseError(scene(R"({"type": "wave", "amount": "big"})")),
               "mesh.deform.amount: string \"big\": expected a number");
  EXPECT_PRED2(has, parseError(scene("3")), "mesh.deform: number 3: expected a deformation object");
  EXPECT_PRED2(has, parseError(scene(R"([{"type": "twist"}, {"type": "twist"}, {"type": "twist"},
      {"type": "twist"}, {"type": "twist"}, {"type": "twist"}, {"type": "twist"}, {"type": "twist"},
      {"type": "twist"}])")), "mesh.deform: 9 deformations: expected at most 8");
}

TEST(SceneDeform, TheLoadedMeshIsThePlacedMeshDeformedAtTheScenesTime) {
  // What the references (pathtrace mesh, integrate mesh, compare) load: loadSceneMesh.
  Scene s = parseScene(kDeformed, "", "deformed");
  const geometry::TriangleMesh rest = loadRestMesh(s);
  Scene undeformed = s;
  undeformed.mesh_deform.clear();
  EXPECT_EQ(rest.positions, loadSceneMesh(undeformed).positions);  // the placement alone
  geometry::TriangleMesh expected = rest;
  geometry::deformMesh(s.mesh_deform, s.time, expected);
  const geometry::TriangleMesh mesh = loadSceneMesh(s);
  EXPECT_EQ(mesh.positions, expected.positions);
  EXPECT_EQ(mesh.normals, expected.normals);
  EXPECT_EQ(mesh.triangles, rest.triangles);
  // It moved (the bend alone moves the ears by several hundredths).
  double moved = 0.0;
  for (size_t i = 0; i < mesh.positions.size(); ++i)
    moved = std::max(moved, glm::length(mesh.positions[i] - rest.positions[i]));
  EXPECT_GT(moved, 0.02);
  // Another time, another mesh.
  s.time = 0.8;
  EXPECT_NE(loadSceneMesh(s).positions, mesh.positions);
}

TEST(SceneDeform, TheMaterialFrameMapsTheDeformedSurfaceToTheRestPose) {
  const Scene s = parseScene(kDeformed, "", "deformed");
  const geometry::TriangleMesh rest = loadRestMesh(s);
  const geometry::TriangleMesh mesh = loadSceneMesh(s);
  const material::Material m = sceneMaterial(s, mesh);
  Scene undeformed = s;
  undeformed.mesh_deform.clear();
  const material::Material r = sceneMaterial(undeformed, rest);
  EXPECT_TRUE(m.frame.deformed());
  EXPECT_FALSE(r.frame.deformed());
  for (size_t i = 0; i < mesh.positions.size(); i += 997) {
    EXPECT_NEAR(glm::length(m.frame.toMaterial(mesh.positions[i]) - r.frame.toMaterial(rest.positions[i])),
                0.0, 1e-9);
    EXPECT_NEAR(glm::length(m.frame.toScene(r.frame.toMaterial(rest.positions[i])) - mesh.positions[i]),
                0.0, 1e-9);
  }
}

}  // namespace
}  // namespace translucent::scene

namespace translucent::scene {
namespace {

// A tabulated profile (bssrdf/tabulated.h) named by a scene is found next to the scene, as a
// .bssrdf file is; a heterogeneous material refuses it (the table is one material's R(r)).
TEST(Scene, TabulatedModelsAreRelativeToTheSceneAndHomogeneousOnly) {
  TempDir dir;
  dir.write("m.obj", "");
  dir.write("skin.csv", "# units: mm\nr,R_r,R_g,R_b\n0.1,1,2,3\n1,0.1,0.2,0.3\n");
  const std::string base = R"({"mesh": {"file": "m.obj"}, "camera": {"position": [0, 0, 5]},
    "lights": [{"type": "directional", "direction": [0, 0, 1]}], )";
  const Scene s = loadScene(dir.write("a.json", base + R"("material": {"preset": "Marble", "model": "skin.csv"}})"));
  EXPECT_EQ(std::filesystem::path(s.model), dir.path() / "skin.csv");
  try {
    (void)loadScene(dir.write("b.json", base + R"("material": {"type": "surface_checker",
      "cells": 8, "media": [{"preset": "Marble"}, {"preset": "Skin1"}], "model": "skin.csv"}})"));
    ADD_FAILURE() << "expected an error";
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("material.model"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("tabulated profile"), std::string::npos) << e.what();
  }
}

// A document nested a few hundred thousand levels deep (the stack overflowed while the tree was
// walked) is refused by the one JSON reader (io/json.h) with the line and column; 512 levels
// are fine, brackets inside strings do not count.
TEST(Scene, RefusesJsonNestedTooDeeplyInsteadOfCrashing) {
  const std::string base = R"({"mesh": {"file": "m.obj"}, "lights": [{"type": "directional",
      "direction": [0, 0, 1]}], "camera": {"position": [0, 0, 5]}, "material": )";
  const size_t depth = 300000;
  const std::string deep = base + std::string(depth, '[') + std::string(depth, ']') + "}";
  const std::string e = parseError(deep);
  EXPECT_NE(e.find("scene: not valid JSON: arrays and objects nest deeper than 512 levels (at "
                   "line 2, column "),
            std::string::npos)
      << e;
  // The same through loadScene: the message names the file.
  TempDir dir;
  dir.write("m.obj", "");
  const auto file = dir.write("deep.json", deep);
  try {
    (void)loadScene(file);
    ADD_FAILURE() << "accepted";
  } catch (const ParameterError& err) {
    EXPECT_NE(std::string(err.what()).find("deep.json"), std::string::npos) << err.what();
    EXPECT_NE(std::string(err.what()).find("nest deeper than 512"), std::string::npos) << err.what();
  }
  // The library reader itself: 512 levels parse, 513 do not; strings are skipped.
  EXPECT_NO_THROW((void)io::parseJson(std::string(512, '[') + std::string(512, ']'), "x"));
  EXPECT_THROW((void)io::parseJson(std::string(513, '[') + std::string(513, ']'), "x"),
               io::JsonError);
  EXPECT_NO_THROW((void)io::parseJson("[\"" + std::string(5000, '[') + "\\\"\"]", "x"));
}

// A number beyond a double's range is named by its line, column and key (nlohmann's message has
// none of them), abbreviated when long.
TEST(Scene, NumberOverflowNamesItsPlaceAndKey) {
  const std::string huge = "1" + std::string(400, '0');
  auto message = [](const std::string& text) {
    try {
      (void)io::parseJson(text, "s.json");
    } catch (const io::JsonError& e) {
      return std::string(e.what());
    }
    return std::string("(accepted)");
  };
  const std::string width = message("{\"camera\": {\"fov\": 30,\n \"width\": " + huge + "}}");
  EXPECT_NE(width.find("s.json: not valid JSON: the number 100000000000… (401 characters) at line 2, "
                       "column 11 (camera.width) is beyond the range of a double"),
            std::string::npos)
      << width;
  // In an array, after a string that holds the same digits and a key with a comma in it.
  const std::string light = message("{\"a,b\": \"" + huge + "\", \"lights\": [{}, {\"irradiance\": [1, -" +
                                    huge + "]}]}");
  EXPECT_NE(light.find("(lights[1].irradiance[1])"), std::string::npos) << light;
  EXPECT_NE(message("[1e400]").find("the number 1e400 at line 1, column 2 ([0])"), std::string::npos)
      << message("[1e400]");
}

// A light must emit something in a channel it lights, and not so little that the image is black
// (or, before, that the tracer's exact sums aborted): refused with the light and the value.
TEST(Scene, RefusesBlackAndTooFaintLights) {
  const std::string head = R"({"mesh": {"file": "m.obj"}, "material": {"preset": "Marble"},
      "camera": {"position": [0, 0, 5]}, "lights": )";
  auto with = [&](const std::string& lights) { return parseError(head + lights + "}"); };
  const std::string tiny = with(R"([{"type": "directional", "direction": [0, 0, 1], "irradiance": 1e-300}])");
  EXPECT_NE(tiny.find("lights[0]: irradiance 1e-300 times red 1 is 1e-300: expected at least 1e-30"),
            std::string::npos)
      << tiny;
  const std::string channel = with(R"([{"type": "point", "position": [0, 0, 3], "color": [1, 1, 1e-320]}])");
  EXPECT_NE(channel.find("lights[0]: intensity 1 times blue 1e-320"), std::string::npos) << channel;
  const std::string black = with(R"([{"type": "point", "position": [0, 0, 3]},
      {"type": "beam", "origin": [0, 0, 3], "direction": [0, 0, -1], "color": [0, 0, 0]}])");
  EXPECT_NE(black.find("lights[1].color: is [0, 0, 0]: the light emits nothing"), std::string::npos)
      << black;
  // A channel of colour 0 in a light that lights the others is fine.
  EXPECT_EQ(with(R"([{"type": "point", "position": [0, 0, 3], "color": [1, 0, 0]}])"), "no error");
}

}  // namespace
}  // namespace translucent::scene

namespace translucent::scene {
namespace {

using namespace geometry;
constexpr const char* kBunny = "/usr/share/glmark2/models/bunny.obj";

// A PLY point cloud (what `translucent pointcloud` writes) as a scene's mesh file: the mesh is the
// surface through its points, and the points come placed as the mesh is (normalised by their
// bounding box, rotated, scaled, moved), areas scaled by the square of the length scale, each
// with a triangle that has it as a vertex. A PLY mesh is not taken for a point cloud.
TEST(Scene, PointCloudFileAsTheMeshIsPlacedWithItsPoints) {
  TempDir dir;
  const PointCloud cloud = samplePointCloud(loadMesh(kBunny), [] {
    SamplingOptions o;
    o.count = 6000;
    o.seed = 1;
    return o;
  }());
  const auto file = dir.path() / "bunny-points.ply";
  writePointCloudPly(cloud, file);
  EXPECT_TRUE(isPointCloudPly(file));
  EXPECT_FALSE(isPointCloudPly(kBunny));

  Scene s;
  s.mesh_file = file;
  s.mesh_normalize = true;
  s.mesh_rotate = {0.0, 30.0, 0.0};
  s.mesh_scale = 1.5;
  s.mesh_translate = {0.1, -0.2, 0.3};
  std::optional<ScenePoints> points;
  const TriangleMesh mesh = loadRestMesh(s, nullptr, nullptr, &points);
  ASSERT_TRUE(points.has_value());
  EXPECT_EQ(points->reconstruction.points, 6000u);
  EXPECT_EQ(points->reconstruction.unused_points, 0u);
  EXPECT_EQ(mesh.openEdgeCount(), 0u);  // the closed bunny's samples give a closed surface
  const PointCloud& placed = points->cloud;
  ASSERT_EQ(placed.size(), cloud.size());
  ASSERT_EQ(placed.faces.size(), placed.size());
  // Normalised: longest side 1.5 after the scale; the mesh and the points share the placement.
  const Bounds b = mesh.bounds();
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(0.5 * (b.lower[k] + b.upper[k]), s.mesh_translate[k], 0.4);
  double pointArea = 0.0;
  for (size_t i = 0; i < placed.size(); ++i) {
    const glm::uvec3 t = mesh.triangles[placed.faces[i]];
    const glm::dvec3 p(placed.positions[i]);
    const double d = std::min({glm::distance(p, mesh.positions[t.x]),
                               glm::distance(p, mesh.positions[t.y]),
                               glm::distance(p, mesh.positions[t.z])});
    ASSERT_LT(d, 1e-5) << "point " << i << " is not a vertex of its triangle";
    EXPECT_NEAR(glm::length(placed.normals[i]), 1.0f, 1e-5f);
    pointArea += double(placed.areas[i]);
  }
  // Σ p_a = the bunny's area, scaled like the mesh; the reconstruction's area is within the
  // chordal deficit of the sampled surface (measured ~0.5% at 6000 points).
  EXPECT_NEAR(mesh.area(), pointArea, 0.02 * pointArea);
  // Normals rotated with the mesh: a point's normal is close to its triangle's, much closer than
  // the file's unrotated normal is, and opposite only at a few creases where the triangle's
  // other corners turn away (5 of 6000 measured).
  size_t disagree = 0;
  double cosines = 0.0, unrotated = 0.0;
  for (size_t i = 0; i < placed.size(); ++i) {
    const glm::uvec3 t = mesh.triangles[placed.faces[i]];
    const glm::dvec3 n = glm::normalize(glm::cross(mesh.positions[t.y] - mesh.positions[t.x],
                                                   mesh.positions[t.z] - mesh.positions[t.x]));
    const double c = glm::dot(n, glm::dvec3(placed.normals[i]));
    disagree += c <= 0.0 ? 1 : 0;
    cosines += c / double(placed.size());
    unrotated += glm::dot(n, glm::dvec3(cloud.normals[i])) / double(placed.size());
  }
  EXPECT_GT(cosines, 0.95);
  EXPECT_GT(cosines, unrotated + 0.05) << "unrotated normals: mean cosine " << unrotated;
  EXPECT_LE(disagree, placed.size() / 500);

  // A triangle mesh gives no points.
  s.mesh_file = kBunny;
  (void)loadRestMesh(s, nullptr, nullptr, &points);
  EXPECT_FALSE(points.has_value());
}

}  // namespace
}  // namespace translucent::scene
