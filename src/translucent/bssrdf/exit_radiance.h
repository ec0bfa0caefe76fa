// SPDX-License-Identifier: GPL-3.0-or-later
// Radiance leaving the surface from the radiant exitance B that a radial profile predicts: the
// exit half of the diffusion BSSRDF, seed Eq. 2.16
//     S_d = (1/π) Ft(η, ω_i) R_d(r) Ft(η, ω_o) / (4 C_φ(1/η)).
// Two conventions are in use:
//   Jensen      L = Ft(η, ω_o) B / π                      (Jensen et al. 2001; what our models'
//               R(r) gives when used as a Lambertian exit lobe with Fresnel transmission)
//   Normalized  L = Ft(η, ω_o) B / (π · 4C_φ(1/η))        (d'Eon & Irving 2011, d'Eon 2012)
// with 4C_φ(1/η) = 1 - 2 C1_ext(η), C1_ext = ∫0^1 Fr(μ) μ dμ the first Fresnel moment of the
// boundary seen from outside (air onto the medium, no total internal reflection), so that
//     ∫_{H²} L cos θ_o dω_o = B · 2π ∫0^1 Ft(μ) μ dμ / (π (1 - 2 C1_ext)) = B:
// the normalized radiance carries exactly the exitance B out of the surface, the Jensen one only
// (1 - 2 C1_ext) B (93.9% at η = 1.3). B is the flux leaving through the surface per unit area
// (the profiles' R(r) already include the boundary's transmission), so the normalized form is
// the energy-consistent one.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace translucent::bssrdf {

enum class ExitConvention { Jensen, Normalized };

// "jensen", "normalized".
const char* toString(ExitConvention convention);
std::vector<std::string> exitConventionNames();
// Throws ParameterError naming the value and listing the valid names.
ExitConvention parseExitConvention(std::string_view name);

// 1 - 2 C1_ext(η) = 2 ∫0^1 Ft(η, μ) μ dμ, the diffuse transmittance of the boundary for light
// arriving from outside (= 4 C_φ(1/η) of Eq. 2.16). 1 at η = 1.
double diffuseTransmittanceFromOutside(double eta);

// L / B for an exit direction with cosine cos_o (> 0) to the outward normal, outside angle.
// `norm` is diffuseTransmittanceFromOutside(eta) (passed in so that per-pixel use does not
// recompute the quadrature).
double exitRadianceFactor(ExitConvention convention, double eta, double cos_o, double norm);
double exitRadianceFactor(ExitConvention convention, double eta, double cos_o);

// What the mesh and sphere tracers' cone_radiance (reference/camera.h) would be, divided by B,
// if the exit radiance followed the convention exactly: the cosine-weighted average of
// exitRadianceFactor over the cone of half-angle `cone_half_angle` [radians, (0, π/2]] about a
// view direction with cosine cos_o (> 0) to the outward normal,
//     ∫cone f(n·ω) max(n·ω, 0) dω / (π sin²θc (n·v)),
// the tracer's own normalisation (the part of the cone below the horizon receives no light, as in
// the tracer). Comparing the tracer's cone radiance with this rather than with the factor at the
// cone's axis removes the cone's averaging from the comparison. Quadrature: ~1e-7 relative.
double coneAveragedExitRadianceFactor(ExitConvention convention, double eta, double cos_o,
                                      double cone_half_angle);

// L_convention / L_Jensen, independent of the exit direction: 1 (Jensen) or
// 1 / diffuseTransmittanceFromOutside(eta) (Normalized). The constant by which a renderer that
// computes Ft B / π turns it into the chosen convention (pointcloud radiance pass).
double exitConventionScale(ExitConvention convention, double eta);

}  // namespace translucent::bssrdf
