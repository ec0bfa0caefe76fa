// SPDX-License-Identifier: GPL-3.0-or-later
// Radial diffuse reflectance profiles and the models that make them.
//
// A Model (dipole, better dipole, ...) is stateless and registered by name (bssrdf/registry.h).
// For one colour channel of a medium it creates a RadialProfile: R(r), the radially symmetric
// diffuse reflectance of a semi-infinite medium lit by a normally incident pencil beam (the
// searchlight problem of Jensen et al. 2001), per unit area per unit incident flux [1/length²].
//
// The base class supplies, for any R(r), an exact radial sampler: r is drawn with density
// p(r) = 2π r R(r) / Rd_table on [0, r_max], where the cumulative integral is tabulated with
// 8-point Gauss-Legendre panels on a logarithmic grid and each sample is refined by Newton-
// bisection on the exact integrand, so pdf() is exactly the density of sample() up to quadrature
// error (~1e-10). Models with closed forms override what they can.
#pragma once

#include <memory>
#include <mutex>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

#include "translucent/optics/medium.h"

namespace translucent::bssrdf {

struct RadialSample {
  double r = 0.0;    // sampled radius [length]
  double pdf = 0.0;  // density of r on [0, ∞) [1/length]
};

class RadialProfile {
 public:
  explicit RadialProfile(const ScalarMedium& medium)
      : medium_(medium), far_radius_(1e30 * medium.reducedMeanFreePath()) {}
  virtual ~RadialProfile() = default;
  RadialProfile(const RadialProfile&) = delete;
  RadialProfile& operator=(const RadialProfile&) = delete;

  // R(r) [1/length²]; per unit area, per unit incident flux. Every model through one guard:
  // beyond farRadius() (10^30 reduced mean free paths) R is 0, as it is in double precision for
  // every profile that decays at least exponentially, and where the closed forms would overflow
  // (r² + z_r² = inf gives inf/inf = NaN at r ~ 1e154): R(∞) = 0, never NaN.
  double R(double r) const { return r > far_radius_ ? 0.0 : evaluate(r); }
  double farRadius() const { return far_radius_; }
  // Total diffuse reflectance Rd = 2π ∫0^∞ R(r) r dr (Eq. 3.1). Default: the tabulated integral.
  virtual double Rd() const;

  // Importance sampling of r ∝ r R(r) from u in [0, 1).
  virtual RadialSample sample(double u) const;
  // Density of sample() at r [1/length].
  virtual double pdf(double r) const;
  // Radius within which `fraction` of Rd is reflected (0.95: the "effective scattering range").
  virtual double radiusForFraction(double fraction) const;

  const ScalarMedium& medium() const { return medium_; }

  // Cumulative table (built lazily, thread-safe): panel edges and 2π∫0^edge R r dr.
  struct Cumulative {
    std::vector<double> edges;  // edges[0] = 0
    std::vector<double> cdf;    // unnormalised cumulative at each edge
    double total() const { return cdf.back(); }
  };
  const Cumulative& cumulative() const;

 protected:
  // The model's R(r) for 0 <= r <= farRadius() (R() above applies the guard).
  virtual double evaluate(double r) const = 0;

  // Length scale on which R varies near the source, used to place the table's first panels.
  // Default: the reduced mean free path ℓ'.
  virtual double innerScale() const;

  // Inverts the cumulative 2π∫0^r R r' dr' = target (unnormalised) on the table.
  double invertCumulative(double target) const;

 private:
  ScalarMedium medium_;
  double far_radius_;
  mutable std::once_flag built_;
  mutable Cumulative cumulative_;
};

// A BSSRDF that depends on where light enters and leaves, on the surface normals there and on
// the incident direction, beyond the distance alone (the directional dipole). Evaluated as the
// exitance kernel of the radial profiles, generalised:
//   R(x_i, n_i, ω_i; x_o, n_o)  [1/length²]
// the radiant exitance leaving through the surface at x_o (normal n_o) per unit flux that enters
// the medium at x_i (normal n_i) from the direction ω_i, so that a renderer computes
//   B(x_o) = ∫ R(x_i, n_i, ω_i; x_o, n_o) Ft(η, n_i·ω_i) (n_i·ω_i) E dA(x_i)
// exactly as with R(|x_o - x_i|), and the exit radiance from B by bssrdf/exit_radiance.h.
// Directions point away from the surface (ω_i towards the light, n_i·ω_i > 0) and all vectors are
// unit length except the positions; coefficients per unit of the positions.
class DirectionalProfile {
 public:
  virtual ~DirectionalProfile() = default;
  virtual double R(const glm::dvec3& x_i, const glm::dvec3& n_i, const glm::dvec3& w_i,
                   const glm::dvec3& x_o, const glm::dvec3& n_o) const = 0;
};

class Model {
 public:
  virtual ~Model() = default;
  virtual std::string_view name() const = 0;
  // One line: what the model is and where it comes from.
  virtual std::string_view description() const = 0;
  // Profile for one channel; the medium is validated first (throws ParameterError).
  virtual std::unique_ptr<RadialProfile> profile(const ScalarMedium& medium) const = 0;
  // Rd as a function of the reduced albedo α' and η alone (all models here are scale invariant).
  // Default: Rd() of a profile with σt' = 1, g = 0. Models with closed forms override.
  virtual double totalReflectance(double alpha_prime, double eta) const;
  // True for a tabulated profile (bssrdf/tabulated.h): one fixed R(r) per RGB channel that ignores
  // σa, σs and g, so it has no profile for a scalar medium and no Rd(α').
  virtual bool tabulated() const { return false; }
  // The directional kernel of a model that has one (null for radial models). profile() then gives
  // its radial restriction: R(r) of the kernel at normal incidence on a plane (the pencil beam).
  virtual std::unique_ptr<DirectionalProfile> directional(const ScalarMedium& medium) const;
};

// The azimuthal average (1/2π) ∮ R(x_i, n, ω_i; x_i + r (cos φ, sin φ, 0), n) dφ of a
// directional kernel on a plane (normal n = z) at distance r from the point of entry, the light
// at polar angle `theta` [radians, outside, in [0, π/2)]: what the radial tally of a path-traced
// pencil beam at that incidence measures (reference/slab.h, SlabSetup::theta). `azimuths`
// equally spaced angles (the periodic trapezoidal rule, spectrally accurate for a smooth
// integrand). At theta = 0 it is the kernel's normal-incidence profile.
double azimuthalAverage(const DirectionalProfile& kernel, double r, double theta,
                        int azimuths = 64);

// Integrates 2π r R(r) over [a, b] with one 8-point Gauss-Legendre panel.
double integratePanel(const RadialProfile& p, double a, double b);

}  // namespace translucent::bssrdf
