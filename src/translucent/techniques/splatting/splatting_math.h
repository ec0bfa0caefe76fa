// SPDX-License-Identifier: GPL-3.0-or-later
// CPU pieces of multiresolution splatting (Chen, Peers, Zhang & Tong 2012, "Real-time rendering
// of deformable heterogeneous translucent objects using multiresolution splatting"; seed
// multiresolution-splatting §4), kept free of GL so that tests (and the GPU passes' uploads)
// share one definition:
//   - the mean normalised profile P̄ (Eqs. 15-16) and the minimal effective rendering radius R̄
//     (Eq. 14) tabulated over the splatting resolution T, and the per-level ranges (Eq. 13);
//   - adaptive sample selection (Eqs. 10-11, Algorithm 1 as the text states it);
//   - the 2×2 median-depth filter of the splatting buffer's mipmap and the min/max depth mip of
//     the irradiance buffer (Nichols et al. 2009);
//   - the bilateral upsampling weights of the accumulation (Eq. 17).
#pragma once

#include <array>
#include <functional>
#include <span>
#include <utility>
#include <vector>

namespace translucent::splatting {

// ---- Eqs. 14-16: the mean normalised profile and R̄ -------------------------------------------

// P̄(r) on the normalised range [0, 1] (Eq. 15: P'(r) = C P(r R_P), Eq. 16: C = R_P² /
// ∫0^R_P P(r) r dr, so that ∫0^1 P'(r) r dr = 1 for every profile), sampled at `samples` + 1
// uniform nodes r_j = j / samples and read by linear interpolation.
class MeanProfile {
 public:
  explicit MeanProfile(int samples = 1024);
  // Adds one point's profile P (any positive function of r in scene units) with its 95% radius
  // R_P (> 0). Throws std::invalid_argument for R_P <= 0 or a profile without energy on [0, R_P].
  void add(const std::function<double(double)>& profile, double effectiveRadius);
  size_t count() const { return count_; }
  int samples() const { return int(values_.size()) - 1; }
  double at(double r) const;  // P̄(r), r in [0, 1]; 0 before any add()
  // ∫_r^1 P̄(s) s ds (the trapezoid rule on the nodes; exact for the interpolated P̄ to O(h²)).
  double tailIntegral(double r) const;

