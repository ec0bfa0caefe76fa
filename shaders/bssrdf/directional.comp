#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// Bssrdf(Xi, Wi, Xo, Wo) of a .bssrdf model at arbitrary geometry, for a batch of queries
// (translucent::gpu::BssrdfEvaluator::evaluate): what a directional model (line 1 without
// `radial`) needs besides the profile kernel's plane. Each query is six vec4 (xyz used): Xi, Ni,
// Wi, Xo, No, Wo, with Ni and No the outward unit normals (interface.glsl) and the directions
// pointing away from the surface (Wi towards the light, Wo towards the viewer).
#include "bssrdf/interface.glsl"
#include "bssrdf:parameters"
#include "bssrdf:initializer"
#include "bssrdf:diffuseReflectance"
#include "bssrdf:shader"

layout(local_size_x = 64) in;
#include "common/compute.glsl"  // after the local size: it uses gl_WorkGroupSize
layout(std430, binding = 0) readonly buffer BssrdfQueries { vec4 bssrdfQuery[]; };
layout(std430, binding = 1) writeonly buffer BssrdfValues { vec4 bssrdfValue[]; };
uniform uint BssrdfCount;  // number of queries

void main() {
  uint i = linearInvocationIndex();
  if (i >= BssrdfCount) return;
  init();
  uint q = 6u * i;
  Ni = bssrdfQuery[q + 1u].xyz;
  No = bssrdfQuery[q + 4u].xyz;
  bssrdfValue[i] = vec4(Bssrdf(bssrdfQuery[q].xyz, bssrdfQuery[q + 2u].xyz,
                               bssrdfQuery[q + 3u].xyz, bssrdfQuery[q + 5u].xyz), 0.0);
}
