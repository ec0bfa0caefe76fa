// SPDX-License-Identifier: GPL-3.0-or-later
// The photon walker in SIMD lanes: the random walk of walk_scalar.cpp (Algorithm 1) for kLanes
// photons at once, in structure-of-arrays form.
//
// Why: one photon at a time, an event is a chain of dependent float operations (log polynomial,
// HG inversion, azimuth polynomials, frame rotation) and the CPU waits on their latency. With
// kLanes independent photons the common part of an event (free flight, boundary test with the
// Fresnel roulette and internal reflection, absorption test, scattering) is straight-line code
// over arrays that the compiler vectorises (walk_lanes_pass.inl); the per-photon events (leaving,
// absorption, roulette, scoring, launching the next photon) are handled afterwards by a scalar
// pass over the flagged lanes only.
//
// The Fresnel reflectance in the vector pass is fresnelReflectanceFloat (fastmath.h): the formula
// of optics/fresnel.h in float, tested against it (the library's double function cannot be
// vectorised); the scalar walker calls the library itself.
//
// Each lane has its own random stream Rng(seed, block * kLanes + lane) and draws four numbers per
// iteration whether it uses them or not, and lanes are refilled from the block's photon counter
// in lane order, so a block's result depends only on (seed, block): determinism is kept.
#include <bit>
#include <cstring>

#include "translucent/reference/fastmath.h"
#include "translucent/reference/walk.h"
#include "translucent/reference/walk_lanes.h"

