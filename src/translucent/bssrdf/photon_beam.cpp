// SPDX-License-Identifier: GPL-3.0-or-later
// Photon beam diffusion (Habel, Christensen & Jarosz 2013, "Photon Beam Diffusion: A Hybrid Monte
// Carlo Method for Subsurface Scattering", EGSR), for a normally incident pencil beam.
//
// What it computes: R(r) = R_ms(r) + R_ss(r) [1/length²], the exitance per unit flux entering the
// medium: multiple plus single scattering (the registered profile is their sum; photon_beam.h gives
// each part). The reduced (unscattered) term is a delta at r = 0 and is not part of R.
//
// Parameters: σa, σs, g, η of the channel. R_ms uses the reduced σs' = (1-g)σs; R_ss uses σs, σa,
// the Henyey-Greenstein g and the exact Fresnel transmittance out of the medium.
//
// Multiple scattering (the paper's beam of better dipoles, as in pbrt-v3's BeamDiffusionMS, plus
// the factor 1 - U, which neither has):
//   R_ms(r) = ∫0^∞ σt' e^{-σt' z} α'² (1 - U(σt' z)) κ(r, z) E(r, z) dz
// - the beam's first collisions at depth z (density σt' e^{-σt' z}) each start a better-dipole
//   point source; α'² = one α' for scattering at z, one from the Grosjean split (the diffusive,
//   collided part of a point source is α' times the diffusion Green's function);
// - 1 - U(y), U(y) = ½ ∫_{μc}^1 T(μ) e^{-y/μ} dμ: of the light scattered at z, the fraction U
//   leaves through the surface before it collides again. That light is what the single-
//   scattering term R_ss counts (for g = 0 exactly: ∫ σs' e^{-σt' z} U dz = Rd_ss), so it is not
//   part of the collided light that Grosjean's split hands to diffusion. Without this factor the
//   dipole, which returns all the light of its source when nothing is absorbed, also returns the
//   once-scattered light a second time: Rd reached 1.035 at α' = 1, η = 1.3 (1.093 at η = 1:
//   more light out than in) and over-predicted the exact half-space Rd by 7-15% at η = 1
//   (e.g. 0.1280 against 0.1152 at α' = 0.5);
// - E(r, z) = C_φ φ(r, z) + C_E (-n·E)(r, z): d'Eon's better dipole with real source at depth z and
//   negative image at height z + 2zb above the surface, Grosjean D and σtr, zb = 2AD
//   (improved_diffusion.h):
//     φ = (e^{-σtr d_r}/d_r - e^{-σtr d_v}/d_v) / (4πD)
//     -n·E = (z (1+σtr d_r) e^{-σtr d_r}/d_r³ + (z + 2zb)(1+σtr d_v) e^{-σtr d_v}/d_v³) / (4π)
// - κ(r, z) = 1 - e^{-2σt'(d_r + z)}: the near-source correction of pbrt-v3's implementation, for
//   sources so close to the exit point that light leaves before it diffuses; it also makes R_ms
//   only logarithmically infinite at r = 0.
// Quadrature (the paper's importance sampling, made deterministic): the integrand is sampled two
// ways, exponentially in depth (u1 = 1 - e^{-σt' z}, density p1 = σt' e^{-σt' z}) and
// equi-angularly as seen from the exit point (u2 = 2θ/π with z = r tan θ, density
// p2 = (2/π) r/(r² + z²), which follows the 1/d² falloff that dominates for r << ℓ'), combined
// with the balance heuristic:
//   R_ms = ∫ f/(p1+p2) du1 + ∫ f/(p1+p2) du2.
// Instead of random numbers each technique uses Gauss-Legendre panels in its own primary variable
// (8 points per panel, 12 on the panels graded by decades towards z = 0 in u1 and towards z = ∞
// in θ, so that 1e-8 ℓ' <= r works), precomputed once per profile: ~500 dipole evaluations per
// radius. From r = 10 ℓ' on the equi-angular technique gets no samples (its hand-over region with
// the exponential one becomes a narrow band in θ) and ~260 evaluations remain. Agrees with a
// long-double brute-force integral to < 1e-7 from 1e-8 ℓ' to 1e4 ℓ'
// (tests/bssrdf/test_photon_beam.cpp).
//
// Single scattering (the paper's single-scattering term; pbrt-v3's BeamDiffusionSS): light
// scattered once at depth t on the beam and leaving through the surface at distance r,
// d = √(r² + t²), exit cosine μ = t/d,
//   R_ss(r) = ∫_{t_c}^∞ σs e^{-σt (t + d)} p(-μ) T(μ) μ / d² dt,   t_c = r √(η² - 1) (η > 1)
// with p the Henyey-Greenstein phase function of the scattering cosine -μ and T(μ) the Fresnel
// transmittance out of the medium (0 under total internal reflection, which is what t >= t_c
// says). With the exit angle θ as variable (t = r cot θ) this is
//   R_ss(r) = (σs / r) ∫_0^{θc} e^{-σt r cot(θ/2)} p(-cos θ) T(cos θ) cos θ dθ,
// which shows the 1/r behaviour near the source (r R_ss -> σs ∫ p T cos θ dθ, finite, so r R is
// integrable and the sampler's density is finite at 0). Quadrature in s with θ = θc (1 - s²)
// (removes the square-root onset of T at the critical angle), 12-point Gauss-Legendre panels
// graded towards both ends (large r concentrates the integrand at θc, small r cuts it off near
// θ = 0): 192 exponentials per radius, < 1e-9 from the brute-force integral.
//
// Evaluation: each profile tabulates R = R_ms + R_ss on one log grid (improved::LogRadialTable,
// 80 points per decade from 1e-8 to 1e9 times min(ℓ', 1/(σt cot(θc/2))), with the slower decay
// rate factored out; ~10-20 ms per profile); interpolation error < 5e-7 relative (tested against
// the direct sum). Outside the grid R is evaluated directly.
// Rd = Rd_ms + Rd_ss from independent quadratures (photon_beam.h). totalReflectance(α', η) uses
// σt' = 1 and g = 0: the multiple part depends on α' and η alone, the single part also on g, which
// the Model interface does not carry (for g != 0 a profile's Rd() is the exact value).
//
// Energy: per source the collided fraction 1 - U goes to the dipole, which returns all of it when
// nothing is absorbed (C_φ 2A + C_E = 1), less what κ removes near the source; the escaping
// fraction U is the single-scattering term. So Rd <= 1 for every α' <= 1 and η (at α' = 1:
// 0.960 at η = 1, 0.965 at η = 1.3; κ's removal is not returned elsewhere). Without κ, Rd would be
// exactly 1 at α' = 1 for g = 0, but against the path-traced searchlight reference the profile is
// worse (mean photon-weighted L1 over the traceable presets 8.9% without κ, 3.9% with; Rd error
// up to +14.6% without, within -3.4%..+4.5% with; docs/model-error.md), so κ stays.
// Against the exact half-space Rd (half_space.h) at η = 1: +2.2% at α' = 0.5, -2.4% at 0.99.
#include "translucent/bssrdf/photon_beam.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "translucent/bssrdf/improved_diffusion.h"
#include "translucent/bssrdf/models.h"
#include "translucent/optics/fresnel.h"

