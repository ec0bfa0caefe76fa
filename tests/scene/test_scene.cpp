// Scene files (scene/scene.h): every key parses, the scene round-trips through toJson, bad input
// names the key, and meshes are normalised and placed as documented.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

#include <unistd.h>

#include <glm/geometric.hpp>

#include "analysis/image_io.h"
#include "scene/scene.h"

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
  "display": {"exposure": -1, "gamma": 2.0},
  "cone_angle": 4
})";

TEST(Scene, ParsesEveryKey) {
  TempDir dir;
  const Scene s = loadScene(dir.write("scene.json", kFull));
  EXPECT_EQ(s.mesh_file, dir.path() / "box.obj");
  EXPECT_FALSE(s.mesh_normalize);
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
  EXPECT_EQ(s.cone_angle, 4.0);
}

TEST(Scene, RoundTripsThroughJson) {
  TempDir dir;
  const Scene s = loadScene(dir.write("scene.json", kFull));
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

std::string parseError(const std::string& json) {
  try {
    (void)parseScene(json, "", "scene");
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
  EXPECT_NE(parseError(scene(mesh, mat, light, cam, R"(, "displya": {})")).find("valid keys"),
            std::string::npos);
  EXPECT_NE(parseError("{ not json").find("not valid JSON"), std::string::npos);
  // Numbers too large for a double are rejected by the JSON reader.
  EXPECT_NE(parseError(scene(R"("mesh": {"file": "m.obj", "scale": 1e999})", mat, light, cam)).find("not valid JSON"),
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

}  // namespace
}  // namespace translucent::scene
