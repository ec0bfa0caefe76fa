// SPDX-License-Identifier: GPL-3.0-or-later
// The empirical shader's per-pixel mathematics (techniques/empirical/shading.h): depth
// linearisation, thickness, the depth-aware smoothing of appendix C (Eq. C.1), the lighting
// equation (Eq. 3.6) term by term and the survey presets (Table 4.3).
#include <gtest/gtest.h>

#include <cmath>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "translucent/optics/medium.h"
#include "translucent/techniques/empirical/shading.h"

namespace translucent::empirical {
namespace {

// Window depth of a point at distance `d` in front of the eye, through P.
double windowDepthOf(double d, const glm::dmat4& P) {
  const glm::dvec4 clip = P * glm::dvec4(0.0, 0.0, -d, 1.0);
  return 0.5 * (clip.z / clip.w) + 0.5;
}

TEST(EmpiricalShading, LinearDepthInvertsPerspectiveAndOrthographicProjections) {
  const glm::dmat4 persp = glm::perspective(0.7, 1.5, 0.1, 50.0);
  const glm::dmat4 ortho = glm::ortho(-2.0, 2.0, -1.0, 1.0, 0.5, 9.0);
  for (double d : {0.1, 0.37, 1.0, 4.2, 8.9}) {
    EXPECT_NEAR(linearDepth(windowDepthOf(d, persp), persp), d, 1e-9 * 50.0) << d;
    EXPECT_NEAR(linearDepth(windowDepthOf(d, ortho), ortho), d, 1e-12 * 9.0) << d;
  }
  // The near and far planes map to window depths 0 and 1.
  EXPECT_NEAR(linearDepth(0.0, persp), 0.1, 1e-12);
  EXPECT_NEAR(linearDepth(1.0, persp), 50.0, 1e-9);
  EXPECT_NEAR(linearDepth(1.0, ortho), 9.0, 1e-12);
}

TEST(EmpiricalShading, ThicknessIsNormalisedByTheDiameterAndClamped) {
  EXPECT_DOUBLE_EQ(thickness(2.0, 3.5, 3.0), 0.5);
  EXPECT_DOUBLE_EQ(thickness(2.0, 9.0, 3.0), 1.0);
  EXPECT_DOUBLE_EQ(thickness(2.0, 1.0, 3.0), 0.0);
  EXPECT_THROW(thickness(0.0, 1.0, 0.0), ParameterError);
}

DepthImage image(int w, int h, float background) {
  DepthImage im;
  im.width = w;
  im.height = h;
  im.background = background;
  im.depth.assign(size_t(w) * size_t(h), background);
  return im;
}

TEST(EmpiricalShading, SmoothingKeepsAFlatDepthFlat) {
  DepthImage im = image(12, 9, 1.0f);
  for (float& z : im.depth) z = 0.4375f;
  const DepthImage out = smoothDepth(im, {});
  for (float z : out.depth) EXPECT_FLOAT_EQ(z, 0.4375f);
}

TEST(EmpiricalShading, SmoothingDoesNotBlurAcrossAStepLargerThanTheThreshold) {
  // Left half 0.30, right half 0.55: a step of 0.25 > threshold 0.1 stays sharp.
  DepthImage im = image(10, 6, 1.0f);
  for (int y = 0; y < im.height; ++y)
    for (int x = 0; x < im.width; ++x) im.depth[size_t(y * im.width + x)] = x < 5 ? 0.30f : 0.55f;
  SmoothingOptions o;
  o.threshold = 0.1;
  const DepthImage out = smoothDepth(im, o);
  for (int y = 0; y < im.height; ++y)
    for (int x = 0; x < im.width; ++x)
      EXPECT_FLOAT_EQ(out.at(x, y), x < 5 ? 0.30f : 0.55f) << x << "," << y;
  // A step of 0.05 < threshold is blurred: next to the edge the value moves towards the other
  // side by the weighted share of the other side's texels (Eq. C.1 with deviation/threshold = 0.5).
  for (int y = 0; y < im.height; ++y)
    for (int x = 5; x < im.width; ++x) im.depth[size_t(y * im.width + x)] = 0.35f;
  const float edge = smoothDepth(im, 4, 3, o);
  double wSame = 0.0, wOther = 0.0;
  for (int dy = -2; dy <= 2; ++dy)
    for (int dx = -2; dx <= 2; ++dx) (dx <= 0 ? wSame : wOther) += gaussianWeight(dx, dy, 1.0) *
                                                                 (dx <= 0 ? 1.0 : 0.5);
  EXPECT_NEAR(edge, (0.30 * wSame + 0.35 * wOther) / (wSame + wOther), 1e-6);
}

TEST(EmpiricalShading, SmoothingSkipsBackgroundTexels) {
  DepthImage im = image(7, 7, 1.0f);
  for (int y = 0; y < 7; ++y)
    for (int x = 0; x < 4; ++x) im.depth[size_t(y * 7 + x)] = 0.2f;
  // With a threshold far above the background's deviation (0.8), background texels would get
  // weight if they were not skipped by value.
  SmoothingOptions o;
  o.threshold = 10.0;
  const DepthImage out = smoothDepth(im, o);
  for (int y = 0; y < 7; ++y)
    for (int x = 0; x < 7; ++x) EXPECT_FLOAT_EQ(out.at(x, y), x < 4 ? 0.2f : 1.0f);
  o.kernelSize = 4;
  EXPECT_THROW(smoothDepth(im, o), ParameterError);
}

ShadingParameters zeroed() {
  ShadingParameters p;
  p.ka = p.wd = p.ws = p.ks = p.wb = p.Kb = 0.0;
  return p;
}

TEST(EmpiricalShading, EachLightingTermInIsolation) {
  const glm::dvec3 N(0, 0, 1);
  const glm::dvec3 L = glm::normalize(glm::dvec3(0.6, 0, 0.8));  // N·L = 0.8
  const glm::dvec3 V(0, 0, 1);
  const glm::dvec3 H = glm::normalize(L + V);
  const double NdotH = glm::dot(N, H);
  ShadingParameters base = zeroed();
  base.Kd = {0.8, 0.5, 0.25};
  base.Ia = {0.5, 1.0, 2.0};
  base.Id = {1.0, 0.5, 0.25};
  base.Is = {0.25, 1.0, 0.5};
  base.shininess = 12.0;
  base.r = 3.0;
  // Ambient, Eq. 3.7.
  ShadingParameters p = base;
  p.ka = 0.3;
  ShadingTerms s = shade(p, 0.6, N, L, H, 0.4);
  for (int c = 0; c < 3; ++c) EXPECT_DOUBLE_EQ(s.total()[c], 0.6 * 0.3 * base.Kd[c] * base.Ia[c]);
  // Diffuse, Eq. 3.8.
  p = base;
  p.wd = 0.7;
  s = shade(p, 0.6, N, L, H, 0.4);
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(s.total()[c], 0.7 * base.Kd[c] * base.Id[c] * 0.8, 1e-15);
  // Specular, Eq. 3.9.
  p = base;
  p.ws = 0.9;
  p.ks = 0.5;
  s = shade(p, 0.6, N, L, H, 0.4);
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(s.total()[c], 0.9 * 0.5 * base.Is[c] * std::pow(NdotH, 12.0), 1e-15);
  // Backlight, Eq. 3.10: wb (1 - t)^r (Kd + Kb), whatever the light direction.
  p = base;
  p.wb = 1.2;
  p.Kb = 0.2;
  s = shade(p, 0.6, N, -L, H, 0.4);
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(s.total()[c], 1.2 * std::pow(0.6, 3.0) * (base.Kd[c] + 0.2), 1e-15);
  EXPECT_EQ(s.diffuse, glm::dvec3(0.0));
  // Facing away from the light: no diffuse and no specular (C.2.3), even with N·H > 0.
  p = base;
  p.wd = p.ws = p.ks = 1.0;
  s = shade(p, 1.0, N, -L, glm::normalize(N + glm::dvec3(0.1, 0, 0)), 0.0);
  EXPECT_EQ(s.total(), glm::dvec3(0.0));
}

TEST(EmpiricalShading, SurveyPresetsFollowTable4_3) {
  ASSERT_EQ(surveyPresetNames().size(), 9u);
  EXPECT_EQ(surveyPresetNames().front(), "survey1");
  EXPECT_EQ(surveyPreset(2).thicknessExponent, 18);
  EXPECT_EQ(surveyPreset(3).thicknessExponent, 30);
  EXPECT_EQ(surveyPreset(5).backlight, 0.80);
  EXPECT_EQ(surveyPreset(6).backlight, 1.60);
  EXPECT_EQ(surveyPreset(8).diffuseWeight, 0.0);
  EXPECT_EQ(surveyPreset(9).diffuseWeight, 0.50);
  for (int i : {1, 4, 7}) {
    EXPECT_EQ(surveyPreset(i).thicknessExponent, 25);
    EXPECT_EQ(surveyPreset(i).backlight, 1.20);
    EXPECT_EQ(surveyPreset(i).diffuseWeight, 0.20);
  }
  EXPECT_THROW(surveyPreset(0), ParameterError);
  EXPECT_THROW(surveyPreset(10), ParameterError);
}

// Random lighting: unit directions, the same path for the same seed, a different one for another
// seed, small steps between frames (no flicker) and, over a long run, every azimuth quadrant and
// elevations near the stated ±64° limits (|y| = 0.9 at the extremes).
TEST(EmpiricalShading, RandomLightingFollowsASmoothPathOverTheSphere) {
  double maxStep = 0.0, minY = 1.0, maxY = -1.0;
  int quadrants[4] = {0, 0, 0, 0};
  glm::dvec3 previous = randomLightDirection(7, 0);
  for (long long f = 0; f < 4000; ++f) {
    const glm::dvec3 d = randomLightDirection(7, f);
    ASSERT_NEAR(glm::length(d), 1.0, 1e-12) << "frame " << f;
    EXPECT_EQ(d, randomLightDirection(7, f));
    maxStep = std::max(maxStep, glm::length(d - previous));
    previous = d;
    minY = std::min(minY, d.y);
    maxY = std::max(maxY, d.y);
    quadrants[(d.x >= 0 ? 0 : 1) + (d.z >= 0 ? 0 : 2)]++;
  }
  // Per frame |Δφ| sin θ <= ω1 <= 0.06 and |Δθ| <= 0.9 ω2 <= 0.054, so a step (chord) is at most
  // sqrt(0.06² + 0.054²) ≈ 0.081 (plus a second-order term).
  EXPECT_LT(maxStep, 0.12);
  EXPECT_GT(maxY, 0.89);
  EXPECT_LT(minY, -0.89);
  for (int q = 0; q < 4; ++q) EXPECT_GT(quadrants[q], 200) << "quadrant " << q;
  EXPECT_GT(glm::length(randomLightDirection(8, 100) - randomLightDirection(7, 100)), 1e-3);
}

}  // namespace
}  // namespace translucent::empirical
