// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/material/point_profiles.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>

#include "translucent/bssrdf/bssrdf_file.h"
#include "translucent/bssrdf/registry.h"

namespace translucent::material {
namespace {

// Up to this many distinct media, r_s is computed exactly from each medium's profiles.
constexpr size_t kExactRadiusMedia = 256;

using Key = std::array<double, 7>;
Key keyOf(const LocalMedium& m) {
  return {m.sigma_a[0], m.sigma_a[1], m.sigma_a[2], m.sigma_s[0], m.sigma_s[1], m.sigma_s[2], m.g};
}

double lnClamped(double p) { return p > 0.0 ? std::max(std::log(p), kLnFloor) : kLnFloor; }

// 2π ∫0^r1 exp(v0 + (v1 − v0) r / r1) r dr (composite Simpson, 64 intervals: the integrand is
// smooth, an exponential times r).
double segmentEnergy(double v0, double v1, double r1) {
  constexpr int kIntervals = 64;
  const double h = r1 / kIntervals;
  double sum = 0.0;
  for (int i = 0; i <= kIntervals; ++i) {
    const double r = h * i;
    const double f = std::exp(v0 + (v1 - v0) * r / r1) * r;
    sum += f * ((i == 0 || i == kIntervals) ? 1.0 : (i % 2 == 1 ? 4.0 : 2.0));
  }
  return 2.0 * std::numbers::pi * sum * h / 3.0;
}

// The model's 2π ∫0^r1 P r dr: Gauss-Legendre panels on a logarithmic grid (r P stays finite
// where P ~ 1/r), the first panel from 0.
double modelEnergy(const bssrdf::RadialProfile& p, double r1) {
  constexpr int kPanels = 24;
  double sum = 0.0, a = 0.0;
  for (int i = kPanels - 1; i >= 0; --i) {
    const double b = r1 * std::pow(2.0, -double(i));
    sum += bssrdf::integratePanel(p, a, b);
    a = b;
  }
  return sum;
}

// Node 0 where P(0) is not finite: the value whose first segment carries the model's energy.
double energyMatchedFirstNode(const bssrdf::RadialProfile& p, double v1, double r1) {
  const double target = modelEnergy(p, r1);
  if (!(target > 0.0) || !std::isfinite(target)) return v1;
  double lo = v1 - 60.0, hi = v1 + 60.0;
  for (int it = 0; it < 100; ++it) {
    const double mid = 0.5 * (lo + hi);
    (segmentEnergy(mid, v1, r1) < target ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace

double lnProfileAt(const double* nodes, size_t stride, int segments, double radius, double r) {
  const double t = std::abs(r) / radius * segments;
  const double vn = nodes[size_t(segments) * stride];
  if (t <= double(segments)) {
    const int k = std::min(static_cast<int>(t), segments - 1);
    const double w = t - k;
    return (1.0 - w) * nodes[size_t(k) * stride] + w * nodes[size_t(k + 1) * stride];
  }
  // The tail: the last segment of ln(r² P) extended (see the header).
  const double c = segments > 1 ? 2.0 * std::log(double(segments) / double(segments - 1)) : 0.0;
  const double l = segments > 1 ? 2.0 * std::log(t / double(segments)) : 0.0;
  const double slope = vn - nodes[size_t(segments - 1) * stride] + c;
  if (!(slope < 0.0) || t > kExtrapolationFactor * segments)
    return -std::numeric_limits<double>::infinity();
  return vn + (t - segments) * slope - l;
}

PointProfiles PointProfiles::build(const Material& material, std::span<const LocalMedium> media,
                                   const ProfileOptions& options) {
  if (options.segments < 1)
    throw ParameterError(fmt::format("point profiles: segments {}: expected at least 1",
                                     options.segments));
  if (!(options.radius >= 0.0) || !std::isfinite(options.radius))
    throw ParameterError(fmt::format("point profiles: radius {}: expected a finite r_s >= 0 "
                                     "(0: the largest 95% radius)", options.radius));
  if (bssrdf::hasBssrdfExtension(material.model))
    throw ParameterError(fmt::format("point profiles: model '{}' is a .bssrdf file, whose R(r) "
                                     "needs the GPU evaluator: expected a registered model",
                                     material.model));
  const bssrdf::Model& model = bssrdf::model(material.model);
  const double eta = material.medium.eta, scale = material.medium.scale;

  // Unique media (a field of a few media has a few profiles to evaluate, not one per point).
  std::map<Key, size_t> uniqueIndex;
  std::vector<LocalMedium> unique;
  std::vector<size_t> of(media.size());
  for (size_t i = 0; i < media.size(); ++i) {
    auto [it, inserted] = uniqueIndex.try_emplace(keyOf(media[i]), unique.size());
    if (inserted) unique.push_back(media[i]);
    of[i] = it->second;
  }
  if (model.tabulated() && unique.size() > 1)
    throw ParameterError(fmt::format("point profiles: model '{}' is a tabulated profile, the R(r) "
                                     "of one material: {} different media need an analytic model",
                                     material.model, unique.size()));

  PointProfiles out;
  out.count_ = media.size();
  out.segments_ = options.segments;
  out.radius_ = options.radius;
  if (out.radius_ == 0.0) {
    if (unique.size() <= kExactRadiusMedia) {
      for (const LocalMedium& m : unique) {
        const Medium med = m.medium(eta, scale);
        med.validate();
        const bssrdf::RgbProfiles prof = bssrdf::profiles(model, med);
        for (const auto& p : prof) out.radius_ = std::max(out.radius_, p->radiusForFraction(kProfileRadiusFraction));
      }
    } else {
      // Many media (a continuous field): the models are scale invariant and depend on α' and η
      // alone (bssrdf::Model::totalReflectance), so the 95% radius is ρ(α') / σt' with ρ that of
      // the medium σt' = 1, g = 0 of the same α'. ρ is evaluated once per bin of 1 − α' (bins of
      // 0.1% in ln(1 − α')): r_s is then the largest radius within ~0.1%, at a cost that no
      // longer grows with the number of media (a radius costs ~0.1 ms: 100k media took 40 s).
      std::map<long long, double> rho;
      for (const LocalMedium& m : unique) {
        const Medium med = m.medium(eta, scale);
        med.validate();
        for (int c = 0; c < 3; ++c) {
          const ScalarMedium sm = med.channel(c);
          const double ap = sm.reducedAlbedo();
          const auto bin = static_cast<long long>(std::llround(std::log(std::max(1.0 - ap, 1e-300)) * 1000.0));
          auto it = rho.find(bin);
          if (it == rho.end()) {
            const double binAlpha = 1.0 - std::exp(double(bin) / 1000.0);
            const ScalarMedium unit{1.0 - binAlpha, binAlpha, 0.0, eta};
            it = rho.emplace(bin, model.profile(unit)->radiusForFraction(kProfileRadiusFraction)).first;
          }
          out.radius_ = std::max(out.radius_, it->second / sm.sigmaTPrime());
        }
      }
    }
    if (unique.empty()) out.radius_ = 1.0;
    if (!(out.radius_ > 0.0) || !std::isfinite(out.radius_))
      throw ParameterError(fmt::format("point profiles: the largest 95% radius is {}: expected a "
                                       "positive finite radius", out.radius_));
  }

  const int n = out.segments_;
  const double step = out.radius_ / n;
  std::vector<double> uniqueNodes(unique.size() * size_t(n + 1) * 3);
  for (size_t u = 0; u < unique.size(); ++u) {
    const Medium med = unique[u].medium(eta, scale);
    med.validate();
    const bssrdf::RgbProfiles prof = bssrdf::profiles(model, med);
    for (int c = 0; c < 3; ++c) {
      double* v = &uniqueNodes[u * size_t(n + 1) * 3 + size_t(c)];
      for (int k = 0; k <= n; ++k) v[size_t(k) * 3] = lnClamped(prof[size_t(c)]->R(step * k));
      const double p0 = prof[size_t(c)]->R(0.0);
      if (!std::isfinite(p0) || !(p0 > 0.0)) v[0] = energyMatchedFirstNode(*prof[size_t(c)], v[3], step);
    }
  }
  out.nodes_.resize(out.count_ * size_t(n + 1) * 3);
  for (size_t i = 0; i < out.count_; ++i)
    std::copy_n(&uniqueNodes[of[i] * size_t(n + 1) * 3], size_t(n + 1) * 3, &out.nodes_[out.index(i, 0)]);
  return out;
}

std::vector<LocalMedium> PointProfiles::surfaceMedia(const Material& material,
                                                     std::span<const glm::vec3> positions,
                                                     std::span<const glm::vec3> normals,
                                                     std::span<const glm::vec2> uvs) {
  if (normals.size() != positions.size())
    throw ParameterError(fmt::format("surface media: {} normals for {} positions: expected one per "
                                     "position", normals.size(), positions.size()));
  if (material.kind == Material::Kind::Surface && uvs.size() != positions.size())
    throw ParameterError(fmt::format("surface media: {} atlas UVs for {} positions of a surface-map "
                                     "material: expected one per position", uvs.size(),
                                     positions.size()));
  std::vector<LocalMedium> out(positions.size());
  for (size_t i = 0; i < positions.size(); ++i)
    out[i] = material.surfaceMedium(glm::dvec3(positions[i]), glm::dvec3(normals[i]),
                                    uvs.empty() ? glm::dvec2(0.0) : glm::dvec2(uvs[i]));
  return out;
}

glm::dvec3 PointProfiles::lnAt(size_t p, double r) const {
  glm::dvec3 out;
  for (int c = 0; c < 3; ++c)
    out[c] = lnProfileAt(&nodes_[index(p, 0) + size_t(c)], 3, segments_, radius_, r);
  return out;
}

glm::dvec3 PointProfiles::at(size_t p, double r) const { return glm::exp(lnAt(p, r)); }

glm::dvec3 PointProfiles::rd(size_t i, size_t o, double r) const {
  return glm::exp(0.5 * (lnAt(i, r) + lnAt(o, r)));
}

}  // namespace translucent::material
