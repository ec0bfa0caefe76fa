// The technique interface without a GPU: typed parameter descriptors and values, the registry,
// and the environment-lighting mathematics of the point-cloud technique (SH irradiance with
// Fresnel transmission, importance sampling of a latitude-longitude map).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

#include "bssrdf/exit_radiance.h"
#include "optics/fresnel.h"
#include "techniques/pointcloud/pointcloud_technique.h"
#include "techniques/pointcloud/environment.h"
#include "techniques/registry.h"

namespace translucent::techniques {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(Parameters, ValuesAreConvertedAndChecked) {
  const auto f = ParameterInfo::floating("epsilon", 0.1, 1e-4, 10.0, "help", "sr", true);
  EXPECT_EQ(std::get<double>(checkedValue(f, 2)), 2.0);            // int -> float
  EXPECT_EQ(std::get<double>(checkedValue(f, std::string("0.5"))), 0.5);  // typed text
  EXPECT_THROW((void)checkedValue(f, std::nan("")), ParameterError);
  EXPECT_THROW((void)checkedValue(f, 11.0), ParameterError);
  EXPECT_THROW((void)checkedValue(f, std::string("0.5x")), ParameterError);
  const auto i = ParameterInfo::integer("points", 10, 1, 100, "help");
  EXPECT_EQ(std::get<int>(checkedValue(i, 12.0)), 12);
  EXPECT_EQ(std::get<int>(checkedValue(i, std::string("1e2"))), 100);
  EXPECT_THROW((void)checkedValue(i, 12.5), ParameterError);
  EXPECT_THROW((void)checkedValue(i, 0), ParameterError);
  const auto b = ParameterInfo::boolean("specular", false, "help");
  EXPECT_EQ(std::get<bool>(checkedValue(b, std::string("on"))), true);
  EXPECT_EQ(std::get<bool>(checkedValue(b, 0)), false);
  EXPECT_THROW((void)checkedValue(b, 2), ParameterError);
  const auto e = ParameterInfo::enumeration("kernel", "table", {"table", "shader"}, "help");
  EXPECT_EQ(std::get<std::string>(checkedValue(e, std::string("shader"))), "shader");
  try {
    (void)checkedValue(e, std::string("magic"));
    FAIL() << "expected an error";
  } catch (const ParameterError& err) {
    EXPECT_NE(std::string(err.what()).find("kernel"), std::string::npos);
    EXPECT_NE(std::string(err.what()).find("table, shader"), std::string::npos);
  }
}

TEST(Parameters, SetReportsChangesAndUnknownNames) {
  ParameterSet set({ParameterInfo::floating("a", 1.0, 0.0, 2.0, "first"),
                    ParameterInfo::integer("b", 3, 0, 9, "second")});
  EXPECT_EQ(set.getFloat("a"), 1.0);
  EXPECT_FALSE(set.set("a", 1.0));
  EXPECT_TRUE(set.set("a", 1.5));
  EXPECT_EQ(set.getFloat("a"), 1.5);
  EXPECT_TRUE(set.set("b", std::string("4")));
  EXPECT_EQ(set.getInt("b"), 4);
  try {
    set.set("c", 1.0);
    FAIL() << "expected an error";
  } catch (const ParameterError& err) {
    EXPECT_NE(std::string(err.what()).find("valid parameters are a, b"), std::string::npos) << err.what();
  }
}

TEST(Registry, MakesTechniquesByNameAndListsValidNames) {
  ASSERT_FALSE(names().empty());
  for (const std::string& name : names()) {
    const auto t = make(name);
    EXPECT_EQ(t->name(), name);
    EXPECT_FALSE(t->description().empty());
    for (const auto& p : t->parameters()) {
      EXPECT_FALSE(p.help.empty()) << name << "." << p.name;
      // Every default passes its own checks, and parameter() returns it.
      EXPECT_EQ(checkedValue(p, p.value), p.value) << name << "." << p.name;
      EXPECT_EQ(t->parameter(p.name), p.value);
    }
  }
  try {
    (void)make("pointclod");
    FAIL() << "expected an error";
  } catch (const UnknownTechniqueError& e) {
    EXPECT_NE(std::string(e.what()).find("pointcloud"), std::string::npos) << e.what();
  }
}

// `translucent compare --sweep` renders every sweep value: each must be a valid value of a
// numeric parameter, and every technique declares a quality parameter to sweep.
TEST(Registry, SweepValuesAreValidAndEveryTechniqueHasOne) {
  for (const std::string& name : names()) {
    const auto t = make(name);
    int swept = 0;
    for (const auto& p : t->parameters()) {
      if (p.sweep.empty()) continue;
      ++swept;
      EXPECT_TRUE(p.type == ParameterType::Float || p.type == ParameterType::Int)
          << name << "." << p.name;
      EXPECT_GE(p.sweep.size(), 3u) << name << "." << p.name;
      for (double v : p.sweep) EXPECT_NO_THROW((void)checkedValue(p, v)) << name << "." << p.name << " = " << v;
    }
    EXPECT_GE(swept, 1) << name;
  }
}

// The point-cloud technique offers both exit-radiance conventions of seed Eq. 2.16 as an enum
// descriptor (so the CLI and the explorer list them), from a scene's technique settings too, and
// rejects anything else naming the valid values. The empirical shader derives no radiance from an
// exitance and has no such parameter.
TEST(Registry, PointCloudListsAndChecksTheRadianceConvention) {
  auto t = make("pointcloud");
  const ParameterInfo* info = nullptr;
  for (const auto& p : t->parameters())
    if (p.name == "radiance_convention") info = &p;
  ASSERT_NE(info, nullptr);
  EXPECT_EQ(info->type, ParameterType::Enum);
  EXPECT_EQ(info->choices, bssrdf::exitConventionNames());
  EXPECT_EQ(std::get<std::string>(info->value), pointcloud::kDefaultRadianceConvention);
  EXPECT_NO_THROW((void)bssrdf::parseExitConvention(pointcloud::kDefaultRadianceConvention));
  scene::Scene s;
  for (const char* name : {"normalized", "jensen"}) {
    s.settings["radiance_convention"] = std::string(name);
    applySettings(*t, s);
    EXPECT_EQ(t->parameter("radiance_convention"), ParameterValue(std::string(name)));
  }
  try {
    t->setParameter("radiance_convention", std::string("deon"));
    FAIL() << "expected an error";
  } catch (const ParameterError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("radiance_convention"), std::string::npos) << what;
    EXPECT_NE(what.find("jensen, normalized"), std::string::npos) << what;
  }
  const auto empirical = make("empirical");
  for (const auto& p : empirical->parameters()) EXPECT_NE(p.name, "radiance_convention");
}

