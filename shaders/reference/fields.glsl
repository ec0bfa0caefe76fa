// SPDX-License-Identifier: GPL-3.0-or-later
// The 3D material fields of src/material in GLSL: fieldAt(q) is the field's at(q) (the medium at
// material-space point q [medium units]: σa and σs per medium unit, and g), the same formulas in
// float (but for the veins' phase and the noise's lattice offsets, in double: see there). The field comes packed by src/reference/gpu/field_gpu.cpp into the words of `FieldWords`
// (floats as their bits); tests/reference/test_field_gpu.cpp compares the two point by point.
//
// Layout (field_gpu.h has it in full): [0] kind (0 none: zeros; 1 checker, 2 gradient, 3 veins,
// 4 layers, 5 voxels by density, 6 voxels by coefficients), [1] word count, [2] n media,
// [3] P, the kind's parameters; medium m at 4 + 8 m: σa.rgb, g, σs.rgb, 0. From P:
//   checker  cell.xyz
//   gradient from.xyz, axis.xyz ((b − a) / |b − a|²)
//   veins    direction.xyz, period, noise_size as doubles (2 words each, low first), then at
//            P + 10 turbulence, sharpness, octaves (uint); at P + 16 the 256 entries of the
//            noise's permutation
//   layers   form (0 plane, 1 surface), nodes at, triangles at, normal.xyz, offset; at P + 7 the
//            n − 1 layer bottoms. Surface: node k at (nodes at) + 10 k {lo.xyz, hi.xyz, first,
//            count, left, right}, triangle k at (triangles at) + 9 k {a.xyz, b.xyz, c.xyz}
//   voxels   density: a grid header at P; coefficients: g at P, σa's grid header at P + 4, σs's
//            at P + 28. Header: origin.xyz, dims.xyz (ints), channels, values at, background.rgb,
//            translation.xyz, world_to_index (3 columns), 0; values x fastest, channels
//            interleaved.
// Include after `#version 450`; the buffer's binding is 7 unless FIELD_BINDING says otherwise.
#pragma once

// WALK_WORK(): bvh.glsl says what it is for (counting loop iterations); nothing by default.
#ifndef WALK_WORK
#define WALK_WORK()
#endif

#ifndef FIELD_BINDING
#define FIELD_BINDING 7
#endif

layout(std430, binding = FIELD_BINDING) readonly buffer FieldWords { uint fieldWords[]; };

const float kFieldInf = uintBitsToFloat(0x7F800000u);  // +inf (1.0 / 0.0 is undefined in GLSL)
const float kFieldPi = 3.14159265358979;

float fieldFloat(uint i) { return uintBitsToFloat(fieldWords[i]); }
int fieldInt(uint i) { return int(fieldWords[i]); }
vec3 fieldVec3(uint i) { return vec3(fieldFloat(i), fieldFloat(i + 1u), fieldFloat(i + 2u)); }

void fieldMedium(uint m, out vec3 sigmaA, out vec3 sigmaS, out float g) {
  const uint at = 4u + 8u * m;
  sigmaA = fieldVec3(at);
  g = fieldFloat(at + 3u);
  sigmaS = fieldVec3(at + 4u);
}

// LocalMedium::mix (material.h): a + t (b − a) for σa, σs and g alike, written out rather than
// GLSL's mix(), whose a (1 − t) + b t rounds differently.
void fieldMix(float t, out vec3 sigmaA, out vec3 sigmaS, out float g) {
  vec3 a0, s0, a1, s1;
  float g0, g1;
  fieldMedium(0u, a0, s0, g0);
  fieldMedium(1u, a1, s1, g1);
  sigmaA = a0 + t * (a1 - a0);
  sigmaS = s0 + t * (s1 - s0);
  g = g0 + t * (g1 - g0);
}

// ---- checker (material/checker.cpp: cellParity) -------------------------------------------
// Cells are floor(q / cell) per axis (a point on a face belongs to the cell above it); media[1]
// where the sum of the three is odd.
uint fieldCheckerCell(uint P, vec3 q) {
  const vec3 cell = fieldVec3(P);
  const float s = floor(q.x / cell.x) + floor(q.y / cell.y) + floor(q.z / cell.z);
  return mod(abs(s), 2.0) == 1.0 ? 1u : 0u;
}

