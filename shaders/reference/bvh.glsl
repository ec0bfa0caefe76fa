// SPDX-License-Identifier: GPL-3.0-or-later
// Closest-hit ray queries against a triangle mesh on the GPU: a binary BVH built on the CPU by
// Embree's BVH builder (src/geometry/flat_bvh.h: rtcBuildBVH, SAH, high quality) and flattened
// depth first, traversed with a stack, nearer child first; triangles tested with the watertight
// algorithm of Woop, Benthin & Wald 2013 ("Watertight ray/triangle intersection", JCGT 2(1)), the
// edge cases (a zero barycentric) redone in double, so that a ray through a shared edge or vertex
// of a closed mesh hits at least one of its triangles: a photon cannot slip out between them.
// Single precision otherwise, as Embree's queries on the CPU.
//
// Layout (flat_bvh.h, std430): node i is {lower, a, upper, count}: count > 0, a leaf with the
// triangles a .. a + count - 1; count = 0, an inner node with children i + 1 and a. Triangle k is
// {v0, index, v1, -, v2, -} with `index` the triangle's index in the mesh.
#pragma once

// WALK_WORK(): called once per iteration of every loop whose trip count is not a constant (and
// once before a loop that may run none), so that a walk can bound the loop iterations the driver
// counts (mesh_walk.comp: Mesa's llvmpipe ends every loop of a shader invocation after 65535
// iterations in all, walk_program.h). Nothing by default.
#ifndef WALK_WORK
#define WALK_WORK()
#endif

#ifndef BVH_NODE_BINDING
#define BVH_NODE_BINDING 1
#endif
#ifndef BVH_TRIANGLE_BINDING
#define BVH_TRIANGLE_BINDING 2
#endif

const float kBvhInf = uintBitsToFloat(0x7F800000u);  // +inf (1.0 / 0.0 is undefined in GLSL)

struct BvhNode {
  vec3 lower;
  uint a;
  vec3 upper;
  uint count;
};
struct BvhTriangle {
  vec3 v0;
  uint index;
  vec3 v1;
  uint pad1;
  vec3 v2;
  uint pad2;
};
layout(std430, binding = BVH_NODE_BINDING) readonly buffer BvhNodes { BvhNode bvhNodes[]; };
layout(std430, binding = BVH_TRIANGLE_BINDING) readonly buffer BvhTriangles {
  BvhTriangle bvhTriangles[];
};

struct BvhRay {
  vec3 o, d, invD;
  int kx, ky, kz;  // the watertight test's axis permutation
  vec3 shear;      // (Sx, Sy, Sz)
};

BvhRay bvhRay(vec3 o, vec3 d) {
  BvhRay r;
  r.o = o;
  r.d = d;
  // A zero component's inverse is +-huge, not inf, so that 0 * invD is never NaN in the slabs.
  for (int k = 0; k < 3; ++k)
    r.invD[k] = abs(d[k]) > 1e-30 ? 1.0 / d[k] : (d[k] >= 0.0 ? 1e30 : -1e30);
  const vec3 a = abs(d);
  r.kz = a.x > a.y ? (a.x > a.z ? 0 : 2) : (a.y > a.z ? 1 : 2);
  r.kx = (r.kz + 1) % 3;
  r.ky = (r.kx + 1) % 3;
  if (d[r.kz] < 0.0) {  // keep the winding of the permuted triangle
    const int t = r.kx;
    r.kx = r.ky;
    r.ky = t;
  }
  r.shear = vec3(d[r.kx] / d[r.kz], d[r.ky] / d[r.kz], 1.0 / d[r.kz]);
  return r;
}

// Entry distance of the ray into the box, or +inf when it misses [tMin, tMax].
float bvhBoxEntry(const BvhRay r, vec3 lower, vec3 upper, float tMin, float tMax) {
  const vec3 t0 = (lower - r.o) * r.invD, t1 = (upper - r.o) * r.invD;
  const vec3 lo = min(t0, t1), hi = max(t0, t1);
  const float enter = max(max(lo.x, lo.y), max(lo.z, tMin));
  // Robust traversal (Ize 2013): widen the exit by 4 2^-24 so that boxes touched at a face are
  // not missed through rounding (measured: 2 to 179 misses per 139k edge rays without it, none
  // with half of it; tests/geometry/test_flat_bvh.cpp).
  const float exit = min(min(hi.x, hi.y), min(hi.z, tMax)) * 1.00000024;
  return enter <= exit ? enter : kBvhInf;
}

