#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// The transfer technique's exitance per node (techniques/transfer/transfer_operator.h):
//     B_i = Σ_j K_c[i][j] E_j     per channel c,
// K the path-traced transfer matrix (node areas folded in), E_j the irradiance transmitted into
// the medium at node j (techniques/common/surface_irradiance.h). One invocation per node.
layout(local_size_x = 64) in;
layout(std430, binding = 3) readonly buffer TxIrradiance { vec4 txIrradiance[]; };
// One buffer per channel (a driver's largest storage buffer may not hold all three): K_c[i N + j].
layout(std430, binding = 20) readonly buffer TxMatrixR { float txMatrixR[]; };
layout(std430, binding = 25) readonly buffer TxMatrixG { float txMatrixG[]; };
layout(std430, binding = 26) readonly buffer TxMatrixB { float txMatrixB[]; };
layout(std430, binding = 21) writeonly buffer TxNodeExitance { vec4 txNodeExitance[]; };
uniform uint Nodes;
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= Nodes) return;
  uint row = i * Nodes;
  vec3 sum = vec3(0.0);
  for (uint j = 0u; j < Nodes; ++j) {
    vec3 e = txIrradiance[j].xyz;
    sum += vec3(txMatrixR[row + j] * e.x, txMatrixG[row + j] * e.y, txMatrixB[row + j] * e.z);
  }
  txNodeExitance[i] = vec4(sum, 1.0);
}
