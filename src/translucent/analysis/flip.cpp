// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/analysis/flip.h"

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "translucent/analysis/separable_filter.h"
#include "translucent/optics/medium.h"  // ParameterError

namespace translucent::analysis {
namespace flip {

namespace {
using std::numbers::pi;

// Contrast sensitivity functions as sums of Gaussians in the spatial domain (the paper's colour
// pipeline): s(x) = a1 sqrt(π/b1) exp(-π² x²/b1) + a2 sqrt(π/b2) exp(-π² x²/b2), x in degrees,
// for the achromatic (Y), red-green (Cx) and blue-yellow (Cz) channels.
struct Csf {
  double a1, b1, a2, b2;
};
constexpr Csf kCsfY{1.0, 0.0047, 0.0, 0.0};
constexpr Csf kCsfCx{1.0, 0.0053, 0.0, 0.0};
constexpr Csf kCsfCz{34.1, 0.04, 13.5, 0.025};
constexpr double kWidestB = 0.04;

// exp(-π² x²/b) at the pixel offsets -r..r, x = offset / ppd degrees.
std::vector<double> csfGaussian(double b, int radius, double ppd) {
  std::vector<double> g(static_cast<size_t>(2 * radius + 1));
  for (int k = -radius; k <= radius; ++k) {
    const double x = k / ppd;
    g[static_cast<size_t>(k + radius)] = std::exp(-pi * pi * x * x / b);
  }
  return g;
}
double sum(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x;
  return s;
}
}  // namespace

color::Vec3 huntAdjust(const color::Vec3& lab) {
  return {lab[0], 0.01 * lab[0] * lab[1], 0.01 * lab[0] * lab[2]};
}

double hyab(const color::Vec3& a, const color::Vec3& b) {
  return std::abs(a[0] - b[0]) + std::hypot(a[1] - b[1], a[2] - b[2]);
}

double maxColorDistance() {
  static const double cmax = [] {
    const auto hunted = [](const color::Vec3& rgb) {
      return huntAdjust(color::xyzToLab(color::linearRgbToXyz(rgb)));
    };
    return std::pow(hyab(hunted({0.0, 1.0, 0.0}), hunted({0.0, 0.0, 1.0})), kQc);
  }();
  return cmax;
}

double colorError(double hyab_distance) {
  const double cmax = maxColorDistance();
  const double e = std::pow(hyab_distance, kQc);
  const double knee = kPc * cmax;
  // Compresses large differences: [0, pc cmax) -> [0, pt), [pc cmax, cmax] -> [pt, 1].
  return e < knee ? e * kPt / knee : kPt + (e - knee) / (cmax - knee) * (1.0 - kPt);
}

int spatialFilterRadius(double ppd) {
  // The CSF Gaussian exp(-π² x²/b) has σ = sqrt(b / (2π²)) degrees.
  return static_cast<int>(std::ceil(3.0 * std::sqrt(kWidestB / (2.0 * pi * pi)) * ppd));
}

int featureFilterRadius(double ppd) {
  return static_cast<int>(std::ceil(3.0 * 0.5 * kFeatureWidth * ppd));
}

}  // namespace flip

namespace {

using detail::Border;

struct Opponent {
  std::vector<float> y, cx, cz;
};

Opponent toYCxCz(std::span<const float> srgb, size_t pixels) {
  Opponent o{std::vector<float>(pixels), std::vector<float>(pixels), std::vector<float>(pixels)};
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, pixels), [&](const tbb::blocked_range<size_t>& r) {
        for (size_t p = r.begin(); p < r.end(); ++p) {
          color::Vec3 lin;
          for (size_t c = 0; c < 3; ++c)
            lin[c] =
                color::srgbToLinear(std::clamp(static_cast<double>(srgb[3 * p + c]), 0.0, 1.0));
          const color::Vec3 v = color::xyzToYCxCz(color::linearRgbToXyz(lin));
          o.y[p] = static_cast<float>(v[0]);
          o.cx[p] = static_cast<float>(v[1]);
          o.cz[p] = static_cast<float>(v[2]);
        }
      });
  return o;
}

