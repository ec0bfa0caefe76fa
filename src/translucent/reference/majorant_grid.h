// SPDX-License-Identifier: GPL-3.0-or-later
// Heterogeneous media in the closed-body walk (transport.h): a material::VolumeField inside the
// body, traced by delta (Woodcock) tracking against a coarse grid of majorants.
//
// The grid. A regular grid of cells over an axis-aligned box in scene space (the body's bounds).
// Per cell and channel it holds an upper bound σ̄ of σt [1/scene unit]: the field's own bound
// (VolumeField::majorant) over the material-space axis-aligned box of the cell's 8 corners taken
// through the material frame (q = scale Rᵀ (x − translate)), cells enlarged by 1% of their size
// first so that rounding at a cell face never reads a neighbour's lower bound, times the
// coefficient scale (Medium::scale: per medium unit -> per scene unit). A thin, clear region and
// a dense one thus do not share one bound; the price of a loose bound is only null collisions.
// Default resolution (defaultCells): 32 cells along the longest side of the box, the same cell
// size along the others, at least 8 cells on every axis (a flat box keeps layers apart in z), at
// most 64: a few thousand to 64k field bounds built once, a few hundred kB.
//
// Delta tracking (Novák et al. 2018, section 4.1; Woodcock 1965). Along a ray the tentative
// collisions form a Poisson process of rate σ̄(x), piecewise constant over the cells: one
// exponential optical depth τ = −ln ξ is spent cell by cell (a 3D DDA, Amanatides & Woo 1987)
// until it runs out at t; there the collision is real with probability σt(x)/σ̄ (the field is
// evaluated once), else it is a null collision and the flight goes on straight with a fresh τ.
// The distance to the first real collision then has exactly the density σt(t) exp(−∫σt), for
// any bound σ̄ >= σt. Beyond the grid's box (only a photon that slipped through the mesh at an
// edge, mesh_tracer.h, flies there) the bound is the largest cell's.
//
// Ratio tracking (Novák et al. 2018, section 5.2) replaces the 0/1 outcome of a tracked segment
// by its transmittance estimate ∏(1 − σt/σ̄), which lowers the variance of estimators of
// T(x, y) along a given segment (shadow rays of next-event estimation, transmittance to a
// light). This tracer has no such estimator: light enters by a ray query at the surface, every
// photon is scored analogically where it crosses the boundary outwards (its exit, the random
// end of a free flight), and the camera's shadow ray (camera.h) runs in air outside the body.
// The free-flight distance itself must be sampled (a photon's next collision point decides
// where it goes), and for sampling delta tracking is the unbiased, unit-weight choice; a
// weighted ("ratio") flight with weights σt/σ̄ at null collisions would only add weight
// variance to the same exits. So ratio tracking is not used.
#pragma once

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include <glm/vec3.hpp>

#include "translucent/material/material.h"
#include "translucent/reference/rng.h"
#include "translucent/reference/sampling.h"

namespace translucent::reference {

class MajorantGrid {
 public:
  // Bounds of `field` (per medium unit, times `coefficient_scale`) over `cells` (0 on any axis:
  // defaultCells) cells of the scene-space box [lower, upper]. Throws ParameterError for an
  // empty or non-finite box, or a field bound that is negative or not finite.
  MajorantGrid(const material::VolumeField& field, const material::MaterialFrame& frame,
               double coefficient_scale, const glm::dvec3& lower, const glm::dvec3& upper,
               glm::ivec3 cells = {0, 0, 0});

  static glm::ivec3 defaultCells(const glm::dvec3& lower, const glm::dvec3& upper);

  glm::ivec3 cells() const { return n_; }
  const glm::dvec3& lower() const { return lower_; }
  const glm::dvec3& upper() const { return upper_; }
  // Channel c's bound in cell (i, j, k) [1/scene unit].
  double bound(int i, int j, int k, int c) const {
    return sigma_[(static_cast<size_t>(k) * static_cast<size_t>(n_.y) + static_cast<size_t>(j)) *
                      static_cast<size_t>(n_.x) * 3 +
                  static_cast<size_t>(i) * 3 + static_cast<size_t>(c)];
  }
  double maxBound(int c) const { return max_[static_cast<size_t>(c)]; }
  double meanBound(int c) const { return mean_[static_cast<size_t>(c)]; }

  // Delta tracking of channel c from o along unit d over (0, t_max] (t_max may be infinite).
  // accept(t, bound) is called at each tentative collision o + t d with the bound in force
  // there and returns whether it is real (it draws its own random number, from `rng` too).
  // Returns true with `t` the first real collision, or false if none happened before t_max.
  template <class Accept>
  bool track(const glm::dvec3& o, const glm::dvec3& d, double t_max, int c, Rng& rng,
             Accept&& accept, double& t) const;

