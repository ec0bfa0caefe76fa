#version 450 core
// Stage 3 of texture-space importance sampling (seed 3.2.2 "Evaluation of the translucency"):
// per pixel of the G-buffer, the exitance of Eq. 3.5 over the frame's N samples,
//     B(x_o) = 1/N Σ_i w_i R(|x_i − x_o|),   w_i = E(x_i) a_i / P(t_i)  (sample.comp),
// R the model's tabulated radial profile (pointcloud/kernel_table.glsl), then the radiance of
// Eq. 3.6, L = s Ft(η, n·ω_o) B / π, with s = ExitScale the exit-radiance convention (seed
// Eq. 2.16, bssrdf/exit_radiance.h), as the point-cloud technique. With Accumulate the frames'
// B are summed (TsAccum) and the output is their mean over FrameIndex + 1 frames.
layout(local_size_x = 8, local_size_y = 8) in;
#include "pointcloud/common.glsl"
#include "pointcloud/kernel_table.glsl"

layout(std430, binding = 11) readonly buffer TsSamples { vec4 tsSample[]; };
layout(std430, binding = 7) writeonly buffer PcRadiance { vec4 pcRadiance[]; };  // rows from the top
layout(std430, binding = 8) writeonly buffer PcExitance { vec4 pcExitance[]; };
layout(std430, binding = 12) buffer TsAccum { vec4 tsAccum[]; };

layout(binding = 0) uniform sampler2D GPosition;  // xyz: world position; w: 1 where covered
layout(binding = 1) uniform sampler2D GNormal;    // xyz: unit shading normal

uniform uvec2 Size;
uniform uint SampleCount;
uniform float Eta;
uniform vec3 ExitScale;
uniform vec3 CameraPosition;
uniform vec3 CameraForward;
uniform bool Orthographic;
uniform bool Accumulate;
uniform uint FrameIndex;  // frames accumulated before this one

void main() {
  uvec2 px = gl_GlobalInvocationID.xy;
  if (px.x >= Size.x || px.y >= Size.y) return;
  uint out_ = (Size.y - 1u - px.y) * Size.x + px.x;
  vec4 g = texelFetch(GPosition, ivec2(px), 0);
  if (g.w == 0.0) {
    pcRadiance[out_] = vec4(0.0);
    pcExitance[out_] = vec4(0.0);
    if (Accumulate) tsAccum[out_] = vec4(0.0);
    return;
  }
  vec3 x = g.xyz;
  vec3 n = normalize(texelFetch(GNormal, ivec2(px), 0).xyz);
  vec3 b = vec3(0.0);
  for (uint i = 0u; i < SampleCount; ++i)
    b += tsSample[2u * i + 1u].rgb * pcKernel(x, n, tsSample[2u * i].xyz, n);
  b /= float(SampleCount);
  if (Accumulate) {
    vec3 sum = (FrameIndex == 0u ? vec3(0.0) : tsAccum[out_].rgb) + b;
    tsAccum[out_] = vec4(sum, 1.0);
    b = sum / float(FrameIndex + 1u);
  }
  vec3 v = Orthographic ? -CameraForward : normalize(CameraPosition - x);
  vec3 l = ExitScale * (pcFresnelTransmittance(dot(n, v), Eta) * b / PC_PI);
  pcRadiance[out_] = vec4(l, 1.0);
  pcExitance[out_] = vec4(b, 1.0);
}
