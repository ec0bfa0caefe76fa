#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// Splatting pass (src/techniques/splatting/splatting_technique.h): at each pixel x_o of the
// splatting buffer (the camera's G-buffer) that the splat of x_i covers, the term of Eq. 5,
//     sqrt(P_xo(d) P_xi(d)) E(x_i) ΔA(x_i),   d = |x_o − x_i| in [RMin, RMax),
// added into the level's target (additive blending).
#include "splatting/profile.glsl"

layout(binding = 0) uniform sampler2D GPosition;  // xyz world position, w = 1 + triangle (0: none)

flat in vec3 vXi;
flat in vec3 vPower;
flat in uint vTri;
flat in vec3 vBary;
flat in float vRMin;
flat in float vRMax;
layout(location = 0) out vec4 outB;

void main() {
  vec4 g = texelFetch(GPosition, ivec2(gl_FragCoord.xy), 0);
  if (g.w == 0.0) discard;
  float d = distance(g.xyz, vXi);
  if (d < vRMin || d >= vRMax) discard;
  uint to = uint(g.w - 1.0 + 0.5);
  PcSegment s = pcSegmentAt(d);
  vec3 ln = spLnProfile(vTri, vBary, s) + spLnProfile(to, spBarycentric(g.xyz, to), s);
  outB = vec4(exp(0.5 * ln) * vPower, 0.0);
}
