// SPDX-License-Identifier: GPL-3.0-or-later
// The vector pass of the lane walker (walk_lanes.cpp): one event for every lane. Included by
// walk_lanes_pass_portable.cpp and walk_lanes_pass_avx2.cpp inside their own namespace, so that
// the same source is compiled for the baseline instruction set and for AVX2 + FMA.
//
// The loop body is straight-line code over the lane arrays (selects instead of branches) so the
// compiler vectorises it (`omp simd`; the library is built with -fopenmp-simd, -fno-math-errno
// and -fno-trapping-math so that sqrt, divisions and selects may be vectorised).

// One event for every lane: free flight, boundary test, absorption test, scattering. Returns the
// OR of the lanes' flags (nonzero: some lane needs the scalar pass).
template <Absorption kAbs, bool kFinite, bool kSmallG>
uint32_t pass(Lanes& L, const PassParams& P) {
  const float invSigmaT = P.invSigmaT, g = P.g, thick = P.thickness;
  const uint32_t thrHi = P.absorbHigh;
  const double albedo = P.albedo;
  const float etaTop = P.etaTop, etaBottom = P.etaBottom;
  const float reflectsTop = P.matchedTop != 0 ? 0.0f : 1.0f;
  const float reflectsBottom = P.matchedBottom != 0 ? 0.0f : 1.0f;
  uint32_t any = 0;
#pragma omp simd reduction(| : any)
  for (int i = 0; i < kLanes; ++i) {
    // Four draws of this lane's xoshiro128+ (rng.h), unrolled for the vectoriser.
    uint32_t a = L.s0[i], b = L.s1[i], c = L.s2[i], d = L.s3[i];
    uint32_t u[4];
    for (int k = 0; k < 4; ++k) {
      u[k] = a + d;
      const uint32_t t = b << 9;
      c ^= a;
      d ^= b;
      b ^= c;
      a ^= d;
      c ^= t;
      d = (d << 11) | (d >> 21);
    }
    L.s0[i] = a;
    L.s1[i] = b;
    L.s2[i] = c;
    L.s3[i] = d;

    // Free flight, or the rest of one after an internal reflection.
    float x = L.x[i], y = L.y[i], z = L.z[i];
    float dx = L.dx[i], dy = L.dy[i], dz = L.dz[i];
    const float left = L.left[i];
    const float sNew = -fastLog(unitOpenZeroFromBits(u[0])) * invSigmaT;
    const float s = left >= 0.0f ? left : sNew;
    const float zn = z + s * dz;
    const bool top = zn < 0.0f;
    const bool bottom = kFinite & (zn > thick);
    const bool hit = top | bottom;
    const float zb = top ? 0.0f : thick;
    const float tHit = (zb - z) / dz;
    const float t = hit ? tHit : s;
    x += t * dx;
    y += t * dy;
    z = hit ? zb : zn;
    const float rest = s - t;
    L.left[i] = hit ? (rest > 0.0f ? rest : 0.0f) : -1.0f;

    // At a boundary the photon leaves unless the Fresnel roulette below reflects it.
    L.boundaryBits[i] = u[1];  // the roulette's draw (only a colliding lane uses u[1] otherwise)

    // Collision: absorption test on the high word (a tie is settled in the scalar pass).
    bool absorb = false, tie = false;
    if constexpr (kAbs == Absorption::Analog) {
      absorb = !hit & (u[1] < thrHi);
      tie = !hit & (u[1] == thrHi);
    }
    const bool scatter = !hit & !absorb;

    // Henyey-Greenstein scattering (phase.h), applied where the lane scattered.
    const float mu = kSmallG ? sampleHgCosineSmallG(g, unitFromBits(u[2]))
                             : sampleHgCosineLargeG(g, unitFromBits(u[2]));
    const CosSin phi = uniformAzimuth(u[3]);
    const Dir nd = scatterDirection({dx, dy, dz}, mu, phi.c, phi.s);
    dx = scatter ? nd.x : dx;
    dy = scatter ? nd.y : dy;
    dz = scatter ? nd.z : dz;
    L.x[i] = x;
    L.y[i] = y;
    L.z[i] = z;
    L.dx[i] = dx;
    L.dy[i] = dy;
    L.dz[i] = dz;
    const uint32_t n = L.scatters[i] + (scatter ? 1u : 0u);
    L.scatters[i] = n;

    const bool attention = scatter & ((n > L.longPathLimit[i]) | (n >= kFlushScatters));
    const uint32_t f = (top ? kExitTop : 0u) | (bottom ? kExitBottom : 0u) |
                       (absorb ? kAbsorb : 0u) | (tie ? kTie : 0u) | (scatter ? kScattered : 0u) |
                       (attention ? kAttention : 0u);
    if constexpr (kAbs == Absorption::Analog) {
      // Lanes that need the scalar pass: an event besides scattering, in an active lane.
      const uint32_t flagged = (((f & ~kScattered) != 0) & (L.active[i] != 0)) ? f : 0u;
      L.flags[i] = flagged;
      any |= flagged;
    } else {
      L.flags[i] = f;  // the weighted loop below still needs kScattered
      any |= f;
    }
  }

  // Fresnel roulette at the boundaries (Algorithm 1 line 6), only when a lane reached one and an
  // interface reflects: reflect (the rest of the flight goes on next time) or leave (the scalar
  // pass scores it). fresnelReflectanceFloat is optics/fresnel.h's formula in float (fastmath.h).
  const bool reflective = P.matchedTop == 0 || (kFinite && P.matchedBottom == 0);
  if (reflective && (any & (kExitTop | kExitBottom)) != 0) {
#pragma omp simd
    for (int i = 0; i < kLanes; ++i) {
      const uint32_t f = L.flags[i];
      const bool top = (f & kExitTop) != 0;
      const bool hit = (f & (kExitTop | kExitBottom)) != 0;
      const float dz = L.dz[i];
      const float eta = top ? etaTop : etaBottom;
      const float fresnel = fresnelReflectanceFloat(dz < 0.0f ? -dz : dz, eta);
      const float reflectance = fresnel * (top ? reflectsTop : reflectsBottom);  // 0: matched
      const bool reflect = hit & (unitFromBits(L.boundaryBits[i]) < reflectance);
      L.dz[i] = reflect ? -dz : dz;
      L.flags[i] = reflect ? f & ~(kExitTop | kExitBottom) : f;
    }
  }

  if constexpr (kAbs == Absorption::Weighted) {
    // MCML's implicit capture in its own loop, so that the loop above has only 32-bit lanes.
#pragma omp simd
    for (int i = 0; i < kLanes; ++i) {
      const bool scatter = (L.flags[i] & kScattered) != 0;
      const double w = L.w[i];
      const double loss = w * (1.0 - albedo), wa = w * albedo;
      L.absorbed[i] += scatter ? loss : 0.0;
      const double wn = scatter ? wa : w;
      L.w[i] = wn;
      L.flags[i] |= (scatter & (wn < kWeightThreshold)) ? kAttention : 0u;
    }
    // Lanes that need the scalar pass: an event besides scattering, in an active lane.
    any = 0;
#pragma omp simd reduction(| : any)
    for (int i = 0; i < kLanes; ++i) {
      const uint32_t f = L.flags[i];
      const uint32_t flagged = (((f & ~kScattered) != 0) & (L.active[i] != 0)) ? f : 0u;
      L.flags[i] = flagged;
      any |= flagged;
    }
  }
  // (A lane whose exit the Fresnel roulette turned into a reflection has flags 0 now; `any` may
  // still count it, which only costs a scalar pass that skips it.)
  return any;
}

template <Absorption kAbs, bool kFinite>
VectorPass select(bool smallG) {
  return smallG ? &pass<kAbs, kFinite, true> : &pass<kAbs, kFinite, false>;
}

VectorPass vectorPass(Absorption absorption, bool finite, bool smallG) {
  if (absorption == Absorption::Analog)
    return finite ? select<Absorption::Analog, true>(smallG)
                  : select<Absorption::Analog, false>(smallG);
  return finite ? select<Absorption::Weighted, true>(smallG)
                : select<Absorption::Weighted, false>(smallG);
}
