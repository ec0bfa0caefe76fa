#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// Writes the interpolated world position (w = 1 marks covered pixels) and normal.
in vec3 vPosition;
in vec3 vNormal;
layout(location = 0) out vec4 outPosition;
layout(location = 1) out vec4 outNormal;
void main() {
#ifdef PC_HETERO
  // Heterogeneous material: w = 1 + the triangle index (exact in float below 2^24 triangles),
  // for the shading point's profile (hetero.glsl).
  outPosition = vec4(vPosition, 1.0 + float(gl_PrimitiveID));
#else
  outPosition = vec4(vPosition, 1.0);
#endif
  vec3 n = normalize(vNormal);
  // A back face seen through a silhouette gap: turn its normal towards the viewer's side.
  outNormal = vec4(gl_FrontFacing ? n : -n, 0.0);
}
