// SPDX-License-Identifier: GPL-3.0-or-later
// Delta and ratio tracking through the CPU's majorant grid (src/reference/majorant_grid.h:
// MajorantGrid::track; Novák et al. 2018, sections 4.1 and 5.2) for the GPU walks of a
// heterogeneous body (mesh_walk.comp, camera_walk.comp, compiled with VOLUME): a 3D DDA over the
// cells' bounds (rounded up to float on upload), the field evaluated at tentative collisions by
// fields.glsl in material space (q = scale Rᵀ (x − translate), x undeformed first when the body
// is deformed: common/deform.glsl, in float, Newton's method for a bend). Tentative collisions
// where the field exceeds the bound in force are counted.
//
// The includer provides nextWord(), uniformFloat(), the uniform Channel and WALK_WORK().
#pragma once

#include "reference/fields.glsl"
#include "common/deform.glsl"

// The majorant grid's bounds of this channel [1/scene unit], cell (i, j, k) at
// (k * ny + j) * nx + i; tentative collisions above the bound in force.
layout(std430, binding = 8) readonly buffer Majorants { float majorants[]; };
layout(std430, binding = 9) buffer Violations { uint violationCount; };

uniform vec3 GridLower, GridUpper, GridCell;  // the grid's box and cell size [scene units]
uniform ivec3 GridCells;
uniform float GridOuterBound;  // the largest cell's bound: beyond the box
uniform float CoefficientScale;  // per medium unit -> per scene unit (Medium::scale)
uniform mat3 FrameRotationT;     // material frame (material.h): q = scale Rᵀ (x − translate)
uniform dvec3 FrameTranslate;
uniform float FrameScale;
// The material frame's deformations at this time (material.h: MaterialFrame::toMaterial undoes
// them before the rest transform; geometry/deform.h), as common/deform.comp takes them.
uniform int DeformCount;                 // 0: the body is not deformed
uniform vec4 DeformA[8];                 // origin, type
uniform vec4 DeformB[8];                 // axis, magnitude at this time
uniform vec4 DeformC[8];                 // direction, wavelength

vec3 gLocalA, gLocalS;  // the medium at the last tentative collision [1/medium unit]
float gLocalG, gLocalSigmaT;  // its g, and its σt in this channel [1/scene unit]
float gTau;                   // optical depth left to the next tentative collision
// Ratio tracking (ratioTracking): the running transmittance instead of a collision.
bool gRatio = false;
float gTransmittance = 1.0;

// The medium at o + tc d into gLocal*; counts a violation of `bound`.
void evaluateField(dvec3 o, vec3 d, float tc, float bound) {
  vec3 q;
  if (DeformCount == 0) {
    q = FrameScale * (FrameRotationT * vec3(o + double(tc) * dvec3(d) - FrameTranslate));
  } else {
    // The rest pose's point first, step by step in reverse order (geometry::undeformPoint).
    vec3 rest = vec3(o + double(tc) * dvec3(d));
    for (int k = DeformCount - 1; k >= 0; --k) {
      WALK_WORK();
      if (DeformB[k].w != 0.0) rest = undeformPoint(DeformA[k], DeformB[k], DeformC[k], rest);
    }
    q = FrameScale * (FrameRotationT * (rest - vec3(FrameTranslate)));
  }
  fieldAt(q, gLocalA, gLocalS, gLocalG);
  gLocalSigmaT = (gLocalA[Channel] + gLocalS[Channel]) * CoefficientScale;
  if (gLocalSigmaT > bound * 1.000001) atomicAdd(violationCount, 1u);
}

// At a tentative collision: delta tracking accepts it with probability σt / bound (true: a real
// collision); ratio tracking multiplies the transmittance by 1 - σt / bound, with a roulette
// (survive 1/2, weight x2) once it is below 0.01, and stops (true) when it is 0 (camera_paths.cpp:
// ratioTracking).
bool acceptCollision(dvec3 o, vec3 d, float tc, float bound) {
  evaluateField(o, d, tc, bound);
  if (gRatio) {
    gTransmittance *= 1.0 - min(1.0, gLocalSigmaT / bound);
    if (!(gTransmittance > 0.0)) return true;
    if (gTransmittance < 0.01) {
      if (uniformFloat() < 0.5) {
        gTransmittance = 0.0;
        return true;
      }
      gTransmittance *= 2.0;
    }
    return false;
  }
  if (gLocalSigmaT >= bound) return true;
  return uniformFloat() * bound < gLocalSigmaT;
}

