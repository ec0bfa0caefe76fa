// SPDX-License-Identifier: GPL-3.0-or-later
// Curve styles shared by the file plots and the explorer's widget; see plot_style.h.
#include "plot/plot_style.h"

#include <fmt/format.h>

#include <algorithm>

namespace translucent::plot {

std::string hexName(Colour c) { return fmt::format("#{:02x}{:02x}{:02x}", c.r, c.g, c.b); }

LineStyle lineStyle(std::size_t index) {
  // Stepping the dash with the colour (rather than after all six colours) gives the first curves
  // different dashes too, so two neighbouring models never differ by hue alone; the extra
  // index / 6 moves each later round of colours onto dashes that colour has not had yet.
  const std::size_t c = index % kPalette.size();
  const std::size_t round = index / kPalette.size();
  return {kPalette[c], kDashes[(c + round) % kDashes.size()]};
}

std::vector<double> dashPattern(Dash dash, double width) {
  // In line widths, as seen (caps included): dash 5, dot 1 (a round cap's diameter), gap 2.5.
  // A dot is a nearly zero-length dash: cairo 1.16 merges an exactly zero "on" between two gaps
  // into one gap, which would turn dash-dot into a sparse dash.
  const double dashOn = 4.0 * width, dotOn = 1e-3 * width, gap = 3.5 * width;
  switch (dash) {
    case Dash::Solid: return {};
    case Dash::Dashed: return {dashOn, gap};
    case Dash::Dotted: return {dotOn, 2.6 * width};
    case Dash::DashDot: return {dashOn, gap, dotOn, gap};
    case Dash::DashDotDot: return {dashOn, gap, dotOn, gap, dotOn, gap};
  }
  return {};
}

Colour channelColour(const std::string& ch) {
  if (ch == "r") return kPalette[1];
  if (ch == "g") return kPalette[2];
  if (ch == "b") return kPalette[0];
  return {0x55, 0x55, 0x55};
}

std::string channelWords(const std::string& ch) {
  if (ch == "r") return "red";
  if (ch == "g") return "green";
  if (ch == "b") return "blue";
  return ch;
}

std::vector<CurveLook> profileLooks(const std::vector<analysis::Curve>& curves) {
  std::vector<std::string> models, channels, references;
  auto addUnique = [](std::vector<std::string>& list, const std::string& s) {
    if (std::find(list.begin(), list.end(), s) == list.end()) list.push_back(s);
  };
  for (const auto& c : curves) {
    addUnique(c.stderr_.empty() ? models : references, c.model);
    addUnique(channels, c.channel);
  }
  auto indexIn = [](const std::vector<std::string>& list, const std::string& s) {
    return static_cast<std::size_t>(std::find(list.begin(), list.end(), s) - list.begin());
  };
  const bool byChannel = channels.size() > 1;
  // Colour for the channel and dash for the model only while the dashes suffice; with more
  // models than dashes every curve gets a style of its own instead.
  const bool dashPerModel = byChannel && models.size() <= kDashes.size();

  std::vector<CurveLook> looks;
  looks.reserve(curves.size());
  std::size_t line = 0;  // index of the next model curve
  for (const auto& c : curves) {
    CurveLook look;
    look.name = byChannel ? fmt::format("{} ({})", c.model, channelWords(c.channel)) : c.model;
    if (!c.stderr_.empty()) {
      look.reference = true;
      look.line.colour = byChannel ? channelColour(c.channel) : kReferenceColour;
      constexpr std::array<Marker, 4> kMarkers = {Marker::Circle, Marker::Square,
                                                  Marker::Triangle, Marker::Diamond};
      look.marker = kMarkers[indexIn(references, c.model) % kMarkers.size()];
      look.name += " ±1 s.e.";
    } else if (dashPerModel) {
      look.line = {channelColour(c.channel), kDashes[indexIn(models, c.model)]};
      ++line;
    } else {
      look.line = lineStyle(line++);
    }
    looks.push_back(std::move(look));
  }
  return looks;
}

}  // namespace translucent::plot
