// SPDX-License-Identifier: GPL-3.0-or-later
// Sums of Monte Carlo scores that do not depend on the order in which their terms are added, so
// that a run traced in shards and merged (issue 17: `pathtrace --shard I/N`, `translucent merge`)
// gives, bit for bit, the numbers of the same run traced in one process.
//
// Floating-point addition is not associative: ((a + b) + c) and (a + (b + c)) differ in the last
// bits, so summing blocks 0..K-1 in order and summing the shards' totals in order give different
// doubles. Here each term is rounded once to a fixed-point grid, a signed 128-bit integer q with
// value q · 2^(e - 64), and the integers add exactly: any grouping of the same terms gives the
// same integer, hence the same double when it is read. The scale 2^e is fixed by the run's
// settings (never by the data: that would depend on the shard), chosen near the size of a typical
// term: terms then keep 64 bits below 2^e (a relative error of ~2^-64 for a typical term, far
// below the Monte Carlo error) and sums may grow to 2^63 · 2^e before they overflow (an error, not
// a wrap-around).
//
// Terms are rounded to nearest; a term below 2^(e - 65) in magnitude is lost (rounds to 0). The
// per-block tallies of the walkers stay in double (a block is traced by one thread, in a fixed
// order, whatever the sharding); only sums across blocks are fixed-point.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "translucent/reference/slab.h"  // Estimate

namespace translucent::reference {

__extension__ typedef __int128 Fixed;  // GCC/Clang (__extension__: no pedantic warning)
__extension__ typedef unsigned __int128 UFixed;

// The grid 2^(e - 64) of one accumulator (or of one array of them).
class FixedScale {
 public:
  FixedScale() : FixedScale(0) {}
  // Any exponent a double's scale gives (down to the subnormals' 2^-1074, and the squares of
  // those): where 2^(64 - e) or 2^(e - 64) is not a normal double (|e| beyond ~950: the scale of
  // a light of power 1e-300, or of its squared scores) the terms are scaled by ldexp, which is
  // exact over the whole range, instead of by one multiplication that would overflow to inf or
  // flush to 0.
  explicit FixedScale(int exponent)
      : exponent_(exponent), up_(std::ldexp(1.0, 64 - exponent)),
        down_(std::ldexp(1.0, exponent - 64)),
        wide_(!(std::isnormal(up_) && std::isnormal(down_))) {}
  // The scale for terms of about `typical` (> 0, finite; otherwise the unit scale).
  static FixedScale around(double typical) {
    return FixedScale(std::isfinite(typical) && typical > 0.0 ? std::ilogb(typical) : 0);
  }
  // The scale of the squares of terms on this grid (for sums of squared scores). Not below the
  // smallest subnormal's exponent: the squares of terms of ~1e-300 underflow in double, and a
  // grid finer than 2^-1074 would put every representable square beyond its range.
  FixedScale squared() const { return FixedScale(std::max(2 * exponent_, kMinSquaredExponent)); }
  static constexpr int kMinSquaredExponent = -1074;
  int exponent() const { return exponent_; }

  Fixed toFixed(double v) const {
    const double x = wide_ ? std::ldexp(v, 64 - exponent_) : v * up_;  // a power of two: exact
    // |x| < 2^120 leaves 2^7 headroom for sums of such terms before int128 overflows; a NaN
    // fails the comparison too.
    if (!(std::fabs(x) < 0x1p120))
      throw std::overflow_error("exact sum: a Monte Carlo score of " + std::to_string(v) +
                                " is not finite or exceeds the accumulator's range (2^" +
                                std::to_string(exponent_ + 56) + ")");
    return static_cast<Fixed>(std::rint(x));  // rint, not nearbyint: no save and restore of the FP environment per term
  }
  // Deterministic: one integer gives one double (the conversion rounds to nearest).
  double toDouble(Fixed q) const {
    return wide_ ? std::ldexp(static_cast<double>(q), exponent_ - 64)
                 : static_cast<double>(q) * down_;
  }

 private:
  int exponent_ = 0;
  double up_ = 1.0, down_ = 1.0;
  bool wide_ = false;  // scale by ldexp (see the constructor)
};

// q += v with a check for overflow (sums of ~2^63 typical terms).
inline void addFixed(Fixed& q, Fixed v) {
  if (__builtin_add_overflow(q, v, &q))
    throw std::overflow_error("exact sum: the accumulator overflowed (more than ~2^63 typical "
                              "scores in one sum)");
}

// Mean over n samples (zeros included) of the values summed in s (squares in s2), and its
// standard error, both divided by `measure` (an area, a solid angle or 1).
inline Estimate meanAndError(double s, double s2, uint64_t n, double measure = 1.0) {
  if (n == 0) return {};
  const double N = static_cast<double>(n);
  const double mean = s / N;
  const double var = n > 1 ? std::max(0.0, s2 / N - mean * mean) * N / (N - 1.0) : 0.0;
  return {mean / measure, std::sqrt(var / N) / measure};
}

// Σ w and Σ w² of per-photon (or per-sample) scores over a run, order-independent: the run
// totals of the per-block double sums. Sums on different grids cannot be merged.
class MomentSum {
 public:
  MomentSum() = default;
  explicit MomentSum(FixedScale scale) : scale_(scale), scale2_(scale.squared()) {}

  // One block's (or one photon's) sums.
  void add(double s, double s2) {
    addFixed(s_, scale_.toFixed(s));
    addFixed(s2_, scale2_.toFixed(s2));
  }
  void merge(const MomentSum& o) {
    if (o.scale_.exponent() != scale_.exponent())
      throw std::logic_error("exact sum: merging sums on different grids");
    addFixed(s_, o.s_);
    addFixed(s2_, o.s2_);
  }
  double s() const { return scale_.toDouble(s_); }
  double s2() const { return scale2_.toDouble(s2_); }
  Estimate estimate(uint64_t n, double measure = 1.0) const {
    return meanAndError(s(), s2(), n, measure);
  }
  const FixedScale& scale() const { return scale_; }
  // The integers, for partial files (run_state.h).
  Fixed rawS() const { return s_; }
  Fixed rawS2() const { return s2_; }
  void setRaw(Fixed s, Fixed s2) {
    s_ = s;
    s2_ = s2;
  }

 private:
  Fixed s_ = 0, s2_ = 0;
  FixedScale scale_, scale2_;
};

}  // namespace translucent::reference
