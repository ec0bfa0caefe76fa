// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/techniques/splatting/splatting_math.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace translucent::splatting {

// ---- Eqs. 14-16 ------------------------------------------------------------------------------

MeanProfile::MeanProfile(int samples) {
  if (samples < 2) throw std::invalid_argument("MeanProfile: samples must be >= 2");
  sum_.assign(size_t(samples) + 1, 0.0);
  values_.assign(size_t(samples) + 1, 0.0);
}

void MeanProfile::add(const std::function<double(double)>& profile, double effectiveRadius) {
  if (!(effectiveRadius > 0.0) || !std::isfinite(effectiveRadius))
    throw std::invalid_argument("MeanProfile::add: the effective radius R_P must be > 0, got " +
                                std::to_string(effectiveRadius));
  // Eq. 16: C = R_P² / ∫0^R_P P(r) r dr, by the midpoint rule on a grid finer than the nodes.
  const int n = samples();
  const int steps = 8 * n;
  double energy = 0.0;
  for (int i = 0; i < steps; ++i) {
    const double r = (i + 0.5) / steps * effectiveRadius;
    energy += profile(r) * r;
  }
  energy *= effectiveRadius / steps;
  if (!(energy > 0.0) || !std::isfinite(energy))
    throw std::invalid_argument("MeanProfile::add: the profile has no finite energy on [0, R_P]");
  const double c = effectiveRadius * effectiveRadius / energy;
  // Eq. 15: P'(r) = C P(r R_P). Node 0 (r = 0) uses a quarter node so that a profile diverging at
  // 0 (normalised diffusion ~1/r) stays finite; its weight r = 0 in every integral anyway.
  for (int j = 0; j <= n; ++j) {
    const double r = (j == 0 ? 0.25 : double(j)) / n;
    sum_[size_t(j)] += c * profile(r * effectiveRadius);
  }
  ++count_;
  for (size_t j = 0; j < sum_.size(); ++j) values_[j] = sum_[j] / double(count_);
}

double MeanProfile::at(double r) const {
  if (count_ == 0) return 0.0;
  const int n = samples();
  const double u = std::clamp(r, 0.0, 1.0) * n;
  const int j = std::min(int(u), n - 1);
  const double w = u - j;
  return (1.0 - w) * values_[size_t(j)] + w * values_[size_t(j) + 1];
}

double MeanProfile::tailIntegral(double r) const {
  // Exact integral of the piecewise-linear P̄ times s: on each piece ∫ (a + b s) s ds, done by
  // Simpson's rule (exact for a cubic), from r to 1.
  const int n = samples();
  r = std::clamp(r, 0.0, 1.0);
  double sum = 0.0;
  auto piece = [&](double a, double b) {
    const double m = 0.5 * (a + b);
    sum += (b - a) / 6.0 * (at(a) * a + 4.0 * at(m) * m + at(b) * b);
  };
  const int first = std::min(int(r * n) + 1, n);
  piece(r, std::max(r, double(first) / n));
  for (int j = first; j < n; ++j) piece(double(j) / n, double(j + 1) / n);
  return sum;
}

double rangeSplitError(const MeanProfile& mean, double r, double T) {
  if (!(T > 0.0)) throw std::invalid_argument("rangeSplitError: T must be > 0");
  const long count = long(std::floor((1.0 - r) * T));
  double sum = 0.0;
  for (long m = 0; m <= count; ++m) {
    const double rh = r + double(m) / T;
    sum += mean.at(rh) * rh;
  }
  return std::abs(sum / T - mean.tailIntegral(r));
}

double minimalRenderingRadius(const MeanProfile& mean, double T, double epsilon, int steps) {
  double rbar = 1.0;
  for (int i = steps; i >= 0; --i) {
    const double r = double(i) / steps;
    if (rangeSplitError(mean, r, T) >= epsilon) break;
    rbar = r;
  }
  return rbar;
}

RbarTable RbarTable::build(const MeanProfile& mean, double epsilon, int count, double tMin,
                           double tMax, int steps) {
  if (count < 2 || !(tMin > 0.0) || !(tMax > tMin))
    throw std::invalid_argument("RbarTable::build: need count >= 2 and 0 < tMin < tMax");
  RbarTable t;
  t.tMin = tMin;
  t.tMax = tMax;
  t.epsilon = epsilon;
  t.rbar.resize(size_t(count));
  for (int j = 0; j < count; ++j) t.rbar[size_t(j)] = minimalRenderingRadius(mean, t.tAt(j), epsilon, steps);
  return t;
}

double RbarTable::tAt(int j) const {
  const int count = int(rbar.size());
  return tMin * std::pow(tMax / tMin, double(j) / double(count - 1));
}

double RbarTable::lookup(double T) const {
  const int count = int(rbar.size());
  if (!(T > tMin)) return T < tMin ? 1.0 : rbar.front();  // coarser than the table: no level
  if (T >= tMax) return rbar.back();
  const double u = std::log(T / tMin) / std::log(tMax / tMin) * (count - 1);
  const int j = std::min(int(u), count - 2);
  return std::max(rbar[size_t(j)], rbar[size_t(j) + 1]);
}

