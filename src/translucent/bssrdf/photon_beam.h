// SPDX-License-Identifier: GPL-3.0-or-later
// The two parts of the photon beam diffusion profile (photon_beam.cpp; Habel, Christensen &
// Jarosz 2013), evaluated directly, without the registered profile's interpolation tables. The
// registered model "photon-beam" has R(r) = photonBeamMultiple(r) + photonBeamSingle(r).
//
// Both are per unit flux entering the medium through a normally incident pencil beam, exitance
// through the surface (after the Fresnel transmission out of the medium) [1/length²].
#pragma once

#include "translucent/optics/medium.h"

namespace translucent::bssrdf {

// Multiple scattering: the better-dipole response of each point of the refracted beam, integrated
// along the beam by the importance-sampled quadrature of the paper. About 10 µs per call.
// Logarithmically infinite at r = 0. Throws ParameterError for an invalid medium or r < 0.
double photonBeamMultiple(double r, const ScalarMedium& medium);

// Single scattering: light scattered exactly once on the refracted beam and transmitted out through
// the surface (depends on σs, σa, g, η, not on reduced coefficients). Behaves like 1/r near the
// source (infinite at r = 0; r·R stays finite). Throws ParameterError as above.
double photonBeamSingle(double r, const ScalarMedium& medium);

// Totals 2π ∫ R r dr of the two parts: the multiple part by a 2D quadrature independent of the
// profile's (closed forms where the dipole has them), the single part by its 1D angular form
// Rd_ss = 2π α ∫_{μc}^1 p(-μ) T(μ) μ / (1 + μ) dμ.
double photonBeamMultipleRd(const ScalarMedium& medium);
double photonBeamSingleRd(const ScalarMedium& medium);

}  // namespace translucent::bssrdf
