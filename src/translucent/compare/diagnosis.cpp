// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/compare/diagnosis.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "translucent/geometry/ray_scene.h"
#include "translucent/reference/camera.h"

namespace translucent::analysis {
namespace {

constexpr double kSilhouetteCos = 0.3;
constexpr int kShadowRadius = 2;
constexpr double kInf = std::numeric_limits<double>::infinity();

size_t pixelCount(int w, int h) { return static_cast<size_t>(w) * static_cast<size_t>(h); }

void checkSizes(const CompareImage& a, const CompareImage& b, const char* what) {
  if (a.width != b.width || a.height != b.height || a.rgb.size() != b.rgb.size())
    throw ParameterError(fmt::format("error split: the {} image is {}x{}, the physical reference "
                                     "{}x{}", what, a.width, a.height, b.width, b.height));
}

double se2(const CompareImage& img, size_t i) {
  return img.se.empty() ? 0.0 : static_cast<double>(img.se[i]) * static_cast<double>(img.se[i]);
}

}  // namespace

ErrorRegions errorRegions(const scene::Scene& scene, const geometry::TriangleMesh& mesh,
                          std::span<const uint8_t> interior) {
  const int w = scene.camera.width, h = scene.camera.height;
  const size_t n = pixelCount(w, h);
  if (interior.size() != n)
    throw ParameterError(fmt::format("error regions: a mask of {} pixels for a {}x{} camera",
                                     interior.size(), w, h));
  ErrorRegions r;
  r.width = w;
  r.height = h;
  r.names = {"silhouettes", "thin parts", "shadow boundaries", "elsewhere"};
  r.masks.assign(4, std::vector<uint8_t>(n, 0));
  // ℓd per channel in scene units (Medium::channel: coefficients per scene unit), averaged over
  // the channels that absorb.
  double ld = 0.0;
  int channels = 0;
  for (int c = 0; c < 3; ++c) {
    const double l = scene.medium.channel(c).diffuseMeanFreePath();
    if (std::isfinite(l)) {
      ld += l;
      ++channels;
    }
  }
  r.thin_threshold = channels > 0 ? ld / channels : kInf;

  struct Delta {
    bool point = false;
    glm::dvec3 v{0.0};  // direction towards a directional light, position of a point light
  };
  std::vector<Delta> lights;
  for (const scene::Light& l : scene.lights) {
    if (const auto* d = std::get_if<reference::DirectionalLight>(&l.emitter))
      lights.push_back({false, glm::normalize(d->direction)});
    else if (const auto* p = std::get_if<reference::PointLight>(&l.emitter))
      lights.push_back({true, p->position});
    else if (const auto* f = std::get_if<scene::FilteredDirectionalLight>(&l.emitter))
      lights.push_back({false, glm::normalize(f->direction)});
    if (lights.size() == 32) break;  // visibility patterns are 32-bit
  }

  const geometry::RayScene rays(mesh, "compare error regions");
  const reference::CameraModel cam(scene.camera);
  const double eps = 1e-5 * std::max(mesh.bounds().radius(), 1e-12);
  std::vector<uint32_t> visible(n, 0);
  tbb::parallel_for(0, h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      const size_t i = static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x);
      if (!interior[i]) continue;
      glm::dvec3 o, d;
      cam.ray(x + 0.5, y + 0.5, o, d);
      geometry::RayHit hit;
      if (!rays.intersect(o, d, 0.0, kInf, hit)) continue;
      const glm::dvec3 p = o + hit.t * d;
      const glm::dvec3 nf = glm::dot(hit.normal, d) < 0.0 ? hit.normal : -hit.normal;
      if (std::abs(glm::dot(nf, d)) < kSilhouetteCos) r.masks[0][i] = 1;
      geometry::RayHit back;
      const double thickness = rays.intersect(p - eps * nf, -nf, eps, kInf, back) ? back.t : kInf;
      if (thickness < r.thin_threshold) r.masks[1][i] = 1;
      uint32_t bits = 0;
      for (size_t k = 0; k < lights.size(); ++k) {
        const glm::dvec3 to = lights[k].point ? lights[k].v - p : lights[k].v;
        const double dist = lights[k].point ? glm::length(to) : kInf;
        const glm::dvec3 l = lights[k].point ? to / dist : to;
        if (glm::dot(nf, l) > 0.0 && !rays.occluded(p + eps * nf, l, eps, dist))
          bits |= 1u << k;
      }
      visible[i] = bits;
    }
  });
  if (!lights.empty())
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const size_t i = static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x);
        if (!interior[i]) continue;
        bool edge = false;
        for (int dy = -kShadowRadius; dy <= kShadowRadius && !edge; ++dy)
          for (int dx = -kShadowRadius; dx <= kShadowRadius && !edge; ++dx) {
            const int xx = x + dx, yy = y + dy;
            if (xx < 0 || yy < 0 || xx >= w || yy >= h) continue;
            const size_t j = static_cast<size_t>(yy) * static_cast<size_t>(w) + static_cast<size_t>(xx);
            edge = interior[j] && visible[j] != visible[i];
          }
        r.masks[2][i] = edge;
      }
  for (size_t i = 0; i < n; ++i)
    r.masks[3][i] = interior[i] && !r.masks[0][i] && !r.masks[1][i] && !r.masks[2][i];
  r.definition = fmt::format(
      "silhouettes: |n·v| < {:g}; thin parts: thinner than ℓd = {:.3g} scene units along the "
      "inward normal; shadow boundaries: within {} pixels of a change in the direct visibility of "
      "{} directional or point light{}{}",
      kSilhouetteCos, r.thin_threshold, kShadowRadius, lights.size(), lights.size() == 1 ? "" : "s",
      lights.size() < scene.lights.size() ? " (other lights cast none here)" : "");
  return r;
}

