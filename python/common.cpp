// SPDX-License-Identifier: GPL-3.0-or-later
#include "common.h"

#include <fmt/format.h>
#include <pybind11/stl.h>

#include <cmath>

#include "translucent/optics/presets.h"

namespace translucent::python {

py::array_t<double> rgbArray(const Rgb& v) {
  return ownedArray<double>(std::vector<double>(v.begin(), v.end()), {3});
}

Rgb toRgb(const py::handle& value, const std::string& what) {
  if (py::isinstance<py::float_>(value) || py::isinstance<py::int_>(value)) {
    const double v = value.cast<double>();
    return {v, v, v};
  }
  try {
    const auto seq = py::cast<std::vector<double>>(value);
    if (seq.size() == 3) return {seq[0], seq[1], seq[2]};
  } catch (const py::cast_error&) {
  }
  throw ParameterError(fmt::format("{} {}: expected one value or three values r, g, b", what,
                                   py::str(py::repr(value)).cast<std::string>()));
}

Medium mediumFromArgs(const std::optional<std::string>& preset, const py::object& sigma_a,
                      const py::object& sigma_s, std::optional<double> g,
                      std::optional<double> eta, double scale,
                      const std::string& default_preset) {
  const bool coefficients = !sigma_a.is_none() || !sigma_s.is_none();
  Medium m;
  if (coefficients) {
    // The CLI refuses these combinations in its option parser (CLI11); the messages name the
    // same options.
    if (preset) throw ParameterError("--preset excludes --sigma-a and --sigma-s");
    if (sigma_a.is_none()) throw ParameterError("--sigma-s requires --sigma-a");
    if (sigma_s.is_none()) throw ParameterError("--sigma-a requires --sigma-s");
    m.sigma_a = toRgb(sigma_a, "--sigma-a");
    m.sigma_s = toRgb(sigma_s, "--sigma-s");
    m.g = g.value_or(0.0);
    m.eta = eta.value_or(1.3);
  } else {
    const Preset& pr = translucent::preset(preset.value_or(default_preset));
    m = pr.medium();
    if (g) m = Medium::fromReduced(pr.sigma_a, pr.sigma_s_prime, *g, m.eta);
    if (eta) m.eta = *eta;
  }
  m.scale = scale;
  m.validate();
  return m;
}

Interruptible::Interruptible(std::optional<double> time_limit)
    : time_limit_(time_limit), start_(std::chrono::steady_clock::now()) {
  if (time_limit_ && !(*time_limit_ > 0.0))
    throw ParameterError(fmt::format("--time-limit is {}: expected seconds > 0", *time_limit_));
}

double Interruptible::elapsed() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

bool Interruptible::poll(uint64_t done, uint64_t total) {
  if (error_ || timed_out_ || !refused_.empty()) return false;
  const double seconds = elapsed();
  if (time_limit_ && seconds >= *time_limit_) {
    timed_out_ = true;
    return false;
  }
  // The CLI's cost check (apps/cli/progress.cpp), with its limits.
  constexpr double kCostCheckSeconds = 5.0, kMaxProjectedSeconds = 24.0 * 3600.0;
  if (!time_limit_ && seconds >= kCostCheckSeconds && done > 0 && done < total) {
    const double projected = seconds * static_cast<double>(total) / static_cast<double>(done);
    if (projected > kMaxProjectedSeconds) {
      refused_ = fmt::format(
          "refused: {} photons at the measured {:.3g} photons/s would take about {:.1f} days "
          "(more than {:.0f} hours); lower the count, or give time_limit to stop early with "
          "partial results",
          total, static_cast<double>(done) / seconds, projected / 86400.0,
          kMaxProjectedSeconds / 3600.0);
      return false;
    }
  }
  py::gil_scoped_acquire gil;
  if (PyErr_CheckSignals() != 0) {
    error_.emplace();  // fetches and clears the exception the handler raised
    return false;
  }
  return true;
}

reference::ProgressCallback Interruptible::callback() {
  return [this](const reference::TraceProgress& p) { return poll(p.photons_done, p.photons_total); };
}

void Interruptible::finish() const {
  if (!refused_.empty()) throw ParameterError(refused_);
}

void Interruptible::rethrow(const py::object& partial) {
  if (!error_) return;
  // The exception object of the handler (KeyboardInterrupt for Ctrl-C), with what was traced.
  py::object value = error_->value();
  if (!value.is_none()) py::setattr(value, "partial_result", partial);
  error_->restore();
  error_.reset();
  throw py::error_already_set();
}

uint64_t photonCount(double v, const char* option) {
  if (!(v >= 1.0) || v > 1e18 || std::floor(v) != v)
    throw ParameterError(
        fmt::format("{} '{}': expected a whole number >= 1 (e.g. 1000000 or 1e6)", option, v));
  return static_cast<uint64_t>(v);
}

}  // namespace translucent::python

