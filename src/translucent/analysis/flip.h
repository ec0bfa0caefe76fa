// SPDX-License-Identifier: GPL-3.0-or-later
// LDR-ꟻLIP (Andersson, Nilsson, Akenine-Möller, Oskarsson, Åström & Fairchild 2020, "ꟻLIP: A
// Difference Evaluator for Alternating Images", Proc. ACM CGIT 3(2), 15:1-15:23): a per-pixel
// estimate in [0, 1] of the difference an observer sees when flipping between a test image and
// its reference, for images as displayed (sRGB-encoded values in [0, 1]).
//
// Two pipelines, both on the opponent space YCxCz (color.h):
//   colour:  each channel is low-pass filtered with the contrast sensitivity function of the eye
//            for that channel at the viewing distance (a Gaussian for Y and Cx, a sum of two for
//            Cz, widths in degrees of visual angle, hence in pixels through the pixels per
//            degree); the result, back in linear RGB and clamped to [0, 1], goes to L*a*b*, is
//            Hunt-adjusted (a*, b* scaled by 0.01 L*: colours look less saturated in the dark)
//            and compared with the HyAB distance |ΔL| + ||(Δa, Δb)||; the distance to the power
//            qc is mapped onto [0, 1] piecewise linearly so that pc · cmax goes to pt, where cmax
//            is the same power of the distance between Hunt-adjusted green and blue (the largest
//            between two sRGB colours) -> ΔE_c.
//   feature: edges (first derivative of a Gaussian) and points (second derivative) of the
//            normalised luminance (Y + 16)/116 (the paper's errata: 116, not 100), Gaussian width
//            σ = ½ · 0.082° · ppd; the larger of the differences of the edge and point
//            magnitudes, over √2, to the power qf -> ΔE_f.
// ꟻLIP = ΔE_c^(1 - ΔE_f): colour differences are amplified where edges or points differ.
//
// Constants: qc = 0.7, qf = 0.5, pc = 0.4, pt = 0.95 (the paper's; also those of the authors'
// code, github.com/NVlabs/flip, which was read to confirm them and the filter definitions; this
// is an independent implementation from the paper's equations). Images are extended beyond their
// borders by repeating the edge pixels, as in the paper's code.
#pragma once

#include <span>
#include <vector>

#include "translucent/analysis/color.h"

namespace translucent::analysis {

namespace flip {

inline constexpr double kQc = 0.7;              // exponent of the HyAB distance
inline constexpr double kQf = 0.5;              // exponent of the feature difference
inline constexpr double kPc = 0.4;              // fraction of cmax ...
inline constexpr double kPt = 0.95;             // ... mapped to this error
inline constexpr double kFeatureWidth = 0.082;  // w [degrees]: feature detector σ = w/2 · ppd

// Hunt adjustment of an L*a*b* colour: (L, 0.01 L a, 0.01 L b).
color::Vec3 huntAdjust(const color::Vec3& lab);
// HyAB distance |ΔL| + sqrt(Δa² + Δb²).
double hyab(const color::Vec3& a, const color::Vec3& b);
// cmax = HyAB(Hunt(green), Hunt(blue))^qc, green and blue the linear-RGB primaries.
double maxColorDistance();
// ΔE_c in [0, 1] from a HyAB distance between Hunt-adjusted colours (applies the qc power and
// the piecewise linear map with pc, pt).
double colorError(double hyab_distance);
// Filter radii in pixels: the CSF filters (3 standard deviations of the widest Gaussian, b = 0.04
// of the Cz channel) and the feature detectors (3σ).
int spatialFilterRadius(double pixels_per_degree);
int featureFilterRadius(double pixels_per_degree);

}  // namespace flip

// Per-pixel LDR-ꟻLIP error in [0, 1] of two sRGB-encoded images (interleaved RGB, rows from the
// top, values clamped to [0, 1]) seen at `pixels_per_degree`. Throws ParameterError on sizes
// that do not match or a pixels per degree that is not finite and > 0. Identical images give 0.
std::vector<float> ldrFlip(std::span<const float> test_srgb, std::span<const float> reference_srgb,
                           int width, int height, double pixels_per_degree);

}  // namespace translucent::analysis
