#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// The transfer technique's exitance per node (techniques/transfer/transfer_operator.h):
//     B_i = Σ_j K_c[i][j] E_j     per channel c,
// K the path-traced transfer matrix (node areas folded in), E_j the irradiance transmitted into
// the medium at node j (techniques/common/surface_irradiance.h). One invocation per node.
layout(local_size_x = 64) in;
layout(std430, binding = 3) readonly buffer TxIrradiance { vec4 txIrradiance[]; };
layout(std430, binding = 20) readonly buffer TxMatrix { float txMatrix[]; };  // [(c N + i) N + j]
layout(std430, binding = 21) writeonly buffer TxNodeExitance { vec4 txNodeExitance[]; };
uniform uint Nodes;
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= Nodes) return;
  uint r = i * Nodes, g = (Nodes + i) * Nodes, b = (2u * Nodes + i) * Nodes;
  vec3 sum = vec3(0.0);
  for (uint j = 0u; j < Nodes; ++j) {
    vec3 e = txIrradiance[j].xyz;
    sum += vec3(txMatrix[r + j] * e.x, txMatrix[g + j] * e.y, txMatrix[b + j] * e.z);
  }
  txNodeExitance[i] = vec4(sum, 1.0);
}
