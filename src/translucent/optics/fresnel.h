// SPDX-License-Identifier: GPL-3.0-or-later
// Exact unpolarized Fresnel reflectance and transmittance of a smooth dielectric interface.
#pragma once

namespace translucent {

// Reflectance for an incident direction with cosine `cos_i` to the normal, where `eta` is the
// relative index n_transmitted / n_incident for light arriving from the normal's side (cos_i > 0).
// cos_i < 0 means the light arrives from the other side: the interface is seen with index 1/eta.
// Returns 1 under total internal reflection.
double fresnelReflectance(double cos_i, double eta);
inline double fresnelTransmittance(double cos_i, double eta) {
  return 1.0 - fresnelReflectance(cos_i, eta);
}

// Cosine of the refracted direction (always >= 0), or a negative value under total internal
// reflection. Same conventions as fresnelReflectance.
double refractedCosine(double cos_i, double eta);

}  // namespace translucent
