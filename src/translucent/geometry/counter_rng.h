// SPDX-License-Identifier: GPL-3.0-or-later
// Counter-based random numbers for the geometry algorithms (point sampling, ambient occlusion):
// stream k of a seed is SplitMix64 started at a state that depends on (seed, k), so any stream
// can be drawn independently of every other, on any thread, and results do not depend on the
// thread count.
#pragma once

#include <cstdint>

namespace translucent::geometry {

// SplitMix64's finaliser: a bijective 64-bit mix with good avalanche.
constexpr uint64_t mix64(uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

class CounterRng {
 public:
  CounterRng(uint64_t seed, uint64_t k) : state_(mix64(seed * 0x9e3779b97f4a7c15ULL + mix64(k))) {}
  double uniform() {  // [0, 1), 53 bits
    state_ += 0x9e3779b97f4a7c15ULL;
    return static_cast<double>(mix64(state_) >> 11) * 0x1.0p-53;
  }

 private:
  uint64_t state_;
};

}  // namespace translucent::geometry
