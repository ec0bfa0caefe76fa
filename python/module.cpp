// SPDX-License-Identifier: GPL-3.0-or-later
// The Python module `translucent` (issue 18): the library's media, models, path tracers, scenes,
// techniques and compare, with NumPy arrays in and out. See README.md, "Python".
#include <pybind11/pybind11.h>

#include "bind.h"
#include "translucent/optics/medium.h"

namespace py = pybind11;

PYBIND11_MODULE(translucent, m) {
  m.doc() = R"doc(Translucent: rendering, comparing and validating translucent materials.

Media and presets (Medium, presets(), preset()), BSSRDF models by name (model(), model_names(),
profile(); .bssrdf files: BssrdfModel), the (Rd, ℓd) inversion (invert()), the reference path
tracers (pathtrace_slab(), pathtrace_sphere(), pathtrace_mesh()), the model integrated over the
lit sphere (integrate_sphere()), scenes (Scene), the real-time
techniques on a headless GL context (render(), Renderer, techniques(), technique_parameters()) and
compare(). Lengths are in scene units (mm unless a medium's scale says otherwise), coefficients
in 1/mm, images (height, width, 3) float32 arrays, rows from the top. Bad parameters raise
ValueError with the command line's message; other failures RuntimeError. Long calls release the
GIL; Ctrl-C stops the path tracers and compare with KeyboardInterrupt, whose `partial_result`
attribute holds what was computed so far. See README.md, "Python".)doc";
  // ParameterError (bad parameters, named as the CLI names them) -> ValueError, with the message.
  // (pybind11 maps the other std::invalid_argument, e.g. an unknown model name, to ValueError and
  // every other std::exception to RuntimeError.)
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const translucent::ParameterError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    }
  });
  translucent::python::bindOptics(m);
  translucent::python::bindBssrdf(m);
  translucent::python::bindReference(m);
  translucent::python::bindScene(m);
  translucent::python::bindRender(m);
  translucent::python::bindCompare(m);
  m.attr("__version__") = TRANSLUCENT_VERSION;
}
