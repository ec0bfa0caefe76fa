// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/optics/inversion.h"

#include <fmt/format.h>

#include <cmath>

namespace translucent {

double invertReducedAlbedo(const AlbedoToReflectance& rd_of_albedo, double rd,
                           const std::string& what) {
  const double rdMax = rd_of_albedo(1.0);
  if (!std::isfinite(rd) || rd <= 0.0 || rd >= rdMax)
    throw ParameterError(fmt::format(
        "{} is {}: not reachable, the model reaches total diffuse reflectances in (0, {:.6g}) "
        "for this index of refraction",
        what, rd, rdMax));
  // Bisection: Rd(α') is monotone in α', so the bracket [lo, hi] always holds the root.
  double lo = 0.0, hi = 1.0;
  while (hi - lo > 1e-12) {
    const double mid = 0.5 * (lo + hi);
    if (rd_of_albedo(mid) < rd)
      lo = mid;
    else
      hi = mid;
  }
  return 0.5 * (lo + hi);
}

ReducedCoefficients coefficientsFromAlbedo(double alpha_prime, double ld) {
  const double sigmaTPrime = 1.0 / (ld * std::sqrt(3.0 * (1.0 - alpha_prime)));  // Eq. 3.3
  const double sigmaSPrime = alpha_prime * sigmaTPrime;                           // Eq. 3.4
  return {sigmaTPrime - sigmaSPrime, sigmaSPrime, alpha_prime};                   // Eq. 3.5
}

Medium invertMedium(const AlbedoToReflectance& rd_of_albedo, const Rgb& rd, const Rgb& ld,
                    double eta, double g) {
  Rgb sigmaA{}, sigmaSPrime{};
  for (size_t c = 0; c < 3; ++c) {
    if (!std::isfinite(ld[c]) || ld[c] <= 0.0)
      throw ParameterError(fmt::format("ld ({} channel) is {}: expected a positive length",
                                       kChannelNames[c], ld[c]));
    const double a = invertReducedAlbedo(rd_of_albedo, rd[c],
                                         fmt::format("Rd ({} channel)", kChannelNames[c]));
    const auto k = coefficientsFromAlbedo(a, ld[c]);
    // A positive ℓd can still be out of reach: 1e-320 makes σt' = 1/(ℓd ...) infinite (and σa
    // NaN), 1e308 makes it vanish below the smallest normal number.
    const double sigmaT = k.sigma_a + k.sigma_s_prime;
    if (!std::isfinite(k.sigma_a) || !std::isfinite(k.sigma_s_prime) || !std::isnormal(sigmaT))
      throw ParameterError(fmt::format(
          "ld ({} channel) is {}: out of range, the coefficients 1/ℓd are not finite and non-zero "
          "numbers (σa {}, σs' {}); expected a length between 1e-300 and 1e300",
          kChannelNames[c], ld[c], k.sigma_a, k.sigma_s_prime));
    sigmaA[c] = k.sigma_a;
    sigmaSPrime[c] = k.sigma_s_prime;
  }
  return Medium::fromReduced(sigmaA, sigmaSPrime, g, eta);
}

}  // namespace translucent
