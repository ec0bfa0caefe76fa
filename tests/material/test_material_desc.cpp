// SPDX-License-Identifier: GPL-3.0-or-later
// Material descriptions in scene files (material/material_desc.h through scene::parseScene):
// every type parses, round-trips through toJson, reports bad input naming the key, and
// scene::sceneMaterial builds the Volume or Surface material it describes.
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include <openvdb/openvdb.h>

#include "translucent/io/image_io.h"
#include "translucent/geometry/mesh.h"
#include "translucent/material/material_desc.h"
#include "translucent/material/parse_context.h"
#include "translucent/scene/scene.h"
#include "test_helpers.h"

namespace translucent::material {
namespace {

using testing::TempDir;

// A scene around `material` (JSON text), with a mesh m.obj in `dir`.
std::string sceneText(const std::string& material) {
  return R"({"mesh": {"file": "m.obj"}, "material": )" + material +
         R"(, "lights": [{"type": "directional", "direction": [0, 0, 1]}],
            "camera": {"position": [0, 0, 5]}})";
}

scene::Scene parse(const TempDir& dir, const std::string& material) {
  dir.write("m.obj", "");
  return scene::parseScene(sceneText(material), dir.path(), "scene");
}

std::string error(const std::string& material) {
  TempDir dir;
  try {
    (void)parse(dir, material);
  } catch (const ParameterError& e) {
    return e.what();
  }
  return "no error";
}

// Material JSON of every type (files in `dir`).
std::vector<std::pair<std::string, std::string>> everyType(const TempDir& dir) {
  // Images and a grid for the file-based types.
  std::vector<float> a(2 * 2 * 3, 0.05f), s(2 * 2 * 3, 2.0f), rd(2 * 2 * 3, 0.4f);
  analysis::writeExr((dir / "sa.exr").string(), 2, 2, a);
  analysis::writeExr((dir / "ssp.exr").string(), 2, 2, s);
  analysis::writeExr((dir / "rd.exr").string(), 2, 2, rd);
  openvdb::initialize();
  auto grid = openvdb::FloatGrid::create(0.0f);
  grid->setName("density");
  grid->tree().setValue(openvdb::Coord(0, 0, 0), 1.0f);
  openvdb::io::File f((dir / "d.vdb").string());
  f.write({grid});
  f.close();
  const std::string A = R"({"sigma_a": [0.01, 0.02, 0.03], "sigma_s": [1, 2, 3], "g": 0.1})";
  const std::string B = R"({"preset": "Skin1"})";
  return {
      {"layers", R"({"type": "layers", "layers": [{"medium": )" + A +
                     R"(, "thickness": 0.25}, {"medium": )" + B + R"(}], "eta": 1.4, "scale": 30})"},
      {"layers", R"({"type": "layers", "from": "plane", "normal": [0, 0, 2], "offset": 1.5,
                     "layers": [{"medium": )" + B + R"(}]})"},
      {"veins", R"({"type": "veins", "media": [)" + A + ", " + B +
                    R"(], "period": 4, "octaves": 3, "sharpness": 2, "direction": [0, 1, 0],
                     "model": "better-dipole"})"},
      {"checker", R"({"type": "checker", "cell": [1, 2, 3], "media": [)" + B + ", " + A + "]}"},
      {"gradient", R"({"type": "gradient", "from": [0, 0, 0], "to": [0, 0, 10], "media": [)" + A +
                       ", " + B + "]}"},
      {"voxels", R"({"type": "voxels", "file": "d.vdb", "media": [)" + A + ", " + B + "]}"},
      {"map", R"({"type": "map", "sigma_a": "sa.exr", "sigma_s_prime": "ssp.exr", "g": 0.3})"},
      {"rd_map", R"({"type": "rd_map", "rd": "rd.exr", "ld": [1, 0.5, 0.25]})"},
      {"surface_checker", R"({"type": "surface_checker", "cells": 6, "media": [)" + A + ", " + B + "]}"},
  };
}

TEST(MaterialDesc, EveryTypeParsesAndRoundTripsThroughToJson) {
  TempDir dir;
  std::set<std::string> seen;
  for (const auto& [type, text] : everyType(dir)) {
    SCOPED_TRACE(text);
    scene::Scene s;
    try {
      s = parse(dir, text);
    } catch (const std::exception& e) {
      FAIL() << e.what();
    }
    EXPECT_EQ(s.material.type(), type);
    seen.insert(type);
    EXPECT_NO_THROW(s.medium.validate());
    const std::string once = scene::toJson(s);
    const scene::Scene again = scene::parseScene(once, "", "round trip");
    EXPECT_EQ(again.material, s.material);
    EXPECT_EQ(again.medium.sigma_a, s.medium.sigma_a);
    EXPECT_EQ(again.medium.eta, s.medium.eta);
    EXPECT_EQ(again.model, s.model);
    EXPECT_EQ(scene::toJson(again), once);
  }
  // Every registered type but the homogeneous one is covered.
  EXPECT_EQ(seen.size() + 1, materialTypes().size());
}

