#include "bssrdf/exit_radiance.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <numbers>

#include "optics/fresnel.h"
#include "optics/medium.h"
#include "optics/quadrature.h"

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

double exitConventionScale(ExitConvention convention, double eta) {
  return convention == ExitConvention::Jensen ? 1.0 : 1.0 / diffuseTransmittanceFromOutside(eta);
}

double exitRadianceFactor(ExitConvention convention, double eta, double cos_o) {
  return exitRadianceFactor(convention, eta, cos_o, diffuseTransmittanceFromOutside(eta));
}

}  // namespace translucent::bssrdf
