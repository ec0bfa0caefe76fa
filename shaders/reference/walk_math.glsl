// SPDX-License-Identifier: GPL-3.0-or-later
// The photon walker's float arithmetic in GLSL: the same formulas as src/reference/fastmath.h
// and phase.h (random bits to floats, -log ξ, the uniform azimuth, Henyey-Greenstein sampling,
// the direction update, Fresnel), so that the GPU walk is the CPU lane walker's event for event.
// The polynomials rather than GLSL's log/sin/cos: the built-ins' accuracy is the driver's
// (GLSL 4.50 §4.7.1 only bounds sin/cos to 2^-11 absolute), these are float-accurate everywhere.
#pragma once

// Upper 24 bits -> [0, 1) and (0, 1] on the grid k 2^-24.
float unitFromBits(uint bits) { return float(bits >> 8) * (1.0 / 16777216.0); }
float unitOpenZeroFromBits(uint bits) { return float((bits >> 8) + 1u) * (1.0 / 16777216.0); }

// Natural logarithm of a positive normal float (Cephes logf, fastmath.h).
float fastLog(float x) {
  const uint bits = floatBitsToUint(x);
  int e = int((bits >> 23) & 0xFFu) - 127;
  float m = uintBitsToFloat((bits & 0x007FFFFFu) | 0x3F800000u);
  const bool big = m > 1.41421356;
  m = big ? 0.5 * m : m;
  e = big ? e + 1 : e;
  const float f = m - 1.0;
  const float z = f * f;
  float y = 7.0376836292e-2;
  y = y * f - 1.1514610310e-1;
  y = y * f + 1.1676998740e-1;
  y = y * f - 1.2420140846e-1;
  y = y * f + 1.4249322787e-1;
  y = y * f - 1.6668057665e-1;
  y = y * f + 2.0000714765e-1;
  y = y * f - 2.4999993993e-1;
  y = y * f + 3.3333331174e-1;
  y = y * f * z;
  const float ef = float(e);
  y += -2.12194440e-4 * ef;
  y += -0.5 * z;
  return f + y + 0.693359375 * ef;
}

// (cos φ, sin φ) of a uniform azimuth from 32 bits: quadrant from the top two bits, an offset in
// [-π/4, π/4) from the next 22, Cephes polynomials (fastmath.h: uniformAzimuth).
vec2 uniformAzimuth(uint bits) {
  const float u = float((bits >> 8) & 0x3FFFFFu) * (1.0 / 4194304.0);
  const float b = (u - 0.5) * 1.57079632679;
  const float b2 = b * b;
  const float sb = b + b * b2 * (-1.6666654611e-1 + b2 * (8.3321608736e-3 + b2 * -1.9515295891e-4));
  const float cb = 1.0 - 0.5 * b2 +
                   b2 * b2 * (4.166664568298827e-2 + b2 * (-1.388731625493765e-3 + b2 * 2.443315711809948e-5));
  const uint k = bits >> 30;
  vec2 cs = (k & 1u) != 0u ? vec2(-sb, cb) : vec2(cb, sb);
  return (k & 2u) != 0u ? -cs : cs;
}

// Inverse-CDF Henyey-Greenstein cosine (phase.h: the cancellation-free form for |g| < 1/2).
float sampleHgCosine(float g, float xi) {
  const float s = 2.0 * xi - 1.0;
  float mu;
  if (abs(g) < 0.5) {
    const float q = 1.0 + g * s;
    mu = (s + 0.5 * g * (3.0 + s * s + 2.0 * g * s + g * g * (s * s - 1.0))) / (q * q);
  } else {
    const float t = (1.0 - g * g) / (1.0 + g * s);
    mu = (1.0 + g * g - t * t) * (0.5 / g);
  }
  return clamp(mu, -1.0, 1.0);
}

// The direction at cosine mu and azimuth cs about d, in the frame of Duff et al. 2017, with one
// Newton step of renormalisation (phase.h: scatterDirection).
vec3 scatterDirection(vec3 d, float mu, vec2 cs) {
  const float sgn = d.z >= 0.0 ? 1.0 : -1.0;
  const float a = -1.0 / (sgn + d.z);
  const float b = d.x * d.y * a;
  const vec3 t1 = vec3(1.0 + sgn * d.x * d.x * a, sgn * b, -sgn * d.x);
  const vec3 t2 = vec3(b, sgn + d.y * d.y * a, -d.y);
  const float sinTheta = sqrt(max(1.0 - mu * mu, 0.0));
  const vec3 o = sinTheta * cs.x * t1 + sinTheta * cs.y * t2 + mu * d;
  return o * (1.5 - 0.5 * dot(o, o));
}

// Unpolarised Fresnel reflectance for cos_i > 0 and eta = n_out / n_in (fastmath.h:
// fresnelReflectanceFloat); 1 under total internal reflection.
float fresnelReflectanceFloat(float cosI, float eta) {
  const float ci = min(cosI, 1.0);
  const float cos2t = (ci * ci + (eta * eta - 1.0)) / (eta * eta);
  const float ct = sqrt(max(cos2t, 0.0));
  const float a = ci - eta * ct, b = ci + eta * ct;
  const float c = eta * ci - ct, e = eta * ci + ct;
  const float r = 0.5 * (a * a * e * e + c * c * b * b) / (b * b * e * e);
  return cos2t > 0.0 ? r : 1.0;
}

// Cosine of the transmitted direction (Snell), for a crossing that is not totally reflected.
float refractedCosineFloat(float cosI, float eta) {
  const float ci = min(cosI, 1.0);
  return sqrt(max((ci * ci + (eta * eta - 1.0)) / (eta * eta), 0.0));
}

// Unpolarised Fresnel reflectance in double, cos_i > 0, eta = n_transmitted / n_incident
// (optics/fresnel.h): the entry weights, which the flux statistics carry.
double fresnelReflectanceDouble(double ci, double eta) {
  const double cos2t = (ci * ci + (eta * eta - 1.0lf)) / (eta * eta);
  if (cos2t <= 0.0lf) return 1.0lf;
  const double ct = sqrt(cos2t);
  const double rs = (ci - eta * ct) / (ci + eta * ct);
  const double rp = (eta * ci - ct) / (eta * ci + ct);
  return 0.5lf * (rs * rs + rp * rp);
}
