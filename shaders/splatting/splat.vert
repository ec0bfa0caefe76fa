#version 450 core
// Splatting pass (src/techniques/splatting/splatting_technique.h): one instance per irradiance
// texel x_i, drawn as a screen-space square (4 vertices, a triangle strip) bounding the sphere of
// radius SplatRadius about x_i; texels without a surface or without irradiance are moved outside
// the clip volume.
#include "common/light_view_map.glsl"
#include "splatting/profile.glsl"

uniform mat4 ViewProjection;  // world -> camera clip space
uniform int MapSize;          // irradiance buffer texels per side
uniform float SplatRadius;    // R_max of the splat [scene units]
uniform vec2 PixelSize;       // 2 / (width, height): one pixel in NDC

flat out vec3 vXi;
flat out vec3 vPower;  // E(x_i) ΔA(x_i)
flat out uint vTri;
flat out vec3 vBary;

void main() {
  ivec2 t = ivec2(gl_InstanceID % MapSize, gl_InstanceID / MapSize);
  vec4 p = texelFetch(LvmPosition, t, 0);
  vec4 n = texelFetch(LvmNormal, t, 0);
  vec3 e = texelFetch(LvmIrradiance, t, 0).rgb;
  if (p.w == 0.0 || all(lessThanEqual(e, vec3(0.0)))) {
    gl_Position = vec4(2.0, 2.0, 2.0, 1.0);  // outside the clip volume: nothing drawn
    return;
  }
  vXi = p.xyz;
  vTri = uint(p.w - 1.0 + 0.5);
  vBary = spBarycentric(p.xyz, vTri);
  float areaUv = 1.0 / float(MapSize * MapSize);
  vPower = e * lvmSurfaceArea(p.xyz, n.w, areaUv);
  // The screen-space bounds of the cube around the sphere (its projection holds the sphere's);
  // the whole screen when a corner lies behind the camera.
  vec2 lo = vec2(1e30), hi = vec2(-1e30);
  bool behind = false;
  for (int c = 0; c < 8; ++c) {
    vec3 o = vec3((c & 1) != 0 ? 1.0 : -1.0, (c & 2) != 0 ? 1.0 : -1.0, (c & 4) != 0 ? 1.0 : -1.0);
    vec4 q = ViewProjection * vec4(p.xyz + SplatRadius * o, 1.0);
    if (q.w <= 1e-6) { behind = true; break; }
    lo = min(lo, q.xy / q.w);
    hi = max(hi, q.xy / q.w);
  }
  if (behind) {
    lo = vec2(-1.0);
    hi = vec2(1.0);
  }
  lo = max(lo - PixelSize, vec2(-1.0));
  hi = min(hi + PixelSize, vec2(1.0));
  vec2 corner = vec2(float(gl_VertexID & 1), float((gl_VertexID >> 1) & 1));
  gl_Position = vec4(mix(lo, hi, corner), 0.0, 1.0);
}
