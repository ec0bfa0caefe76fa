#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// Total diffuse reflectance Rdr(alpha') of a .bssrdf model for a batch of reduced albedos
// (seed 3.4: the Rdr, ld parametrisation inverts this function by bisection on the GPU).
// init() runs first, so DiffuseReflectance() may use what it computes from the standard inputs
// (listing A.2 uses A, which depends on IOR only).
#include "bssrdf/interface.glsl"
#include "bssrdf:parameters"
#include "bssrdf:initializer"
#include "bssrdf:diffuseReflectance"
#include "bssrdf:shader"

layout(local_size_x = 64) in;
#include "common/compute.glsl"  // after the local size: it uses gl_WorkGroupSize
layout(std430, binding = 0) readonly buffer BssrdfAlbedos { float bssrdfAlphaPrime[]; };
layout(std430, binding = 1) writeonly buffer BssrdfReflectance { vec4 bssrdfRdr[]; };
uniform uint BssrdfCount;  // number of albedos

void main() {
  uint i = linearInvocationIndex();
  if (i >= BssrdfCount) return;
  init();
  bssrdfRdr[i] = vec4(DiffuseReflectance(vec3(bssrdfAlphaPrime[i])), 0.0);
}
