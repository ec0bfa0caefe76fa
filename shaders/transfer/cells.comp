#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// The transfer technique's inputs per node (techniques/transfer/transfer_operator.h): the mean
// E_j of the irradiance at the kCellSamples points of node j's cell (the irradiance pass ran on
// those points), and with TX_FIRST_ORDER the first-order inputs E^u = E (τ·u), E^v = E (τ·v),
// τ the tangential part of the refracted direction of the light that lit the cell. From the
// irradiance pass's light directions (surface_irradiance.h: per point Σ_l w_l ω_l and Σ_l w_l over
// the directional, filtered, beam and point lights; ω_l towards the light), summed over the
// cell: light travels along -ω_l, whose tangential part keeps its direction and shrinks by 1/η on
// refraction (Snell), so
//     τ = -(m - (m·n) n) / (η W),   m = Σ w_l ω_l,  W = Σ w_l,
// with v = n × u. Environment light carries no direction (W = 0 where it alone lit the cell:
// τ = 0, normal incidence). One invocation per node.
layout(local_size_x = 64) in;
const uint TX_CELL_SAMPLES = 16u;  // transfer::kCellSamples
layout(std430, binding = 3) readonly buffer TxIrradiance { vec4 txIrradiance[]; };  // per sample
layout(std430, binding = 14) readonly buffer TxLightDir { vec4 txLightDir[]; };     // per sample
layout(std430, binding = 27) readonly buffer TxFrames { vec4 txFrame[]; };  // per node: n, u
layout(std430, binding = 29) writeonly buffer TxNodeIrradiance { vec4 txNodeIrradiance[]; };
layout(std430, binding = 28) writeonly buffer TxTilted { vec4 txTilted[]; };  // per node: E^u, E^v
uniform uint Nodes;
uniform float Eta;
void main() {
  uint j = gl_GlobalInvocationID.x;
  if (j >= Nodes) return;
  vec3 e = vec3(0.0);
  vec4 m = vec4(0.0);
  for (uint s = 0u; s < TX_CELL_SAMPLES; ++s) {
    e += txIrradiance[j * TX_CELL_SAMPLES + s].xyz;
    m += txLightDir[j * TX_CELL_SAMPLES + s];
  }
  e /= float(TX_CELL_SAMPLES);
  txNodeIrradiance[j] = vec4(e, 0.0);
#ifdef TX_FIRST_ORDER
  vec3 n = txFrame[2u * j].xyz;
  vec3 u = txFrame[2u * j + 1u].xyz;
  vec3 v = cross(n, u);
  vec3 tau = m.w > 0.0 ? -(m.xyz - dot(m.xyz, n) * n) / (Eta * m.w) : vec3(0.0);
  txTilted[2u * j] = vec4(e * dot(tau, u), 0.0);
  txTilted[2u * j + 1u] = vec4(e * dot(tau, v), 0.0);
#endif
}