 private:
  std::vector<double> sum_;     // Σ P'_x at the nodes
  std::vector<double> values_;  // sum_ / count_
  size_t count_ = 0;
};

// The sampling error of Eq. 14 at r for splatting resolution T (samples per normalised range):
//     | (1/T) Σ_{m=0}^{⌊(1−r)T⌋} P̄(r̂_m) r̂_m − ∫_r^1 P̄(s) s ds |,   r̂_m = r + m / T.
double rangeSplitError(const MeanProfile& mean, double r, double T);

// R̄(T): Eq. 14 defines it as the minimal r whose error is below ε. The error is not monotone in
// r, so R̄ here is the smallest grid r (`steps` uniform steps of [0, 1]) such that every grid
// r' >= r has an error below ε: the range [R̄, 1] then meets ε wherever a splat starts in it.
// R̄ = 1 when no r qualifies (this level contributes nothing).
// At r = 1 the error is P̄(1)/T, so R̄ = 1 for every T <= P̄(1)/ε: with the seed's ε = 0.001 and
// a diffusion profile's P̄(1) ~ 0.1, a level needs T(x_i) above ~100 samples before it splats
// anything, which 800x600 frames rarely give level 1 (BENCHMARKS.md of commit 91fe617, "Why level 1 idles").
double minimalRenderingRadius(const MeanProfile& mean, double T, double epsilon = 0.001,
                              int steps = 512);

// The precomputed lookup table of R̄ over T (the paper's texture): `count` values of T spaced
// geometrically over [tMin, tMax]. lookup(T) is conservative: the larger R̄ of the two grid
// neighbours (R̄ shrinks as T grows), clamped at the ends (T < tMin: R̄(tMin)... 1 below 1).
struct RbarTable {
  double tMin = 1.0, tMax = 4096.0;
  std::vector<double> rbar;  // R̄ at T_j = tMin (tMax / tMin)^(j / (count − 1))
  double epsilon = 0.001;
  static RbarTable build(const MeanProfile& mean, double epsilon = 0.001, int count = 64,
                         double tMin = 1.0, double tMax = 4096.0, int steps = 512);
  double tAt(int j) const;
  double lookup(double T) const;
};

// T(x_i) of Eq. 14 for splatting resolution T^k (pixels across the frame's height):
// T^k R_P / (2 tan(fov / 2) z), z the view depth of x_i (perspective camera).
double projectedResolution(double levelResolution, double effectiveRadius, double fovY,
                           double depth);

// Eq. 13: the range [R^k_min, R^k_max] (scene units) in which a sample with 95% radius R_P
// splats at each of `levels` levels, T0 the projected resolution at level 0 (level k: T0 / 2^k).
// R^0_min = 0, R^k_min = R_P R̄(T0 / 2^k), R^k_max = R^{k+1}_min, R^{n−1}_max = R_P; the minima
// are made non-decreasing so the ranges never overlap (each distance is splatted once).
std::vector<std::pair<double, double>> splatRanges(const RbarTable& table, double effectiveRadius,
                                                   double T0, int levels);

// ---- Eqs. 10-11: adaptive sample selection ---------------------------------------------------

struct SelectionParams {
  double z0 = 0.0;     // depth threshold: 0.03 × the bounding-sphere radius
  double alpha = 15.0; // α
  double rw = 0.0;     // R_w: the bounding-sphere diameter
  // The two geometric terms, for the ablation of Chen et al. 2012's Fig. 5: without the
  // discontinuity term a sample spanning a depth step passes Eq. 10; without the orientation
  // term Eq. 11 takes |n·L| = 1.
  bool discontinuity = true;
  bool orientation = true;
};

// Eq. 11: M(x) = α R_w / (R_P |n·L|) (|n·L| clamped at 1e-3: grazing samples need full rate).
double materialSamplingRate(const SelectionParams& p, double effectiveRadius, double cosNL);
// Eq. 10: z_max − z_min < z0 and T > M(x), T the irradiance-buffer resolution at the level.
bool passesEq10(const SelectionParams& p, double zMin, double zMax, double levelResolution,
                double effectiveRadius, double cosNL);

// Algorithm 1 as printed is garbled (its two tests discard almost every sample). The text's rule:
// "if a sample is marked valid at a specific level, all descendants at finer levels are
// discarded". With passes[k] = Eq. 10 for the sample's ancestor at level k (k = 0: the texel
// itself; the coarsest level has no parent), the sample at `level` is valid when it passes at
// `level` and no coarser ancestor passes — the parent-only rule ("passes at k, its parent at
// k + 1 does not") whenever Eq. 10 is monotone up the hierarchy, and otherwise the rule that
// still covers every finest texel once. Level 0 is the fallback: a texel no level accepts is
// splatted at level 0, else its light would be lost.
bool validSample(std::span<const bool> passes, int level);

// ---- Buffer mipmaps --------------------------------------------------------------------------

// The 2×2 median-depth filter of the splatting buffer: for four depths (background: +∞), the
// index (0..3) of the median texel, whose normal, coordinates and depth the coarse texel copies.
// With four values the median is one of the two middle ones: this picks the lower middle (the
// second smallest depth, ties broken by the smaller index), i.e. the nearer of the two middle
// texels, so a coarse texel keeps a surface as long as two of its children are on one.
int medianDepthIndex(const std::array<float, 4>& depths);

// One level of the min/max depth mip (Nichols et al. 2009): the parent of children (2x, 2y),
// (2x+1, 2y), (2x, 2y+1), (2x+1, 2y+1) holds their min and max. Background children carry
// (+∞, −∞) and do not widen the range. Images are row-major w × h; the parent is ⌈w/2⌉ × ⌈h/2⌉.
struct MinMax {
  float zMin, zMax;
};
std::vector<MinMax> minMaxLevel(std::span<const MinMax> child, int width, int height);

// ---- Eq. 17: bilateral upsampling ------------------------------------------------------------

inline constexpr double kLambdaZ = 8.0;  // λz
inline constexpr double kLambdaM = 8.0;  // λm

// w = w_p · exp(−λz |z_o − z_j| / R_w) · exp(−λm |R_P,o − R_P,j|).
double bilateralWeight(double bilinear, double zo, double zj, double rw, double rpo, double rpj,
                       double lambdaZ = kLambdaZ, double lambdaM = kLambdaM);

// Eq. 17 on one channel: the coarse image (cw × ch, with its depths and R_P) upsampled to the
// fine level (2 cw × 2 ch at most, fine depths and R_P) from the four nearest coarse pixels.
// Fine pixels with no weight (all four coarse pixels weightless) get 0.
std::vector<float> bilateralUpsample(std::span<const float> coarse, std::span<const float> coarseZ,
                                     std::span<const float> coarseRp, int cw, int ch,
                                     std::span<const float> fineZ, std::span<const float> fineRp,
                                     int fw, int fh, double rw);

}  // namespace translucent::splatting
