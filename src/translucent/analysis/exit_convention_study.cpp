// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/analysis/exit_convention_study.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <glm/geometric.hpp>

#include "translucent/optics/medium.h"

namespace translucent::analysis {
namespace {

using bssrdf::ExitConvention;

void checkOptions(const ExitConventionStudyOptions& o) {
  const auto& e = o.cos_edges;
  if (e.size() < 2)
    throw ParameterError("exit convention study: cos_edges needs at least two bin edges");
  for (size_t i = 0; i < e.size(); ++i) {
    if (!(e[i] > 0.0 && e[i] <= 1.0))
      throw ParameterError(fmt::format(
          "exit convention study: cos_edges[{}] is {}: expected a cosine in (0, 1]", i, e[i]));
    if (i > 0 && !(e[i] > e[i - 1]))
      throw ParameterError("exit convention study: cos_edges must increase");
  }
  if (!(o.depth_tolerance > 0.0))
    throw ParameterError(fmt::format("exit convention study: depth_tolerance is {}: expected > 0",
                                     o.depth_tolerance));
}

// κ(μ) = cone-averaged Jensen factor / Jensen factor on the axis, tabulated on [μ0, 1] (smooth:
// linear interpolation between 257 nodes is exact to ~1e-7).
class ConeCorrection {
 public:
  ConeCorrection(double eta, double mu0, double cone) : mu0_(mu0) {
    values_.resize(kNodes);
    for (int i = 0; i < kNodes; ++i) {
      const double mu = mu0 + (1.0 - mu0) * i / (kNodes - 1);
      values_[size_t(i)] =
          bssrdf::coneAveragedExitRadianceFactor(ExitConvention::Jensen, eta, mu, cone) /
          bssrdf::exitRadianceFactor(ExitConvention::Jensen, eta, mu);
    }
  }
  double operator()(double mu) const {
    const double x = std::clamp((mu - mu0_) / (1.0 - mu0_), 0.0, 1.0) * (kNodes - 1);
    const int i = std::min(static_cast<int>(x), kNodes - 2);
    const double f = x - i;
    return (1.0 - f) * values_[size_t(i)] + f * values_[size_t(i) + 1];
  }

 private:
  static constexpr int kNodes = 257;
  double mu0_;
  std::vector<double> values_;
};

ViewAngleBin summarize(const reference::CameraImages& images, std::span<const uint32_t> pixels,
                       std::span<const double> cosines, const ConeCorrection& kappa, int c,
                       double eta, double lo, double hi) {
  ViewAngleBin bin;
  bin.cos_lo = lo;
  bin.cos_hi = hi;
  bin.pixels = pixels.size();
  if (pixels.empty()) return bin;
  bin.cone = images.cone_radiance.average(pixels, c);
  bin.exitance = images.exitance.average(pixels, c);
  const reference::Estimate plain = images.radiance.average(pixels, c);
  const int w = images.radiance.width();
  double weighted = 0.0;
  for (uint32_t p : pixels)
    weighted += kappa(cosines[p]) *
                images.radiance.pixel(static_cast<int>(p % uint32_t(w)), static_cast<int>(p / uint32_t(w)), c).value;
  weighted /= static_cast<double>(pixels.size());
  // κ is within a few percent of 1 and smooth: the weighted mean's error is the plain one's,
  // scaled.
  bin.jensen = {weighted, plain.value > 0.0 ? plain.std_error * weighted / plain.value : 0.0};
  for (ExitConvention conv : {ExitConvention::Jensen, ExitConvention::Normalized}) {
    const double prediction = bin.jensen.value * bssrdf::exitConventionScale(conv, eta);
    ConventionRatio& r = bin.ratio[static_cast<size_t>(conv)];
    if (!(prediction > 0.0) || !(bin.cone.value > 0.0)) continue;
    r.value = bin.cone.value / prediction;
    const double a = bin.cone.std_error / bin.cone.value, b = bin.jensen.std_error / bin.jensen.value;
    r.std_error = r.value * std::sqrt(a * a + b * b);
  }
  return bin;
}

}  // namespace

std::vector<double> interiorViewCosines(const reference::Body& body,
                                        const reference::CameraModel& camera,
                                        const ExitConventionStudyOptions& options) {
  checkOptions(options);
  const int w = camera.camera().width, h = camera.camera().height;
  const double tol = options.depth_tolerance * body.bounds().radius;
  const double lowest = options.cos_edges.front();
  constexpr double kOffsets[5][2] = {{0.0, 0.0}, {-0.35, -0.35}, {0.35, -0.35}, {-0.35, 0.35}, {0.35, 0.35}};
  std::vector<double> cosines(size_t(w) * size_t(h), 0.0);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      double centre = 0.0;
      glm::dvec3 p0{0.0}, n0{0.0};
      bool keep = true;
      for (int k = 0; k < 5 && keep; ++k) {
        glm::dvec3 o, d;
        camera.ray(i + 0.5 + kOffsets[k][0], j + 0.5 + kOffsets[k][1], o, d);
        reference::SurfaceHit hit;
        if (!body.intersect(o, d, 0.0, std::numeric_limits<double>::infinity(), hit)) {
          keep = false;
          break;
        }
        // The normal may have either orientation (SurfaceHit); the visible side faces the camera.
        const double mu = std::abs(glm::dot(hit.normal, d));
        if (k == 0) {
          centre = mu;
          p0 = o + hit.t * d;
          n0 = hit.normal;
        } else {
          // Same surface: the hit lies near the centre's tangent plane (a slope is no step).
          const double tPlane = glm::dot(p0 - o, n0) / glm::dot(d, n0);
          if (std::abs(hit.t - tPlane) > tol) keep = false;
        }
        if (!(mu > lowest)) keep = false;
      }
      if (keep) cosines[size_t(j) * size_t(w) + size_t(i)] = centre;
    }
  return cosines;
}

