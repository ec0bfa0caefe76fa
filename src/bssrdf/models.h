// Factories of the built-in models; one line each in registry.cpp. Private to src/bssrdf.
#pragma once

#include <memory>

#include "bssrdf/profile.h"

namespace translucent::bssrdf {

std::unique_ptr<Model> makeDipole();
std::unique_ptr<Model> makeBetterDipole();
std::unique_ptr<Model> makeNormalizedDiffusion();
std::unique_ptr<Model> makeNormalizedDiffusionFit();
std::unique_ptr<Model> makeQuantizedDiffusion();
std::unique_ptr<Model> makePhotonBeam();

// Eq. 3.2, shared with models that reuse the dipole's total reflectance.
double dipoleTotalReflectance(double alpha_prime, double eta);

}  // namespace translucent::bssrdf
