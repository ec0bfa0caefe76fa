// SPDX-License-Identifier: GPL-3.0-or-later
// The extension module `translucent._translucent`, which the package `translucent`
// (python/translucent/__init__.py) re-exports: the library's media, models, path tracers, scenes,
// techniques and compare, with NumPy arrays in and out. See README.md, "Python".
#include <pybind11/pybind11.h>
#include <pybind11/stl/filesystem.h>

#include "bind.h"
#include "common.h"
#include "translucent/io/resources.h"
#include "translucent/optics/medium.h"

namespace py = pybind11;

PYBIND11_MODULE(_translucent, m) {
  m.doc() = R"doc(The compiled part of the package `translucent`: import `translucent`, which
re-exports it with the result types and the type stubs.)doc";
  // ParameterError and the other std::invalid_argument (bad parameters, an unknown model name)
  // -> ValueError, their command-line option names turned into the Python arguments' names
  // (common.h pythonMessage). pybind11 maps every other std::exception to RuntimeError.
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const std::invalid_argument& e) {
      PyErr_SetString(PyExc_ValueError, translucent::python::pythonMessage(e.what()).c_str());
    }
  });
  translucent::python::bindOptics(m);
  translucent::python::bindBssrdf(m);
  translucent::python::bindReference(m);
  translucent::python::bindScene(m);
  translucent::python::bindRender(m);
  translucent::python::bindCompare(m);
  m.def(
      "share_directory", [] { return translucent::io::shareDirectory(); },
      R"doc(The folder holding the shaders/ and data/ the module reads (a pathlib.Path): the
package's own share/translucent in an installed package; $TRANSLUCENT_SHARE_DIR when set; the
source tree in a build-tree run. RuntimeError listing the places looked in when none holds
them.)doc");
  m.attr("__version__") = TRANSLUCENT_VERSION;
}
