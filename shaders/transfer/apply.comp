#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// The transfer technique's exitance per node (techniques/transfer/transfer_operator.h):
//     B_i = Σ_j K⁰_c[i][j] E_j + K^u_c[i][j] E^u_j + K^v_c[i][j] E^v_j     per channel c,
// K the path-traced transfer matrices (node areas folded in), E_j the irradiance transmitted into
// the medium over node j's cell, E^u, E^v its first-order inputs (cells.comp; E^u, E^v only with
// TX_FIRST_ORDER). One invocation per node.
layout(local_size_x = 64) in;
layout(std430, binding = 29) readonly buffer TxNodeIrradiance { vec4 txNodeIrradiance[]; };
#ifdef TX_FIRST_ORDER
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
  for (uint m = 0u; m < TX_MATRICES; ++m) {
    uint row = (m * Nodes + i) * Nodes;
    for (uint j = 0u; j < Nodes; ++j) {
      vec3 e = m == 0u ? txNodeIrradiance[j].xyz :
#ifdef TX_FIRST_ORDER
                         txTilted[2u * j + m - 1u].xyz;
#else
                         vec3(0.0);
#endif
      sum += vec3(txMatrixR[row + j] * e.x, txMatrixG[row + j] * e.y, txMatrixB[row + j] * e.z);
    }
  }
  txNodeExitance[i] = vec4(sum, 1.0);
}