ErrorRegions reportRegions(const scene::Scene& scene, const geometry::TriangleMesh& mesh,
                           std::span<const Reference> references, std::span<const uint8_t> interior) {
  const auto has = [&](ReferenceKind k) {
    return std::any_of(references.begin(), references.end(),
                       [&](const Reference& r) { return r.kind == k && !r.radiance.empty(); });
  };
  if (!has(ReferenceKind::Model) || !has(ReferenceKind::Physical)) return {};
  return errorRegions(scene, mesh, interior);
}

std::vector<RegionSplit> splitError(const CompareImage& technique, const CompareImage& model,
                                    const CompareImage& physical, const ErrorRegions& regions,
                                    std::span<const uint8_t> interior) {
  checkSizes(technique, physical, "technique");
  checkSizes(model, physical, "model reference");
  const size_t n = pixelCount(physical.width, physical.height);
  if (interior.size() != n || regions.width != physical.width || regions.height != physical.height)
    throw ParameterError("error split: the regions do not match the images' size");
  auto rows = std::vector<RegionSplit>{};
  auto measure = [&](const std::string& name, std::span<const uint8_t> mask) {
    // compare's relative RMSE: sqrt(max(0, mean(d²) − mean(se² of both))) / mean(P).
    double tp = 0, tm = 0, mp = 0, ref = 0;
    uint64_t pixels = 0;
    for (size_t i = 0; i < n; ++i) {
      if (!mask[i] || !interior[i]) continue;
      ++pixels;
      for (size_t c = 0; c < 3; ++c) {
        const size_t k = 3 * i + c;
        const double t = technique.rgb[k], m = model.rgb[k], p = physical.rgb[k];
        tp += (t - p) * (t - p) - se2(technique, k) - se2(physical, k);
        tm += (t - m) * (t - m) - se2(technique, k) - se2(model, k);
        mp += (m - p) * (m - p) - se2(model, k) - se2(physical, k);
        ref += p;
      }
    }
    RegionSplit s{name, pixels, std::nan(""), std::nan(""), std::nan("")};
    if (pixels > 0 && ref > 0.0) {
      const double count = 3.0 * static_cast<double>(pixels), mean = ref / count;
      auto rel = [&](double sum) { return std::sqrt(std::max(0.0, sum / count)) / mean; };
      s.vs_physical = rel(tp);
      s.technique_part = rel(tm);
      s.model_part = rel(mp);
    }
    rows.push_back(s);
  };
  measure("interior", interior);
  for (size_t k = 0; k < regions.names.size(); ++k) measure(regions.names[k], regions.masks[k]);
  return rows;
}

std::vector<uint8_t> splitMap(const CompareImage& technique, const CompareImage& model,
                              const CompareImage& physical, std::span<const uint8_t> interior,
                              double full_scale) {
  checkSizes(technique, physical, "technique");
  checkSizes(model, physical, "model reference");
  const size_t n = pixelCount(physical.width, physical.height);
  std::vector<uint8_t> out(3 * n, 0);
  constexpr double kTechnique[3] = {0.90, 0.45, 0.0}, kModel[3] = {0.0, 0.45, 0.90};
  for (size_t i = 0; i < n && i < interior.size(); ++i) {
    if (!interior[i]) continue;
    double dt = 0, dm = 0, d = 0, p = 0;
    for (size_t c = 0; c < 3; ++c) {
      const size_t k = 3 * i + c;
      const double t = technique.rgb[k], m = model.rgb[k], ph = physical.rgb[k];
      dt += std::abs(t - m);
      dm += std::abs(m - ph);
      d += std::abs(t - ph);
      p += ph;
    }
    const double level = p > 0.0 ? std::clamp(d / p / full_scale, 0.0, 1.0) : 1.0;
    const double share = dt + dm > 0.0 ? dm / (dt + dm) : 0.5;  // 1: all the model's
    for (size_t c = 0; c < 3; ++c) {
      const double v = level * ((1.0 - share) * kTechnique[c] + share * kModel[c]) / 0.9;
      out[3 * i + c] = static_cast<uint8_t>(std::lround(255.0 * std::clamp(v, 0.0, 1.0)));
    }
  }
  return out;
}

std::vector<uint8_t> regionMap(const ErrorRegions& regions, std::span<const uint8_t> interior) {
  const size_t n = pixelCount(regions.width, regions.height);
  std::vector<uint8_t> out(3 * n, 0);
  for (size_t i = 0; i < n && i < interior.size(); ++i) {
    if (!interior[i]) continue;
    const bool s = regions.masks[0][i], t = regions.masks[1][i], b = regions.masks[2][i];
    out[3 * i + 0] = s ? 230 : 70;
    out[3 * i + 1] = t ? 200 : 70;
    out[3 * i + 2] = b ? 255 : 70;
  }
  return out;
}

}  // namespace translucent::analysis