// Woop et al. 2013, Fig. 2: t of the hit in (tMin, tMax], or -1 (tMin >= 0).
float bvhTriangleHit(const BvhRay r, const BvhTriangle tri, float tMin, float tMax) {
  const vec3 A = tri.v0 - r.o, B = tri.v1 - r.o, C = tri.v2 - r.o;
  const float Ax = A[r.kx] - r.shear.x * A[r.kz], Ay = A[r.ky] - r.shear.y * A[r.kz];
  const float Bx = B[r.kx] - r.shear.x * B[r.kz], By = B[r.ky] - r.shear.y * B[r.kz];
  const float Cx = C[r.kx] - r.shear.x * C[r.kz], Cy = C[r.ky] - r.shear.y * C[r.kz];
  // `precise`: a fused multiply-add would break the exact sign flip of U, V, W across a shared
  // edge that makes the test watertight (GLSL allows fusing otherwise; the CPU copy is compiled
  // with -ffp-contract=off for the same reason).
  precise float U = Cx * By - Cy * Bx, V = Ax * Cy - Ay * Cx, W = Bx * Ay - By * Ax;
  if (U == 0.0 || V == 0.0 || W == 0.0) {  // on an edge in float: decide in double
    U = float(double(Cx) * double(By) - double(Cy) * double(Bx));
    V = float(double(Ax) * double(Cy) - double(Ay) * double(Cx));
    W = float(double(Bx) * double(Ay) - double(By) * double(Ax));
  }
  if ((U < 0.0 || V < 0.0 || W < 0.0) && (U > 0.0 || V > 0.0 || W > 0.0)) return -1.0;
  const float det = U + V + W;
  if (det == 0.0) return -1.0;
  const float Az = r.shear.z * A[r.kz], Bz = r.shear.z * B[r.kz], Cz = r.shear.z * C[r.kz];
  const float T = U * Az + V * Bz + W * Cz;
  const float t = T / det;
  return t > tMin && t <= tMax ? t : -1.0;
}

// The closest hit of o + t d, t in (tMin, tMax] (tMin >= 0; the BVH's depth is at most 64): its t, the unit geometric normal of the hit
// triangle (its winding's side) and the triangle's index. False when the ray misses.
bool bvhIntersect(vec3 o, vec3 d, float tMin, float tMax, out float tHit, out vec3 normal,
                  out uint triangle) {
  const BvhRay r = bvhRay(o, d);
  uint stack[64];
  int top = 0;
  uint node = 0u;
  float best = tMax;
  int bestTri = -1;
  if (bvhBoxEntry(r, bvhNodes[0].lower, bvhNodes[0].upper, tMin, best) == kBvhInf) return false;
  for (;;) {
    WALK_WORK();
    const BvhNode n = bvhNodes[node];
    if (n.count > 0u) {
      for (uint k = n.a; k < n.a + n.count; ++k) {
        WALK_WORK();
        const float t = bvhTriangleHit(r, bvhTriangles[k], tMin, best);
        if (t >= 0.0) {  // a hit in (tMin, best]: tMin >= 0
          best = t;
          bestTri = int(k);
        }
      }
    } else {
      const uint left = node + 1u, right = n.a;
      const float tl = bvhBoxEntry(r, bvhNodes[left].lower, bvhNodes[left].upper, tMin, best);
      const float tr = bvhBoxEntry(r, bvhNodes[right].lower, bvhNodes[right].upper, tMin, best);
      const bool hitL = tl != kBvhInf, hitR = tr != kBvhInf;
      if (hitL && hitR) {
        const bool leftFirst = tl <= tr;
        stack[top++] = leftFirst ? right : left;
        node = leftFirst ? left : right;
        continue;
      }
      if (hitL || hitR) {
        node = hitL ? left : right;
        continue;
      }
    }
    if (top == 0) break;
    node = stack[--top];
  }
  if (bestTri < 0) return false;
  const BvhTriangle tri = bvhTriangles[bestTri];
  tHit = best;
  normal = normalize(cross(tri.v1 - tri.v0, tri.v2 - tri.v0));
  triangle = tri.index;
  return true;
}
