#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// The transfer technique's image: per pixel of the G-buffer (position, w = 1 + the triangle
// index; normal), the exitance B interpolated from the triangle's vertices (barycentrics of the
// pixel's point, pcClampedBarycentric), then the radiance L = s Ft(η, n·ω_o) B / π with s the
// radiance convention's scale (as the point-cloud technique's radiance.comp).
layout(local_size_x = 8, local_size_y = 8) in;
#include "pointcloud/common.glsl"
#include "pointcloud/hetero.glsl"  // pcVertex, pcTriangle (bindings 12, 13), pcClampedBarycentric
layout(std430, binding = 24) readonly buffer TxVertexExitance { vec4 txVertexExitance[]; };
layout(std430, binding = 7) writeonly buffer TxRadiance { vec4 txRadiance[]; };  // rows from the top
layout(std430, binding = 8) writeonly buffer TxExitance { vec4 txExitance[]; };
layout(binding = 0) uniform sampler2D GPosition;  // xyz: world position; w: 1 + triangle, 0: empty
layout(binding = 1) uniform sampler2D GNormal;    // xyz: unit shading normal
uniform uvec2 Size;
uniform float Eta;
uniform vec3 ExitScale;
uniform vec3 CameraPosition;
uniform vec3 CameraForward;
uniform bool Orthographic;
void main() {
  uvec2 px = gl_GlobalInvocationID.xy;
  if (px.x >= Size.x || px.y >= Size.y) return;
  uint out_ = (Size.y - 1u - px.y) * Size.x + px.x;  // GL rows start at the bottom
  vec4 g = texelFetch(GPosition, ivec2(px), 0);
  if (g.w == 0.0) {
    txRadiance[out_] = vec4(0.0);
    txExitance[out_] = vec4(0.0);
    return;
  }
  vec3 x = g.xyz;
  uvec4 t = pcTriangle[uint(g.w + 0.5) - 1u];
  vec3 bc = pcClampedBarycentric(pcVertex[t.x].xyz, pcVertex[t.y].xyz, pcVertex[t.z].xyz, x);
  vec3 b = bc.x * txVertexExitance[t.x].xyz + bc.y * txVertexExitance[t.y].xyz +
           bc.z * txVertexExitance[t.z].xyz;
  vec3 n = normalize(texelFetch(GNormal, ivec2(px), 0).xyz);
  vec3 v = Orthographic ? -CameraForward : normalize(CameraPosition - x);
  vec3 l = ExitScale * (pcFresnelTransmittance(dot(n, v), Eta) * b / PC_PI);
  txRadiance[out_] = vec4(l, 1.0);
  txExitance[out_] = vec4(b, 1.0);
}
