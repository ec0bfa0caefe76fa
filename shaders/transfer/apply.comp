#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// The transfer technique's exitance per node (techniques/transfer/transfer_operator.h):
//     B_i = Σ_j K⁰_c[i][j] E_j + K^u_c[i][j] E^u_j + K^v_c[i][j] E^v_j     per channel c,
// K the path-traced transfer matrices (node areas folded in), E_j the irradiance transmitted into
// the medium over node j's cell, E^u, E^v its first-order inputs (cells.comp; E^u, E^v only with
// TX_FIRST_ORDER). With TX_SECANT the matrices are the beams' own (K⁰, K(+u), K(-u), K(+v),
// K(-v)) and each column j is interpolated towards the beam on the side of its light's tilt
// t = (E^u, E^v) / (E τ0): K⁰ (1 - |t_u| - |t_v|) + K(±u) |t_u| + K(±v) |t_v|, t scaled down to
// |t_u| + |t_v| = 1 where it exceeds it (transfer_operator.h, "secant"). One invocation per node.
layout(local_size_x = 64) in;
layout(std430, binding = 29) readonly buffer TxNodeIrradiance { vec4 txNodeIrradiance[]; };
#ifdef TX_SECANT
layout(std430, binding = 28) readonly buffer TxTilted { vec4 txTilted[]; };  // E^u, E^v per node
const uint TX_MATRICES = 5u;
uniform float Tilt;  // transfer::kTilt, τ0
#elif defined(TX_FIRST_ORDER)
layout(std430, binding = 28) readonly buffer TxTilted { vec4 txTilted[]; };  // E^u, E^v per node
const uint TX_MATRICES = 3u;
#else
const uint TX_MATRICES = 1u;
#endif
// One buffer per channel (a driver's largest storage buffer may not hold all three), each with
// its matrices one after the other: K^m_c[(m N + i) N + j].
layout(std430, binding = 20) readonly buffer TxMatrixR { float txMatrixR[]; };
layout(std430, binding = 25) readonly buffer TxMatrixG { float txMatrixG[]; };
layout(std430, binding = 26) readonly buffer TxMatrixB { float txMatrixB[]; };
layout(std430, binding = 21) writeonly buffer TxNodeExitance { vec4 txNodeExitance[]; };
uniform uint Nodes;
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= Nodes) return;
  vec3 sum = vec3(0.0);
#ifdef TX_SECANT
  uint N2 = Nodes * Nodes;
  for (uint j = 0u; j < Nodes; ++j) {
    vec3 e = txNodeIrradiance[j].xyz;
    // An unlit node (in the body's shadow) adds nothing: skip its column (every invocation
    // takes the same branch, so the whole group skips it).
    if (e == vec3(0.0)) continue;
    vec3 eu = txTilted[2u * j].xyz, ev = txTilted[2u * j + 1u].xyz;
    uint mu = (eu.x + eu.y + eu.z) >= 0.0 ? 1u : 2u;
    uint mv = (ev.x + ev.y + ev.z) >= 0.0 ? 3u : 4u;
    vec3 wu = abs(eu) / Tilt, wv = abs(ev) / Tilt;
    // Beyond the tilted beams (|t_u| + |t_v| > 1, light steeper than they came in) the tilt is
    // clamped to them rather than extrapolated: the weights stay convex.
    float t = (wu.x + wu.y + wu.z + wv.x + wv.y + wv.z) / (e.x + e.y + e.z);
    if (t > 1.0) {
      wu /= t;
      wv /= t;
    }
    vec3 w0 = e - wu - wv;
    uint r0 = i * Nodes + j, ru = mu * N2 + r0, rv = mv * N2 + r0;
    sum += vec3(txMatrixR[r0], txMatrixG[r0], txMatrixB[r0]) * w0 +
           vec3(txMatrixR[ru], txMatrixG[ru], txMatrixB[ru]) * wu +
           vec3(txMatrixR[rv], txMatrixG[rv], txMatrixB[rv]) * wv;
  }
#else
  for (uint m = 0u; m < TX_MATRICES; ++m) {
    uint row = (m * Nodes + i) * Nodes;
    for (uint j = 0u; j < Nodes; ++j) {
      if (txNodeIrradiance[j].xyz == vec3(0.0)) continue;  // unlit: adds nothing
      vec3 e = m == 0u ? txNodeIrradiance[j].xyz :
#ifdef TX_FIRST_ORDER
                         txTilted[2u * j + m - 1u].xyz;
#else
                         vec3(0.0);
#endif
      sum += vec3(txMatrixR[row + j] * e.x, txMatrixG[row + j] * e.y, txMatrixB[row + j] * e.z);
    }
  }
#endif
  txNodeExitance[i] = vec4(sum, 1.0);
}
