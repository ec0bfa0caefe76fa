// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/bssrdf/profile_curves.h"

#include <fmt/format.h>
#include <fmt/os.h>

#include <algorithm>
#include <stdexcept>

#include "translucent/bssrdf/registry.h"

namespace translucent::analysis {

const char* channelName(Channel c) {
  switch (c) {
    case Channel::Red: return "r";
    case Channel::Green: return "g";
    case Channel::Blue: return "b";
    case Channel::Luminance: return "luminance";
  }
  return "?";
}

Channel parseChannel(const std::string& s) {
  if (s == "r" || s == "red") return Channel::Red;
  if (s == "g" || s == "green") return Channel::Green;
  if (s == "b" || s == "blue") return Channel::Blue;
  if (s == "luminance" || s == "lum" || s == "y") return Channel::Luminance;
  throw ParameterError(
      fmt::format("unknown channel '{}': expected r, g, b, luminance (or all)", s));
}

std::vector<double> radiusGrid(double r_max, int points) {
  if (!(r_max > 0.0) || points < 2)
    throw ParameterError(fmt::format(
        "radius grid needs rmax > 0 and at least 2 points (got rmax {}, points {})", r_max, points));
  std::vector<double> r(static_cast<size_t>(points));
  for (int i = 0; i < points; ++i) r[static_cast<size_t>(i)] = r_max * (i + 1) / points;
  return r;
}

double defaultRadius(const std::vector<std::string>& models, const Medium& medium) {
  double r = 0.0;
  for (const auto& name : models) {
    const auto ps = bssrdf::profiles(bssrdf::model(name), medium);
    for (const auto& p : ps) r = std::max(r, p->radiusForFraction(0.95));
  }
  return r;
}

ModelCurve::ModelCurve(const bssrdf::Model& model, const Medium& medium, double incidence)
    : profiles_(bssrdf::profiles(model, medium)), incidence_(incidence) {
  if (incidence != 0.0 && !model.tabulated())
    for (int c = 0; c < 3; ++c) kernels_[static_cast<size_t>(c)] = model.directional(medium.channel(c));
}

Rgb ModelCurve::at(double r) const {
  Rgb v;
  for (size_t c = 0; c < 3; ++c)
    v[c] = kernels_[c] ? bssrdf::azimuthalAverage(*kernels_[c], r, incidence_) : profiles_[c]->R(r);
  return v;
}

std::vector<Curve> sampleCurves(const ModelCurve& model, const std::string& label,
                                const std::vector<Channel>& channels,
                                const std::vector<double>& grid, bool times_r) {
  std::vector<Curve> curves;
  std::vector<Rgb> values;
  values.reserve(grid.size());
  for (double r : grid) values.push_back(model.at(r));
  for (Channel ch : channels) {
    Curve c{label, channelName(ch), grid, {}, {}};
    c.value.reserve(grid.size());
    for (size_t i = 0; i < grid.size(); ++i) {
      double y = ch == Channel::Luminance ? luminance(values[i]) : values[i][static_cast<size_t>(ch)];
      if (times_r) y *= grid[i];
      c.value.push_back(y);
    }
    curves.push_back(std::move(c));
  }
  return curves;
}

std::vector<Curve> profileCurves(const std::vector<std::string>& models, const Medium& medium,
                                 const std::vector<Channel>& channels, const CurveOptions& opts) {
  const double rMax = opts.r_max ? *opts.r_max : defaultRadius(models, medium);
  const auto grid = radiusGrid(rMax, opts.points);
  std::vector<Curve> curves;
  for (const auto& name : models) {
    const auto c = sampleCurves(ModelCurve(bssrdf::model(name), medium, opts.incidence), name,
                                channels, grid, opts.times_r);
    curves.insert(curves.end(), c.begin(), c.end());
  }
  return curves;
}

void writeCurvesCsv(const std::string& path, const std::vector<Curve>& curves) {
  const bool withErr =
      std::any_of(curves.begin(), curves.end(), [](const Curve& c) { return !c.stderr_.empty(); });
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) throw std::runtime_error(fmt::format("cannot write '{}'", path));
  fmt::print(f, "model,channel,r,value{}\n", withErr ? ",stderr" : "");
  for (const auto& c : curves)
    for (size_t i = 0; i < c.r.size(); ++i) {
      fmt::print(f, "{},{},{:.9g},{:.9g}", c.model, c.channel, c.r[i], c.value[i]);
      if (withErr) {
        if (c.stderr_.empty())
          fmt::print(f, ",\n");
        else
          fmt::print(f, ",{:.9g}\n", c.stderr_[i]);
      } else {
        fmt::print(f, "\n");
      }
    }
  const bool ok = std::ferror(f) == 0;
  if (std::fclose(f) != 0 || !ok) throw std::runtime_error(fmt::format("cannot write '{}'", path));
}

}  // namespace translucent::analysis