namespace translucent::bssrdf {
namespace {

constexpr double kInvFourPi = 0.25 * std::numbers::inv_pi;
constexpr int kPanelPoints = 8;
// Points on panels graded by decades (edge ratio >= 5, or starting at 0): there the integrand's
// shape changes within a panel (1/z regions, hand-over between the techniques).
constexpr int kGradedPanelPoints = 12;
// Sources deeper than this many reduced mean free paths carry e^{-50} of the beam: ignored.
constexpr double kDeepest = 50.0;
// Radius (in ℓ') from which the beam integral uses exponential sampling alone.
constexpr double kEquiAngularRange = 10.0;
constexpr double kTableLo = 1e-8, kTableHi = 1e9;  // in mean free paths
constexpr int kTablePerDecade = 80;
constexpr double kEscapeLo = 1e-12;  // escape table range in σt' z
constexpr int kEscapePerDecade = 160;

void checkRadius(double r, const char* what) {
  if (!(r >= 0.0) || !std::isfinite(r))
    throw ParameterError(fmt::format("{}: radius r must be finite and >= 0, got {}", what, r));
}

// Gauss-Legendre points for the panel [a, b].
int panelPoints(double a, double b) { return b >= 5.0 * a ? kGradedPanelPoints : kPanelPoints; }

// Appends Gauss-Legendre nodes/weights of each panel [e_k, e_{k+1}] to x, w (`points` per panel,
// or panelPoints() when 0).
void appendPanels(const std::vector<double>& edges, std::vector<double>& x, std::vector<double>& w,
                  int points = 0) {
  for (size_t k = 0; k + 1 < edges.size(); ++k) {
    const double a = edges[k], len = edges[k + 1] - edges[k];
    const auto& g = improved::gaussLegendre(points > 0 ? points : panelPoints(a, edges[k + 1]));
    for (size_t i = 0; i < g.x.size(); ++i) {
      x.push_back(a + len * g.x[i]);
      w.push_back(len * g.w[i]);
    }
  }
}

// ---- Uncollided escape ---------------------------------------------------------------------

double henyeyGreenstein(double cosScatter, double g) {
  const double denom = 1.0 + g * g - 2.0 * g * cosScatter;
  return kInvFourPi * (1.0 - g * g) / (denom * std::sqrt(denom));
}

// Critical exit angle θc: total internal reflection beyond it when η > 1, none otherwise.
double criticalAngle(double eta) {
  return eta > 1.0 ? std::asin(1.0 / eta) : 0.5 * std::numbers::pi;
}

// Once-scattered light that leaves without colliding again, the single-scattering term's share
// of each depth (see the header):
//   U(x) = 2π ∫_{μc}^1 p(-μ) T(μ) e^{-x/μ} dμ,  x = σt t,
// the fraction of the light scattered on the beam at depth t (Henyey-Greenstein p of the
// scattering cosine -μ, Fresnel transmittance T out of the medium) that reaches the surface
// uncollided and leaves; the single-scattering total is Rd_ss = ∫ σs e^{-σt t} U(σt t) dt.
// Quadrature in s with μ = μc + (1 - μc) s², which smooths the √ onset of T at μc.
class UncollidedEscape {
 public:
  UncollidedEscape(double eta, double g) {
    const double muC = std::cos(criticalAngle(eta));
    std::vector<double> s, w;
    appendPanels({0.0, 0.25, 0.5, 0.75, 1.0}, s, w, 16);
    for (size_t i = 0; i < s.size(); ++i) {
      const double mu = muC + (1.0 - muC) * s[i] * s[i];
      invMu_.push_back(1.0 / mu);
      w_.push_back(2.0 * std::numbers::pi * w[i] * 2.0 * (1.0 - muC) * s[i] *
                   henyeyGreenstein(-mu, g) * (1.0 - fresnelReflectance(-mu, eta)));
    }
  }
  double operator()(double x) const {
    double sum = 0.0;
    for (size_t i = 0; i < w_.size(); ++i) sum += w_[i] * std::exp(-x * invMu_[i]);
    return sum;
  }

