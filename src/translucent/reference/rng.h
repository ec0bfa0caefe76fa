// SPDX-License-Identifier: GPL-3.0-or-later
// Random numbers for the reference Monte Carlo transport: one independent stream per block of
// photons, so that a run's result depends only on (seed, block index) and never on which thread
// traced which block (the determinism rule: same seed -> same result on 1 or N threads).
//
// Generator: xoshiro128+ (Blackman & Vigna 2018), 128 bits of state, period 2^128 - 1, only 32-bit
// integer operations (cheap in scalar code and in SIMD lanes). Its lowest bits are weak (linear),
// so every float below is built from the upper 24 bits only, in the spirit of the seed's
// Listing A.1 (which keeps the upper 23 bits of an LCG and builds the float by bit operations).
//
// (fastmath.h turns the bits into floats for the walkers.)
//
// Stream derivation: the 128-bit state of stream (seed, index) is filled by SplitMix64 (Steele,
// Lea & Flood 2014) started from a 64-bit key that mixes seed and index through two rounds of the
// SplitMix64 finaliser. Distinct (seed, index) pairs thus start at unrelated points of the
// 2^128 period; with at most ~2^40 numbers per stream an overlap has probability < 2^-48.
#pragma once

#include <array>
#include <bit>
#include <cstdint>

namespace translucent::reference {

// SplitMix64's output function: a bijective 64-bit mixer.
constexpr uint64_t mix64(uint64_t z) {
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

class Rng {
 public:
  // Stream `index` of the family selected by `seed`.
  Rng(uint64_t seed, uint64_t index) {
    uint64_t sm = mix64(mix64(seed + 0x9E3779B97F4A7C15ull) ^ (index * 0xD1B54A32D192ED03ull));
    auto next = [&sm] {
      sm += 0x9E3779B97F4A7C15ull;
      return mix64(sm);
    };
    const uint64_t a = next(), b = next();
    s_[0] = static_cast<uint32_t>(a);
    s_[1] = static_cast<uint32_t>(a >> 32);
    s_[2] = static_cast<uint32_t>(b);
    s_[3] = static_cast<uint32_t>(b >> 32);
    if ((s_[0] | s_[1] | s_[2] | s_[3]) == 0) s_[0] = 1;  // the all-zero state is a fixed point
  }

  // 32 random bits (use the upper ones).
  uint32_t next() {
    const uint32_t result = s_[0] + s_[3];
    const uint32_t t = s_[1] << 9;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = std::rotl(s_[3], 11);
    return result;
  }

  // Uniform in [0, 1) on the grid k 2^-24 (exact floats), from the upper 24 bits.
  float uniform() { return static_cast<float>(next() >> 8) * 0x1.0p-24f; }

  // The generator state, for walkers that run the same generator in SIMD lanes.
  std::array<uint32_t, 4> state() const { return {s_[0], s_[1], s_[2], s_[3]}; }


 private:
  uint32_t s_[4];
};

}  // namespace translucent::reference