// ---- gradient (material/gradient.cpp: t) --------------------------------------------------
// t = clamp((q − a)·axis, 0, 1): media[0] at and before a, media[1] at and beyond b.
float fieldGradientT(uint P, vec3 q) {
  return clamp(dot(q - fieldVec3(P), fieldVec3(P + 3u)), 0.0, 1.0);
}

// ---- Perlin's improved noise and its turbulence (material/noise.cpp) -----------------------

int fieldPerm(uint table, int i) { return int(fieldWords[table + uint(i & 255)]); }
// 6t⁵ − 15t⁴ + 10t³, near t = 1 as 1 − fade(1 − t) (the same polynomial: it is symmetric
// about (1/2, 1/2)): in float, t (t 6 − 15) + 10 → 1 cancels to ulp(10) there, which the noise
// passes on (on the CPU it is below a double's ulp).
float fieldFade(float t) {
  const float s = t > 0.5 ? 1.0 - t : t;
  const float f = s * s * s * (s * (s * 6.0 - 15.0) + 10.0);
  return t > 0.5 ? 1.0 - f : f;
}
float fieldLerp(float t, float a, float b) { return a + t * (b - a); }
float fieldGrad(int hash, float x, float y, float z) {
  const int h = hash & 15;
  const float u = h < 8 ? x : y;
  const float v = h < 4 ? y : (h == 12 || h == 14 ? x : z);
  return ((h & 1) == 0 ? u : -u) + ((h & 2) == 0 ? v : -v);
}

// The lattice cell and the offset in it in double, the rest in float: in float, the offset of a
// point some cells from the origin would carry the point's rounding (ulp(|p|)), which the vein
// phase amplifies; this way it is within an ulp of 1.
float fieldNoise(uint table, dvec3 p) {
  const dvec3 fp = floor(p);
  // The lattice repeats every 256 cells; wrapped before the int conversion, as on the CPU.
  const int X = int(fp.x - 256.0lf * floor(fp.x / 256.0lf));
  const int Y = int(fp.y - 256.0lf * floor(fp.y / 256.0lf));
  const int Z = int(fp.z - 256.0lf * floor(fp.z / 256.0lf));
  const float x = float(p.x - fp.x), y = float(p.y - fp.y), z = float(p.z - fp.z);
  const float u = fieldFade(x), v = fieldFade(y), w = fieldFade(z);
  const int A = fieldPerm(table, X) + Y, AA = fieldPerm(table, A) + Z, AB = fieldPerm(table, A + 1) + Z;
  const int B = fieldPerm(table, X + 1) + Y, BA = fieldPerm(table, B) + Z, BB = fieldPerm(table, B + 1) + Z;
  const float n = fieldLerp(w,
      fieldLerp(v, fieldLerp(u, fieldGrad(fieldPerm(table, AA), x, y, z),
                                fieldGrad(fieldPerm(table, BA), x - 1.0, y, z)),
                   fieldLerp(u, fieldGrad(fieldPerm(table, AB), x, y - 1.0, z),
                                fieldGrad(fieldPerm(table, BB), x - 1.0, y - 1.0, z))),
      fieldLerp(v, fieldLerp(u, fieldGrad(fieldPerm(table, AA + 1), x, y, z - 1.0),
                                fieldGrad(fieldPerm(table, BA + 1), x - 1.0, y, z - 1.0)),
                   fieldLerp(u, fieldGrad(fieldPerm(table, AB + 1), x, y - 1.0, z - 1.0),
                                fieldGrad(fieldPerm(table, BB + 1), x - 1.0, y - 1.0, z - 1.0))));
  return n > 1.0 ? 1.0 : (n < -1.0 ? -1.0 : n);
}

float fieldTurbulence(uint table, dvec3 p, uint octaves) {
  float sum = 0.0, amplitude = 1.0;
  dvec3 q = p;
  for (uint o = 0u; o < octaves; ++o) {
    WALK_WORK();
    sum += amplitude * abs(fieldNoise(table, q));
    q *= 2.0lf;
    amplitude *= 0.5;
  }
  return sum;
}

