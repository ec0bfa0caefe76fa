// SPDX-License-Identifier: GPL-3.0-or-later
// Per-point local profiles of a heterogeneous material: the SubEdit representation (Song et al.
// 2009; seed multiresolution-splatting §3, Eqs. 8-9).
//
// For every surface point x (a point of a point cloud, an atlas texel, a mesh vertex) and every
// RGB channel, the radial profile P_x(r) [1/scene unit²] of the point's local medium
// (Material::surfaceMedium) under the material's model, as if the whole object were made of that
// medium. It is stored as a piecewise-linear function of ln P with n segments on [0, r_s]
// (Eq. 9): n + 1 nodes ln P_x^k = ln P_x(r_k), r_k = k r_s / n, and
//     ln P_x(r) = (1 − w) ln P_x^k + w ln P_x^{k+1},   k = ⌊n r / r_s⌋,  w = n r / r_s − k.
// The transport between two points is Eq. 8 (the geometric mean of their profiles),
//     R_d(x_i, x_o) = sqrt(P_xi(r) P_xo(r)) = exp((ln P_xi(r) + ln P_xo(r)) / 2),  r = |x_i − x_o|,
// exactly the model's R(r) when both points have the same medium.
//
// Choices (the issue leaves them open):
//  - r_s (`radius`): by default the largest 95% radius (RadialProfile::radiusForFraction(0.95))
//    over every point and channel, so every profile keeps ≥ 95% of its energy inside [0, r_s]
//    and the grid is common to all points (one r_s for the whole cloud: the GPU reads one
//    uniform, and Eq. 8 combines two profiles on the same nodes).
//  - r → 0: node 0 is ln P(0) where the model's P(0) is finite and positive (the dipole and the
//    better dipole: P(0) is finite, d_r = z_r > 0 at r = 0). Where P diverges at 0 (normalized
//    diffusion ~1/r) node 0 is chosen so that the first segment carries the model's energy
//    2π∫0^{r_1} P r dr exactly (solved by bisection): a node at r = 0 cannot be ln ∞, and any
//    finite value other than the energy-preserving one changes Rd.
//  - beyond r_s: the tail is extrapolated as the last segment of ln(r² P) extended linearly,
//        ln P(r) = ln P_n + (r − r_s) s − 2 ln(r / r_s),  s = the slope of ln(r² P) on [r_{n−1}, r_s]
//    (n = 1: the slope of ln P), while s < 0 (P = 0 beyond r_s otherwise), up to
//    r_cut = kExtrapolationFactor · r_s, and P = 0 beyond r_cut. Why: cutting at r_s would drop
//    up to 5% of the widest profile's energy (a 5% bias on Rd: Eq. 8 would no longer reduce to
//    the model's Rd), and far from the source every diffusion profile decays as e^{−σtr r} times a
//    power of r — the dipole as σtr e^{−σtr r} / r², which this form continues exactly (extending
//    ln P itself underestimated Marble's tail by 54% at 2 r_s). At 3 r_s an exponential tail that
//    holds 5% beyond r_s holds ≈ 0.05³ ≈ 1e-4 (the homogeneous table keeps 99.9%,
//    techniques/common/profile_kernel.h).
//  - ln P is clamped to kLnFloor (≈ e^-80), so that a profile that underflows (P = 0 far out in
//    a dense medium) stays finite in the logarithm and in float on the GPU.
// Models: any registered radial model (bssrdf/registry.h). A .bssrdf file model needs its GPU
// evaluator for R(r) and is rejected here (ParameterError).
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "translucent/material/material.h"

namespace translucent::material {

inline constexpr int kDefaultProfileSegments = 16;
inline constexpr double kProfileRadiusFraction = 0.95;
inline constexpr double kExtrapolationFactor = 3.0;
inline constexpr double kLnFloor = -80.0;

struct ProfileOptions {
  int segments = kDefaultProfileSegments;  // n >= 1
  double radius = 0.0;                     // r_s [scene units]; 0: the largest 95% radius
};

// Eq. 9 on one channel's n + 1 nodes (stride: distance between consecutive nodes in `nodes`):
// ln P at r >= 0, with the extrapolation and cut described above (−∞ beyond r_cut, or beyond
// r_s when the last slope is >= 0).
double lnProfileAt(const double* nodes, size_t stride, int segments, double radius, double r);

class PointProfiles {
 public:
  PointProfiles() = default;
  // Profiles of the given local media (coefficients per medium unit) under `material`'s model,
  // η and scale (material.medium.eta, material.medium.scale). Identical media share one profile
  // evaluation. Throws ParameterError for a .bssrdf model, an invalid medium, segments < 1 or a
  // radius that is negative or not finite.
  static PointProfiles build(const Material& material, std::span<const LocalMedium> media,
                             const ProfileOptions& options = {});
  // The local media of surface points (Material::surfaceMedium of each position, normal and atlas
  // UV; `uvs` may be empty unless the material is Kind::Surface).
  static std::vector<LocalMedium> surfaceMedia(const Material& material,
                                               std::span<const glm::vec3> positions,
                                               std::span<const glm::vec3> normals,
                                               std::span<const glm::vec2> uvs = {});

  size_t size() const { return count_; }
  int segments() const { return segments_; }
  double radius() const { return radius_; }                           // r_s
  double cutRadius() const { return kExtrapolationFactor * radius_; }  // r_cut

  // Node k (0..n) of point p, channel c: ln P_p(r_k).
  double node(size_t p, int c, int k) const { return nodes_[index(p, k) + size_t(c)]; }
  // All nodes: [(p (n + 1) + k) 3 + c].
  const std::vector<double>& nodes() const { return nodes_; }

  glm::dvec3 lnAt(size_t p, double r) const;  // ln P_p(r) per channel
  glm::dvec3 at(size_t p, double r) const;    // P_p(r) per channel [1/scene unit²]
  // Eq. 8: sqrt(P_i(r) P_o(r)) per channel [1/scene unit²].
  glm::dvec3 rd(size_t i, size_t o, double r) const;

 private:
  size_t index(size_t p, int k) const { return (p * size_t(segments_ + 1) + size_t(k)) * 3; }
  size_t count_ = 0;
  int segments_ = kDefaultProfileSegments;
  double radius_ = 0.0;
  std::vector<double> nodes_;
};

}  // namespace translucent::material
