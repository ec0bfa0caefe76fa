// SPDX-License-Identifier: GPL-3.0-or-later
// BSSRDF kernel of the radiance pass from a .bssrdf file (seed appendix A.2): Bssrdf(Xi, Wi, Xo,
// Wo) with both directions along the normals, as in the profile kernel (bssrdf/profile.comp).
// Included after the file's sections (gpu::bssrdfPreprocessor); the standard inputs and the
// declared parameters are uniforms set by the technique.
#pragma once

void pcKernelInit() { init(); }

vec3 pcKernel(vec3 xo, vec3 no, vec3 xi, vec3 ni) {
  Ni = ni;
  No = no;
  return Bssrdf(xi, ni, xo, no);
}

// A directional file (line 1 without `radial`; PC_DIRECTIONAL): Bssrdf() with the direction wi
// of the light that lit x_i (towards it) and the normals at both ends.
vec3 pcKernelDirectional(vec3 xo, vec3 no, vec3 xi, vec3 ni, vec3 wi) {
  Ni = ni;
  No = no;
  return Bssrdf(xi, wi, xo, no);
}
