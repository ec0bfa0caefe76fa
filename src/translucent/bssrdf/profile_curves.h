// SPDX-License-Identifier: GPL-3.0-or-later
// Radial-profile curves for plots and CSV (seed 3.6.3, the pencil plot): one curve per model and
// channel (red, green, blue or luminance), optionally multiplied by r.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <array>
#include <memory>

#include "translucent/bssrdf/registry.h"
#include "translucent/optics/medium.h"

namespace translucent::analysis {

enum class Channel { Red, Green, Blue, Luminance };
const char* channelName(Channel c);          // "r", "g", "b", "luminance"
Channel parseChannel(const std::string& s);  // r|g|b|red|green|blue|luminance|lum

// Rec. 709 luminance weights (linear RGB).
inline double luminance(const Rgb& c) { return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]; }

struct Curve {
  std::string model;    // model name (or "reference")
  std::string channel;  // channelName()
  std::vector<double> r;
  std::vector<double> value;
  std::vector<double> stderr_;  // empty unless the curve is a Monte Carlo estimate
};

struct CurveOptions {
  std::optional<double> r_max;  // default: largest 95% radius over models and channels
  int points = 200;
  bool times_r = false;  // plot r·R(r) (seed 3.6.3: damps the peak at the source)
  // Polar angle of the incident pencil beam [radians, outside, in [0, π/2)]. A directional model
  // (bssrdf::Model::directional) is plotted as its kernel's azimuthal average at that incidence
  // (bssrdf::azimuthalAverage: what the path tracer's radial tally of an oblique beam measures);
  // radial models do not depend on it (their R(r) assumes normal incidence).
  double incidence = 0.0;
};

// One model's RGB values along a pencil-plot curve: R(r) of its three channel profiles, or, at
// an oblique incidence (CurveOptions::incidence), a directional model's kernel averaged over the
// azimuth (bssrdf::azimuthalAverage). Built once per model and medium (building the profiles is
// the costly part); profileCurves and the explorer's pencil plot both sample it.
class ModelCurve {
 public:
  ModelCurve(const bssrdf::Model& model, const Medium& medium, double incidence = 0.0);
  Rgb at(double r) const;
  const bssrdf::RgbProfiles& profiles() const { return profiles_; }
  // True when the values depend on the incidence (a directional model at incidence != 0).
  bool directional() const { return kernels_[0] != nullptr; }

 private:
  bssrdf::RgbProfiles profiles_;
  std::array<std::unique_ptr<bssrdf::DirectionalProfile>, 3> kernels_;
  double incidence_;
};

// The curves of `model` on `grid` for each channel, labelled `label` (luminance from the RGB
// values; times r when `times_r`).
std::vector<Curve> sampleCurves(const ModelCurve& model, const std::string& label,
                                const std::vector<Channel>& channels,
                                const std::vector<double>& grid, bool times_r);

// Curves of the named models for `medium`, in scene units of length (Medium::channel).
std::vector<Curve> profileCurves(const std::vector<std::string>& models, const Medium& medium,
                                 const std::vector<Channel>& channels, const CurveOptions& opts);

// Radius grid used by profileCurves: r_i = r_max (i + 1) / points (excludes r = 0, where some
// profiles diverge like 1/r).
std::vector<double> radiusGrid(double r_max, int points);
// Default plot range: the largest 95% radius over the models' channels.
double defaultRadius(const std::vector<std::string>& models, const Medium& medium);

// Writes curves as CSV with columns model,channel,r,value[,stderr]. Throws std::runtime_error
// naming the file when it cannot be written.
void writeCurvesCsv(const std::string& path, const std::vector<Curve>& curves);

}  // namespace translucent::analysis
