#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// Radiance of the splatting technique (src/techniques/splatting/splatting_technique.h): per pixel
// the accumulated exitance B (Eq. 5) and L = s Ft(η, n·ω_o) B / π (Eq. 7; as tsm/filter.comp).
layout(local_size_x = 8, local_size_y = 8) in;
#include "pointcloud/common.glsl"

layout(std430, binding = 7) buffer PcRadiance { vec4 pcRadiance[]; };  // rows from the top
layout(std430, binding = 8) buffer PcExitance { vec4 pcExitance[]; };

layout(binding = 0) uniform sampler2D GPosition;
layout(binding = 1) uniform sampler2D GNormal;
layout(binding = 2) uniform sampler2D Accumulated;  // rgb B

uniform uvec2 Size;
uniform float Eta;
uniform vec3 ExitScale;
uniform vec3 CameraPosition;
uniform vec3 CameraForward;
uniform bool Orthographic;

void main() {
  uvec2 px = gl_GlobalInvocationID.xy;
  if (px.x >= Size.x || px.y >= Size.y) return;
  uint out_ = (Size.y - 1u - px.y) * Size.x + px.x;
  vec4 g = texelFetch(GPosition, ivec2(px), 0);
  if (g.w == 0.0) {
    pcRadiance[out_] = vec4(0.0);
    pcExitance[out_] = vec4(0.0);
    return;
  }
  vec3 n = normalize(texelFetch(GNormal, ivec2(px), 0).xyz);
  vec3 b = texelFetch(Accumulated, ivec2(px), 0).rgb;
  vec3 v = Orthographic ? -CameraForward : normalize(CameraPosition - g.xyz);
  pcRadiance[out_] = vec4(ExitScale * (pcFresnelTransmittance(dot(n, v), Eta) * b / PC_PI), 1.0);
  pcExitance[out_] = vec4(b, 1.0);
}
