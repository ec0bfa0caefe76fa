#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// The transfer technique's first-order inputs per node (techniques/transfer/transfer_operator.h):
// the tangential part τ of the refracted direction of the light that lit the node, from the
// irradiance pass's light directions (surface_irradiance.h: Σ_l w_l ω_l and Σ_l w_l over the
// directional, filtered, beam and point lights; ω_l towards the light): light travels along -ω_l,
// whose tangential part keeps its direction and shrinks by 1/η on refraction (Snell), so
//     τ = -(m - (m·n) n) / (η W),   m = Σ_l w_l ω_l,  W = Σ_l w_l,
// and E^u = E (τ·u), E^v = E (τ·v), v = n × u. Environment light carries no direction (W = 0
// where it alone lit the node: τ = 0, normal incidence). One invocation per node.
layout(local_size_x = 64) in;
#include "pointcloud/common.glsl"
layout(std430, binding = 2) readonly buffer TxPoints { PcPoint txPoint[]; };
layout(std430, binding = 3) readonly buffer TxIrradiance { vec4 txIrradiance[]; };
layout(std430, binding = 14) readonly buffer TxLightDir { vec4 txLightDir[]; };
layout(std430, binding = 27) readonly buffer TxTangents { vec4 txTangent[]; };
layout(std430, binding = 28) writeonly buffer TxTilted { vec4 txTilted[]; };  // 2 per node: E^u, E^v
uniform uint Nodes;
uniform float Eta;
void main() {
  uint j = gl_GlobalInvocationID.x;
  if (j >= Nodes) return;
  vec3 n = txPoint[j].normal.xyz;
  vec3 u = txTangent[j].xyz;
  vec3 v = cross(n, u);
  vec4 m = txLightDir[j];
  vec3 tau = m.w > 0.0 ? -(m.xyz - dot(m.xyz, n) * n) / (Eta * m.w) : vec3(0.0);
  vec3 e = txIrradiance[j].xyz;
  txTilted[2u * j] = vec4(e * dot(tau, u), 0.0);
  txTilted[2u * j + 1u] = vec4(e * dot(tau, v), 0.0);
}