TEST(Registry, SceneSettingsApplyWithTheKeyInErrors) {
  auto t = make("pointcloud");
  scene::Scene s;
  s.settings["epsilon"] = 0.05;
  s.settings["specular"] = true;
  applySettings(*t, s);
  EXPECT_EQ(std::get<double>(t->parameter("epsilon")), 0.05);
  EXPECT_EQ(std::get<bool>(t->parameter("specular")), true);
  s.settings["points"] = 12.5;
  try {
    applySettings(*t, s);
    FAIL() << "expected an error";
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("technique.points"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace translucent::techniques

namespace translucent::pointcloud {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(Environment, LambdasReduceToRamamoorthiHanrahanWithoutFresnel) {
  // λ_l = 2π ∫0^1 Ft(η, t) t P_l(t) dt against an independent fine midpoint rule; Ft <= 1 bounds
  // λ_0 and λ_1 by the values without an interface (π, 2π/3).
  for (double eta : {1.0, 1.3, 1.5}) {
    const auto lambda = transmittedIrradianceLambdas(eta);
    std::array<double, 3> check{};
    const int n = 200000;
    for (int i = 0; i < n; ++i) {
      const double t = (i + 0.5) / n, w = 2.0 * kPi * fresnelTransmittance(t, eta) * t / n;
      check[0] += w;
      check[1] += w * t;
      check[2] += w * 0.5 * (3.0 * t * t - 1.0);
    }
    for (int l = 0; l < 3; ++l) EXPECT_NEAR(lambda[size_t(l)], check[size_t(l)], 1e-6) << "eta " << eta;
    EXPECT_LE(lambda[0], kPi + 1e-9);
    EXPECT_LE(lambda[1], 2.0 * kPi / 3.0 + 1e-9);
  }
  const auto one = transmittedIrradianceLambdas(1.0);
  EXPECT_NEAR(one[0], kPi, 1e-6);  // η = 1: Ft = 1 at every angle (no interface)
  EXPECT_NEAR(one[1], 2.0 * kPi / 3.0, 1e-6);
  EXPECT_NEAR(one[2], kPi / 4.0, 1e-6);
}

TEST(Environment, ShIrradianceOfALinearSkyIsExact) {
  // L(ω) = 1 + ω_y has only l = 0, 1 terms: E(n) = λ0 + λ1 n_y exactly (up to the midpoint
  // quadrature over the map), for any rotation about +y.
  EnvironmentMap map = EnvironmentMap::constant(glm::vec3(1.0f), 256, 128);
  for (int y = 0; y < map.height; ++y)
    for (int x = 0; x < map.width; ++x) {
      const double v = (y + 0.5) / map.height;
      const float value = float(1.0 + std::cos(kPi * v));
      for (int c = 0; c < 3; ++c) map.rgb[(size_t(y) * size_t(map.width) + size_t(x)) * 3 + size_t(c)] = value;
    }
  const auto lambda = transmittedIrradianceLambdas(1.3);
  const auto sh = irradianceSh9(map, 40.0, 1.3, glm::dvec3(1.0, 2.0, 3.0));
  for (const glm::dvec3 n : {glm::dvec3(0, 1, 0), glm::dvec3(0, -1, 0), glm::dvec3(1, 0, 0),
                             glm::normalize(glm::dvec3(1, 2, -3))}) {
    const double want = lambda[0] + lambda[1] * n.y;
    const glm::dvec3 e = evalSh9(sh, n);
    EXPECT_NEAR(e.x, want, 2e-4 * lambda[0]) << n.x << " " << n.y << " " << n.z;
    EXPECT_NEAR(e.z, 3.0 * want, 6e-4 * lambda[0]);
  }
}

TEST(Environment, ImportanceSamplesHaveTheirDensity) {
  // A grey map with a bright patch: sampling ∝ luminance · sin θ makes L/p almost constant; its
  // mean over 4096 quasi-random samples is ∫ L dω (midpoint quadrature) to 0.5%.
  EnvironmentMap map = EnvironmentMap::constant(glm::vec3(0.2f), 128, 64);
  for (int y = 10; y < 20; ++y)
    for (int x = 30; x < 50; ++x)
      for (int c = 0; c < 3; ++c) map.rgb[(size_t(y) * 128 + size_t(x)) * 3 + size_t(c)] = 50.0f;
  double integral = 0.0;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 128; ++x)
      integral += double(map.texel(x, y).g) * std::sin(kPi * (y + 0.5) / 64) * (kPi / 64) * (2 * kPi / 128);
  const EnvironmentSampler sampler(map, 25.0);
  double mean = 0.0;
  int bright = 0;
  const int n = 4096;
  for (int k = 0; k < n; ++k) {
    const auto s = sampler.sequence(uint64_t(k), 1);
    ASSERT_NEAR(glm::length(s.direction), 1.0, 1e-12);
    ASSERT_GT(s.pdf, 0.0);
    mean += s.radiance.g / s.pdf;
    bright += s.radiance.g > 1.0 ? 1 : 0;
  }
  EXPECT_NEAR(mean / n, integral, 5e-3 * integral);
  EXPECT_GT(bright, n / 2);  // the patch holds most of the energy
  EnvironmentMap black = EnvironmentMap::constant(glm::vec3(0.0f), 8, 4);
  EXPECT_THROW(EnvironmentSampler(black, 0.0), ParameterError);
}

}  // namespace
}  // namespace translucent::pointcloud
