#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// Radial profile R(r) of a .bssrdf model for a batch of radii (translucent::gpu::BssrdfEvaluator).
//
// Geometry (the seed's pencil plot, 3.6.3: a semi-infinite slab lit by a normally incident
// pencil beam at the origin): the surface is the plane z = 0 with outward normal N = (0, 0, 1),
// Xi = origin, Xo = (r, 0, 0), and both directions along the normal, Wi = Wo = N (directions
// point away from the surface, as in BRDF Explorer). The plotted value is Bssrdf() itself: in
// listing A.2, Bssrdf() returns the diffuse reflectance profile Rd(||Xo - Xi||) of Eq. 2.37 (no
// Fresnel or 1/pi factors), per unit area per unit incident flux [1/scene unit^2].
// Negative radii are allowed (Xo on the negative x axis: a cross-section).
#include "bssrdf/interface.glsl"
#include "bssrdf:parameters"
#include "bssrdf:initializer"
#include "bssrdf:diffuseReflectance"
#include "bssrdf:shader"

layout(local_size_x = 64) in;
#include "common/compute.glsl"  // after the local size: it uses gl_WorkGroupSize
layout(std430, binding = 0) readonly buffer BssrdfRadii { float bssrdfRadius[]; };
layout(std430, binding = 1) writeonly buffer BssrdfProfile { vec4 bssrdfProfile[]; };
uniform uint BssrdfCount;  // number of radii

void main() {
  uint i = linearInvocationIndex();
  if (i >= BssrdfCount) return;
  init();
  const vec3 n = vec3(0.0, 0.0, 1.0);
  vec3 xi = vec3(0.0);
  vec3 xo = vec3(bssrdfRadius[i], 0.0, 0.0);
  Ni = n;
  No = n;
  bssrdfProfile[i] = vec4(Bssrdf(xi, n, xo, n), 0.0);
}