std::vector<ChannelStudy> studyExitConventions(const reference::CameraImages& images,
                                               const reference::Body& body,
                                               const reference::CameraModel& camera,
                                               std::span<const double> etas,
                                               double cone_half_angle_degrees,
                                               const ExitConventionStudyOptions& options) {
  const auto cosines = interiorViewCosines(body, camera, options);
  return studyExitConventions(images, cosines, etas, cone_half_angle_degrees, options);
}

std::vector<ChannelStudy> studyExitConventions(const reference::CameraImages& images,
                                               std::span<const double> view_cosines,
                                               std::span<const double> etas,
                                               double cone_half_angle_degrees,
                                               const ExitConventionStudyOptions& options) {
  checkOptions(options);
  if (!(cone_half_angle_degrees > 0.0 && cone_half_angle_degrees <= 90.0))
    throw ParameterError(fmt::format("exit convention study: cone half-angle {} degrees: expected "
                                     "a value in (0, 90]", cone_half_angle_degrees));
  const int w = images.radiance.width(), h = images.radiance.height();
  if (view_cosines.size() != size_t(w) * size_t(h))
    throw ParameterError(fmt::format("exit convention study: {} view cosines for a {}x{} image",
                                     view_cosines.size(), w, h));
  if (etas.size() != size_t(images.radiance.channels()))
    throw ParameterError(fmt::format("exit convention study: {} values of eta for {} channels",
                                     etas.size(), images.radiance.channels()));
  const auto& edges = options.cos_edges;
  const size_t nb = edges.size() - 1;
  std::vector<std::vector<uint32_t>> binPixels(nb);
  std::vector<uint32_t> all;
  for (size_t p = 0; p < view_cosines.size(); ++p) {
    const double mu = view_cosines[p];
    if (!(mu >= edges.front())) continue;
    size_t b = static_cast<size_t>(std::upper_bound(edges.begin(), edges.end(), mu) - edges.begin());
    b = std::min(b, nb) - 1;  // μ = the last edge (1) belongs to the last bin
    binPixels[b].push_back(static_cast<uint32_t>(p));
    all.push_back(static_cast<uint32_t>(p));
  }
  const double cone = cone_half_angle_degrees * std::numbers::pi / 180.0;
  std::vector<ChannelStudy> out;
  for (int c = 0; c < images.radiance.channels(); ++c) {
    const double eta = etas[size_t(c)];
    const ConeCorrection kappa(eta, edges.front(), cone);
    ChannelStudy s;
    s.eta = eta;
    for (size_t b = 0; b < nb; ++b)
      s.bins.push_back(summarize(images, binPixels[b], view_cosines, kappa, c, eta, edges[b], edges[b + 1]));
    s.all = summarize(images, all, view_cosines, kappa, c, eta, edges.front(), edges.back());
    out.push_back(std::move(s));
  }
  return out;
}

}  // namespace translucent::analysis
