// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/lights/environment_map.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/common.hpp>

#include "translucent/io/image_io.h"
#include "translucent/optics/fresnel.h"
#include "translucent/optics/medium.h"

namespace translucent::lights {

namespace {

constexpr float kMaxEnvironmentRadiance = 1e20f;  // [W/(m² sr)] per texel and channel

constexpr double kPi = std::numbers::pi;

// Real SH basis for l <= 2 (same constants and order as irradiance.comp).
std::array<double, 9> shBasis(const glm::dvec3& n) {
  return {0.282095,
          0.488603 * n.y,
          0.488603 * n.z,
          0.488603 * n.x,
          1.092548 * n.x * n.y,
          1.092548 * n.y * n.z,
          0.315392 * (3.0 * n.z * n.z - 1.0),
          1.092548 * n.x * n.z,
          0.546274 * (n.x * n.x - n.y * n.y)};
}

double luminance(const glm::vec3& c) {
  return 0.2126 * double(c.r) + 0.7152 * double(c.g) + 0.0722 * double(c.b);
}

}  // namespace

EnvironmentMap EnvironmentMap::load(const std::filesystem::path& file) {
  analysis::RgbImage img;
  try {
    img = analysis::readRgb(file.string());
  } catch (const std::exception& e) {
    throw ParameterError(fmt::format("environment map '{}' cannot be read: {}", file.string(), e.what()));
  }
  if (img.width < 2 || img.height < 1 || img.rgb.size() != size_t(img.width) * size_t(img.height) * 3)
    throw ParameterError(fmt::format("environment map '{}' is {}x{}: expected a latitude-longitude "
                                     "image of at least 2x1 pixels", file.string(), img.width, img.height));
  // Negative values are clamped to 0 (as pbrt-v4's image lights do): lossy-compressed HDRs hold
  // slightly negative texels (Blender's studio lights, e.g. -1e-5 next to radiance ~1), which
  // no light can emit; how many were clamped is kept. Non-finite values are an error.
  size_t clamped = 0;
  bool emits = false;
  for (size_t i = 0; i < img.rgb.size(); ++i) {
    if (!std::isfinite(img.rgb[i]))
      throw ParameterError(fmt::format("environment map '{}': pixel {} holds {}: expected finite "
                                       "radiance", file.string(), i / 3, img.rgb[i]));
    // Finite but near float's limit, a texel overflows the sums and products made of it (3e38
    // gave NaN pixels): far beyond any measured sky (the sun's disc is ~1e9).
    if (img.rgb[i] > kMaxEnvironmentRadiance)
      throw ParameterError(fmt::format("environment map '{}': pixel {} holds {}: expected radiance "
                                       "at most {:g}", file.string(), i / 3, img.rgb[i],
                                       kMaxEnvironmentRadiance));
    if (img.rgb[i] < 0.0f) {
      img.rgb[i] = 0.0f;
      ++clamped;
    }
    emits = emits || img.rgb[i] > 0.0f;
  }
  // A black map lights nothing: every renderer and tracer would give a black image.
  if (!emits)
    throw ParameterError(fmt::format("environment map '{}': every pixel is 0 (black){}: it emits "
                                     "no light; expected some radiance > 0", file.string(),
                                     clamped ? " once negative values are clamped to 0" : ""));
  EnvironmentMap m;
  m.width = img.width;
  m.height = img.height;
  m.rgb = std::move(img.rgb);
  m.clamped_negative = clamped;
  return m;
}

EnvironmentMap EnvironmentMap::constant(const glm::vec3& radiance, int width, int height) {
  EnvironmentMap m;
  m.width = width;
  m.height = height;
  m.rgb.resize(size_t(width) * size_t(height) * 3);
  for (size_t i = 0; i < m.rgb.size(); i += 3) {
    m.rgb[i] = radiance.r;
    m.rgb[i + 1] = radiance.g;
    m.rgb[i + 2] = radiance.b;
  }
  return m;
}

glm::vec3 EnvironmentMap::texel(int x, int y) const {
  const size_t i = (size_t(y) * size_t(width) + size_t(x)) * 3;
  return {rgb[i], rgb[i + 1], rgb[i + 2]};
}

glm::dvec3 EnvironmentMap::direction(double u, double v, double rotate) {
  const double phi = 2.0 * kPi * u - kPi + rotate * kPi / 180.0;
  const double theta = kPi * v;
  return {std::sin(theta) * std::sin(phi), std::cos(theta), -std::sin(theta) * std::cos(phi)};
}

glm::ivec2 EnvironmentMap::texelOf(const glm::dvec3& d, double rotate) const {
  const double theta = std::acos(std::clamp(d.y, -1.0, 1.0));
  double phi = std::atan2(d.x, -d.z) - rotate * kPi / 180.0;
  double u = (phi + kPi) / (2.0 * kPi);
  u -= std::floor(u);
  const double v = theta / kPi;
  return {std::min(width - 1, static_cast<int>(u * width)),
          std::min(height - 1, static_cast<int>(v * height))};
}

glm::vec3 EnvironmentMap::lookup(const glm::dvec3& d, double rotate) const {
  const glm::ivec2 t = texelOf(d, rotate);
  return texel(t.x, t.y);
}

std::array<double, 3> transmittedIrradianceLambdas(double eta) {
  // λ_l = 2π ∫0^1 Ft(η, t) t P_l(t) dt by composite Gauss-Legendre (Ft has a kink only at t = 0).
  static constexpr double x[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563,
                                  0.8611363115940526};
  static constexpr double w[4] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461,
                                  0.3478548451374538};
  std::array<double, 3> lambda{};
  const int panels = 256;
  for (int p = 0; p < panels; ++p) {
    const double a = double(p) / panels, b = double(p + 1) / panels;
    for (int k = 0; k < 4; ++k) {
      const double t = 0.5 * (a + b) + 0.5 * (b - a) * x[k];
      const double f = fresnelTransmittance(t, eta) * t * 0.5 * (b - a) * w[k];
      lambda[0] += f;
      lambda[1] += f * t;
      lambda[2] += f * 0.5 * (3.0 * t * t - 1.0);
    }
  }
  for (double& l : lambda) l *= 2.0 * kPi;
  return lambda;
}

