// SPDX-License-Identifier: GPL-3.0-or-later
// The majorant grid and the heterogeneous medium of the closed-body walk (majorant_grid.h).
#include "translucent/reference/majorant_grid.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include <glm/mat3x3.hpp>

namespace translucent::reference {
namespace {
bool finite3(const glm::dvec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}
}  // namespace

glm::ivec3 MajorantGrid::defaultCells(const glm::dvec3& lower, const glm::dvec3& upper) {
  const glm::dvec3 e = upper - lower;
  const double longest = std::max({e.x, e.y, e.z});
  glm::ivec3 n;
  for (int a = 0; a < 3; ++a)
    n[a] = std::clamp(static_cast<int>(std::ceil(32.0 * e[a] / longest - 1e-9)), 8, 64);
  return n;
}

MajorantGrid::MajorantGrid(const material::VolumeField& field, const material::MaterialFrame& frame,
                           double scale, const glm::dvec3& lower, const glm::dvec3& upper,
                           glm::ivec3 cells)
    : lower_(lower), upper_(upper) {
  if (!finite3(lower) || !finite3(upper) || !(upper.x > lower.x && upper.y > lower.y && upper.z > lower.z))
    throw ParameterError(fmt::format(
        "majorant grid: the box ({}, {}, {}) .. ({}, {}, {}) is empty or not finite", lower.x,
        lower.y, lower.z, upper.x, upper.y, upper.z));
  if (!(std::isfinite(scale) && scale > 0.0))
    throw ParameterError(fmt::format("majorant grid: coefficient scale is {}: expected > 0", scale));
  if (cells.x <= 0 || cells.y <= 0 || cells.z <= 0) cells = defaultCells(lower, upper);
  if (static_cast<int64_t>(cells.x) * cells.y * cells.z > (1 << 24))
    throw ParameterError("majorant grid: more than 2^24 cells");
  n_ = cells;
  cell_ = (upper - lower) / glm::dvec3(n_);
  invCell_ = 1.0 / cell_;
  sigma_.reserve(static_cast<size_t>(n_.x) * static_cast<size_t>(n_.y) * static_cast<size_t>(n_.z) * 3);
  for (int k = 0; k < n_.z; ++k)
    for (int j = 0; j < n_.y; ++j)
      for (int ii = 0; ii < n_.x; ++ii) {
        // The cell, enlarged by 1% of its size on each side, and the material-space box of its
        // corners.
        const glm::dvec3 lo = lower + glm::dvec3(ii - 0.01, j - 0.01, k - 0.01) * cell_;
        const glm::dvec3 hi = lower + glm::dvec3(ii + 1.01, j + 1.01, k + 1.01) * cell_;
        glm::dvec3 qlo(std::numeric_limits<double>::infinity()), qhi(-qlo);
        // A deformed frame (mesh.deform) maps a cell to a curved region whose corners do not
        // bound it: the field's bound over all of material space instead (a global majorant:
        // unbiased, with more null collisions).
        if (frame.deformed()) {
          qlo = glm::dvec3(-1e12);
          qhi = glm::dvec3(1e12);
        }
        for (int corner = 0; corner < 8 && !frame.deformed(); ++corner) {
          const glm::dvec3 x{(corner & 1) ? hi.x : lo.x, (corner & 2) ? hi.y : lo.y,
                             (corner & 4) ? hi.z : lo.z};
          const glm::dvec3 q = frame.toMaterial(x);
          qlo = glm::min(qlo, q);
          qhi = glm::max(qhi, q);
        }
        const Rgb m = field.majorant(qlo, qhi);
        for (size_t c = 0; c < 3; ++c) {
          if (!(std::isfinite(m[c]) && m[c] >= 0.0))
            throw ParameterError(fmt::format(
                "majorant grid: the field's bound in channel {} over a cell is {}: expected a "
                "finite value >= 0", kChannelNames[c], m[c]));
          const double b = m[c] * scale;
          sigma_.push_back(b);
          max_[c] = std::max(max_[c], b);
          mean_[c] += b;
        }
      }
  for (double& m : mean_) m /= static_cast<double>(sigma_.size() / 3);
}

VolumeMedium VolumeMedium::make(const material::Material& material, const glm::dvec3& lower,
                                const glm::dvec3& upper, glm::ivec3 cells) {
  if (material.kind != material::Material::Kind::Volume || !material.volume)
    throw ParameterError("heterogeneous transport: the material is not a 3D field (kind Volume "
                         "with a field)");
  material.medium.validate();
  VolumeMedium v;
  v.field = material.volume;
  v.frame = material.frame;
  v.coefficient_scale = material.medium.scale;
  v.eta = material.medium.eta;
  v.grid = std::make_shared<const MajorantGrid>(*v.field, v.frame, v.coefficient_scale, lower,
                                                upper, cells);
  return v;
}

}  // namespace translucent::reference
