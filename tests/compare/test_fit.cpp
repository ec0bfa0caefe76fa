// SPDX-License-Identifier: GPL-3.0-or-later
// translucent fit (compare/fit.h): fitting the empirical shader to an image it rendered itself
// with other parameters recovers that image (the fit's error falls from tens of per cent to under
// one), the technique is left at the fitted values, and malformed requests are refused.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>

#include "translucent/compare/compare.h"
#include "translucent/compare/compare_run.h"
#include "translucent/compare/fit.h"
#include "translucent/gpu/context.h"
#include "translucent/scene/scene.h"

namespace translucent::analysis {
namespace {

// The cube at 48x36 with compare's masks and the empirical technique prepared on it.
struct Cube {
  scene::Scene s;
  Masks masks;
  gpu::Context gl;
  std::unique_ptr<techniques::Technique> t;
  Cube() : s(scene::loadScene(TRANSLUCENT_CUBE_SCENE)) {
    s.camera.width = 48;
    s.camera.height = 36;
    masks = compareMasks(s, scene::loadSceneMesh(s), {});
    t = makeTechniqueSpec("empirical", &s);
    t->prepare(s, gl);
  }
};

TEST(Fit, TheEmpiricalShaderRecoversAnImageOfItsOwn) {
  Cube cube;
  const scene::Scene& s = cube.s;
  const Masks& masks = cube.masks;
  auto& t = cube.t;
  // The target: the shader at values away from its defaults (within the fitted ranges).
  const std::vector<std::pair<std::string, double>> truth = {
      {"ka", 0.5}, {"kd_red", 0.3}, {"kd_green", 0.7}, {"kd_blue", 0.45},
      {"diffuse_contribution", 1.6}, {"specular_contribution", 0.1}, {"backlight", 3.0},
      {"thickness_exponent", 8.0}, {"diffuse_weight", 0.5}};
  std::vector<std::pair<std::string, techniques::ParameterValue>> defaults;
  for (const auto& [name, v] : truth) {
    defaults.emplace_back(name, t->parameter(name));
    t->setParameter(name, v);
  }
  const CompareImage target = renderTimed(*t, "empirical", s, 0, 0).images.radiance;
  for (const auto& [name, v] : defaults) t->setParameter(name, v);

  const auto params = empiricalFitParameters();
  FitOptions o;
  o.max_evaluations = 1500;  // renders of 48x36 take about a millisecond
  int calls = 0;
  const FitResult r = fitTechnique(*t, s, target, masks.interior, params, o, [&](int n, double) {
    calls = n;
    return true;
  });
  std::printf("fit: %.2f%% -> %.4f%% in %d renders (%d starts, %s)\n", 100 * r.before_metrics.rel_rmse,
              100 * r.after_metrics.rel_rmse, r.evaluations, r.starts, r.stop_reason.c_str());
  EXPECT_GT(r.before_metrics.rel_rmse, 0.2) << "the defaults are far from the target";
  EXPECT_LT(r.after_metrics.rel_rmse, 0.01) << r.stop_reason << " after " << r.evaluations;
  EXPECT_LE(r.evaluations, o.max_evaluations);
  EXPECT_EQ(calls, r.evaluations);
  ASSERT_EQ(r.after.size(), params.size());
  // The technique renders at the fitted values, inside their ranges.
  for (size_t k = 0; k < params.size(); ++k) {
    const auto v = std::get<double>(t->parameter(params[k].name));
    EXPECT_EQ(v, r.after[k].second) << params[k].name;
    EXPECT_GE(v, params[k].lo);
    EXPECT_LE(v, params[k].hi);
  }
  const CompareImage now = renderTimed(*t, "empirical", s, 0, 0).images.radiance;
  EXPECT_NEAR(compareImages(now, target, masks.interior).rel_rmse, r.after_metrics.rel_rmse, 1e-6);

  // A stop from the progress callback keeps the best values so far (never worse than the start).
  for (const auto& [name, v] : defaults) t->setParameter(name, v);
  const FitResult stopped = fitTechnique(*t, s, target, masks.interior, params, o,
                                         [](int n, double) { return n < 20; });
  EXPECT_EQ(stopped.stop_reason, "stopped");
  EXPECT_EQ(stopped.evaluations, 20);
  EXPECT_LE(stopped.after_metrics.rel_rmse_raw, stopped.before_metrics.rel_rmse_raw + 1e-12);
}

TEST(Fit, RefusesWhatItCannotFit) {
  Cube cube;
  const scene::Scene& s = cube.s;
  const Masks& masks = cube.masks;
  auto& t = cube.t;
  const CompareImage target = renderTimed(*t, "empirical", s, 0, 0).images.radiance;
  const std::vector<FitParameter> not_a_number = {{"smoothing", 0.0, 1.0, false}};
  EXPECT_THROW(fitTechnique(*t, s, target, masks.interior, not_a_number), ParameterError);
  const std::vector<FitParameter> unknown = {{"nope", 0.0, 1.0, false}};
  EXPECT_THROW(fitTechnique(*t, s, target, masks.interior, unknown), ParameterError);
  const std::vector<FitParameter> empty = {{"ka", 1.0, 1.0, false}};
  EXPECT_THROW(fitTechnique(*t, s, target, masks.interior, empty), ParameterError);
  const std::vector<FitParameter> log_zero = {{"ka", 0.0, 1.0, true}};
  EXPECT_THROW(fitTechnique(*t, s, target, masks.interior, log_zero), ParameterError);
  EXPECT_THROW(fitTechnique(*t, s, target, masks.interior, {}), ParameterError);
}

}  // namespace
}  // namespace translucent::analysis
