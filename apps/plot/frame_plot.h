// SPDX-License-Identifier: GPL-3.0-or-later
// A technique's plot (techniques::FramePlot, e.g. splatting's effective rendering radius) as the
// x-y plot of profile_plot.h, for the command line's files and the explorer's charts. Header-only:
// translucent::plot itself does not depend on the techniques; its users that show frame plots do.
#pragma once

#include <vector>

#include "plot/profile_plot.h"
#include "translucent/techniques/technique.h"

namespace translucent::plot {

struct FrameXyPlot {
  std::vector<XySeries> series;
  XyPlotOptions options;
};

inline FrameXyPlot xyPlotOf(const techniques::FramePlot& fp) {
  FrameXyPlot out;
  for (const auto& s : fp.series) out.series.push_back({s.label, s.x, s.y});
  out.options.title = fp.title;
  out.options.x_label = fp.x_label;
  out.options.y_label = fp.y_label;
  out.options.log_x = fp.log_x;
  out.options.log_y = fp.log_y;
  return out;
}

}  // namespace translucent::plot
