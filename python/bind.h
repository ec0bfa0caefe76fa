// SPDX-License-Identifier: GPL-3.0-or-later
// The binding functions, one per part of the library (module.cpp calls them in order).
#pragma once

#include <pybind11/pybind11.h>

namespace translucent::python {

void bindOptics(pybind11::module_& m);     // Medium, presets, invert
void bindBssrdf(pybind11::module_& m);     // models, profiles, profile()
void bindReference(pybind11::module_& m);  // slab, layered slab and sphere path tracers
void bindScene(pybind11::module_& m);      // scenes and the mesh path tracer
void bindRender(pybind11::module_& m);     // techniques: render(), Renderer
void bindCompare(pybind11::module_& m);    // compare()

}  // namespace translucent::python
