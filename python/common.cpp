// SPDX-License-Identifier: GPL-3.0-or-later
#include "common.h"

#include <fmt/format.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <cmath>

#include "translucent/optics/presets.h"

namespace translucent::python {

py::array_t<double> rgbArray(const Rgb& v) {
  return ownedArray<double>(std::vector<double>(v.begin(), v.end()), {3});
}

namespace {
bool optionChar(char c) { return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '-'; }
bool wordChar(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
         c == '-';
}
}  // namespace

std::string pythonMessage(std::string_view m) {
  std::string out;
  out.reserve(m.size());
  size_t i = 0;
  while (i < m.size()) {
    const bool option = m.compare(i, 2, "--") == 0 && (i == 0 || !wordChar(m[i - 1])) &&
                        i + 2 < m.size() && m[i + 2] >= 'a' && m[i + 2] <= 'z';
    if (!option) {
      out += m[i++];
      continue;
    }
    size_t j = i + 2;
    while (j < m.size() && optionChar(m[j])) ++j;
    while (m[j - 1] == '-') --j;  // "--sigma-a-" is "--sigma-a" and a dash
    for (size_t k = i + 2; k < j; ++k) out += m[k] == '-' ? '_' : m[k];
    if (m.compare(j, 2, " '") == 0) {  // "--channel 'x'" -> "channel='x'"
      out += '=';
      ++j;
    }
    i = j;
  }
  return out;
}

py::object result(const char* type, py::dict fields) {
  return py::module_::import("translucent._results").attr(type)(std::move(fields));
}

std::string reprOf(const py::handle& value) {
  // For a message about a bad argument, which must not fail itself: repr() of a list nested
  // deeper than the recursion limit raises RecursionError, a class's __repr__ may raise anything,
  // and a huge value would bury the message (hostile-argument test, tests/python/hostile_check.py).
  std::string text;
  try {
    text = py::str(py::repr(value)).cast<std::string>();
  } catch (const py::error_already_set&) {
    return fmt::format("<{} object>", Py_TYPE(value.ptr())->tp_name);
  }
  constexpr size_t kMaxRepr = 200;
  if (text.size() > kMaxRepr) {
    size_t cut = kMaxRepr;
    while (cut > 0 && (static_cast<unsigned char>(text[cut]) & 0xC0) == 0x80) --cut;  // UTF-8
    text = text.substr(0, cut) + "...";
  }
  return text;
}

Rgb toRgb(const py::handle& value, const std::string& what) {
  const auto typeError = [&] {
    return py::type_error(fmt::format("{}={}: expected a number or three numbers r, g, b", what,
                                      reprOf(value)));
  };
  if (py::isinstance<py::bool_>(value) || value.is_none() || py::isinstance<py::str>(value) ||
      py::isinstance<py::bytes>(value))
    throw typeError();
  // A number (Python's or NumPy's scalars): grey.
  if (py::isinstance<py::float_>(value) || py::isinstance<py::int_>(value) ||
      (PyNumber_Check(value.ptr()) != 0 && !py::hasattr(value, "__len__"))) {
    try {
      const double v = value.cast<double>();
      return {v, v, v};
    } catch (const py::cast_error&) {
      throw typeError();
    }
  }
  // A sequence or an array of numbers (a 0-d array: grey).
  auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(value);
  if (!a || a.ndim() > 1) throw typeError();
  if (a.ndim() == 0) return {a.data()[0], a.data()[0], a.data()[0]};
  if (a.size() != 3)
    throw ParameterError(fmt::format("{} {}: expected one value or three values r, g, b", what,
                                     reprOf(value)));
  return {a.data()[0], a.data()[1], a.data()[2]};
}

Rgb finiteRgb(const py::handle& value, const std::string& what) {
  const Rgb v = toRgb(value, what);
  static const char* const names[] = {"red", "green", "blue"};
  for (size_t c = 0; c < 3; ++c)
    if (!std::isfinite(v[c]))
      throw ParameterError(fmt::format("{} ({} channel) is {}: expected a finite value", what,
                                       names[c], v[c]));
  return v;
}

py::array_t<double, py::array::c_style | py::array::forcecast> checkedArray(
    const py::object& values, const char* what, double lo, double hi, bool open_hi) {
  using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;
  const auto typeError = [&] {
    return py::type_error(fmt::format("{}={}: expected a number or an array-like of numbers", what,
                                      reprOf(values)));
  };
  if (values.is_none() || py::isinstance<py::str>(values) || py::isinstance<py::bytes>(values))
    throw typeError();
  Array a = Array::ensure(values);  // clears NumPy's error when it cannot convert
  if (!a) throw typeError();
  const double* x = a.data();
  for (py::ssize_t i = 0; i < a.size(); ++i) {
    const double v = x[i];
    if (std::isfinite(v) && v >= lo && (open_hi ? v < hi : v <= hi)) continue;
    const std::string range =
        std::isinf(hi) ? fmt::format("a finite value >= {}", lo)
                       : fmt::format("a value in [{}, {}{}", lo, hi, open_hi ? ")" : "]");
    if (a.ndim() == 0)
      throw ParameterError(fmt::format("{} is {}: expected {}", what, v, range));
    throw ParameterError(fmt::format("{}.flat[{}] is {}: expected {}", what, i, v, range));
  }
  return a;
}

std::filesystem::path pathArgument(const py::handle& value, const char* what) {
  if (py::isinstance<py::str>(value) ||
      py::isinstance(value, py::module_::import("os").attr("PathLike"))) {
    // pybind11's caster fails (a RuntimeError "Unable to cast") for a name the file system
    // cannot hold: one with a NUL, a PathLike whose __fspath__ raises or returns another type.
    std::filesystem::path p;
    try {
      p = value.cast<std::filesystem::path>();
    } catch (const py::cast_error&) {
      throw py::type_error(
          fmt::format("{}={}: expected a file name (str or os.PathLike)", what, reprOf(value)));
    }
    checkNoNul(p.native(), what);
    return p;
  }
  throw py::type_error(
      fmt::format("{}={}: expected a file name (str or os.PathLike)", what, reprOf(value)));
}

const std::string& checkNoNul(const std::string& name, const char* what) {
  // The C++ library passes names to the OS as C strings, which end at the first NUL: "a\0b"
  // would open "a".
  if (const size_t nul = name.find('\0'); nul != std::string::npos)
    throw ParameterError(
        fmt::format("{}: the name holds a NUL character (at byte {}): expected a file or model "
                    "name", what, nul));
  return name;
}

double finiteArgument(double value, const char* what) {
  if (!std::isfinite(value))
    throw ParameterError(fmt::format("{} is {}: expected a finite number", what, value));
  return value;
}

std::optional<std::string> materialArgument(const std::optional<std::string>& material,
                                            const std::optional<std::string>& preset,
                                            const char* function) {
  if (!preset) return material;
  if (material)
    throw ParameterError(fmt::format("{}: material= and preset= name the same preset: give "
                                     "material= only (preset= is its deprecated spelling)",
                                     function));
  const std::string text = fmt::format("{}: preset= is deprecated: use material={} (the CLI's "
                                       "--material)", function, *preset);
  if (PyErr_WarnEx(PyExc_DeprecationWarning, text.c_str(), 1) != 0) throw py::error_already_set();
  return preset;
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
    if (preset) throw ParameterError("material excludes sigma_a and sigma_s");
    if (sigma_a.is_none()) throw ParameterError("--sigma-s requires --sigma-a");
    if (sigma_s.is_none()) throw ParameterError("--sigma-a requires --sigma-s");
    m.sigma_a = toRgb(sigma_a, "sigma_a");
    m.sigma_s = toRgb(sigma_s, "sigma_s");
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

