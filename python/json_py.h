// SPDX-License-Identifier: GPL-3.0-or-later
// JSON (nlohmann) to Python objects and back, for dicts with the keys of the CLI's JSON files.
#pragma once

#include <pybind11/pybind11.h>

#include <nlohmann/json.hpp>

namespace translucent::python {

// null -> None, booleans, integers, floats, strings, arrays -> list, objects -> dict.
pybind11::object toPython(const nlohmann::json& j);
// A JSON-serialisable Python object (dicts, lists, numbers, strings, None; NumPy arrays as
// lists) through Python's json module.
nlohmann::json fromPython(const pybind11::handle& o);

}  // namespace translucent::python
