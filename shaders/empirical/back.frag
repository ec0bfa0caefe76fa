#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// Second depth layer by depth peeling (seed appendix B, steps 1-3): fragments at or in front of
// the first layer (plus ε) are discarded, so the depth test keeps the nearest surface *behind*
// it: the far side of the first solid span, also for non-convex meshes.
#include "empirical/depth.glsl"
layout(binding = 0) uniform sampler2D FrontDepth;  // window depth of the first layer
uniform mat4 Projection;
uniform float PeelEpsilon;  // [scene units]
void main() {
  const float front = texelFetch(FrontDepth, ivec2(gl_FragCoord.xy), 0).x;
  // ε in eye space rather than window depth: the same margin for any projection and depth range.
  if (eyeDistance(gl_FragCoord.z, Projection) <= eyeDistance(front, Projection) + PeelEpsilon)
    discard;
}