// ---- veins (material/veins.cpp: veinWeight) -----------------------------------------------
// φ = q·d / period + turbulence · T(q / noise_size), w = min((1 − |sin πφ|)^sharpness, 1).
// dw/dφ reaches π · sharpness, so φ is summed in double (direction, period and noise size are
// packed as doubles), the noise's lattice offsets are found in double (fieldNoise), and as
// |sin πφ| has period 1 in φ, sin gets π (φ − round(φ)), within ±π/2, where GPU sines are
// accurate.
double fieldDouble(uint i) { return packDouble2x32(uvec2(fieldWords[i], fieldWords[i + 1u])); }

float fieldVeinWeight(uint P, vec3 q) {
  const dvec3 d = dvec3(fieldDouble(P), fieldDouble(P + 2u), fieldDouble(P + 4u));
  const double period = fieldDouble(P + 6u), noiseSize = fieldDouble(P + 8u);
  const float turbulence = fieldFloat(P + 10u), sharpness = fieldFloat(P + 11u);
  const uint octaves = fieldWords[P + 12u];
  const dvec3 qd = dvec3(q);
  const double phase = dot(qd, d) / period +
                       double(turbulence * fieldTurbulence(P + 16u, qd / noiseSize, octaves));
  const float s = abs(sin(kFieldPi * float(phase - round(phase))));
  return min(pow(max(0.0, 1.0 - s), sharpness), 1.0);
}

// ---- distance to the surface (material/surface_distance.cpp) ------------------------------

// Closest point of triangle abc to p (Ericson, Real-Time Collision Detection, 5.1.5).
vec3 fieldClosestOnTriangle(vec3 p, vec3 a, vec3 b, vec3 c) {
  const vec3 ab = b - a, ac = c - a, ap = p - a;
  const float d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0) return a;
  const vec3 bp = p - b;
  const float d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0.0 && d4 <= d3) return b;
  const float vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return a + (d1 / (d1 - d3)) * ab;
  const vec3 cp = p - c;
  const float d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0.0 && d5 <= d6) return c;
  const float vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return a + (d2 / (d2 - d6)) * ac;
  const float va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0)
    return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  const float denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

float fieldBoxDistance2(vec3 q, uint node) {
  const vec3 d = max(max(fieldVec3(node) - q, q - fieldVec3(node + 3u)), vec3(0.0));
  return dot(d, d);
}

// SurfaceDistance::distance: the tree's nodes nearer child first, pruned by the best squared
// distance so far (field_gpu.cpp rounds the boxes outwards, so pruning in float drops nothing
// the double traversal keeps). field_gpu.cpp refuses trees deeper than the stack.
float fieldSurfaceDistance(vec3 q, uint nodes, uint triangles) {
  float best = kFieldInf;
  uint stack[64];
  int top = 0;
  stack[top++] = 0u;
  while (top > 0) {
    WALK_WORK();
    const uint n = nodes + 10u * stack[--top];
    if (fieldBoxDistance2(q, n) >= best) continue;
    const uint count = fieldWords[n + 7u];
    if (count > 0u) {
      const uint first = fieldWords[n + 6u];
      for (uint i = first; i < first + count; ++i) {
        WALK_WORK();
        const uint t = triangles + 9u * i;
        const vec3 d = fieldClosestOnTriangle(q, fieldVec3(t), fieldVec3(t + 3u), fieldVec3(t + 6u)) - q;
        best = min(best, dot(d, d));
      }
      continue;
    }
    const uint l = fieldWords[n + 8u], r = fieldWords[n + 9u];
    const float dl = fieldBoxDistance2(q, nodes + 10u * l), dr = fieldBoxDistance2(q, nodes + 10u * r);
    if (dl < dr) {
      stack[top++] = r;
      stack[top++] = l;
    } else {
      stack[top++] = l;
      stack[top++] = r;
    }
  }
  return sqrt(best);
}

// ---- layers (material/layers.cpp: depth, layerAt) -----------------------------------------
// Plane depth offset − q·normal (points above the top plane have negative depth: the top
// layer), surface depth the distance to the mesh. Layer i holds depths [Σ_{j<i} t_j, Σ_{j≤i} t_j):
// the first layer whose bottom lies below the depth (std::upper_bound, which a NaN depth runs
// to the end of, as here).
uint fieldLayer(uint P, vec3 q) {
  const float z = fieldWords[P] == 0u ? fieldFloat(P + 6u) - dot(q, fieldVec3(P + 3u))
                                      : fieldSurfaceDistance(q, fieldWords[P + 1u], fieldWords[P + 2u]);
  const uint bottoms = fieldWords[2] - 1u;
  uint i = 0u;
  WALK_WORK();  // the loop may run no iteration
  while (i < bottoms && !(z < fieldFloat(P + 7u + i))) {
    WALK_WORK();
    ++i;
  }
  return i;
}

