// SPDX-License-Identifier: GPL-3.0-or-later
#include "json_py.h"

#include <pybind11/pybind11.h>

#include <string>

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

nlohmann::json fromPython(const py::handle& o) {
  // NumPy arrays and scalars become lists and numbers (tolist), everything else as json.dumps
  // takes it.
  py::object def = py::cpp_function([](const py::object& x) -> py::object {
    if (py::hasattr(x, "tolist")) return x.attr("tolist")();
    throw py::type_error("not JSON serialisable: " + py::str(py::repr(x)).cast<std::string>());
  });
  const std::string text =
      py::module_::import("json").attr("dumps")(o, py::arg("default") = def).cast<std::string>();
  // The one JSON reader (its depth limit: toPython() and the readers of the result recurse).
  return io::parseJson(text, "the Python value");
}

}  // namespace translucent::python