 private:
  std::vector<double> invMu_, w_;
};

// The collided part 1 - u(y) of the light that starts the diffusion source at reduced optical
// depth y = σt' z, where u is the single-scattering term's escaping light from that depth per unit
// of the source: u(y) = σs e^{-σt z} U(σt z) / (σs' e^{-σt' z}). For g = 0, u = U. Clamped at 0
// (not reached by Henyey-Greenstein media: u(0) = U(0)/(1-g) < 1).
class CollidedFraction {
 public:
  explicit CollidedFraction(const ScalarMedium& m)
      : escape_(m.eta, m.g),
        ratio_(m.sigmaT() / m.sigmaTPrime()),
        scale_(m.sigma_s > 0.0 ? m.sigma_s / (m.sigma_s * (1.0 - m.g)) : 0.0) {
    // U on a log grid of x = σt z (it decays like e^{-x}/x); outside it, evaluated directly.
    table_ = improved::LogRadialTable([this](double x) { return escape_(x); }, kEscapeLo,
                                      kDeepest * 1.01 * std::max(ratio_, 1.0), 1.0,
                                      kEscapePerDecade);
  }
  double operator()(double y) const {
    const double x = ratio_ * y;
    double U;
    if (table_.covers(x))
      U = table_(x);
    else if (x > table_.lastRadius() && table_.vanishesBeyond())
      U = 0.0;
    else
      U = escape_(x);
    return std::max(0.0, 1.0 - scale_ * std::exp(-(ratio_ - 1.0) * y) * U);
  }

