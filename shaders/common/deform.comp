#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// The GPU mesh's deformation (techniques::GpuMesh::deform): every vertex of the rest pose (its
// position and smooth normal, kept in a buffer of their own) through the chain of deformations
// at this time, written into the vertex buffer that the techniques draw. Normals transform with
// the inverse transpose of each step's Jacobian, as geometry::deformPointNormal does.
layout(local_size_x = 64) in;
#include "common/compute.glsl"
#include "common/deform.glsl"

// Interleaved floats, `Stride` per vertex: position (3), normal (3), [a scalar], the same layout
// in both buffers (the rest buffer is a copy of the vertex buffer as first uploaded).
layout(std430, binding = 0) readonly buffer DeformRest { float rest[]; };
layout(std430, binding = 1) buffer DeformVertices { float vertices[]; };

const int kMaxDeformations = 8;  // geometry::kMaxDeformations
uniform uint VertexCount;
uniform uint Stride;
uniform int DeformCount;
uniform vec4 DeformA[kMaxDeformations];  // origin, type
uniform vec4 DeformB[kMaxDeformations];  // axis, magnitude
uniform vec4 DeformC[kMaxDeformations];  // direction, wavelength

void main() {
  uint i = linearInvocationIndex();
  if (i >= VertexCount) return;
  uint base = i * Stride;
  vec3 p = vec3(rest[base], rest[base + 1u], rest[base + 2u]);
  vec3 n = vec3(rest[base + 3u], rest[base + 4u], rest[base + 5u]);
  for (int k = 0; k < DeformCount; ++k) {
    if (DeformB[k].w == 0.0) continue;  // the identity, as on the CPU
    mat3 j = deformJacobian(DeformA[k], DeformB[k], DeformC[k], p);
    n = normalize(transpose(inverse(j)) * n);
    p = deformPoint(DeformA[k], DeformB[k], DeformC[k], p);
  }
  vertices[base] = p.x;
  vertices[base + 1u] = p.y;
  vertices[base + 2u] = p.z;
  vertices[base + 3u] = n.x;
  vertices[base + 4u] = n.y;
  vertices[base + 5u] = n.z;
}