 private:
  glm::dvec3 lower_, upper_, cell_, invCell_;
  glm::ivec3 n_;
  std::vector<double> sigma_;  // [k][j][i][c]
  double max_[3] = {0.0, 0.0, 0.0}, mean_[3] = {0.0, 0.0, 0.0};
};

// A heterogeneous medium filling a body: the field, its frame and units, the object's single η,
// and the majorant grid built over the body's bounds.
struct VolumeMedium {
  std::shared_ptr<const material::VolumeField> field;
  material::MaterialFrame frame;
  double coefficient_scale = 1.0;  // per medium unit -> per scene unit (Medium::scale)
  double eta = 1.3;                // n_inside / n_outside, the same for every point
  std::shared_ptr<const MajorantGrid> grid;
  // Tentative collisions where the field exceeded the bound in force (a field whose majorant()
  // is wrong: delta tracking is then biased there), summed over every run with this medium; a
  // check for field implementations, 0 when the bounds hold. (It may also count collisions of a
  // photon that slipped out of the body and flies beyond the grid's box, where the bound is the
  // largest cell's and the field is not bounded by anything.)
  std::shared_ptr<std::atomic<uint64_t>> majorant_violations =
      std::make_shared<std::atomic<uint64_t>>(0);
  uint64_t majorantViolations() const {
    return majorant_violations ? majorant_violations->load() : 0;
  }

  // From a Kind::Volume material (its medium's η and scale); the grid over [lower, upper].
  // Throws ParameterError for another kind or a missing field.
  static VolumeMedium make(const material::Material& material, const glm::dvec3& lower,
                           const glm::dvec3& upper, glm::ivec3 cells = {0, 0, 0});

  // The local medium (coefficients per medium unit) at scene point x.
  material::LocalMedium at(const glm::dvec3& x) const { return field->at(frame.toMaterial(x)); }
};

// ---------------------------------------------------------------------------------------------

template <class Accept>
bool MajorantGrid::track(const glm::dvec3& o, const glm::dvec3& d, double tMax, int c, Rng& rng,
                         Accept&& accept, double& tOut) const {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  double tau = -std::log(1.0 - detail::uniform01(rng));
  // Spends the optical depth over [ta, tb) at rate m; true at a real collision (tOut set).
  auto segment = [&](double ta, double tb, double m) {
    if (!(m > 0.0)) return false;
    for (;;) {
      const double len = tb > ta ? tb - ta : 0.0;
      if (tau >= m * len) {
        tau -= m * len;
        return false;
      }
      const double t = ta + tau / m;
      if (accept(t, m)) {
        tOut = t;
        return true;
      }
      tau = -std::log(1.0 - detail::uniform01(rng));
      ta = t;
    }
  };
  const double mOut = max_[c];
  // Clip [0, t_max] to the box (slab test).
  double t0 = 0.0, t1 = tMax;
  double inv[3];
  for (int a = 0; a < 3; ++a) {
    inv[a] = d[a] != 0.0 ? 1.0 / d[a] : 0.0;
    if (d[a] == 0.0) {
      if (o[a] < lower_[a] || o[a] > upper_[a]) t1 = -1.0;
      continue;
    }
    double ta = (lower_[a] - o[a]) * inv[a], tb = (upper_[a] - o[a]) * inv[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  if (!(t0 < t1)) return segment(0.0, tMax, mOut);
  if (t0 > 0.0 && segment(0.0, t0, mOut)) return true;

  // DDA over the cells from o + t0 d.
  const glm::dvec3 p = o + t0 * d;
  int cell[3], step[3];
  double next[3], delta[3];
  for (int a = 0; a < 3; ++a) {
    const int na = n_[a];
    cell[a] = std::clamp(static_cast<int>((p[a] - lower_[a]) * invCell_[a]), 0, na - 1);
    if (d[a] > 0.0) {
      step[a] = 1;
      next[a] = (lower_[a] + (cell[a] + 1) * cell_[a] - o[a]) * inv[a];
      delta[a] = cell_[a] * inv[a];
    } else if (d[a] < 0.0) {
      step[a] = -1;
      next[a] = (lower_[a] + cell[a] * cell_[a] - o[a]) * inv[a];
      delta[a] = -cell_[a] * inv[a];
    } else {
      step[a] = 0;
      next[a] = kInf;
      delta[a] = kInf;
    }
  }
  double t = t0;
  for (;;) {
    const int a = next[0] < next[1] ? (next[0] < next[2] ? 0 : 2) : (next[1] < next[2] ? 1 : 2);
    const double tExit = std::min(next[a], t1);
    if (segment(t, tExit, bound(cell[0], cell[1], cell[2], c))) return true;
    if (tExit >= t1) break;
    t = tExit;
    cell[a] += step[a];
    if (cell[a] < 0 || cell[a] >= n_[a]) {  // left the box early (rounding): the outer bound
      if (segment(t, t1, mOut)) return true;
      break;
    }
    next[a] += delta[a];
  }
  return t1 < tMax && segment(t1, tMax, mOut);
}

}  // namespace translucent::reference
