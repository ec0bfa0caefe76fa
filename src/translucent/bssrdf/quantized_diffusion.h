// SPDX-License-Identifier: GPL-3.0-or-later
// Direct (untabulated) evaluation of the quantized-diffusion profile (quantized_diffusion.cpp), for
// callers that need the model's exact sum rather than the registered profile's interpolation table.
#pragma once

#include "translucent/optics/medium.h"

namespace translucent::bssrdf {

// R(r) [1/length²] of quantized diffusion for one channel, summing every time quantum (a few
// microseconds per call). Throws ParameterError for an invalid medium or r < 0.
double quantizedDiffusionDirect(double r, const ScalarMedium& medium);

// Total diffuse reflectance of quantized diffusion, α' Σ_i w_i w_R(v_i): exact for the model,
// since each quantum's radial Gaussian integrates to 1. Throws ParameterError for an invalid medium.
double quantizedDiffusionRd(const ScalarMedium& medium);

}  // namespace translucent::bssrdf
