// SPDX-License-Identifier: GPL-3.0-or-later
// Factories of the built-in models; one line each in registry.cpp. Private to src/bssrdf.
#pragma once

#include <memory>

#include "translucent/bssrdf/profile.h"

namespace translucent::bssrdf {

std::unique_ptr<Model> makeDipole();
std::unique_ptr<Model> makeDipoleExactFdr();  // boundary from the exact Fdr (dipole.cpp)
std::unique_ptr<Model> makeQuantizedDiffusionFdrFit();  // boundary from the Fdr fit
std::unique_ptr<Model> makeBetterDipole();
std::unique_ptr<Model> makeNormalizedDiffusion();
std::unique_ptr<Model> makeNormalizedDiffusionFit();
std::unique_ptr<Model> makeQuantizedDiffusion();
std::unique_ptr<Model> makePhotonBeam();
std::unique_ptr<Model> makeDirectionalDipole();

// Eq. 3.2, shared with models that reuse the dipole's total reflectance.
double dipoleTotalReflectance(double alpha_prime, double eta);
// The same for a given A of Eq. 2.32.
double dipoleTotalReflectanceForA(double alpha_prime, double A);

// The boundary constants of d'Eon's exitance for relative index η (boundary.cpp), from the exact
// first two Fresnel moments Cᵢ = ∫0^1 Fr(μ; 1/η) μⁱ dμ of the interface seen from inside.
struct BoundaryTerms {
  double A;     // (1 + 3C₂) / (1 - 2C₁): z_b = 2AD
  double cPhi;  // C_φ = (1 - 2C₁) / 4, weight of the fluence
  double cE;    // C_E = (1 - 3C₂) / 2, weight of the normal flux
};
BoundaryTerms boundaryTerms(double eta);

}  // namespace translucent::bssrdf
