// SPDX-License-Identifier: GPL-3.0-or-later
// Bend, twist and wave on the GPU: the formulas of src/geometry/deform.{h,cpp}, line by line, in
// float (the header there defines them; keep the two in step). A deformation is three vec4s:
//   a = (origin, type), b = (axis, magnitude m at this time), c = (direction, wavelength),
// type 0 bend, 1 twist, 2 wave (geometry::Deformation::Type), m in degrees per unit length
// (bend, twist) or scene units (wave). Axis and direction are unit and perpendicular.
#pragma once

// WALK_WORK(): reference/bvh.glsl says what it is for (counting loop iterations for llvmpipe's
// loop limit); nothing by default.
#ifndef WALK_WORK
#define WALK_WORK()
#endif

const float kDeformPi = 3.14159265358979;
const float kDeformDegree = kDeformPi / 180.0;

// sin(x)/x, 1 at 0 (the series where float's quotient would lose digits).
float deformSinc(float x) { return abs(x) < 1e-3 ? 1.0 - x * x / 6.0 : sin(x) / x; }

// Rotation of q about the unit axis a by theta, as the displacement q' - q.
vec3 deformRotationDisplacement(vec3 a, float theta, vec3 q) {
  return sin(theta) * cross(a, q) + (1.0 - cos(theta)) * (dot(a, q) * a - q);
}

mat3 deformRotationMatrix(vec3 a, float theta) {
  mat3 crossA = mat3(0.0, a.z, -a.y, -a.z, 0.0, a.x, a.y, -a.x, 0.0);
  return cos(theta) * mat3(1.0) + sin(theta) * crossA + (1.0 - cos(theta)) * outerProduct(a, a);
}

vec3 deformPoint(vec4 da, vec4 db, vec4 dc, vec3 p) {
  int type = int(da.w);
  vec3 o = da.xyz, a = db.xyz, d = dc.xyz;
  float m = db.w;
  vec3 q = p - o;
  float u = dot(q, a), v = dot(q, d);
  if (type == 1) return p + deformRotationDisplacement(a, m * kDeformDegree * u, q);
  if (type == 0) {
    float k = m * kDeformDegree;
    float s = sin(k * u), h = sin(0.5 * k * u);
    float du = u * deformSinc(k * u) - u - v * s;
    float dv = u * h * deformSinc(0.5 * k * u) - 2.0 * v * h * h;
    return p + du * a + dv * d;
  }
  return p + (m * sin(2.0 * kDeformPi * v / dc.w)) * a;
}

mat3 deformJacobian(vec4 da, vec4 db, vec4 dc, vec3 p) {
  int type = int(da.w);
  vec3 o = da.xyz, a = db.xyz, d = dc.xyz;
  float m = db.w;
  vec3 q = p - o;
  float u = dot(q, a), v = dot(q, d);
  if (type == 1) {
    float k = m * kDeformDegree;
    mat3 r = deformRotationMatrix(a, k * u);
    return r + k * outerProduct(cross(a, r * q), a);
  }
  if (type == 0) {
    float k = m * kDeformDegree;
    float s = sin(k * u), c = cos(k * u), f = 1.0 - k * v;
    return mat3(1.0) + (f * c - 1.0) * outerProduct(a, a) - s * outerProduct(a, d) +
           f * s * outerProduct(d, a) + (c - 1.0) * outerProduct(d, d);
  }
  float kw = 2.0 * kDeformPi / dc.w;
  return mat3(1.0) + (m * kw * cos(kw * v)) * outerProduct(a, d);
}

// The point whose deformation is x (geometry::undeformPoint for one step): a twist turns back by
// -κu (u is unchanged), a wave's displacement along a does not change (p - o)·d, a bend is
// inverted by Newton's method from x (its displacement is smooth and J invertible away from the
// centre of curvature), to float precision of the displacement.
vec3 undeformPoint(vec4 da, vec4 db, vec4 dc, vec3 x) {
  int type = int(da.w);
  vec3 o = da.xyz, a = db.xyz, d = dc.xyz;
  float m = db.w;
  if (type == 1) {
    vec3 q = x - o;
    return x + deformRotationDisplacement(a, -m * kDeformDegree * dot(q, a), q);
  }
  if (type == 2) return x - (m * sin(2.0 * kDeformPi * dot(x - o, d) / dc.w)) * a;
  float tol = 2e-7 * (1.0 + length(x - o));
  vec3 r = x;
  for (int i = 0; i < 30; ++i) {
    WALK_WORK();
    vec3 err = deformPoint(da, db, dc, r) - x;
    if (length(err) <= tol) break;
    r -= inverse(deformJacobian(da, db, dc, r)) * err;
  }
  return r;
}
