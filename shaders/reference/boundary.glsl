// SPDX-License-Identifier: GPL-3.0-or-later
// The refractive boundary of the GPU mesh walks (mesh_walk.comp, camera_walk.comp): Snell
// refraction and the flight in air from an exit to the re-entry (transport_impl.h: refract,
// reenter). The includer provides the uniforms Matched (η = 1), Eta (n_inside / n_outside) and
// Epsilon, uniformFloat(), WALK_WORK() and kInf, after bvh.glsl and walk_math.glsl.
#pragma once

vec3 refractDir(vec3 d, vec3 n, float ratio, float cosT) {  // transport_impl.h: refract
  return normalize(ratio * d + (cosT - ratio * dot(d, n)) * n);
}

// The flight in air after an exit at x along d (transport_impl.h: reenter): at every hit of the
// body's outside a mirror reflection with probability F, else refraction in. True with x, d the
// re-entry point and the inward direction, false when it escapes; `mirrored` set when it was
// reflected on the way.
bool reenter(inout dvec3 x, inout vec3 d, inout bool mirrored) {
  for (;;) {
    WALK_WORK();
    float t;
    vec3 n;
    uint tri;
    if (!bvhIntersect(vec3(x), d, Epsilon, kInf, t, n, tri)) return false;
    x += double(t) * dvec3(d);
    if (Matched) return true;
    const vec3 inward = dot(n, d) > 0.0 ? n : -n;
    const float cosI = dot(d, inward);
    const float F = fresnelReflectanceFloat(max(cosI, 0.0), Eta);
    if (uniformFloat() < F) {
      d = normalize(d - 2.0 * cosI * inward);
      mirrored = true;
      continue;
    }
    d = refractDir(d, inward, 1.0 / Eta, refractedCosineFloat(max(cosI, 0.0), Eta));
    return true;
  }
}
