// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/bssrdf/exit_radiance.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "translucent/optics/fresnel.h"
#include "translucent/optics/medium.h"
#include "translucent/optics/quadrature.h"

namespace translucent::bssrdf {

const char* toString(ExitConvention convention) {
  return convention == ExitConvention::Jensen ? "jensen" : "normalized";
}

std::vector<std::string> exitConventionNames() { return {"jensen", "normalized"}; }

ExitConvention parseExitConvention(std::string_view name) {
  if (name == "jensen") return ExitConvention::Jensen;
  if (name == "normalized") return ExitConvention::Normalized;
  throw ParameterError(fmt::format("radiance convention '{}': expected one of {}", name,
                                   fmt::join(exitConventionNames(), ", ")));
}

double diffuseTransmittanceFromOutside(double eta) {
  if (eta == 1.0) return 1.0;
  // From outside there is no total internal reflection and Ft(μ) is smooth on [0, 1] except for
  // the Brewster-angle kink, which 16 panels of 8 Gauss points resolve to ~1e-12.
  constexpr int kPanels = 16;
  double sum = 0.0;
  for (int p = 0; p < kPanels; ++p) {
    const double a = static_cast<double>(p) / kPanels, h = 1.0 / kPanels;
    for (int i = 0; i < 8; ++i) {
      const double mu = a + 0.5 * h * (1.0 + kGauss8X[i]);
      sum += 0.5 * h * kGauss8W[i] * fresnelTransmittance(mu, eta) * mu;
    }
  }
  return 2.0 * sum;
}

double exitRadianceFactor(ExitConvention convention, double eta, double cos_o, double norm) {
  const double ft = eta == 1.0 ? 1.0 : fresnelTransmittance(cos_o, eta);
  const double f = ft / std::numbers::pi;
  return convention == ExitConvention::Jensen ? f : f / norm;
}

double coneAveragedExitRadianceFactor(ExitConvention convention, double eta, double cos_o,
                                      double cone_half_angle) {
  if (!(cos_o > 0.0 && cos_o <= 1.0))
    throw ParameterError(fmt::format("exit cosine {}: expected a value in (0, 1]", cos_o));
  if (!(cone_half_angle > 0.0 && cone_half_angle <= 0.5 * std::numbers::pi))
    throw ParameterError(fmt::format("cone half-angle {} rad: expected a value in (0, π/2]",
                                     cone_half_angle));
  const double norm = diffuseTransmittanceFromOutside(eta);
  // Directions about v: polar angle a from v in [0, θc], azimuth φ from the plane of n and v,
  // n·ω = cos a cos θv + sin a sin θv cos φ; the integrand is even in φ, so φ in [0, π] twice.
  // Gauss panels in both; where the cone crosses the horizon the integrand has a kink (the
  // clamp) that the panels resolve to the stated accuracy.
  const double sinV = std::sqrt(std::max(0.0, 1.0 - cos_o * cos_o));
  constexpr int kPanelsA = 8, kPanelsPhi = 16;
  double sum = 0.0;
  for (int pa = 0; pa < kPanelsA; ++pa) {
    const double ha = cone_half_angle / kPanelsA, a0 = pa * ha;
    for (int ia = 0; ia < 8; ++ia) {
      const double a = a0 + 0.5 * ha * (1.0 + kGauss8X[ia]);
      const double wa = 0.5 * ha * kGauss8W[ia] * std::sin(a);
      double inner = 0.0;
      for (int pp = 0; pp < kPanelsPhi; ++pp) {
        const double hp = std::numbers::pi / kPanelsPhi, p0 = pp * hp;
        for (int ip = 0; ip < 8; ++ip) {
          const double phi = p0 + 0.5 * hp * (1.0 + kGauss8X[ip]);
          const double mu = std::cos(a) * cos_o + std::sin(a) * sinV * std::cos(phi);
          if (mu > 0.0)
            inner += 0.5 * hp * kGauss8W[ip] * exitRadianceFactor(convention, eta, std::min(mu, 1.0), norm) * mu;
        }
      }
      sum += wa * 2.0 * inner;
    }
  }
  const double s = std::sin(cone_half_angle);
  return sum / (std::numbers::pi * s * s * cos_o);
}

double exitConventionScale(ExitConvention convention, double eta) {
  return convention == ExitConvention::Jensen ? 1.0 : 1.0 / diffuseTransmittanceFromOutside(eta);
}

double exitRadianceFactor(ExitConvention convention, double eta, double cos_o) {
  return exitRadianceFactor(convention, eta, cos_o, diffuseTransmittanceFromOutside(eta));
}

}  // namespace translucent::bssrdf
