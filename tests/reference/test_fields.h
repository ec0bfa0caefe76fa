// SPDX-License-Identifier: GPL-3.0-or-later
// Small material::VolumeField implementations for the heterogeneous tracer's tests: a homogeneous
// medium as a field (with a majorant that may be loose on purpose), plane layers in material z,
// and a sphere of one medium inside another.
#pragma once

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>

#include "translucent/material/material.h"

namespace translucent::reference::testing {

inline Rgb maxRgb(const Rgb& a, const Rgb& b) {
  return {std::max(a[0], b[0]), std::max(a[1], b[1]), std::max(a[2], b[2])};
}

// The same medium everywhere; the bound is `factor` >= 1 times σt (factor > 1: null collisions).
class UniformField final : public material::VolumeField {
 public:
  UniformField(material::LocalMedium m, double factor) : m_(m), factor_(factor) {}
  material::LocalMedium at(const glm::dvec3&) const override { return m_; }
  Rgb majorant(const glm::dvec3&, const glm::dvec3&) const override {
    const Rgb t = m_.sigmaT();
    return {factor_ * t[0], factor_ * t[1], factor_ * t[2]};
  }

 private:
  material::LocalMedium m_;
  double factor_;
};

// Media stacked downwards in material z: media[0] for z > planes[0], media[1] for
// planes[0] >= z > planes[1], …, the last below the last plane (planes descending).
class PlaneLayers final : public material::VolumeField {
 public:
  PlaneLayers(std::vector<double> planes, std::vector<material::LocalMedium> media)
      : planes_(std::move(planes)), media_(std::move(media)) {}
  material::LocalMedium at(const glm::dvec3& q) const override { return media_[layerOf(q.z)]; }
  Rgb majorant(const glm::dvec3& lo, const glm::dvec3& hi) const override {
    Rgb m{0.0, 0.0, 0.0};
    for (size_t i = layerOf(hi.z); i <= layerOf(lo.z); ++i) m = maxRgb(m, media_[i].sigmaT());
    return m;
  }

 private:
  size_t layerOf(double z) const {
    size_t i = 0;
    while (i < planes_.size() && !(z > planes_[i])) ++i;
    return i;
  }
  std::vector<double> planes_;
  std::vector<material::LocalMedium> media_;
};

// `inner` within distance `radius` of the origin, `outer` elsewhere.
class CoreField final : public material::VolumeField {
 public:
  CoreField(double radius, material::LocalMedium inner, material::LocalMedium outer)
      : r_(radius), inner_(inner), outer_(outer) {}
  material::LocalMedium at(const glm::dvec3& q) const override {
    return glm::length(q) < r_ ? inner_ : outer_;
  }
  Rgb majorant(const glm::dvec3& lo, const glm::dvec3& hi) const override {
    const glm::dvec3 nearest = glm::clamp(glm::dvec3(0.0), lo, hi);
    return glm::length(nearest) < r_ ? maxRgb(inner_.sigmaT(), outer_.sigmaT()) : outer_.sigmaT();
  }

 private:
  double r_;
  material::LocalMedium inner_, outer_;
};

inline material::LocalMedium grey(double sigma_a, double sigma_s, double g) {
  return {{sigma_a, sigma_a, sigma_a}, {sigma_s, sigma_s, sigma_s}, g};
}

}  // namespace translucent::reference::testing