// The colour pipeline's spatial filtering: each opponent channel convolved with its CSF (2D,
// normalised to unit sum; separable since each term is an isotropic Gaussian).
struct CsfKernels {
  std::vector<double> y, cx, cz1, cz2;  // cz = w1 (cz1 ⊗ cz1) + w2 (cz2 ⊗ cz2)
  double w1 = 0.0, w2 = 0.0;
};

CsfKernels csfKernels(double ppd) {
  using namespace flip;
  const int r = spatialFilterRadius(ppd);
  CsfKernels k;
  k.y = csfGaussian(kCsfY.b1, r, ppd);
  k.cx = csfGaussian(kCsfCx.b1, r, ppd);
  for (auto* g : {&k.y, &k.cx}) {
    const double s = sum(*g);
    for (double& v : *g) v /= s;
  }
  k.cz1 = csfGaussian(kCsfCz.b1, r, ppd);
  k.cz2 = csfGaussian(kCsfCz.b2, r, ppd);
  // The 2D kernel A1 g1(x)g1(y) + A2 g2(x)g2(y), Ai = ai sqrt(π/bi), divided by its sum.
  const double A1 = kCsfCz.a1 * std::sqrt(std::numbers::pi / kCsfCz.b1);
  const double A2 = kCsfCz.a2 * std::sqrt(std::numbers::pi / kCsfCz.b2);
  const double s1 = sum(k.cz1), s2 = sum(k.cz2);
  const double total = A1 * s1 * s1 + A2 * s2 * s2;
  k.w1 = A1 / total;
  k.w2 = A2 / total;
  return k;
}

// Hunt-adjusted L*a*b* of the CSF-filtered opponent image (clamped to the RGB cube first: the
// filtered colour may leave it).
std::vector<color::Vec3> filteredHuntLab(const Opponent& o, int w, int h, const CsfKernels& k) {
  using detail::filter2d;
  const std::vector<float> y = filter2d<float>(o.y, w, h, k.y, Border::Clamp);
  const std::vector<float> cx = filter2d<float>(o.cx, w, h, k.cx, Border::Clamp);
  const std::vector<float> cz1 = filter2d<float>(o.cz, w, h, k.cz1, Border::Clamp);
  const std::vector<float> cz2 = filter2d<float>(o.cz, w, h, k.cz2, Border::Clamp);
  std::vector<color::Vec3> lab(y.size());
  tbb::parallel_for(
      tbb::blocked_range<size_t>(0, y.size()), [&](const tbb::blocked_range<size_t>& r) {
        for (size_t p = r.begin(); p < r.end(); ++p) {
          const color::Vec3 v{
              static_cast<double>(y[p]), static_cast<double>(cx[p]),
              k.w1 * static_cast<double>(cz1[p]) + k.w2 * static_cast<double>(cz2[p])};
          color::Vec3 rgb = color::xyzToLinearRgb(color::yCxCzToXyz(v));
          for (double& c : rgb) c = std::clamp(c, 0.0, 1.0);
          lab[p] = flip::huntAdjust(color::xyzToLab(color::linearRgbToXyz(rgb)));
        }
      });
  return lab;
}

// Edge and point magnitudes of the normalised luminance (the feature pipeline): gradients of
// the image filtered with x- and y-derivatives of a Gaussian, first and second order.
struct Features {
  std::vector<float> edge, point;
};

struct FeatureKernels {
  std::vector<double> g, d1, d2;
};

