#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// The empirical translucency shader's second pass (seed appendix C.2) per pixel: thickness from
// the two depth layers, with the depth-aware Gaussian smoothing of the back layer (Eq. C.1), then
// the lighting equation (Eq. 3.6). CPU reference: techniques/empirical/shading.h.
layout(local_size_x = 8, local_size_y = 8) in;
#include "empirical/depth.glsl"

layout(binding = 0) uniform sampler2D FrontDepth;     // window depth (1: background)
layout(binding = 1) uniform sampler2D BackDepth;      // window depth of the peeled layer
layout(binding = 2) uniform sampler2D FrontNormalAo;  // unit world normal, AO
layout(binding = 3) uniform sampler2D FrontPosition;  // world position
#ifdef EMP_VERTEX_COLOUR
// Heterogeneous material: K_d is scaled per pixel by the interpolated per-vertex factor
// Rd(local medium) / Rd(representative medium) (empirical_technique.h).
layout(binding = 4) uniform sampler2D FrontColour;
#endif
layout(rgba32f, binding = 0) writeonly uniform image2D OutColor;
// x: front distance, y: back distance (unsmoothed) [scene units], z: normalised thickness t
// (smoothed, unclamped), w: AO; all 0 on the background.
layout(rgba32f, binding = 1) writeonly uniform image2D OutDebug;

uniform ivec2 Size;
uniform mat4 Projection;
uniform float Diameter;      // of the scene's bounding sphere [scene units]
uniform int KernelRadius;    // (kernel size - 1) / 2; 0: no smoothing
uniform float Sigma;         // Gaussian σ [texels]
uniform float Threshold;     // Eq. C.1 deviation at which a weight reaches 0 [diameters]
uniform vec3 CameraPosition;
uniform vec3 CameraForward;
uniform bool Orthographic;
// Gascons 2011, A.1.1 (the fixed-function light model's controls, OpenGL 2.1 section 2.14.1):
uniform bool LocalViewer;     // V towards the camera per point; else -CameraForward
uniform float SpotCosCutoff;  // point lights: cos of the cutoff angle (-2: no spot)
uniform float SpotExponent;   // (cos of the angle from the spot axis)^SpotExponent
uniform vec3 SpotTarget;      // the spot axis runs from the light to this point (mesh centre)
const int kMaxLights = 4;
uniform int LightCount;
uniform bool LightIsPoint[kMaxLights];
uniform vec3 LightDirection[kMaxLights];  // directional: unit, towards the light; point: position
uniform vec3 LightValue[kMaxLights];      // I_d = I_s: colour × irradiance (point: × intensity,
                                          // divided by the squared distance here)
uniform vec3 Ia;              // ambient light: intensity × ambient colour
uniform vec3 SpecularColour;  // the lights' specular colour (× each light's value)
uniform bool DirectOnly;      // no back layer (not rendered this frame), no Eq. 3.10 term
uniform vec3 Kd;
uniform float Ka, Wd, Ws, Ks, Shininess, Wb, R, Kb;

bool covered(float windowDepth) { return windowDepth < 1.0; }

void main() {
  const ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(p, Size))) return;
  const float zf = texelFetch(FrontDepth, p, 0).x;
  if (!covered(zf)) {
    imageStore(OutColor, p, vec4(0.0));
    imageStore(OutDebug, p, vec4(0.0));
    return;
  }
  const float front = eyeDistance(zf, Projection);
  // Direct light only: the back layer was not rendered this frame; no thickness is read.
  const float zb = DirectOnly ? 1.0 : texelFetch(BackDepth, p, 0).x;
  float back = front;  // no second layer (an open mesh): zero thickness... see below
  float t = 1.0;       // ... treated as opaque: no backlight
  float rawBack = 0.0;
  if (covered(zb)) {
    rawBack = eyeDistance(zb, Projection);
    // Eq. C.1 on the back distance in diameters: background texels skipped, weights falling
    // linearly to 0 at a deviation of Threshold.
    const float centre = rawBack / Diameter;
    float sum = 0.0, weight = 0.0;
    for (int dy = -KernelRadius; dy <= KernelRadius; ++dy)
      for (int dx = -KernelRadius; dx <= KernelRadius; ++dx) {
        const ivec2 q = p + ivec2(dx, dy);
        if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, Size))) continue;
        const float zq = texelFetch(BackDepth, q, 0).x;
        if (!covered(zq)) continue;
        const float b = eyeDistance(zq, Projection) / Diameter;
        const float w = exp(-float(dx * dx + dy * dy) / (2.0 * Sigma * Sigma)) *
                        (1.0 - clamp(abs(b - centre) / Threshold, 0.0, 1.0));
        sum += w * b;
        weight += w;
      }
    back = sum / weight * Diameter;
    t = (back - front) / Diameter;
  }
  const vec4 na = texelFetch(FrontNormalAo, p, 0);
  const vec3 N = normalize(na.xyz);
  const float ao = na.w;
  const vec3 position = texelFetch(FrontPosition, p, 0).xyz;
  const vec3 V = Orthographic || !LocalViewer ? -CameraForward : normalize(CameraPosition - position);

#ifdef EMP_VERTEX_COLOUR
  const vec3 kd = Kd * texelFetch(FrontColour, p, 0).rgb;
#else
  const vec3 kd = Kd;
#endif
  vec3 color = ao * Ka * kd * Ia;  // Eq. 3.7
  for (int i = 0; i < LightCount; ++i) {
    vec3 L = LightDirection[i];
    vec3 I = LightValue[i];
    if (LightIsPoint[i]) {
      const vec3 d = LightDirection[i] - position;
      L = normalize(d);
      I /= dot(d, d);
      if (SpotCosCutoff > -1.5) {  // a spotlight aimed at the mesh's centre
        const float c = dot(-L, normalize(SpotTarget - LightDirection[i]));
        // (pow(0, 0) is undefined in GLSL: an exponent of 0 is a factor of 1 inside the cone.)
        I *= c >= SpotCosCutoff ? (SpotExponent > 0.0 ? pow(max(c, 0.0), SpotExponent) : 1.0) : 0.0;
      }
    }
    const float NdotL = max(dot(N, L), 0.0);
    if (NdotL > 0.0) {  // as computeLight (C.2.3)
      color += Wd * kd * I * NdotL;  // Eq. 3.8
      const float NdotH = max(dot(N, normalize(L + V)), 0.0);
      color += Ws * Ks * (SpecularColour * I) * pow(NdotH, Shininess);  // Eq. 3.9
    }
  }
  if (!DirectOnly) color += Wb * pow(1.0 - clamp(t, 0.0, 1.0), R) * (kd + vec3(Kb));  // Eq. 3.10
  imageStore(OutColor, p, vec4(color, 1.0));
  imageStore(OutDebug, p, vec4(front, rawBack, t, ao));
}