 private:
  UncollidedEscape escape_;
  double ratio_, scale_;  // σt/σt', σs/σs'
  improved::LogRadialTable table_;
};

// ---- Multiple scattering -------------------------------------------------------------------

class MultipleScattering {
 public:
  explicit MultipleScattering(const ScalarMedium& m) : p_(m), collided_(m) {
    const double st = p_.sigma_tp;
    // Exponential technique: panels in optical depth y = σt' z, graded by decades towards 0 where
    // (for small r) the integrand's 1/z region starts; u1 = 1 - e^{-y} per panel. Node y and
    // weight du1 are computed from the panel start without forming 1 - u (no cancellation).
    std::vector<double> yEdges{0.0};
    for (double e = 1e-9; e < 0.05; e *= 10.0) yEdges.push_back(e);
    for (double e : {0.1, 0.3, 0.6, 1.0, 1.5, 2.0, 3.0, 4.0, 5.0, 6.0, 8.0, 10.0, 13.0, 16.0, 20.0,
                     25.0, 32.0, 40.0, kDeepest})
      yEdges.push_back(e);
    for (size_t k = 0; k + 1 < yEdges.size(); ++k) {
      const auto& g = improved::gaussLegendre(panelPoints(yEdges[k], yEdges[k + 1]));
      const double ya = yEdges[k], q = -std::expm1(-(yEdges[k + 1] - ya));  // Δu / (1 - u_a)
      for (size_t i = 0; i < g.x.size(); ++i) {
        const double y = ya - std::log1p(-g.x[i] * q);
        expZ_.push_back(y / st);
        expW_.push_back(std::exp(-ya) * q * g.w[i]);
        expP1_.push_back(st * std::exp(-y));
      }
    }
    // Equi-angular technique (used for r < kEquiAngularRange ℓ', see operator()): u2 = 2θ/π,
    // du2 = (2/π) dθ. Panels in θ: a few towards θ = 0 (z << r, where the exponential technique
    // dominates anyway) and graded by decades towards θ = π/2 (z >> r: for r << ℓ' the 1/z²
    // falloff hands over to the exponential at z ~ sqrt(r ℓ')). Nodes near π/2 are stored through
    // w = π/2 - θ so that tan θ keeps its precision.
    std::vector<double> lower{0.0, 1e-3, 1e-2, 0.1, 0.3, 0.25 * std::numbers::pi};  // θ
    std::vector<double> upper{0.0};                                                    // π/2 - θ
    for (double e = 1e-12; e < 0.05; e *= 10.0) upper.push_back(e);
    for (double e : {0.1, 0.3, 0.25 * std::numbers::pi}) upper.push_back(e);
    std::vector<double> ts, tw, ws, ww;
    appendPanels(lower, ts, tw);
    appendPanels(upper, ws, ww);
    for (size_t i = 0; i < ts.size(); ++i) {
      eaTan_.push_back(std::tan(ts[i]));
      eaCos2_.push_back(std::cos(ts[i]) * std::cos(ts[i]));
      eaW_.push_back(2.0 * std::numbers::inv_pi * tw[i]);
    }
    for (size_t i = 0; i < ws.size(); ++i) {
      eaTan_.push_back(1.0 / std::tan(ws[i]));
      eaCos2_.push_back(std::sin(ws[i]) * std::sin(ws[i]));
      eaW_.push_back(2.0 * std::numbers::inv_pi * ww[i]);
    }
  }

  // f(z) = σt' e^{-σt' z} α'² κ E for the source at depth z; `p1` = σt' e^{-σt' z} is passed in.
  double integrand(double r, double z, double p1) const {
    const double s = p_.sigma_tr, zv = z + 2.0 * p_.zb;
    const double dr = std::sqrt(r * r + z * z), dv = std::sqrt(r * r + zv * zv);
    const double er = std::exp(-s * dr);
    double ev, phi;
    const double gap = (zv - z) * (zv + z) / (dr + dv);  // d_v - d_r without cancellation
    if (gap < 0.1 * dr) {
      // Far from the source real and image fluence nearly cancel: write the difference as
      // e^{-σtr d_r}/d_r (1 - (d_r/d_v) e^{-σtr (d_v - d_r)}) with expm1/log1p.
      const double t = -std::log1p(gap / dr) - s * gap;
      ev = er * std::exp(-s * gap);
      phi = kInvFourPi / p_.D * er / dr * -std::expm1(t);
    } else {
      ev = std::exp(-s * dv);
      phi = kInvFourPi / p_.D * (er / dr - ev / dv);
    }
    const double flux = kInvFourPi * (z * (1.0 + s * dr) * er / (dr * dr * dr) +
                                      zv * (1.0 + s * dv) * ev / (dv * dv * dv));
    const double kappa = -std::expm1(-2.0 * p_.sigma_tp * (dr + z));
    return p1 * p_.alpha_p * p_.alpha_p * collided(p_.sigma_tp * z) * kappa *
           (p_.c_phi * phi + p_.c_e * flux);
  }

