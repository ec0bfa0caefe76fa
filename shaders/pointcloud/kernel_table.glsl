// SPDX-License-Identifier: GPL-3.0-or-later
// BSSRDF kernel of the radiance pass from a tabulated radial profile: R(r) per RGB channel on a
// uniform grid r_i = r_max · i / (n - 1), linearly interpolated, 0 beyond r_max; the same table
// and interpolation as bssrdf::ProfileTable::lookup (the CPU traversal's RgbKernel::fromTables).
// Interpolation is done here, not by the texture unit, whose weights have 8 bits on most GPUs.
#pragma once

layout(std430, binding = 5) readonly buffer PcProfile { vec4 pcProfile[]; };  // R(r_i), RGB
uniform float ProfileRMax;  // r_max [scene units]
uniform uint ProfileCount;  // n >= 2

void pcKernelInit() {}

vec3 pcKernel(vec3 xo, vec3 no, vec3 xi, vec3 ni) {
  float r = distance(xo, xi);
  if (r > ProfileRMax) return vec3(0.0);
  float x = r / ProfileRMax * float(ProfileCount - 1u);
  uint i = min(uint(x), ProfileCount - 2u);
  float t = x - float(i);
  return mix(pcProfile[i].rgb, pcProfile[i + 1u].rgb, t);
}