TEST(MaterialDesc, TheHomogeneousFormIsTheDefaultAndUnchanged) {
  TempDir dir;
  const scene::Scene s = parse(dir, R"({"preset": "Marble", "scale": 25})");
  EXPECT_TRUE(s.material.homogeneous());
  const scene::Scene t = parse(dir, R"({"type": "homogeneous", "preset": "Marble", "scale": 25})");
  EXPECT_EQ(scene::toJson(s), scene::toJson(t));
  EXPECT_EQ(scene::toJson(s).find("\"type\": \"homogeneous\""), std::string::npos);
}

TEST(MaterialDesc, TheRepresentativeMediumIsTheTopLayerOrFirstMedium) {
  TempDir dir;
  const auto types = everyType(dir);
  const scene::Scene layers = parse(dir, types[0].second);
  EXPECT_EQ(layers.medium.sigma_a[2], 0.03);
  EXPECT_EQ(layers.medium.eta, 1.4);
  EXPECT_EQ(layers.medium.scale, 30.0);
  EXPECT_EQ(layers.medium.g, 0.1);
  const scene::Scene map = parse(dir, types[6].second);
  EXPECT_NEAR(map.medium.sigma_a[0], 0.05, 1e-7);
  EXPECT_NEAR(map.medium.sigma_s[0], 2.0 / 0.7, 1e-6);  // the mean texel, σs = σs'/(1 − g)
}

TEST(MaterialDesc, BadInputIsAnErrorNamingTheKey) {
  const std::string A = R"({"sigma_a": 0.1, "sigma_s": 1})";
  struct Case {
    std::string material, expected;
  };
  const std::vector<Case> cases = {
      {R"({"type": "marble"})", "scene: material.type: 'marble': expected one of homogeneous, layers, veins, checker, gradient, voxels, map, rd_map, surface_checker"},
      {R"({"type": "veins", "media": [)" + A + "," + A + R"(], "period": 1, "colour": 1})",
       "material.colour: unknown key; valid keys here are type, eta, scale, model, media, period"},
      {R"({"type": "veins", "media": [)" + A + "," + A + R"(], "period": -1})",
       "material.period: is -1: expected a number > 0"},
      {R"({"type": "veins", "media": [)" + A + "," + A + R"(], "period": 1, "octaves": 40})",
       "material.octaves: is 40: expected a whole number in [1, 12]"},
      {R"({"type": "veins", "media": [)" + A + R"(], "period": 1})",
       "material.media: array [{\"sigma_a\":0.1,\"sigma_s\":1}]: expected an array of 2 media"},
      {R"({"type": "checker", "cell": 1, "media": [)" + A + R"(, {"preset": "Jade"}]})",
       "material.media[1].preset: unknown"},
      {R"({"type": "checker", "cell": 1, "media": [)" + A + R"(, {"sigma_a": -1, "sigma_s": 1}]})",
       "material.media[1]: sigma_a"},
      {R"({"type": "checker", "cell": [1, 0, 1], "media": [)" + A + "," + A + "]}",
       "material.cell: is [1, 0, 1]: expected each > 0"},
      {R"({"type": "layers", "layers": [{"medium": )" + A + R"(, "thickness": 1}, {"medium": )" + A +
           R"(, "thickness": 0}, {"medium": )" + A + "}]}",
       "material.layers[1].thickness: is 0: expected a number > 0"},
      {R"({"type": "layers", "layers": [{"medium": )" + A + R"(}, {"medium": )" + A + "}]}",
       "material.layers[0].thickness: required"},
      {R"({"type": "layers", "layers": [{"medium": )" + A + R"(, "thickness": 2}]})",
       "material.layers[0].thickness: the last layer is semi-infinite"},
      {R"({"type": "layers", "normal": [0, 1, 0], "layers": [{"medium": )" + A + "}]}",
       "material.normal: applies to \"from\": \"plane\" only"},
      {R"({"type": "layers", "from": "plane", "normal": [0, 0, 0], "layers": [{"medium": )" + A + "}]}",
       "material.normal: is [0, 0, 0]: expected a non-zero direction"},
      {R"({"type": "gradient", "from": [1, 1, 1], "to": [1, 1, 1], "media": [)" + A + "," + A + "]}",
       "material.to: equals \"from\""},
      {R"({"type": "voxels", "file": "nowhere.vdb", "media": [)" + A + "," + A + "]}",
       "material.file: file 'nowhere.vdb' not found"},
      {R"({"type": "map", "sigma_a": "a.exr", "sigma_s_prime": "b.exr"})",
       "material.sigma_a: file 'a.exr' not found"},
      {R"({"type": "rd_map", "rd": 0.3, "ld": 1, "g": 1})", "material.g: is 1: expected |g| < 1"},
      {R"({"type": "rd_map", "rd": 0.3, "ld": 1, "model": "dipol"})", "material.model:"},
      {R"({"type": "rd_map", "rd": 0.3, "ld": 1, "model": "x.bssrdf"})",
       "rd_map inverts Rd with a registered model"},
      {R"({"type": "rd_map", "rd": [0.3, 1.5, 0.3], "ld": 1})",
       "material.rd (value): texel (0, 0) green is 1.5: expected Rd in (0, "},
      {R"({"type": "rd_map", "rd": 0.3, "ld": [1, 1, -1]})",
       "material.ld (value): texel (0, 0) blue is -1: expected ℓd > 0"},
      {R"({"type": "surface_checker", "cells": [1, 2, 3], "media": [)" + A + "," + A + "]}",
       "material.cells: array [1,2,3]: expected a number or [nu, nv]"},
      {R"({"type": "checker", "cell": 1, "media": [)" + A + "," + A + R"(], "eta": -1})",
       "material: eta"},
      {R"({"type": "checker", "cell": 1, "media": [)" + A + "," + A + R"(], "preset": "Marble"})",
       "material.preset: unknown key"},
  };
  for (const Case& c : cases) {
    const std::string e = error(c.material);
    EXPECT_NE(e.find(c.expected), std::string::npos) << c.material << "\n  gave: " << e;
  }
}

