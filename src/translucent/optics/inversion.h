// SPDX-License-Identifier: GPL-3.0-or-later
// Parameter inversion (seed section 3.4, after Jensen & Buhler 2002): from the total diffuse
// reflectance Rd and the diffuse mean free path ℓd per channel back to σa and σs'.
#pragma once

#include <functional>

#include "translucent/optics/medium.h"

namespace translucent {

// Rd as a function of the reduced albedo α' in [0, 1] (η fixed); must be increasing.
using AlbedoToReflectance = std::function<double(double alpha_prime)>;

// Solves Rd(α') = rd for α' by bisection on [0, 1] (bracketing, so it never diverges) to an
// absolute width below 1e-12. Throws ParameterError stating the reachable range (0, Rd(1)) when
// rd is out of it. `what` names the parameter in messages (e.g. "Rd (red channel)").
double invertReducedAlbedo(const AlbedoToReflectance& rd_of_albedo, double rd,
                           const std::string& what = "Rd");

struct ReducedCoefficients {
  double sigma_a;        // [1/length]
  double sigma_s_prime;  // [1/length]
  double alpha_prime;
};

// Eqs. 3.3-3.5: σt' = 1 / (ℓd sqrt(3(1 - α'))), σs' = α' σt', σa = σt' - σs'. This uses the
// classic diffusion σtr = sqrt(3 σa σt') for every model, so that ℓd means the same thing (1/σtr
// of the medium) whichever model produced Rd(α').
ReducedCoefficients coefficientsFromAlbedo(double alpha_prime, double ld);

// Whole-medium inversion: per channel rd[c], ld[c] > 0 -> medium with g and eta given.
Medium invertMedium(const AlbedoToReflectance& rd_of_albedo, const Rgb& rd, const Rgb& ld,
                    double eta, double g = 0.0);

}  // namespace translucent