std::array<glm::vec3, 9> irradianceSh9(const EnvironmentMap& map, double rotate, double eta,
                                       const glm::dvec3& scale) {
  // L_lm = ∫ L(ω) Y_lm(ω) dω, texel by texel with the exact solid angle ΔΩ = Δφ (cos θ0 - cos θ1)
  // (so that the constant term is exact, as the samplers' integrals) and Y_lm at its centre.
  std::array<glm::dvec3, 9> l{};
  const double dPhi = 2.0 * kPi / map.width;
  for (int y = 0; y < map.height; ++y) {
    const double v = (y + 0.5) / map.height;
    const double dOmega =
        dPhi * (std::cos(kPi * y / map.height) - std::cos(kPi * (y + 1) / map.height));
    for (int x = 0; x < map.width; ++x) {
      const glm::dvec3 d = EnvironmentMap::direction((x + 0.5) / map.width, v, rotate);
      const glm::dvec3 c = glm::dvec3(map.texel(x, y)) * dOmega;
      const auto y9 = shBasis(d);
      for (int k = 0; k < 9; ++k) l[size_t(k)] += c * y9[size_t(k)];
    }
  }
  const auto lambda = transmittedIrradianceLambdas(eta);
  std::array<glm::vec3, 9> out{};
  for (int k = 0; k < 9; ++k) {
    const int band = k == 0 ? 0 : k < 4 ? 1 : 2;
    out[size_t(k)] = glm::vec3(l[size_t(k)] * lambda[size_t(band)] * scale);
  }
  return out;
}

glm::dvec3 evalSh9(const std::array<glm::vec3, 9>& sh, const glm::dvec3& n) {
  const auto y = shBasis(n);
  glm::dvec3 e(0.0);
  for (int k = 0; k < 9; ++k) e += glm::dvec3(sh[size_t(k)]) * y[size_t(k)];
  return glm::max(e, glm::dvec3(0.0));
}

double EnvironmentSampler::weightOf(const glm::vec3& c) const {
  switch (weight_) {
    case SampleWeight::Red: return double(c.r);
    case SampleWeight::Green: return double(c.g);
    case SampleWeight::Blue: return double(c.b);
    case SampleWeight::Luminance: break;
  }
  return luminance(c);
}

