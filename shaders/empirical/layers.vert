#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// The empirical technique's depth layers: world position, normal and per-vertex AO.
layout(location = 0) in vec3 Position;  // world space [scene units]
layout(location = 1) in vec3 Normal;    // unit, outward
layout(location = 2) in float Ao;       // ambient occlusion a of Eq. 3.6, in [0, 1]
uniform mat4 ViewProjection;            // world -> camera clip space
out vec3 vPosition;
out vec3 vNormal;
out float vAo;
#ifdef EMP_VERTEX_COLOUR
// Heterogeneous material: the per-vertex colour factor (empirical_technique.h), indexed by the
// vertex index of the indexed draw.
layout(std430, binding = 0) readonly buffer EmpVertexColour { vec4 empVertexColour[]; };
out vec3 vColour;
#endif
void main() {
#ifdef EMP_VERTEX_COLOUR
  vColour = empVertexColour[gl_VertexID].rgb;
#endif
  vPosition = Position;
  vNormal = Normal;
  vAo = Ao;
  gl_Position = ViewProjection * vec4(Position, 1.0);
}
