// SPDX-License-Identifier: GPL-3.0-or-later
// The technique interface without a GPU: typed parameter descriptors and values, the registry,
// and the environment-lighting mathematics of the point-cloud technique (SH irradiance with
// Fresnel transmission, importance sampling of a latitude-longitude map).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

#include "translucent/bssrdf/exit_radiance.h"
#include "translucent/optics/fresnel.h"
#include "translucent/techniques/pointcloud/pointcloud_technique.h"
#include "translucent/lights/environment_map.h"
#include "translucent/techniques/registry.h"

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
