// SPDX-License-Identifier: GPL-3.0-or-later
// Exact total reflectance of an isotropically scattering half-space under a normally incident
// beam (the searchlight problem's Rd, which by translation invariance equals the plane albedo for
// normal incidence), with and without a Fresnel boundary. Used where a model needs the true Rd of
// a medium rather than its own diffusion estimate (normalized_diffusion.cpp).
//
// Index matched (η = 1): Rd = 1 - H(1) sqrt(1 - ω) with Chandrasekhar's H-function (Chandrasekhar
// 1960, "Radiative Transfer", ch. IV-V: the plane albedo of a semi-infinite atmosphere), where ω
// is the single-scattering albedo of isotropic scattering.
//
// Fresnel boundary (η != 1): the adding method. The half-space's reflection function is exact,
// ρ(μ, μ') = (ω/4) H(μ) H(μ') / (μ + μ') (Chandrasekhar ch. IV, isotropic scattering: the
// scattering function S = ω μ μ' H(μ) H(μ') / (μ + μ') with I = F S / (4μ);
// an incident radiance I(μ') gives the reflected radiance 2∫0^1 ρ(μ, μ') I(μ') μ' dμ', no azimuth
// dependence). Below the interface the upward radiance U(μ) is the half-space's reflection of the
// refracted beam plus that of the downward radiance the interface reflects back, Fr(μ) U(μ):
//   U(μ) = ρ(μ, 1) / π + 2 ∫0^1 ρ(μ, μ') Fr(μ') U(μ') μ' dμ'          (unit flux entering, μ0 = 1)
//   Rd   = 2π ∫0^1 (1 - Fr(μ)) U(μ) μ dμ,
// with Fr the exact unpolarised Fresnel reflectance seen from inside (total internal reflection
// below the critical cosine when η > 1). The integral equation is solved by Nyström's method on
// Gauss-Legendre panels (break points at the critical cosine and graded towards μ = 0, where H has
// a logarithmic derivative): a dense linear solve, no Monte Carlo, converged to ~1e-9.
//
// H itself comes from Chandrasekhar's explicit integral (ch. V, for the characteristic function
// Ψ = ω/2):
//   ln H(μ) = -(μ/π) ∫0^{π/2} ln(1 - ω θ cot θ) / (cos²θ + μ² sin²θ) dθ,
// a closed quadrature that needs no iteration (the tests check it against the classical fixed-point
// iteration, the identity (ω/2)∫0^1 H dμ = 1 - sqrt(1 - ω) and Chandrasekhar's table).
//
// Units: Rd per unit flux entering the medium (the beam's Fresnel entry loss excluded), as the
// models' Rd. η is the medium's index relative to the outside.
#pragma once

namespace translucent::bssrdf {

// Chandrasekhar's H-function for isotropic scattering with albedo omega in [0, 1], at μ in [0, 1].
double chandrasekharH(double mu, double omega);

// Rd of the isotropically scattering half-space with albedo omega in [0, 1] and relative index
// eta > 0 under a normally incident beam, per unit flux entering. Increasing in omega; 0 at
// omega = 0 and 1 at omega = 1. Throws ParameterError for arguments outside those ranges.
double halfSpaceAlbedo(double omega, double eta);

}  // namespace translucent::bssrdf