  double operator()(double r) const {
    if (r <= 0.0) return std::numeric_limits<double>::infinity();
    // Beyond a few ℓ' the integrand varies on the scale r >> ℓ' and exponential sampling alone is
    // ideal; equi-angular sampling would only add its hand-over region (where p1 ~ p2, at depth
    // ~ln(σt' r) ℓ', a narrow band in θ) for the quadrature to resolve. So the equi-angular
    // technique gets no samples there (MIS with sample counts n2 = 0).
    const bool equiAngular = p_.sigma_tp * r < kEquiAngularRange;
    const double ea = equiAngular ? 2.0 * std::numbers::inv_pi * r : 0.0;  // p2 = ea / (r² + z²)
    double sum = 0.0;
    for (size_t j = 0; j < expZ_.size(); ++j) {
      const double z = expZ_[j], p1 = expP1_[j];
      sum += expW_[j] * integrand(r, z, p1) / (p1 + ea / (r * r + z * z));
    }
    for (size_t j = 0; equiAngular && j < eaTan_.size(); ++j) {
      const double z = r * eaTan_[j];
      if (p_.sigma_tp * z > kDeepest) continue;
      const double p1 = p_.sigma_tp * std::exp(-p_.sigma_tp * z);
      const double p2 = 2.0 * std::numbers::inv_pi * eaCos2_[j] / r;
      sum += eaW_[j] * integrand(r, z, p1) / (p1 + p2);
    }
    return sum;
  }

  const improved::ImprovedDiffusion& params() const { return p_; }
  // The part of the light scattered at optical depth y that collides again.
  double collided(double y) const { return collided_(y); }

