// SPDX-License-Identifier: GPL-3.0-or-later
// How curves look in every plot, file or widget: a colour from the Okabe-Ito palette (Okabe and
// Ito 2008; told apart with any common colour-vision deficiency) together with a dash pattern.
// Colour alone runs out after six curves and fails in grey print; colour and dash together keep
// kDistinctLineStyles curves apart, and neighbouring curves differ in both.
//
// Profile plots (profileLooks) colour by channel when several channels are shown (red, green and
// blue of a model in vermillion, bluish green and blue) and then tell models apart by the dash;
// with one channel every curve gets its own lineStyle(). Monte Carlo references (curves with
// standard errors) are markers with error bars, black or the channel's colour, one marker shape
// per reference.
//
// Qt-free: shared by the cairo file writer (plot_file.cpp) and the explorer's Qt Charts widget
// (profile_chart.cpp), so that a figure and the widget show a model in the same style.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "translucent/bssrdf/profile_curves.h"

namespace translucent::plot {

struct Colour {
  std::uint8_t r = 0, g = 0, b = 0;
  friend bool operator==(const Colour&, const Colour&) = default;
};
std::string hexName(Colour c);  // "#0072b2"

enum class Dash { Solid, Dashed, Dotted, DashDot, DashDotDot };
enum class Marker { Circle, Square, Triangle, Diamond };

struct LineStyle {
  Colour colour;
  Dash dash = Dash::Solid;
  friend bool operator==(const LineStyle&, const LineStyle&) = default;
};

// Okabe-Ito without its yellow (too faint as a line on white) and black (the references' colour).
inline constexpr std::array<Colour, 6> kPalette = {{{0x00, 0x72, 0xB2},    // blue
                                                    {0xD5, 0x5E, 0x00},    // vermillion
                                                    {0x00, 0x9E, 0x73},    // bluish green
                                                    {0xCC, 0x79, 0xA7},    // reddish purple
                                                    {0xE6, 0x9F, 0x00},    // orange
                                                    {0x56, 0xB4, 0xE9}}};  // sky blue
inline constexpr std::array<Dash, 5> kDashes = {Dash::Solid, Dash::Dashed, Dash::Dotted,
                                                Dash::DashDot, Dash::DashDotDot};
inline constexpr std::size_t kDistinctLineStyles = kPalette.size() * kDashes.size();  // 30
inline constexpr Colour kReferenceColour = {0x00, 0x00, 0x00};
// Width of a curve (layout units, points on a PDF page). Nothing else in a plot is drawn this
// wide, so a curve's strokes can be told from grid lines, ticks and error bars (the tests do).
inline constexpr double kCurveLineWidth = 1.6;

// The style of the index-th curve: colour index % 6, dash (index % 6 + index / 6) % 5. No two
// indices below kDistinctLineStyles share colour and dash; consecutive indices differ in both.
LineStyle lineStyle(std::size_t index);

// On/off lengths of a dash pattern for a line `width` wide drawn with round caps (empty: solid).
// Round caps make the zero-length "on" segments dots and lengthen every dash by the width, so
// the gaps are widened by as much: the pattern looks the same at any width.
std::vector<double> dashPattern(Dash dash, double width);

// Colours of the r, g, b channels: vermillion, bluish green and blue (Okabe-Ito), which readers
// with a red-green deficiency still tell apart; anything else (luminance) dark grey.
Colour channelColour(const std::string& channel);
std::string channelWords(const std::string& channel);  // "r" -> "red", ...; others as given

struct CurveLook {
  LineStyle line;          // a reference's colour (its dash is unused)
  bool reference = false;  // markers with ±1 standard-error bars instead of a line
  Marker marker = Marker::Circle;
  std::string name;        // legend entry
};

// The look of each curve, in order; see the comment at the top.
std::vector<CurveLook> profileLooks(const std::vector<analysis::Curve>& curves);

}  // namespace translucent::plot