// ---- voxels (material/voxels.cpp: DenseGrid::voxel, DenseGrid::trilinear, VoxelsField::at) -

struct FieldGrid {
  ivec3 origin, dims;
  uint channels, values;
  vec3 background, translation;
  mat3 toIndex;
};

FieldGrid fieldGrid(uint at) {
  FieldGrid g;
  g.origin = ivec3(fieldInt(at), fieldInt(at + 1u), fieldInt(at + 2u));
  g.dims = ivec3(fieldInt(at + 3u), fieldInt(at + 4u), fieldInt(at + 5u));
  g.channels = fieldWords[at + 6u];
  g.values = fieldWords[at + 7u];
  g.background = fieldVec3(at + 8u);
  g.translation = fieldVec3(at + 11u);
  g.toIndex = mat3(fieldVec3(at + 14u), fieldVec3(at + 17u), fieldVec3(at + 20u));
  return g;
}

// The background outside the stored voxels.
vec3 fieldVoxel(FieldGrid g, ivec3 c) {
  const ivec3 i = c - g.origin;
  if (any(lessThan(i, ivec3(0))) || any(greaterThanEqual(i, g.dims))) return g.background;
  const uint n = (uint(i.z) * uint(g.dims.y) + uint(i.y)) * uint(g.dims.x) + uint(i.x);
  if (g.channels == 1u) return vec3(fieldFloat(g.values + n));
  return fieldVec3(g.values + 3u * n);
}

// Trilinear between voxel centres (integer index points); corners of weight 0 are skipped, and
// far outside (or non-finite) is the background, as on the CPU.
vec3 fieldTrilinear(FieldGrid g, vec3 q) {
  const vec3 p = g.toIndex * (q - g.translation);
  const vec3 f = floor(p);
  const vec3 t = p - f;
  const float kFar = 1e9;
  if (!(abs(f.x) < kFar && abs(f.y) < kFar && abs(f.z) < kFar)) return g.background;
  const ivec3 b = ivec3(f);
  vec3 sum = vec3(0.0);
  for (int c = 0; c < 8; ++c) {
    const int dx = c & 1, dy = (c >> 1) & 1, dz = (c >> 2) & 1;
    const float w = (dx != 0 ? t.x : 1.0 - t.x) * (dy != 0 ? t.y : 1.0 - t.y) *
                    (dz != 0 ? t.z : 1.0 - t.z);
    if (w == 0.0) continue;
    sum += w * fieldVoxel(g, b + ivec3(dx, dy, dz));
  }
  return sum;
}

// ---- the field -----------------------------------------------------------------------------

void fieldAt(vec3 q, out vec3 sigmaA, out vec3 sigmaS, out float g) {
  const uint kind = fieldWords[0];
  const uint P = fieldWords[3];
  if (kind == 1u) {
    fieldMedium(fieldCheckerCell(P, q), sigmaA, sigmaS, g);
  } else if (kind == 2u) {
    fieldMix(fieldGradientT(P, q), sigmaA, sigmaS, g);
  } else if (kind == 3u) {
    fieldMix(fieldVeinWeight(P, q), sigmaA, sigmaS, g);
  } else if (kind == 4u) {
    fieldMedium(fieldLayer(P, q), sigmaA, sigmaS, g);
  } else if (kind == 5u) {
    // The density clamped to [0, 1] blends media 0 and 1.
    fieldMix(clamp(fieldTrilinear(fieldGrid(P), q).x, 0.0, 1.0), sigmaA, sigmaS, g);
  } else if (kind == 6u) {
    sigmaA = fieldTrilinear(fieldGrid(P + 4u), q);
    sigmaS = fieldTrilinear(fieldGrid(P + 28u), q);
    g = fieldFloat(P);
  } else {
    sigmaA = vec3(0.0);
    sigmaS = vec3(0.0);
    g = 0.0;
  }
}
