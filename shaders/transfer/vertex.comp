#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// The transfer technique's exitance per mesh vertex: the nodes' B interpolated with the
// precomputed weights (a partition of unity over the vertex's nearest nodes on its side of the
// surface; techniques/transfer/transfer_operator.h). One invocation per vertex.
layout(local_size_x = 64) in;
const uint TX_VERTEX_NODES = 8u;  // transfer::kVertexNodes
layout(std430, binding = 21) readonly buffer TxNodeExitance { vec4 txNodeExitance[]; };
layout(std430, binding = 22) readonly buffer TxVertexNodes { uint txVertexNode[]; };
layout(std430, binding = 23) readonly buffer TxVertexWeights { float txVertexWeight[]; };
layout(std430, binding = 24) writeonly buffer TxVertexExitance { vec4 txVertexExitance[]; };
uniform uint Vertices;
void main() {
  uint v = gl_GlobalInvocationID.x;
  if (v >= Vertices) return;
  vec3 sum = vec3(0.0);
  for (uint k = 0u; k < TX_VERTEX_NODES; ++k) {
    uint s = v * TX_VERTEX_NODES + k;
    sum += txVertexWeight[s] * txNodeExitance[txVertexNode[s]].xyz;
  }
  txVertexExitance[v] = vec4(sum, 1.0);
}