EnvironmentSampler::EnvironmentSampler(const EnvironmentMap& map, double rotate, SampleWeight weight)
    : map_(&map), rotate_(rotate), weight_(weight) {
  const int w = map.width, h = map.height;
  rowCdf_.assign(size_t(h) + 1, 0.0);
  colCdf_.assign(size_t(h), std::vector<double>(size_t(w) + 1, 0.0));
  rowWeight_.assign(size_t(h), 0.0);
  const double dPhi = 2.0 * kPi / w;
  for (int y = 0; y < h; ++y) {
    // The row's exact solid angle per texel: Δφ (cos θ0 - cos θ1).
    const double dOmega = dPhi * (std::cos(kPi * y / h) - std::cos(kPi * (y + 1) / h));
    auto& cdf = colCdf_[size_t(y)];
    for (int x = 0; x < w; ++x) cdf[size_t(x) + 1] = cdf[size_t(x)] + weightOf(map.texel(x, y)) * dOmega;
    rowWeight_[size_t(y)] = cdf[size_t(w)];
    rowCdf_[size_t(y) + 1] = rowCdf_[size_t(y)] + cdf[size_t(w)];
  }
  total_ = rowCdf_.back();
  if (!(total_ > 0.0))
    throw ParameterError(fmt::format("environment map: its {} is zero everywhere: nothing to sample",
                                     weight == SampleWeight::Luminance ? "luminance"
                                     : weight == SampleWeight::Red     ? "red channel"
                                     : weight == SampleWeight::Green   ? "green channel"
                                                                       : "blue channel"));
}

EnvironmentSampler::Sample EnvironmentSampler::sample(const glm::dvec2& u) const {
  const int w = map_->width, h = map_->height;
  // Row, then column, by inverting the cumulative sums (binary search).
  const double ty = std::clamp(u.y, 0.0, 1.0 - 1e-12) * total_;
  int y = std::clamp(static_cast<int>(std::upper_bound(rowCdf_.begin(), rowCdf_.end(), ty) -
                                      rowCdf_.begin()) - 1, 0, h - 1);
  while (rowWeight_[size_t(y)] <= 0.0 && y > 0) --y;  // ty on a boundary below empty rows
  const double ry = std::clamp((ty - rowCdf_[size_t(y)]) / rowWeight_[size_t(y)], 0.0, 1.0);
  const auto& cdf = colCdf_[size_t(y)];
  const double tx = std::clamp(u.x, 0.0, 1.0 - 1e-12) * cdf.back();
  int x = std::clamp(static_cast<int>(std::upper_bound(cdf.begin(), cdf.end(), tx) -
                                      cdf.begin()) - 1, 0, w - 1);
  while (cdf[size_t(x) + 1] - cdf[size_t(x)] <= 0.0 && x > 0) --x;
  const double rx = std::clamp((tx - cdf[size_t(x)]) / std::max(cdf[size_t(x) + 1] - cdf[size_t(x)], 1e-300),
                               0.0, 1.0);
  // Uniform in solid angle within the texel: φ linear in rx, cos θ linear in ry.
  const double c0 = std::cos(kPi * y / h), c1 = std::cos(kPi * (y + 1) / h);
  const double cosT = std::clamp(c0 + ry * (c1 - c0), -1.0, 1.0);
  const double su = (x + rx) / w;
  const double sv = std::acos(cosT) / kPi;
  Sample s;
  s.direction = EnvironmentMap::direction(su, sv, rotate_);
  const glm::vec3 c = map_->texel(x, y);
  s.radiance = glm::dvec3(c);
  s.pdf = weightOf(c) / total_;
  return s;
}

double EnvironmentSampler::pdf(const glm::dvec3& d) const {
  const glm::ivec2 t = map_->texelOf(d, rotate_);
  return weightOf(map_->texel(t.x, t.y)) / total_;
}

EnvironmentSampler::Sample EnvironmentSampler::sequence(uint64_t k, uint64_t seed) const {
  // R2: the additive recurrence with the plastic number's reciprocal powers.
  constexpr double g = 1.32471795724474602596;
  constexpr double a1 = 1.0 / g, a2 = 1.0 / (g * g);
  const double o1 = std::fmod(0.5 + 0.61803398874989485 * double(seed % 1000003), 1.0);
  const double o2 = std::fmod(0.5 + 0.41421356237309505 * double(seed % 1000003), 1.0);
  glm::dvec2 u(std::fmod(o1 + a1 * double(k), 1.0), std::fmod(o2 + a2 * double(k), 1.0));
  return sample(u);
}

}  // namespace translucent::lights