TEST(SceneMaterial, BuildsVolumeAndSurfaceMaterialsWithTheirFrameAndSurfaceDepth) {
  TempDir dir;
  const auto types = everyType(dir);
  // Layers from the surface of a placed box: the frame takes the scene to material space.
  scene::Scene s = parse(dir, types[0].second);  // 0.25 of A over Skin1, scale 30
  s.mesh_translate = {1.0, 0.0, 0.0};
  const geometry::TriangleMesh box = geometry::makeBox(glm::dvec3(0.5, -0.5, -0.5), glm::dvec3(1.5, 0.5, 0.5));
  const Material m = scene::sceneMaterial(s, box);
  ASSERT_EQ(m.kind, Material::Kind::Volume);
  ASSERT_TRUE(m.volume);
  EXPECT_EQ(m.model, s.model);
  EXPECT_EQ(m.frame.scale, 30.0);
  EXPECT_DOUBLE_EQ(m.surface_depth, surfaceDepth(LocalMedium::of(s.medium)));
  EXPECT_GT(m.surface_depth, 0.0);
  // 0.005 scene units = 0.15 mm below the top face: layer A; the centre (15 mm deep): Skin1.
  EXPECT_EQ(m.atScenePoint({1.0, 0.495, 0.0}).sigma_a, s.material.representative().sigma_a);
  const auto& layers = std::get<LayersDesc>(s.material.field);
  EXPECT_EQ(m.atScenePoint({1.0, 0.0, 0.0}), layers.layers[1].medium.medium);
  // surfaceMedium averages over [0, surface_depth]: between the two layers' σa.
  const LocalMedium sm = m.surfaceMedium({1.0, 0.5, 0.0}, {0.0, 1.0, 0.0}, {});
  EXPECT_GE(sm.sigma_a[0], std::min(layers.layers[0].medium.medium.sigma_a[0], layers.layers[1].medium.medium.sigma_a[0]));
  EXPECT_LE(sm.sigma_a[0], std::max(layers.layers[0].medium.medium.sigma_a[0], layers.layers[1].medium.medium.sigma_a[0]));

  // A surface map: Kind::Surface, looked up at the UV.
  const scene::Scene checker = parse(dir, types[8].second);
  const Material c = scene::sceneMaterial(checker, box);
  ASSERT_EQ(c.kind, Material::Kind::Surface);
  ASSERT_TRUE(c.surface);
  EXPECT_FALSE(c.volume);
  const auto& cd = std::get<SurfaceCheckerDesc>(checker.material.field);
  EXPECT_EQ(c.surfaceMedium({}, {0, 0, 1}, {0.05, 0.05}), cd.media[0].medium);
  EXPECT_EQ(c.surfaceMedium({}, {0, 0, 1}, {0.25, 0.05}), cd.media[1].medium);

  // Homogeneous: as before.
  const scene::Scene h = parse(dir, R"({"preset": "Marble"})");
  const Material hm = scene::sceneMaterial(h, box);
  EXPECT_EQ(hm.kind, Material::Kind::Homogeneous);
  EXPECT_FALSE(hm.volume);
}

TEST(SurfaceDepth, IsTheSmallestDiffusionLengthOfTheTopMedium) {
  const LocalMedium m{{0.01, 0.1, 1.0}, {1.0, 1.0, 1.0}, 0.0};
  const double want = ScalarMedium{1.0, 1.0, 0.0, 1.0}.diffuseMeanFreePath();
  EXPECT_DOUBLE_EQ(surfaceDepth(m), want);
  // Without absorption (ℓd infinite): ten reduced mean free paths.
  EXPECT_DOUBLE_EQ(surfaceDepth({{0.0, 0.0, 0.0}, {2.0, 4.0, 5.0}, 0.0}), 10.0 * 0.2);
}

}  // namespace
}  // namespace translucent::material
