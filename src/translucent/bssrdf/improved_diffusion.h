// SPDX-License-Identifier: GPL-3.0-or-later
// Pieces shared by the extended-source models (quantized_diffusion.cpp, photon_beam.cpp): the
// improved diffusion of d'Eon & Irving 2011 (Grosjean's diffusion coefficient, the boundary from
// the Fresnel moments, the exitance weights C_φ and C_E), a scaled complementary error function,
// Gauss-Legendre rules, and a log-grid table for profiles too expensive to evaluate directly.
// Private to src/bssrdf.
#pragma once

#include <cmath>
#include <span>
#include <vector>

#include "translucent/optics/medium.h"

namespace translucent::bssrdf::improved {

// Fresnel moment C_n(η) = ∫0^1 Fr(μ) μ^n dμ of the reflectance seen from inside the medium (light
// arriving at the boundary from the medium side with cosine μ; total internal reflection below the
// critical cosine when η > 1). Computed by quadrature of the exact Fresnel formula (no fit).
double fresnelMoment(int n, double eta);

// Diffusion parameters of one channel with the modified (Grosjean) diffusion coefficient and the
// improved boundary condition (d'Eon & Irving 2011, §3; d'Eon 2012 "A better dipole"):
//   D  = (2σa + σs') / (3σt'²)            diffusion coefficient (Grosjean)
//   σtr = sqrt(σa / D)                    effective transport coefficient
//   A  = (1 + 3 C2) / (1 - 2 C1)          boundary mismatch, from the Fresnel moments
//   zb = 2 A D                            extrapolation distance above the surface
//   C_φ = (1 - 2 C1) / 4, C_E = (1 - 3 C2) / 2   weights of fluence and flux in the exitance
// The exitance through the surface is R = C_φ φ + C_E D ∂φ/∂z (z into the medium).
struct ImprovedDiffusion {
  double sigma_a = 0.0;      // σa [1/length]
  double sigma_tp = 0.0;     // σt' [1/length]
  double alpha_p = 0.0;      // α'
  double D = 0.0;            // [length]
  double sigma_tr = 0.0;     // [1/length]
  double zb = 0.0;           // [length]
  double c_phi = 0.0, c_e = 0.0;

  explicit ImprovedDiffusion(const ScalarMedium& m);
};

// erfcx(x) = exp(x²) erfc(x) for x >= 0, without overflow for large x.
double erfcx(double x);
// 1 / (√π x) - erfcx(x) for x > 0, without the cancellation of the direct difference at large x
// (erfcx(x) ~ 1/(√π x) (1 - 1/(2x²) + ...)).
double erfcxDeficit(double x);

// n-point Gauss-Legendre rule on [0, 1] (nodes ascending, weights summing to 1); n in [1, 64].
struct GaussRule {
  std::vector<double> x, w;
};
const GaussRule& gaussLegendre(int n);

// A function of r >= 0 tabulated on a logarithmic grid, for models whose direct evaluation costs
// microseconds but which the generic sampler and tests evaluate millions of times.
//
// Stored: y_i = ln(r_i f(r_i)) + k r_i at r_i = r_lo 10^(i / per_decade). With k the function's
// asymptotic exponential decay rate, y is slowly varying in ln r at both ends (f ~ 1/r or ~ const
// near the source, ~ e^{-k r} r^-p far away), so 4-point Lagrange interpolation in ln r is accurate
// to O(h⁴) with h the grid step in ln r. The grid stops early where f drops below 1e-280 of its
// largest tabulated r f(r) (f is then 0 beyond, as far as double precision is concerned).
class LogRadialTable {
 public:
  LogRadialTable() = default;
  template <class F>
  LogRadialTable(F&& f, double r_lo, double r_hi, double k, int per_decade) {
    build([&](double r) { return f(r); }, r_lo, r_hi, k, per_decade);
  }

  // Whether r lies inside the tabulated range (outside it the caller evaluates directly).
  bool covers(double r) const { return !y_.empty() && r >= rLo_ && r <= rEnd_; }
  // True when the grid ended because f became negligible: f(r) = 0 beyond the last node.
  bool vanishesBeyond() const { return vanishes_; }
  double lastRadius() const { return rEnd_; }
  // Interpolated f(r); requires covers(r).
  double operator()(double r) const;
  size_t size() const { return y_.size(); }

 private:
  template <class F>
  void build(F&& f, double r_lo, double r_hi, double k, int per_decade);

  double x0_ = 0.0, h_ = 1.0, k_ = 0.0, rLo_ = 0.0, rEnd_ = -1.0;
  bool vanishes_ = false;
  std::vector<double> y_;
};

template <class F>
void LogRadialTable::build(F&& f, double r_lo, double r_hi, double k, int per_decade) {
  k_ = k;
  rLo_ = r_lo;
  x0_ = std::log(r_lo);
  h_ = std::log(10.0) / per_decade;
  const int n = static_cast<int>(std::ceil((std::log(r_hi) - x0_) / h_)) + 1;
  double peak = 0.0;
  y_.clear();
  for (int i = 0; i < n; ++i) {
    const double r = std::exp(x0_ + h_ * i);
    const double rf = r * f(r);
    peak = std::max(peak, rf);
    if (!(rf > 1e-280 * peak)) {
      vanishes_ = true;
      break;
    }
    y_.push_back(std::log(rf) + k * r);
  }
  if (y_.size() < 4) {  // too short to interpolate: everything is evaluated directly
    y_.clear();
    rEnd_ = -1.0;
    return;
  }
  rEnd_ = std::exp(x0_ + h_ * double(y_.size() - 1));
}

}  // namespace translucent::bssrdf::improved