double projectedResolution(double levelResolution, double effectiveRadius, double fovY,
                           double depth) {
  return levelResolution * effectiveRadius / (2.0 * std::tan(0.5 * fovY) * depth);
}

std::vector<std::pair<double, double>> splatRanges(const RbarTable& table, double effectiveRadius,
                                                   double T0, int levels) {
  if (levels < 1) throw std::invalid_argument("splatRanges: levels must be >= 1");
  std::vector<double> rmin(size_t(levels), 0.0);
  for (int k = 1; k < levels; ++k)
    rmin[size_t(k)] = std::max(rmin[size_t(k) - 1],
                               effectiveRadius * table.lookup(T0 / std::ldexp(1.0, k)));
  std::vector<std::pair<double, double>> out{size_t(levels)};
  for (int k = 0; k < levels; ++k)
    out[size_t(k)] = {rmin[size_t(k)], k + 1 < levels ? rmin[size_t(k) + 1] : effectiveRadius};
  return out;
}

// ---- Eqs. 10-11 ------------------------------------------------------------------------------

double materialSamplingRate(const SelectionParams& p, double effectiveRadius, double cosNL) {
  const double orientation = p.orientation ? std::max(std::abs(cosNL), 1e-3) : 1.0;
  return p.alpha * p.rw / (effectiveRadius * orientation);
}

bool passesEq10(const SelectionParams& p, double zMin, double zMax, double levelResolution,
                double effectiveRadius, double cosNL) {
  return (!p.discontinuity || zMax - zMin < p.z0) &&
         levelResolution > materialSamplingRate(p, effectiveRadius, cosNL);
}

bool validSample(std::span<const bool> passes, int level) {
  if (level < 0 || size_t(level) >= passes.size())
    throw std::invalid_argument("validSample: level out of range");
  for (size_t k = size_t(level) + 1; k < passes.size(); ++k)
    if (passes[k]) return false;  // a coarser ancestor is valid: descendants are discarded
  return passes[size_t(level)] || level == 0;
}

// ---- Mipmaps ---------------------------------------------------------------------------------

int medianDepthIndex(const std::array<float, 4>& depths) {
  std::array<int, 4> order = {0, 1, 2, 3};
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return depths[size_t(a)] < depths[size_t(b)]; });
  return order[1];  // the lower middle (see the header)
}

std::vector<MinMax> minMaxLevel(std::span<const MinMax> child, int width, int height) {
  const int pw = (width + 1) / 2, ph = (height + 1) / 2;
  constexpr float inf = std::numeric_limits<float>::infinity();
  std::vector<MinMax> out(size_t(pw) * size_t(ph), MinMax{inf, -inf});
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const MinMax& c = child[size_t(y) * size_t(width) + size_t(x)];
      MinMax& p = out[size_t(y / 2) * size_t(pw) + size_t(x / 2)];
      p.zMin = std::min(p.zMin, c.zMin);
      p.zMax = std::max(p.zMax, c.zMax);
    }
  return out;
}

// ---- Eq. 17 ----------------------------------------------------------------------------------

double bilateralWeight(double bilinear, double zo, double zj, double rw, double rpo, double rpj,
                       double lambdaZ, double lambdaM) {
  if (!std::isfinite(zo) || !std::isfinite(zj)) return 0.0;  // background: no surface to share
  return bilinear * std::exp(-lambdaZ * std::abs(zo - zj) / rw) *
         std::exp(-lambdaM * std::abs(rpo - rpj));
}

std::vector<float> bilateralUpsample(std::span<const float> coarse, std::span<const float> coarseZ,
                                     std::span<const float> coarseRp, int cw, int ch,
                                     std::span<const float> fineZ, std::span<const float> fineRp,
                                     int fw, int fh, double rw) {
  std::vector<float> out(size_t(fw) * size_t(fh), 0.0f);
  for (int y = 0; y < fh; ++y)
    for (int x = 0; x < fw; ++x) {
      const size_t o = size_t(y) * size_t(fw) + size_t(x);
      // The fine pixel's centre in coarse pixel units, and its four nearest coarse pixels.
      const double u = (x + 0.5) * cw / fw - 0.5, v = (y + 0.5) * ch / fh - 0.5;
      const int x0 = int(std::floor(u)), y0 = int(std::floor(v));
      const double fx = u - x0, fy = v - y0;
      double sum = 0.0, wsum = 0.0;
      for (int j = 0; j < 4; ++j) {
        const int cx = std::clamp(x0 + (j & 1), 0, cw - 1);
        const int cy = std::clamp(y0 + (j >> 1), 0, ch - 1);
        const double wp = ((j & 1) ? fx : 1.0 - fx) * ((j >> 1) ? fy : 1.0 - fy);
        const size_t c = size_t(cy) * size_t(cw) + size_t(cx);
        const double w = bilateralWeight(wp, double(fineZ[o]), double(coarseZ[c]), rw, double(fineRp[o]),
                                         double(coarseRp[c]));
        sum += w * double(coarse[c]);
        wsum += w;
      }
      out[o] = wsum > 0.0 ? float(sum / wsum) : 0.0f;
    }
  return out;
}

}  // namespace translucent::splatting
