#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// First depth layer (seed appendix B, first pass): the nearest surface, with its normal and AO.
in vec3 vPosition;
in vec3 vNormal;
in float vAo;
layout(location = 0) out vec4 outNormalAo;  // xyz: unit world normal facing the viewer; w: AO
layout(location = 1) out vec4 outPosition;  // xyz: world position; w = 1 where covered
#ifdef EMP_VERTEX_COLOUR
in vec3 vColour;
layout(location = 2) out vec4 outColour;  // rgb: the interpolated per-vertex colour factor
#endif
void main() {
  vec3 n = normalize(vNormal);
  outNormalAo = vec4(gl_FrontFacing ? n : -n, vAo);
  outPosition = vec4(vPosition, 1.0);
#ifdef EMP_VERTEX_COLOUR
  outColour = vec4(vColour, 1.0);
#endif
}
