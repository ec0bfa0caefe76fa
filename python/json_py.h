// SPDX-License-Identifier: GPL-3.0-or-later
// JSON (nlohmann) to Python objects and back, for dicts with the keys of the CLI's JSON files.
#pragma once

#include <pybind11/pybind11.h>

#include <nlohmann/json.hpp>

namespace translucent::python {

// null -> None, booleans, integers, floats, strings, arrays -> list, objects -> dict.
pybind11::object toPython(const nlohmann::json& j);
// A JSON-serialisable Python object (dicts, lists, numbers, strings, None; NumPy arrays as
// lists) through Python's json module. `what` names the argument in errors: TypeError for a type
// JSON cannot hold, ValueError for NaN or an infinity (which JSON cannot hold either) and for
// nesting past Python's recursion limit or io::kMaxJsonDepth.
nlohmann::json fromPython(const pybind11::handle& o, const std::string& what);

}  // namespace translucent::python
