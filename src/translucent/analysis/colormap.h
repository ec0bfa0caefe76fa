// SPDX-License-Identifier: GPL-3.0-or-later
// False colour for scalar maps (the compare report's error, z-score and SSIM/ꟻLIP images) and
// colour bars with tick labels to read them by.
//
//   Viridis, Magma  matplotlib's perceptually uniform sequential maps (Smith, van der Walt &
//                   Firing 2015; CC0 tables in colormap_tables.inc), lightness increasing from
//                   lo to hi; looked up as matplotlib does with its 256-entry tables
//                   (entry floor(256 t), t = (v - lo)/(hi - lo) clamped to [0, 1]).
//   Diverging       for signed values: white at the middle of [lo, hi], towards red above and blue
//                   below, interpolated linearly in CIELAB from white (L* = 100) to red
//                   (L* = 45, C* = 70, h = 38°) and blue (L* = 45, C* = 60, h = -72°): lightness
//                   falls linearly and equally on both sides, so equal |values| look equally
//                   strong (both ends are inside the sRGB gamut, and so is the path to them).
// NaN (no value: outside the mask, no reference signal) is mid grey (128, 128, 128).
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "translucent/io/image_io.h"  // writePng8

namespace translucent::analysis {

enum class ColorMap { Viridis, Magma, Diverging };  // Diverging: blue - white - red (signed values)

// "viridis", "magma", "diverging"; anything else throws ParameterError listing the names.
ColorMap parseColorMap(const std::string& name);
const char* colorMapName(ColorMap map);

// 8-bit sRGB colour at t in [0, 1] (clamped; NaN -> mid grey).
std::array<uint8_t, 3> mapColor(ColorMap map, double t);

// 8-bit RGB (interleaved, width*height*3) of a scalar map; values mapped from [lo, hi]; NaN ->
// mid grey. Throws ParameterError unless values.size() == width*height and lo < hi are finite.
std::vector<uint8_t> falseColor(std::span<const float> values, int width, int height, ColorMap map,
                                double lo, double hi);

// A horizontal colour bar image (width x height, 8-bit RGB, white background) for the same map
// and range: the bar on top, the column at x showing the value lo + (hi - lo)(x + ½)/width; below
// it `ticks` (>= 2) tick marks at lo + k (hi - lo)/(ticks - 1), at column
// round(k (width - 1)/(ticks - 1)), labelled with the value ({:.3g}; the first label left-aligned
// to its tick, the last right-aligned, the others centred). Text is drawn with OpenImageIO's
// FreeType text renderer in DejaVu Sans (Debian: fonts-dejavu-core); ImageError if no font is
// found. Throws ParameterError unless width >= 2 * ticks, height >= 24 (room for the labels).
std::vector<uint8_t> colorBar(int width, int height, ColorMap map, double lo, double hi,
                              int ticks = 5);

// The layout colorBar draws: bar rows [0, bar_height), tick columns, label font size in pixels.
struct ColorBarLayout {
  int bar_height = 0;
  int font_size = 0;
  std::vector<int> tick_x;
  std::vector<double> tick_value;
};
ColorBarLayout colorBarLayout(int width, int height, double lo, double hi, int ticks = 5);

}  // namespace translucent::analysis
