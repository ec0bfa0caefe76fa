// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/optics/medium.h"

#include <fmt/format.h>

#include <utility>

#include "translucent/optics/fresnel.h"
#include "translucent/optics/quadrature.h"

namespace translucent {
namespace {

std::string where(const std::string& channel) {
  return channel.empty() ? std::string{} : fmt::format(" ({} channel)", channel);
}

void checkCoefficient(const char* name, double v, const std::string& channel) {
  if (!std::isfinite(v))
    throw ParameterError(fmt::format("{}{} is {}: expected a finite value", name, where(channel), v));
  if (v < 0.0)
    throw ParameterError(
        fmt::format("{}{} is {}: expected a non-negative coefficient", name, where(channel), v));
}

// Legal numbers that lead nowhere are refused with the others: an index of refraction of 1e-320,
// a scale of 1e308 or a coefficient of 1e300 gave NaN profiles or empty radius grids whose
// messages named something else. The bounds are far outside any material.
constexpr double kMinEta = 1e-2, kMaxEta = 1e2;
constexpr double kMinScale = 1e-9, kMaxScale = 1e9;
constexpr double kMaxCoefficient = 1e12;  // per medium unit (1/mm for the presets)

void checkShared(double g, double eta) {
  if (!std::isfinite(g) || std::abs(g) >= 1.0)
    throw ParameterError(fmt::format("g is {}: expected a mean cosine in (-1, 1)", g));
  if (!std::isfinite(eta) || eta <= 0.0)
    throw ParameterError(fmt::format("eta is {}: expected a positive index of refraction", eta));
  if (eta < kMinEta || eta > kMaxEta)
    throw ParameterError(fmt::format("eta is {}: expected an index of refraction in [{:g}, {:g}]",
                                     eta, kMinEta, kMaxEta));
}

}  // namespace

void ScalarMedium::validate(const std::string& channel_name) const {
  checkCoefficient("sigma_a", sigma_a, channel_name);
  checkCoefficient("sigma_s", sigma_s, channel_name);
  checkShared(g, eta);
  if (!(sigmaTPrime() > 0.0))
    throw ParameterError(fmt::format(
        "sigma_t'{} is {}: the medium neither absorbs nor scatters (need sigma_a + sigma_s' > 0)",
        where(channel_name), sigmaTPrime()));
}

void Medium::validate() const {
  checkShared(g, eta);
  if (!std::isfinite(scale) || scale <= 0.0)
    throw ParameterError(fmt::format("scale is {}: expected a positive number", scale));
  if (scale < kMinScale || scale > kMaxScale)
    throw ParameterError(fmt::format("scale is {}: expected medium units per scene unit in "
                                     "[{:g}, {:g}]", scale, kMinScale, kMaxScale));
  // The coefficients as given (messages name those values, not the ones times the scale).
  for (int c = 0; c < 3; ++c) {
    const auto k = static_cast<size_t>(c);
    checkCoefficient("sigma_a", sigma_a[k], kChannelNames[c]);
    checkCoefficient("sigma_s", sigma_s[k], kChannelNames[c]);
    for (const auto& [name, v] : {std::pair{"sigma_a", sigma_a[k]}, std::pair{"sigma_s", sigma_s[k]}})
      if (v > kMaxCoefficient)
        throw ParameterError(fmt::format("{} ({} channel) is {}: expected at most {:g} per unit "
                                         "length", name, kChannelNames[c], v, kMaxCoefficient));
  }
  for (int c = 0; c < 3; ++c) channel(c).validate(kChannelNames[c]);
}

Medium Medium::fromReduced(const Rgb& sigma_a, const Rgb& sigma_s_prime, double g, double eta,
                           double scale) {
  checkShared(g, eta);
  Medium m;
  m.sigma_a = sigma_a;
  for (size_t c = 0; c < 3; ++c) m.sigma_s[c] = sigma_s_prime[c] / (1.0 - g);
  m.g = g;
  m.eta = eta;
  m.scale = scale;
  return m;
}

double fdrRational(double eta) {
  // Eq. 2.30 (Egan & Hilgeman 1979).
  return -1.440 / (eta * eta) + 0.710 / eta + 0.668 + 0.0636 * eta;
}

double fdrIntegral(double eta) {
  // Fdr = 2 ∫0^1 Fr(μ) μ dμ for light inside the medium (relative index 1/η on the way out).
  // Below the critical cosine μc everything is reflected (TIR): that part is exactly μc². Above
  // it, Fr has a square-root kink at μc, removed by the substitution μ = μc + (1 - μc) t², after
  // which composite Gauss-Legendre converges to ~1e-13.
    const double inv = 1.0 / eta;
  const double muCrit = eta > 1.0 ? std::sqrt(1.0 - 1.0 / (eta * eta)) : 0.0;
  constexpr int kPanels = 64;
  double sum = 0.0;
  const double h = 1.0 / kPanels;
  for (int p = 0; p < kPanels; ++p) {
    for (int i = 0; i < 8; ++i) {
      const double t = (p + 0.5 * (kGauss8X[i] + 1.0)) * h;
      const double mu = muCrit + (1.0 - muCrit) * t * t;
      const double dmu = 2.0 * (1.0 - muCrit) * t;
      sum += 0.5 * h * kGauss8W[i] * fresnelReflectance(mu, inv) * mu * dmu;
    }
  }
  return muCrit * muCrit + 2.0 * sum;
}

double internalReflectionA(double eta) {
  const double fdr = fdrRational(eta);
  return (1.0 + fdr) / (1.0 - fdr);
}

}  // namespace translucent