 private:
  improved::ImprovedDiffusion p_;
  CollidedFraction collided_;
  std::vector<double> expZ_, expW_, expP1_;
  std::vector<double> eaTan_, eaCos2_, eaW_;
};

// Rd_ms = α'² ∫0^∞ σt' e^{-σt' z} [∫0^∞ 2π r κ E dr] dz, in units σt' = 1. The inner integral is
// (∫ 2πr E dr) - (∫ 2πr e^{-2(d_r + z)} E dr): the first in closed form, the second in closed form
// for the real source (with E1) and by quadrature for the image terms (d_r and d_v mixed).
double multipleRd(const ScalarMedium& m) {
  const double alpha_prime = m.reducedAlbedo(), eta = m.eta;
  if (alpha_prime <= 0.0) return 0.0;
  constexpr int kRdPoints = 8;
  const improved::ImprovedDiffusion p(ScalarMedium{1.0 - alpha_prime, alpha_prime, 0.0, eta});
  const double s = p.sigma_tr, D = p.D, zb = p.zb, a = s + 2.0;
  // (e^{-s z} - e^{-s (z + 2zb)}) / s without cancellation as s -> 0.
  const double imageGap = s > 0.0 ? -std::expm1(-2.0 * s * zb) / s : 2.0 * zb;
  const auto& g = improved::gaussLegendre(kRdPoints);
  const CollidedFraction collided(m);  // a function of σt' z: the same in units σt' = 1
  // Inner panels in x = 2(d_r - z) (the factor e^{-x} comes from κ).
  std::vector<double> xs, xw;
  appendPanels({0.0, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0, 32.0, 48.0}, xs, xw, kRdPoints);
  auto inner = [&](double z) {
    const double es = std::exp(-s * z);
    const double phiTotal = es * imageGap / (2.0 * D);
    const double fluxTotal = 0.5 * es * (1.0 + std::exp(-2.0 * s * zb));
    // J1 = ∫ r e^{-2 d_r} e^{-s d_v}/d_v dr, J2 = ∫ r zv (1 + s d_v) e^{-2 d_r - s d_v}/d_v³ dr,
    // with r dr = d dd, d = d_r = z + x/2, d_v² = d² + 4 zb (z + zb).
    double j1 = 0.0, j2 = 0.0;
    const double zv = z + 2.0 * zb, shift = 4.0 * zb * (z + zb);
    for (size_t i = 0; i < xs.size(); ++i) {
      const double d = z + 0.5 * xs[i], dv = std::sqrt(d * d + shift);
      const double common = xw[i] * std::exp(-xs[i]) * d * std::exp(-s * dv) / dv;
      j1 += common;
      j2 += common * zv * (1.0 + s * dv) / (dv * dv);
    }
    const double e2z = std::exp(-2.0 * z);
    j1 *= 0.5 * e2z;
    j2 *= 0.5 * e2z;
    const double e1 = z > 0.0 ? std::expint(-a * z) : 0.0;  // std::expint(-x) = -E1(x)
    const double phiKappa = e2z / (2.0 * D) * (std::exp(-a * z) / a - j1);
    const double fluxKappa = 0.5 * e2z * (std::exp(-a * z) + 2.0 * z * e1 + j2);
    return p.c_phi * (phiTotal - phiKappa) + p.c_e * (fluxTotal - fluxKappa);
  };
  std::vector<double> zEdges{0.0};
  for (double e = 1e-6; e < 0.05; e *= 10.0) zEdges.push_back(e);
  for (double e : {0.1, 0.3, 1.0, 2.0, 4.0, 8.0, 16.0, 32.0, 50.0}) zEdges.push_back(e);
  double sum = 0.0;
  for (size_t k = 0; k + 1 < zEdges.size(); ++k) {
    const double za = zEdges[k], len = zEdges[k + 1] - za;
    for (size_t i = 0; i < g.x.size(); ++i) {
      const double z = za + len * g.x[i];
      sum += len * g.w[i] * std::exp(-z) * collided(z) * inner(z);
    }
  }
  return alpha_prime * alpha_prime * sum;
}

// ---- Single scattering ---------------------------------------------------------------------

class SingleScattering {
 public:
  explicit SingleScattering(const ScalarMedium& m)
      : sigmaS_(m.sigma_s), sigmaT_(m.sigmaT()) {
    const double thetaC = criticalAngle(m.eta);
    std::vector<double> sEdges{0.0, 1e-4, 1e-3, 1e-2, 0.05, 0.2, 0.5, 0.8, 0.9};
    for (double e = 1e-2; e > 1e-7; e /= 10.0) sEdges.push_back(1.0 - e);
    sEdges.push_back(1.0);
    std::vector<double> ss, sw;
    appendPanels(sEdges, ss, sw, kGradedPanelPoints);  // graded at both ends: 12 points each
    for (size_t i = 0; i < ss.size(); ++i) {
      const double theta = thetaC * (1.0 - ss[i] * ss[i]);
      const double jac = 2.0 * thetaC * ss[i];
      const double mu = std::cos(theta);
      const double t = 1.0 - fresnelReflectance(-mu, m.eta);
      h_.push_back(sw[i] * jac * henyeyGreenstein(-mu, m.g) * t * mu);
      cotHalf_.push_back(1.0 / std::tan(0.5 * theta));
    }
    decay_ = sigmaT_ / std::tan(0.5 * thetaC);
    for (double h : h_) limit_ += sigmaS_ * h;
  }

  double operator()(double r) const {
    if (r <= 0.0) return std::numeric_limits<double>::infinity();
    double sum = 0.0;
    for (size_t i = 0; i < h_.size(); ++i) sum += h_[i] * std::exp(-sigmaT_ * r * cotHalf_[i]);
    return sigmaS_ * sum / r;
  }

  // lim_{r->0} r R_ss(r) = σs ∫ p T cos θ dθ.
  double rTimesRAtZero() const { return limit_; }
  // Asymptotic decay rate σt cot(θc/2) of R_ss (the exponent at θ = θc).
  double decayRate() const { return decay_; }

