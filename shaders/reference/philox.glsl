// SPDX-License-Identifier: GPL-3.0-or-later
// Philox4x32-10 (Salmon, Moraes, Dror & Shaw 2011, "Parallel random numbers: as easy as 1, 2,
// 3"): a counter-based generator. The 128-bit counter and the 64-bit key give four 32-bit words
// with no state carried between calls, so photon p's n-th event draws philox(p, n) wherever and
// whenever it is traced: a GPU run does not depend on scheduling. Known-answer vectors of
// Random123 are checked in tests/reference/test_slab_gpu.cpp (and src/reference/gpu/philox.h is
// the same function on the CPU).
#pragma once

const uint kPhiloxM0 = 0xD2511F53u, kPhiloxM1 = 0xCD9E8D57u;  // round multipliers
const uint kPhiloxW0 = 0x9E3779B9u, kPhiloxW1 = 0xBB67AE85u;  // Weyl key increments

uvec4 philox4x32_10(uvec4 ctr, uvec2 key) {
  for (int round = 0; round < 10; ++round) {
    uint hi0, lo0, hi1, lo1;
    umulExtended(kPhiloxM0, ctr.x, hi0, lo0);
    umulExtended(kPhiloxM1, ctr.z, hi1, lo1);
    ctr = uvec4(hi1 ^ ctr.y ^ key.x, lo1, hi0 ^ ctr.w ^ key.y, lo0);
    key += uvec2(kPhiloxW0, kPhiloxW1);
  }
  return ctr;
}
