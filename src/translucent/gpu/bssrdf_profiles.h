// SPDX-License-Identifier: GPL-3.0-or-later
// Radial `.bssrdf` models (seed appendix A.2) as profiles, tables and inversions, evaluated on the
// GPU through BssrdfEvaluator (a current 4.5 context is needed for all of these):
//   bssrdfCurves        R(r) curves for `translucent profile`, beside the registered C++ models;
//   bssrdfRadiusForFraction / tabulateBssrdf
//                       the radius holding a fraction of Rd, found from the GPU values themselves
//                       (2π ∫ R r dr with 8-point Gauss-Legendre panels on a log grid), and a
//                       bssrdf::ProfileTable on that radius, the same layout as bssrdf::tabulate();
//   invertBssrdfMedium  (Rd, ℓd) -> (σa, σs') through the file's DiffuseReflectance(α') kernel by
//                       parallel subdivision (seed 3.4): Rdr(α') at the 513 edges of 512
//                       subintervals in one dispatch, keep the bracketing subinterval, repeat.
// Radii are in scene units (Medium::channel: σ · scale), as for the C++ models.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "translucent/bssrdf/profile_curves.h"
#include "translucent/bssrdf/profile_table.h"
#include "translucent/bssrdf/tabulated.h"
#include "translucent/gpu/bssrdf_kernels.h"
#include "translucent/optics/medium.h"

namespace translucent::gpu {

// R(r) of `evaluator` for `medium` at the radii, per channel, in double (values from float): the
// profile kernel's plane with the light along the normal. For a directional file (no `radial`)
// that is its normal-incidence restriction (Ni = No = Wi = Wo = N), which the functions below
// tabulate, integrate and sample as any radial profile.
std::vector<Rgb> bssrdfProfile(BssrdfEvaluator& evaluator, const Medium& medium,
                               const std::vector<double>& radii);

// Curves of one .bssrdf model on `grid`, labelled `label` (profileCurves' layout: one curve per
// channel, luminance from the RGB values, optionally times r).
std::vector<analysis::Curve> bssrdfCurves(BssrdfEvaluator& evaluator, const std::string& label,
                                          const Medium& medium,
                                          const std::vector<analysis::Channel>& channels,
                                          const std::vector<double>& grid, bool times_r);

// Total diffuse reflectance Rd = 2π ∫0^∞ R r dr and the radius holding `fraction` of it, per
// channel, integrated from GPU values of R. Throws ParameterError when the profile is not
// integrable on the range searched (no absorption, or a non-decaying profile).
struct BssrdfEnergy {
  Rgb rd{};
  Rgb radius{};
};
BssrdfEnergy bssrdfRadiusForFraction(BssrdfEvaluator& evaluator, const Medium& medium,
                                     double fraction);

// A ProfileTable of channel `channel` with n >= 2 entries up to the radius holding `fraction` of
// Rd (as bssrdf::tabulate: where R(0) is not finite, R[0] holds R(Δr/4) and r_times_R[0] the
// value of r·R at r = 1e-7 Δr); the cdf integrates GPU values with one Gauss-Legendre panel per
// table interval.
bssrdf::ProfileTable tabulateBssrdf(BssrdfEvaluator& evaluator, const Medium& medium, int channel,
                                    size_t n = 1024, double fraction = 0.999);

// A radial .bssrdf file for one medium as a tabulated model (bssrdf/tabulated.h), named `name`:
// R(r) from the GPU at `n` log-spaced radii from 1e-6 to 1 of the largest radius holding
// 1 − 1e-7 of Rd over the channels, stored in mm (r · scale, R / scale²). It is that medium's
// profile only (a file's R depends on the medium): what the sphere integration of a plug-in
// (seed 3.5) samples and integrates on the CPU. Throws ParameterError as bssrdfRadiusForFraction.
std::unique_ptr<bssrdf::TabulatedModel> bssrdfTabulatedModel(BssrdfEvaluator& evaluator,
                                                             const Medium& medium,
                                                             const std::string& name,
                                                             int n = 4000);

// Inverts the file's Rdr(α') per channel (seed 3.4) and returns the medium (coefficients per mm,
// σs from σs' and g). Throws ParameterError when the file has no diffuseReflectance section, when
// Rd is outside the reachable range (Rdr(0), Rdr(1)) or ℓd is not positive.
Medium invertBssrdfMedium(BssrdfEvaluator& evaluator, const Rgb& rd, const Rgb& ld, double eta,
                          double g = 0.0);

}  // namespace translucent::gpu
