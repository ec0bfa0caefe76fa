// SPDX-License-Identifier: GPL-3.0-or-later
// The camera geometry shared by the lss passes (shaders/lss/): the ray through a point of the
// image plane, and the surface area that an image-plane area stands for.
// Prefix: ls (local subsurface scattering). Image-plane coordinates u are in pixels, (0, 0) the
// lower left corner of the G-buffer (its row 0), pixel p's centre at p + ½.
#pragma once

uniform mat4 InverseViewProjection;  // camera clip space -> world
uniform uvec2 Size;                  // pixels
uniform vec3 CameraPosition;
uniform vec3 CameraForward;          // unit
uniform bool Orthographic;
// World size of a pixel: orthographic, view_height / height [scene units]; pinhole,
// 2 tan(fov/2) / height per unit depth along CameraForward.
uniform float PixelScale;
// Floor of |n·ω| in the area of a pixel (grazing pixels: the area per pixel diverges at the
// silhouette, where LSS cannot see the surface anyway).
const float LS_MIN_COS = 0.05;

// The camera ray through image-plane point u: origin on the near plane, unit direction.
void lsRay(vec2 u, out vec3 origin, out vec3 dir) {
  vec2 ndc = 2.0 * u / vec2(Size) - 1.0;
  vec4 a = InverseViewProjection * vec4(ndc, -1.0, 1.0);
  vec4 b = InverseViewProjection * vec4(ndc, 1.0, 1.0);
  origin = a.xyz / a.w;
  dir = normalize(b.xyz / b.w - origin);
}

// World size of a pixel at x (orthographic: everywhere the same; pinhole: grows with the depth).
float lsPixelSize(vec3 x) {
  return Orthographic ? PixelScale : PixelScale * dot(x - CameraPosition, CameraForward);
}

// dA/du: the surface area [scene units²] per pixel² of the image plane at surface point x with
// normal n seen along the ray direction `dir`. The pixel's footprint perpendicular to the axis
// at x's depth z is (s z)² (s: PixelScale; orthographic: s²), perpendicular to the ray (s z)² cosθ
// (θ the angle between the ray and the axis), on the surface (s z)² cosθ / |n·ω|: the
// foreshortening 1/|n·ω| and, for a pinhole camera, the depth² of the perspective (for a pinhole
// dω = s² cos³θ du and dA = ρ² dω / |n·ω| with ρ = z / cosθ give the same).
float lsAreaPerPixel(vec3 x, vec3 n, vec3 dir) {
  float s = lsPixelSize(x);
  float cosTheta = Orthographic ? 1.0 : dot(dir, CameraForward);
  return s * s * cosTheta / max(abs(dot(n, dir)), LS_MIN_COS);
}
