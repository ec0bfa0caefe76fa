// SPDX-License-Identifier: GPL-3.0-or-later
// The empirical translucency shader's per-pixel mathematics on the CPU (shading.h).
#include "translucent/techniques/empirical/shading.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include <glm/geometric.hpp>

#include "translucent/optics/medium.h"  // ParameterError

namespace translucent::empirical {

double linearDepth(double windowDepth, const glm::dmat4& P) {
  // Window [0, 1] -> NDC [-1, 1]; then solve ndc = (P22 z + P32) / (P23 z + P33) for eye z.
  const double ndc = 2.0 * windowDepth - 1.0;
  const double z = (P[3][2] - ndc * P[3][3]) / (ndc * P[2][3] - P[2][2]);
  return -z;  // the camera looks down -z
}

double thickness(double frontDistance, double backDistance, double diameter) {
  if (!(diameter > 0.0))
    throw ParameterError(fmt::format("thickness: scene diameter {}: expected > 0", diameter));
  return std::clamp((backDistance - frontDistance) / diameter, 0.0, 1.0);
}

double gaussianWeight(int dx, int dy, double sigma) {
  return std::exp(-double(dx * dx + dy * dy) / (2.0 * sigma * sigma));
}

namespace {
void checkSmoothing(const SmoothingOptions& o) {
  if (o.kernelSize < 1 || o.kernelSize > 15 || o.kernelSize % 2 == 0)
    throw ParameterError(fmt::format("smoothing kernel size {}: expected an odd number in [1, 15]",
                                     o.kernelSize));
  if (!(o.sigma > 0.0) || !std::isfinite(o.sigma))
    throw ParameterError(fmt::format("smoothing sigma {}: expected a finite value > 0", o.sigma));
  if (!(o.threshold > 0.0) || !std::isfinite(o.threshold))
    throw ParameterError(fmt::format("smoothing threshold {}: expected a finite value > 0",
                                     o.threshold));
}
}  // namespace

float smoothDepth(const DepthImage& image, int x, int y, const SmoothingOptions& options) {
  checkSmoothing(options);
  const float centre = image.at(x, y);
  if (centre == image.background) return image.background;
  const int radius = options.kernelSize / 2;
  double sum = 0.0, weight = 0.0;
  for (int dy = -radius; dy <= radius; ++dy)
    for (int dx = -radius; dx <= radius; ++dx) {
      const int sx = x + dx, sy = y + dy;
      if (sx < 0 || sy < 0 || sx >= image.width || sy >= image.height) continue;
      const float z = image.at(sx, sy);
      if (z == image.background) continue;  // the seed's `tmp < 0.99` test
      // Eq. C.1: the weight falls linearly to 0 at a deviation of `threshold`, so the blur never
      // mixes depths across a silhouette or a step in the back surface.
      const double deviation = std::abs(double(z) - double(centre));
      const double w = gaussianWeight(dx, dy, options.sigma) *
                       (1.0 - std::clamp(deviation / options.threshold, 0.0, 1.0));
      sum += w * double(z);
      weight += w;
    }
  return static_cast<float>(sum / weight);  // weight >= 1: the centre always counts fully
}

DepthImage smoothDepth(const DepthImage& image, const SmoothingOptions& options) {
  checkSmoothing(options);
  DepthImage out = image;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      out.depth[size_t(y) * size_t(image.width) + size_t(x)] = smoothDepth(image, x, y, options);
  return out;
}

ShadingTerms shade(const ShadingParameters& p, double ao, const glm::dvec3& N, const glm::dvec3& L,
                   const glm::dvec3& H, double t) {
  ShadingTerms s;
  s.ambient = ao * p.ka * p.Kd * p.Ia;  // Eq. 3.7
  const double NdotL = std::max(glm::dot(N, L), 0.0);
  if (NdotL > 0.0) {
    s.diffuse = p.wd * p.Kd * p.Id * NdotL;  // Eq. 3.8
    const double NdotH = std::max(glm::dot(N, H), 0.0);
    s.specular = p.ws * p.ks * p.Is * std::pow(NdotH, p.shininess);  // Eq. 3.9
  }
  // Eq. 3.10: thin parts (t -> 0) get the most backlight.
  s.backlight = p.wb * std::pow(1.0 - std::clamp(t, 0.0, 1.0), p.r) * (p.Kd + glm::dvec3(p.Kb));
  return s;
}

SurveyPreset surveyPreset(int image) {
  // Table 4.3 (thickness exponent, backlight contribution, diffuse weight); images 1, 4 and 7
  // share their values in the table.
  static constexpr SurveyPreset kTable[kSurveyPresetCount] = {
      {25, 1.20, 0.20}, {18, 1.20, 0.20}, {30, 1.20, 0.20}, {25, 1.20, 0.20}, {25, 0.80, 0.20},
      {25, 1.60, 0.20}, {25, 1.20, 0.20}, {25, 1.20, 0.0},  {25, 1.20, 0.50}};
  if (image < 1 || image > kSurveyPresetCount)
    throw ParameterError(fmt::format("survey preset {}: expected 1 .. {} (Gascons 2011, Table 4.3)", image,
                                     kSurveyPresetCount));
  return kTable[image - 1];
}

std::vector<std::string> surveyPresetNames() {
  std::vector<std::string> names;
  for (int i = 1; i <= kSurveyPresetCount; ++i) names.push_back(fmt::format("survey{}", i));
  return names;
}

glm::dvec3 randomLightDirection(unsigned long long seed, long long frame) {
  // std::mt19937_64 and uniform draws by hand (uniform_real_distribution is not specified
  // bit-exactly across standard libraries; the canonical 53-bit mapping is).
  std::mt19937_64 rng(seed);
  auto uniform = [&rng] { return double(rng() >> 11) * 0x1.0p-53; };
  const double phi0 = 2.0 * std::numbers::pi * uniform();
  const double phi1 = 2.0 * std::numbers::pi * uniform();
  const double w1 = 0.02 + 0.04 * uniform();
  const double w2 = 0.02 + 0.04 * uniform();
  const double f = double(frame);
  const double phi = phi0 + w1 * f;
  const double cosTheta = 0.9 * std::sin(w2 * f + phi1);
  const double sinTheta = std::sqrt(1.0 - cosTheta * cosTheta);
  return {sinTheta * std::cos(phi), cosTheta, sinTheta * std::sin(phi)};
}

}  // namespace translucent::empirical