namespace translucent::reference::detail {
namespace {

// The fastest vector pass this CPU runs; `portable` forces the baseline build.
VectorPass chooseVectorPass(Absorption a, bool finite, bool smallG, bool portable) {
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
  if (!portable && __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma"))
    if (VectorPass p = avx2::vectorPass(a, finite, smallG)) return p;
#endif
  (void)portable;
  return portable::vectorPass(a, finite, smallG);
}

class LaneWalker {
 public:
  LaneWalker(const Walk& W, VectorPass pass, uint64_t seed, uint64_t block, uint64_t count,
             Tally& T)
      : W_(W), T_(T), pass_(pass), count_(count) {
    params_ = {W.invSigmaT,
               W.g,
               W.thickness,
               static_cast<uint32_t>(W.absorbThreshold >> 32),
               W.albedo,
               static_cast<float>(W.top.eta),
               static_cast<float>(W.bottom.eta),
               W.top.matched ? 1u : 0u,
               W.bottom.matched ? 1u : 0u};
    std::memset(&L_, 0, sizeof(L_));
    for (int i = 0; i < kLanes; ++i) {
      // Seed each lane's xoshiro state from its own stream (rng.h).
      const auto st = Rng(seed, block * kLanes + static_cast<uint64_t>(i)).state();
      L_.s0[i] = st[0];
      L_.s1[i] = st[1];
      L_.s2[i] = st[2];
      L_.s3[i] = st[3];
      launch(i);
    }
  }

  template <Absorption kAbs>
  bool run(const std::atomic<bool>& stop) {
    uint64_t iterations = 0;
    while (activeCount_ > 0) {
      if ((++iterations & 1023u) == 0 && stop.load(std::memory_order_relaxed)) return false;
      if (pass_(L_, params_) != 0) scalarPass<kAbs>();
    }
    return true;
  }

 private:
  void launch(int i) {
    if (launched_ == count_) {
      if (L_.active[i]) --activeCount_;
      L_.active[i] = 0;
      L_.flags[i] = 0;
      L_.w[i] = 1.0;  // keeps the idle lane's arithmetic away from denormals
      return;
    }
    if (!L_.active[i]) ++activeCount_;
    ++launched_;
    L_.active[i] = 1;
    L_.x[i] = L_.y[i] = L_.z[i] = 0.0f;
    L_.dx[i] = W_.entry.x;
    L_.dy[i] = W_.entry.y;
    L_.dz[i] = W_.entry.z;
    L_.left[i] = -1.0f;
    L_.scatters[i] = 0;
    L_.scatterBase[i] = 0;
    L_.longPathLimit[i] = longPathLimit(0);
    L_.w[i] = W_.entryWeight;
    L_.absorbed[i] = 0.0;
  }

  // Flag scattering counts above this value (in the lane's 32-bit counter).
  uint32_t longPathLimit(uint64_t base) const {
    if (W_.longPath == 0) return 0xFFFFFFFFu;
    if (base >= W_.longPath) return 0;
    return static_cast<uint32_t>(std::min<uint64_t>(W_.longPath - base, 0xFFFFFFFFu));
  }

  void finish(int i) {
    T_.absorbed.add(L_.absorbed[i]);
    T_.events += L_.scatterBase[i] + L_.scatters[i];
    ++T_.photons;
    launch(i);
  }

  // The per-photon events of the lanes flagged by the vector pass, in lane order.
  template <Absorption kAbs>
  void scalarPass() {
    // Visit only the flagged lanes (in lane order), via a bit mask: a test-and-branch per lane
    // would mispredict on every random flag.
    uint32_t mask = 0;
    for (int i = 0; i < kLanes; ++i) mask |= (L_.flags[i] != 0 ? 1u : 0u) << i;
    for (; mask != 0; mask &= mask - 1) {
      const int i = std::countr_zero(mask);
      const uint32_t f = L_.flags[i];
      if (f & (kExitTop | kExitBottom)) {
        // The photon left (the vector pass played the Fresnel roulette): score it.
        const double w = L_.w[i];
        if (f & kExitTop) {
          const double cosOut =
              W_.na > 0 ? cross(W_.top, std::abs(static_cast<double>(L_.dz[i]))).cosOut : 0.0;
          scoreTop(W_, T_, L_.x[i], L_.y[i], cosOut, L_.scatterBase[i] + L_.scatters[i], w);
        } else {
          scoreBottom(T_, L_.scatterBase[i] + L_.scatters[i], w);
        }
        finish(i);
        continue;
      }
      if (f & kAbsorb) {
        L_.absorbed[i] = L_.w[i];
        finish(i);
        continue;
      }
      if ((f & kTie) && absorbsLowWord(L_.next(i), W_.absorbThreshold)) {
        L_.absorbed[i] = L_.w[i];
        finish(i);
        continue;
      }
      if (!(f & kScattered)) continue;
      if (L_.scatters[i] >= kFlushScatters) {
        L_.scatterBase[i] += L_.scatters[i];
        L_.scatters[i] = 0;
        L_.longPathLimit[i] = longPathLimit(L_.scatterBase[i]);
      }
      // Roulette of small weights (MCML) and long-path roulette (seed 3.2), as in the scalar
      // walker, after the scattering event.
      if (kAbs == Absorption::Weighted && L_.w[i] < kWeightThreshold) {
        if (L_.next(i) >= kSurviveThreshold) {
          finish(i);
          continue;
        }
        L_.w[i] *= kSurviveBoost;
      }
      if (W_.longPath != 0 && L_.scatterBase[i] + L_.scatters[i] > W_.longPath) {
        if (L_.next(i) >= kSurviveThreshold) {
          finish(i);
          continue;
        }
        L_.w[i] *= kSurviveBoost;
      }
    }
  }

  const Walk& W_;
  Tally& T_;
  VectorPass pass_;
  PassParams params_;
  Lanes L_;
  uint64_t count_, launched_ = 0;
  int activeCount_ = 0;
};

template <Absorption kAbs>
bool runBlock(const Walk& W, VectorPass pass, uint64_t seed, uint64_t block, uint64_t count,
              Tally& T, const std::atomic<bool>& stop) {
  LaneWalker walker(W, pass, seed, block, count, T);
  return walker.run<kAbs>(stop);
}

}  // namespace

LanesKernel lanesKernel(Absorption absorption, bool finite, float g, bool portable) {
  LanesKernel k;
  k.pass = chooseVectorPass(absorption, finite, hgUsesSmallG(g), portable);
  k.run = absorption == Absorption::Analog ? &runBlock<Absorption::Analog>
                                           : &runBlock<Absorption::Weighted>;
  return k;
}

}  // namespace translucent::reference::detail