 private:
  double sigmaS_, sigmaT_, decay_ = 0.0, limit_ = 0.0;
  std::vector<double> h_, cotHalf_;
};

double singleRd(const ScalarMedium& m) {
  // 2π α ∫_{μc}^1 p(-μ) T(μ) μ/(1+μ) dμ, with μ = μc + (1 - μc) s² for the √ onset of T at μc.
  const double muC = std::cos(criticalAngle(m.eta));
  const auto& g = improved::gaussLegendre(16);
  double sum = 0.0;
  const int panels = 4;
  for (int k = 0; k < panels; ++k) {
    for (size_t i = 0; i < g.x.size(); ++i) {
      const double s = (k + g.x[i]) / panels;
      const double mu = muC + (1.0 - muC) * s * s;
      const double jac = 2.0 * (1.0 - muC) * s / panels;
      const double t = 1.0 - fresnelReflectance(-mu, m.eta);
      sum += g.w[i] * jac * henyeyGreenstein(-mu, m.g) * t * mu / (1.0 + mu);
    }
  }
  return 2.0 * std::numbers::pi * m.albedo() * sum;
}

// ---- The model -----------------------------------------------------------------------------

class PhotonBeamProfile final : public RadialProfile {
 public:
  explicit PhotonBeamProfile(const ScalarMedium& m) : RadialProfile(m), ms_(m), ss_(m) {
    // One table for the sum: near the source both parts are smooth in log-log, far away the
    // slower decay (σtr of the multiple part, normally) dominates and is factored out.
    const double scale = innerScale();
    const double decay = std::min(ms_.params().sigma_tr, ss_.decayRate());
    table_ = improved::LogRadialTable([this](double r) { return direct(r); }, kTableLo * scale,
                                      kTableHi * scale, decay, kTablePerDecade);
    rd_ = multipleRd(m) + singleRd(m);
  }

  double evaluate(double r) const override {
    if (table_.covers(r)) return table_(r);
    if (r > table_.lastRadius() && table_.vanishesBeyond()) return 0.0;
    return direct(r);
  }

  double Rd() const override { return rd_; }

  // R is infinite at r = 0 but r R is not: the density there is the limit of 2π r R / total.
  double pdf(double r) const override {
    if (r == 0.0) return 2.0 * std::numbers::pi * ss_.rTimesRAtZero() / cumulative().total();
    return RadialProfile::pdf(r);
  }

 protected:
  // The single-scattering part decays on 1/(σt cot(θc/2)), shorter than ℓ' when g > 0.
  double innerScale() const override {
    return std::min(medium().reducedMeanFreePath(), 1.0 / ss_.decayRate());
  }

 private:
  double direct(double r) const { return ms_(r) + ss_(r); }

  MultipleScattering ms_;
  SingleScattering ss_;
  improved::LogRadialTable table_;
  double rd_ = 0.0;
};

class PhotonBeam final : public Model {
 public:
  std::string_view name() const override { return "photon-beam"; }
  std::string_view description() const override {
    return "photon beam diffusion: better-dipole sources integrated along the refracted beam, "
           "plus single scattering (Habel, Christensen & Jarosz 2013)";
  }
  std::unique_ptr<RadialProfile> profile(const ScalarMedium& m) const override {
    m.validate();
    return std::make_unique<PhotonBeamProfile>(m);
  }
  double totalReflectance(double alpha_prime, double eta) const override {
    // σt' = 1, g = 0 (then α = α').
    const ScalarMedium m{1.0 - alpha_prime, alpha_prime, 0.0, eta};
    return multipleRd(m) + singleRd(m);
  }
};

}  // namespace

double photonBeamMultiple(double r, const ScalarMedium& medium) {
  medium.validate();
  checkRadius(r, "photonBeamMultiple");
  return MultipleScattering(medium)(r);
}

double photonBeamSingle(double r, const ScalarMedium& medium) {
  medium.validate();
  checkRadius(r, "photonBeamSingle");
  return SingleScattering(medium)(r);
}

double photonBeamMultipleRd(const ScalarMedium& medium) {
  medium.validate();
  return multipleRd(medium);
}

double photonBeamSingleRd(const ScalarMedium& medium) {
  medium.validate();
  return singleRd(medium);
}

std::unique_ptr<Model> makePhotonBeam() { return std::make_unique<PhotonBeam>(); }

}  // namespace translucent::bssrdf
