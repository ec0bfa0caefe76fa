// SPDX-License-Identifier: GPL-3.0-or-later
// Standard inputs of every .bssrdf model (seed appendix A.2; listing A.2 uses these names).
// The host (src/gpu/bssrdf_kernels.cpp) sets them from a translucent::Medium; parameters that a
// .bssrdf file declares become uniforms next to these. Coefficients are per scene unit: the
// medium's coefficients times its scale (seed 3.6.1), as in Medium::channel().
#pragma once

uniform vec3 SigmaA;  // absorption coefficient sigma_a per RGB channel [1/scene unit]
uniform vec3 SigmaS;  // scattering coefficient sigma_s per RGB channel [1/scene unit]
uniform float G;      // Henyey-Greenstein mean cosine g; sigma_s' = (1 - g) sigma_s
uniform float IOR;    // relative index of refraction eta = n_medium / n_outside

const float PI = 3.14159265358979323846;

// Outward unit normals at Xi and Xo, set by the kernel before each Bssrdf() call (an extension of
// the seed's interface, whose Bssrdf(Xi, Wi, Xo, Wo) has no normals): a directional model (line 1
// without `radial`, e.g. data/bssrdf/directional-dipole.bssrdf) needs them besides Wi and Wo.
// The profile kernel sets both to the plane's normal, where Wi = Wo = N as well.
vec3 Ni = vec3(0.0, 0.0, 1.0);
vec3 No = vec3(0.0, 0.0, 1.0);