// Spends gTau over [ta, tb) at rate m: true at a real collision (tOut set).
bool spend(dvec3 o, vec3 d, float ta, float tb, float m, inout float tOut) {
  if (!(m > 0.0)) return false;
  for (;;) {
    WALK_WORK();
    const float len = tb > ta ? tb - ta : 0.0;
    if (gTau >= m * len) {
      gTau -= m * len;
      return false;
    }
    const float t = ta + gTau / m;
    if (acceptCollision(o, d, t, m)) {
      tOut = t;
      return true;
    }
    gTau = -fastLog(unitOpenZeroFromBits(nextWord()));
    ta = t;
  }
}

float cellBound(ivec3 c) {
  return majorants[(c.z * GridCells.y + c.y) * GridCells.x + c.x];
}

// The first real collision from o along d in (0, tMax] (tMax may be kBvhInf), false when none.
// The segments (before the box at the outer bound, the cells by a 3D DDA, after the box) are
// spent by one call of spend, so that the field's code is inlined once per call of trackTo.
bool trackTo(dvec3 o, vec3 d, float tMax, out float tOut) {
  tOut = 0.0;
  gTau = -fastLog(unitOpenZeroFromBits(nextWord()));
  const vec3 p = vec3(o);
  float t0 = 0.0, t1 = tMax;
  vec3 inv;
  for (int a = 0; a < 3; ++a) {
    inv[a] = d[a] != 0.0 ? 1.0 / d[a] : 0.0;
    if (d[a] == 0.0) {
      if (p[a] < GridLower[a] || p[a] > GridUpper[a]) t1 = -1.0;
      continue;
    }
    float ta = (GridLower[a] - p[a]) * inv[a], tb = (GridUpper[a] - p[a]) * inv[a];
    if (ta > tb) {
      const float tmp = ta;
      ta = tb;
      tb = tmp;
    }
    t0 = max(t0, ta);
    t1 = min(t1, tb);
  }
  // Stage 0: [0, t0) at the outer bound; 1: the cells over [t0, t1); 2: [t1, tMax) at the outer
  // bound; 3: done. A ray that misses the box: [0, tMax) at the outer bound only.
  const bool inBox = t0 < t1;
  int stage = inBox ? 0 : 2;
  if (!inBox) t1 = 0.0;
  ivec3 cell = ivec3(0), step = ivec3(0);
  vec3 next = vec3(kBvhInf), delta = vec3(kBvhInf);
  if (inBox) {
    const vec3 start = p + t0 * d;
    for (int a = 0; a < 3; ++a) {
      cell[a] = clamp(int((start[a] - GridLower[a]) / GridCell[a]), 0, GridCells[a] - 1);
      if (d[a] > 0.0) {
        step[a] = 1;
        next[a] = (GridLower[a] + float(cell[a] + 1) * GridCell[a] - p[a]) * inv[a];
        delta[a] = GridCell[a] * inv[a];
      } else if (d[a] < 0.0) {
        step[a] = -1;
        next[a] = (GridLower[a] + float(cell[a]) * GridCell[a] - p[a]) * inv[a];
        delta[a] = -GridCell[a] * inv[a];
      }
    }
  }
  float t = t0;
  for (;;) {
    WALK_WORK();
    float ta, tb, m;
    int axis = 0;
    if (stage == 0) {
      ta = 0.0;
      tb = t0;
      m = GridOuterBound;
    } else if (stage == 1) {
      axis = next[0] < next[1] ? (next[0] < next[2] ? 0 : 2) : (next[1] < next[2] ? 1 : 2);
      ta = t;
      tb = min(next[axis], t1);
      m = cellBound(cell);
    } else {
      if (!(t1 < tMax)) return false;
      ta = t1;
      tb = tMax;
      m = GridOuterBound;
    }
    if (tb > ta && spend(o, d, ta, tb, m, tOut)) return true;
    if (stage == 0) {
      stage = 1;
    } else if (stage == 1) {
      if (tb >= t1) {
        stage = 2;
        continue;
      }
      t = tb;
      cell[axis] += step[axis];
      if (cell[axis] < 0 || cell[axis] >= GridCells[axis]) {  // left the box early (rounding)
        t1 = t;  // the outer bound from here
        stage = 2;
        continue;
      }
      next[axis] += delta[axis];
    } else {
      return false;
    }
  }
  return false;
}

// The first real collision from o along d, no end: the boundary is the caller's (false: a ray
// that leaves the grid's box into nothing).
bool track(dvec3 o, vec3 d, out float tOut) { return trackTo(o, d, kBvhInf, tOut); }

// Ratio tracking of the transmittance over o + t d, t in (0, len] (Novák et al. 2018, Eq. 29).
float ratioTracking(dvec3 o, vec3 d, float len) {
  gRatio = true;
  gTransmittance = 1.0;
  float t;
  trackTo(o, d, len, t);
  gRatio = false;
  return gTransmittance;
}
