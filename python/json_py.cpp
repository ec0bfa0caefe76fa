// SPDX-License-Identifier: GPL-3.0-or-later
#include "json_py.h"

#include <pybind11/pybind11.h>

#include <fmt/format.h>

#include <cmath>
#include <string>

#include "common.h"

#include "translucent/io/json.h"

namespace translucent::python {

namespace py = pybind11;

py::object toPython(const nlohmann::json& j) {
  switch (j.type()) {
    case nlohmann::json::value_t::null: return py::none();
    case nlohmann::json::value_t::boolean: return py::bool_(j.get<bool>());
    case nlohmann::json::value_t::number_integer: return py::int_(j.get<int64_t>());
    case nlohmann::json::value_t::number_unsigned: return py::int_(j.get<uint64_t>());
    case nlohmann::json::value_t::number_float: return py::float_(j.get<double>());
    case nlohmann::json::value_t::string: return py::str(j.get<std::string>());
    case nlohmann::json::value_t::array: {
      py::list l;
      for (const auto& e : j) l.append(toPython(e));
      return l;
    }
    case nlohmann::json::value_t::object: {
      py::dict d;
      for (const auto& [k, v] : j.items()) d[py::str(k)] = toPython(v);
      return d;
    }
    default: return py::none();
  }
}

namespace {

// Where json.dumps(allow_nan=False) found a NaN or an infinity: the first non-finite float under
// `o` as a Python subscript path (what + '["lights"][0]["irradiance"]'), or "" if none is found
// within the depth limit (lists, tuples, dicts and NumPy arrays, through tolist()).
std::string nonFinitePath(const py::handle& o, const std::string& path, int depth,
                          double& value) {
  if (depth > io::kMaxJsonDepth) return "";
  if (py::isinstance<py::float_>(o)) {
    value = o.cast<double>();
    return std::isfinite(value) ? "" : path;
  }
  if (py::isinstance<py::dict>(o)) {
    for (const auto& [k, v] : py::reinterpret_borrow<py::dict>(o)) {
      std::string p = nonFinitePath(v, fmt::format("{}[{}]", path, reprOf(k)), depth + 1, value);
      if (!p.empty()) return p;
    }
    return "";
  }
  if (py::isinstance<py::list>(o) || py::isinstance<py::tuple>(o)) {
    size_t i = 0;
    for (const auto& v : py::reinterpret_borrow<py::sequence>(o)) {
      std::string p = nonFinitePath(v, fmt::format("{}[{}]", path, i++), depth + 1, value);
      if (!p.empty()) return p;
    }
    return "";
  }
  if (!py::isinstance<py::str>(o) && py::hasattr(o, "tolist")) {
    try {
      return nonFinitePath(o.attr("tolist")(), path, depth + 1, value);
    } catch (const py::error_already_set&) {
      return "";
    }
  }
  return "";
}

}  // namespace

nlohmann::json fromPython(const py::handle& o, const std::string& what) {
  // NumPy arrays and scalars become lists and numbers (tolist), everything else as json.dumps
  // takes it.
  py::object def = py::cpp_function([](const py::object& x) -> py::object {
    if (py::hasattr(x, "tolist")) return x.attr("tolist")();
    throw py::type_error("not JSON serialisable: " + reprOf(x));
  });
  std::string text;
  try {
    // allow_nan=False: json.dumps would write NaN and Infinity, which are not JSON; refused here
    // by name instead of by the reader's "not valid JSON" at some column of the dumped text.
    text = py::module_::import("json")
               .attr("dumps")(o, py::arg("default") = def, py::arg("allow_nan") = false)
               .cast<std::string>();
  } catch (py::error_already_set& e) {
    // RecursionError (a RuntimeError) for nesting past Python's limit, ValueError for NaN,
    // TypeError for another type; the key or index is not known here, the value's kind is.
    if (e.matches(PyExc_ValueError)) {
      // json.dumps says only "Out of range float values are not JSON compliant": name the value.
      double value = 0.0;
      if (const std::string at = nonFinitePath(o, what, 0, value); !at.empty())
        throw py::value_error(fmt::format(
            "{} is {}: expected a finite number (JSON has no NaN or infinity)", at, value));
      throw py::value_error(
          fmt::format("{}: {}", what, py::str(e.value()).cast<std::string>()));
    }
    if (e.matches(PyExc_RecursionError))  // as parseJson's depth limit: ValueError
      throw py::value_error(fmt::format("{}: nested too deeply to be JSON (at most {} levels)",
                                       what, io::kMaxJsonDepth));
    if (e.matches(PyExc_TypeError))
      throw py::type_error(fmt::format("{}: {}", what, py::str(e.value()).cast<std::string>()));
    throw;
  }
  // The one JSON reader (its depth limit: toPython() and the readers of the result recurse).
  return io::parseJson(text, what);
}

}  // namespace translucent::python
