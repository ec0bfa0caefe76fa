// SPDX-License-Identifier: GPL-3.0-or-later
// Monte Carlo integration of a radial profile model over the lit sphere (sphere_integration.h).
#include "translucent/reference/sphere_integration.h"

#include <fmt/format.h>

#include <cmath>
#include <numbers>

#include "translucent/optics/fresnel.h"
#include "translucent/reference/block_driver.h"
#include "translucent/reference/sampling.h"

namespace translucent::reference {

using detail::tangentFrame;
using detail::uniform01;

void IntegrationOptions::validate() const {
  if (!(defensive > 0.0 && defensive <= 1.0))
    throw ParameterError(fmt::format(
        "integration: defensive fraction is {}: expected a value in (0, 1] (uniform samples "
        "keep the importance sampler unbiased for every profile)",
        defensive));
  if (threads < 0)
    throw ParameterError(
        fmt::format("integration: threads is {}: expected >= 0 (0: all)", threads));
}

SphereIntegrator::SphereIntegrator(const bssrdf::Model& model, const SphereScene& scene,
                                   const Medium& medium, const IntegrationOptions& options)
    : scene_(scene), options_(options), camera_((scene.validate(), scene.camera())) {
  medium.validate();
  for (int c = 0; c < 3; ++c) channels_.push_back(medium.channel(c));
  init(model);
}

SphereIntegrator::SphereIntegrator(const bssrdf::Model& model, const SphereScene& scene,
                                   const ScalarMedium& medium, const IntegrationOptions& options)
    : scene_(scene), channels_{medium}, options_(options),
      camera_((scene.validate(), scene.camera())) {
  medium.validate();
  init(model);
}

void SphereIntegrator::init(const bssrdf::Model& model) {
  options_.validate();
  if (options_.sampling == SurfaceSampling::Uniform) options_.defensive = 1.0;
  for (const auto& m : channels_) {
    profiles_.push_back(model.profile(m));
    directional_.push_back(model.directional(m));
    const auto& table = profiles_.back()->cumulative();
    rdTable_.push_back(table.total());
    rMax_.push_back(table.edges.back());
  }
  light_ = glm::normalize(scene_.light_direction);
  const int w = scene_.width, h = scene_.height, nc = static_cast<int>(channels_.size());
  images_.exitance = McImage(w, h, nc, McImage::Statistics::PerPixel);
  images_.radiance = images_.exitance;
}

double SphereIntegrator::sampleExitance(const glm::dvec3& x_o, int c, Rng& rng) const {
  const double R = scene_.radius;
  const double eta = channels_[static_cast<size_t>(c)].eta;
  const bssrdf::RadialProfile& profile = *profiles_[static_cast<size_t>(c)];
  const bssrdf::DirectionalProfile* directional = directional_[static_cast<size_t>(c)].get();
  const double rdTable = rdTable_[static_cast<size_t>(c)], rMax = rMax_[static_cast<size_t>(c)];
  const double q = options_.defensive;
  const double uniformDensity = 1.0 / (2.0 * std::numbers::pi * R * R);
  const glm::dvec3 n_o = x_o / R;
  glm::dvec3 axes[3];
  axes[0] = n_o;
  tangentFrame(n_o, axes[1], axes[2]);
  constexpr double kAxisProbability[3] = {0.5, 0.25, 0.25};

  // Integrand: R(|x_o - x_i|) E(x_i), irradiance transmitted into the lit side; a directional
  // model's kernel R(x_i, n_i, l; x_o, n_o) in place of R(r) (bssrdf/profile.h). The radial
  // sampler below then draws from the model's normal-incidence restriction: still unbiased (the
  // uniform share covers the whole lit side), only less efficient where the kernel leans forward.
  auto integrand = [&](const glm::dvec3& x) {
    const glm::dvec3 n_i = x / R;
    const double cosI = glm::dot(n_i, light_);
    if (!(cosI > 0.0)) return 0.0;
    const double ft = eta == 1.0 ? 1.0 : fresnelTransmittance(cosI, eta);
    const double kernel =
        directional ? directional->R(x, n_i, light_, x_o, n_o) : profile.R(glm::length(x - x_o));
    return kernel * scene_.irradiance * ft * cosI;
  };
  // Expected number of hits per unit area at x of the mixture (see the header).
  auto density = [&](const glm::dvec3& x) {
    const glm::dvec3 n = x / R;
    double p = glm::dot(n, light_) > 0.0 ? q * uniformDensity : 0.0;
    if (q < 1.0) {
      const glm::dvec3 dx = x - x_o;
      for (int a = 0; a < 3; ++a) {
        const glm::dvec3 radial = dx - glm::dot(dx, axes[a]) * axes[a];
        const double rho = glm::length(radial);
        if (rho > rMax) continue;
        p += (1.0 - q) * kAxisProbability[a] * profile.R(rho) / rdTable *
             std::abs(glm::dot(n, axes[a]));
      }
    }
    return p;
  };

  if (q >= 1.0 || uniform01(rng) < q) {
    // Uniform on the lit hemisphere: cos θ about l uniform in [0, 1) is uniform in area.
    const double cosT = uniform01(rng), phi = 2.0 * std::numbers::pi * uniform01(rng);
    const double sinT = std::sqrt(std::max(0.0, 1.0 - cosT * cosT));
    glm::dvec3 t1, t2;
    tangentFrame(light_, t1, t2);
    const glm::dvec3 x = R * (sinT * std::cos(phi) * t1 + sinT * std::sin(phi) * t2 + cosT * light_);
    const double f = integrand(x);
    return f > 0.0 ? f / density(x) : 0.0;
  }
  // Probe line along an axis through a point of the perpendicular plane at radius r.
  const double ua = uniform01(rng);
  const int a = ua < 0.5 ? 0 : (ua < 0.75 ? 1 : 2);
  const glm::dvec3& axis = axes[a];
  const glm::dvec3& b1 = axes[(a + 1) % 3];
  const glm::dvec3& b2 = axes[(a + 2) % 3];
  const double r = profile.sample(uniform01(rng)).r;
  const double phi = 2.0 * std::numbers::pi * uniform01(rng);
  const glm::dvec3 p = x_o + r * (std::cos(phi) * b1 + std::sin(phi) * b2);
  // |p + t axis|² = R²: t = -b ± sqrt(b² - c).
  const double b = glm::dot(p, axis), cc = glm::dot(p, p) - R * R;
  const double disc = b * b - cc;
  if (!(disc > 0.0)) return 0.0;
  const double root = std::sqrt(disc);
  double sum = 0.0;
  for (const double t : {-b - root, -b + root}) {
    const glm::dvec3 x = p + t * axis;
    const double f = integrand(x);
    if (f > 0.0) sum += f / density(x);
  }
  return sum;
}

IntegrationStats SphereIntegrator::addPass(uint64_t samples, const ProgressCallback& progress) {
  if (samples == 0) throw ParameterError("integration: samples is 0: expected at least 1");
  const int w = scene_.width, h = scene_.height;
  const size_t nc = channels_.size();
  const glm::dvec3 view = glm::normalize(scene_.view_direction);
  const SphereBody body(scene_.radius);
  const uint64_t pass = passes_++;

  // One block per row: per pixel and channel the sums of B and of L samples and their squares.
  struct Row {
    std::vector<double> b, b2, l, l2;
  };
  auto make = [&] { return Row{}; };
  auto work = [&](uint64_t j, Row& row, const std::atomic<bool>& stop) {
    const size_t n = static_cast<size_t>(w) * nc;
    row.b.assign(n, 0.0);
    row.b2.assign(n, 0.0);
    row.l.assign(n, 0.0);
    row.l2.assign(n, 0.0);
    for (int i = 0; i < w; ++i) {
      if (stop.load(std::memory_order_relaxed)) return false;
      for (size_t c = 0; c < nc; ++c) {
        const uint64_t pixel = static_cast<uint64_t>(j) * static_cast<uint64_t>(w) + static_cast<uint64_t>(i);
        Rng rng(options_.seed, ((pass * static_cast<uint64_t>(h) * static_cast<uint64_t>(w)) + pixel) * nc + c);
        const double eta = channels_[c].eta;
        double sb = 0.0, sb2 = 0.0, sl = 0.0, sl2 = 0.0;
        for (uint64_t s = 0; s < samples; ++s) {
          // A stop within a pixel drops its row whole (rows merge complete): with 10^7 samples a
          // pixel took seconds, and Ctrl-C or SIGTERM waited for it.
          if ((s & 4095u) == 4095u && stop.load(std::memory_order_relaxed)) return false;
          // x_o uniform on the pixel's square of the image plane.
          glm::dvec3 o, d;
          camera_.ray(i + uniform01(rng), static_cast<double>(j) + uniform01(rng), o, d);
          SurfaceHit hit;
          if (!body.intersect(o, d, 0.0, std::numeric_limits<double>::infinity(), hit)) continue;
          const glm::dvec3 x_o = o + hit.t * d;
          const double B = sampleExitance(x_o, static_cast<int>(c), rng);
          const double cosO = glm::dot(x_o / scene_.radius, view);
          const double L = B * (eta == 1.0 ? 1.0 : fresnelTransmittance(cosO, eta)) / std::numbers::pi;
          sb += B;
          sb2 += B * B;
          sl += L;
          sl2 += L * L;
        }
        const size_t k = static_cast<size_t>(i) * nc + c;
        row.b[k] = sb;
        row.b2[k] = sb2;
        row.l[k] = sl;
        row.l2[k] = sl2;
      }
    }
    return true;
  };
  auto merge = [&](uint64_t j, Row& row) {
    for (int i = 0; i < w; ++i) {
      for (size_t c = 0; c < nc; ++c) {
        const size_t k = static_cast<size_t>(i) * nc + c;
        const size_t idx = images_.exitance.index(i, static_cast<int>(j), static_cast<int>(c));
        images_.exitance.addSums(idx, row.b[k], row.b2[k]);
        images_.radiance.addSums(idx, row.l[k], row.l2[k]);
      }
      const size_t pix = static_cast<size_t>(j) * static_cast<size_t>(w) + static_cast<size_t>(i);
      images_.exitance.addPixelCount(pix, samples);
      images_.radiance.addPixelCount(pix, samples);
    }
  };
  const uint64_t perRow = static_cast<uint64_t>(w) * samples * nc;
  const uint64_t total = perRow * static_cast<uint64_t>(h);
  std::function<bool(uint64_t, double)> tick;
  if (progress)
    tick = [&](uint64_t rows, double seconds) {
      return progress(TraceProgress{rows * perRow, total, seconds});
    };
  const detail::BlockRun run = detail::runBlocks<Row>(0, static_cast<uint64_t>(h), options_.threads,
                                                      make, work, merge, tick);
  if (progress) progress(TraceProgress{run.blocks_done * perRow, total, run.seconds});
  IntegrationStats pass_stats;
  pass_stats.samples = samples;
  pass_stats.seconds = run.seconds;
  pass_stats.threads = run.threads;
  pass_stats.partial = run.stopped;
  stats_.samples += samples;
  stats_.seconds += run.seconds;
  stats_.threads = run.threads;
  stats_.partial = stats_.partial || run.stopped;
  return pass_stats;
}

}  // namespace translucent::reference