FeatureKernels featureKernels(double ppd) {
  const double sd = 0.5 * flip::kFeatureWidth * ppd;
  const int r = flip::featureFilterRadius(ppd);
  FeatureKernels k;
  for (int x = -r; x <= r; ++x) {
    const double g = std::exp(-(x * x) / (2.0 * sd * sd));
    k.g.push_back(g);
    k.d1.push_back(-x * g);
    k.d2.push_back((x * x / (sd * sd) - 1.0) * g);
  }
  // The Gaussian sums to 1; the derivatives' positive weights to 1 and negative ones to -1, so
  // that a unit step gives an edge response of 1 whatever the width (2D: the product with the
  // unit-sum Gaussian across keeps these sums).
  const double gs = flip::sum(k.g);
  for (double& v : k.g) v /= gs;
  for (auto* d : {&k.d1, &k.d2}) {
    double pos = 0.0, neg = 0.0;
    for (double v : *d) (v > 0.0 ? pos : neg) += std::abs(v);
    for (double& v : *d) v /= v > 0.0 ? pos : neg;
  }
  return k;
}

Features features(const std::vector<float>& ycxcz_y, int w, int h, const FeatureKernels& k) {
  using detail::filterColumns;
  using detail::filterRows;
  const size_t n = ycxcz_y.size();
  std::vector<float> yn(n);
  for (size_t p = 0; p < n; ++p) yn[p] = (ycxcz_y[p] + 16.0f) / 116.0f;
  std::vector<float> rg(n), r1(n), r2(n), ex(n), ey(n), px(n), py(n);
  filterRows<float>(yn, rg, w, h, k.g, Border::Clamp);
  filterRows<float>(yn, r1, w, h, k.d1, Border::Clamp);
  filterRows<float>(yn, r2, w, h, k.d2, Border::Clamp);
  filterColumns<float>(r1, ex, w, h, k.g, Border::Clamp);
  filterColumns<float>(rg, ey, w, h, k.d1, Border::Clamp);
  filterColumns<float>(r2, px, w, h, k.g, Border::Clamp);
  filterColumns<float>(rg, py, w, h, k.d2, Border::Clamp);
  Features f{std::vector<float>(n), std::vector<float>(n)};
  for (size_t p = 0; p < n; ++p) {
    f.edge[p] = std::hypot(ex[p], ey[p]);
    f.point[p] = std::hypot(px[p], py[p]);
  }
  return f;
}

}  // namespace

std::vector<float> ldrFlip(std::span<const float> test, std::span<const float> reference, int width,
                           int height, double ppd) {
  if (width < 1 || height < 1)
    throw ParameterError(
        fmt::format("ꟻLIP: image size {}x{}: expected at least 1x1", width, height));
  const size_t n = static_cast<size_t>(width) * static_cast<size_t>(height);
  if (test.size() != 3 * n || reference.size() != 3 * n)
    throw ParameterError(
        fmt::format("ꟻLIP: test has {} values, reference {}: expected {} (3 per pixel of {}x{})",
                    test.size(), reference.size(), 3 * n, width, height));
  if (!(std::isfinite(ppd) && ppd > 0.0))
    throw ParameterError(
        fmt::format("ꟻLIP: pixels_per_degree is {}: expected a finite value > 0", ppd));

  const Opponent ot = toYCxCz(test, n), orf = toYCxCz(reference, n);

  // Colour pipeline -> ΔE_c.
  const CsfKernels ck = csfKernels(ppd);
  const std::vector<color::Vec3> labT = filteredHuntLab(ot, width, height, ck);
  const std::vector<color::Vec3> labR = filteredHuntLab(orf, width, height, ck);

  // Feature pipeline -> ΔE_f.
  const FeatureKernels fk = featureKernels(ppd);
  const Features ft = features(ot.y, width, height, fk), fr = features(orf.y, width, height, fk);

  std::vector<float> out(n);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t p = r.begin(); p < r.end(); ++p) {
      const double dc = flip::colorError(flip::hyab(labR[p], labT[p]));
      const double df = std::pow(
          std::max(std::abs(static_cast<double>(fr.edge[p]) - static_cast<double>(ft.edge[p])),
                   std::abs(static_cast<double>(fr.point[p]) - static_cast<double>(ft.point[p]))) /
              std::numbers::sqrt2,
          flip::kQf);
      out[p] = static_cast<float>(std::pow(dc, 1.0 - df));
    }
  });
  return out;
}

}  // namespace translucent::analysis
