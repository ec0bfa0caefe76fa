// SPDX-License-Identifier: GPL-3.0-or-later
// Shared pieces of the Python bindings: NumPy arrays that own C++ buffers (no copy), media from
// keyword arguments as the CLI builds them, and long calls that release the GIL and stop on
// Ctrl-C.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <chrono>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "translucent/optics/medium.h"
#include "translucent/reference/camera.h"
#include "translucent/reference/slab.h"
#include "translucent/reference/transport.h"

namespace translucent::python {

namespace py = pybind11;

// A NumPy array of `shape` that takes over `data` (moved to the heap, freed with the array):
// large images leave C++ without a copy. C-contiguous.
template <class T>
py::array_t<T> ownedArray(std::vector<T>&& data, std::vector<py::ssize_t> shape) {
  auto* owned = new std::vector<T>(std::move(data));
  py::capsule free(owned, [](void* p) { delete static_cast<std::vector<T>*>(p); });
  return py::array_t<T>(shape, owned->data(), free);
}

// A float64 array of three values (an RGB triple).
py::array_t<double> rgbArray(const Rgb& v);

// The message of a ParameterError (the library's, worded for the command line) for Python: every
// option name becomes the Python argument's, "--sigma-a" -> "sigma_a", and an option followed by
// its quoted value an assignment, "--channel 'x'" -> "channel='x'". The module's exception
// translator applies it to every ValueError it raises.
std::string pythonMessage(std::string_view message);

// `fields` as an instance of the result type `type` of translucent._results (a Result: its fields
// as attributes, and a mapping with the dict's keys).
py::object result(const char* type, py::dict fields);

// repr(value), for messages: at most 200 characters, and "<type object>" when repr() raises
// (a list nested past the recursion limit, a class whose __repr__ fails).
std::string reprOf(const py::handle& value);

// An RGB triple from a number (grey) or a sequence of three numbers: TypeError naming the
// argument `what` for anything else (None, text), ValueError for another count of numbers.
Rgb toRgb(const py::handle& value, const std::string& what);

// An RGB triple of finite values (toRgb, then ValueError naming `what` and the channel).
Rgb finiteRgb(const py::handle& value, const std::string& what);

// An array of radii or other sample positions: any array-like of numbers (converted to a
// C-contiguous float64 array), each value finite and in [lo, hi] (hi excluded when
// `open_hi`). TypeError naming the argument `what` for None, text or what NumPy cannot convert;
// ValueError naming the first value out of range and its index otherwise.
py::array_t<double, py::array::c_style | py::array::forcecast> checkedArray(
    const py::object& values, const char* what, double lo, double hi, bool open_hi = false);

// A file name argument: str or os.PathLike; TypeError naming the argument otherwise, ValueError
// for a name with a NUL character.
std::filesystem::path pathArgument(const py::handle& value, const char* what);

// `name` (a model name or file name the library may open), unless it holds a NUL character:
// ValueError naming the argument `what` then.
const std::string& checkNoNul(const std::string& name, const char* what);

// A finite number; ValueError naming the argument otherwise.
double finiteArgument(double value, const char* what);

// The medium as the CLI's --preset/--sigma-a/--sigma-s/--g/--eta/--scale make it
// (apps/cli/options.cpp MediumOptions::medium): explicit coefficients (g default 0, η 1.3), or a
// preset (default `default_preset`) with g and η overriding its own; validated.
// The material preset of a function that takes `material=` (the CLI's --material) and its
// deprecated spelling `preset=`: the one given (preset= with a DeprecationWarning naming
// `function`); both given is a ParameterError.
std::optional<std::string> materialArgument(const std::optional<std::string>& material,
                                            const std::optional<std::string>& preset,
                                            const char* function);

Medium mediumFromArgs(const std::optional<std::string>& preset, const py::object& sigma_a,
                      const py::object& sigma_s, std::optional<double> g,
                      std::optional<double> eta, double scale,
                      const std::string& default_preset = "Marble");

// Runs a long C++ call without the GIL. The progress callback it hands out polls Python's signal
// handlers (with the GIL taken back) about ten times a second, and `time_limit` seconds; it
// returns false to stop the call when a handler raised (Ctrl-C: KeyboardInterrupt) or the limit
// passed. After the call, rethrow() raises the handler's exception, if any, with the partial
// result attached as its attribute `partial_result`.
class Interruptible {
 public:
  explicit Interruptible(std::optional<double> time_limit = std::nullopt);
  // Called from a progress callback (on the calling thread, GIL released) with the work done
  // and the total: false to stop. Like the CLI's progress bar (apps/cli/progress.h), a run
  // without a time limit whose projected total passes 24 hours after 5 s is stopped, and
  // finish() raises ValueError with the measured rate.
  bool poll(uint64_t done, uint64_t total);
  // The callback for one call of reference::ProgressCallback.
  reference::ProgressCallback callback();
  double elapsed() const;
  // Restarts the clock of the time limit (when the work it limits begins, after loading).
  void restart() { start_ = std::chrono::steady_clock::now(); }
  // After the call, with the GIL held: the refusal above, if any.
  void finish() const;
  bool interrupted() const { return error_.has_value(); }
  bool timedOut() const { return timed_out_; }
  // With the GIL held: raises the pending exception (KeyboardInterrupt) carrying `partial`.
  void rethrow(const py::object& partial);

 private:
  std::optional<double> time_limit_;
  std::chrono::steady_clock::time_point start_;
  std::optional<py::error_already_set> error_;
  bool timed_out_ = false;
  std::string refused_;
};

// The three quantities of a photon tracer's camera images and their standard errors as
// (height, width, 3) float32 arrays: "exitance", "exitance_stderr", "radiance", ... (the layers
// of the CLI's EXR).
// `suffix` follows each quantity's name ("exitance" + suffix, then "_stderr").
py::dict imageDict(const reference::CameraImages& images, const std::string& suffix = "");
// imageDict of a path tracer's images (SpherePathTracer, MeshPathTracer), and when it splits
// scattering orders those of each order as "exitance_single", "exitance_single_stderr", ...
template <class Tracer>
py::dict tracerImageDict(const Tracer& tracer);
// Per channel: emitted, entered, exited, escaped flux with standard errors (the CLI's
// "flux_per_channel").
py::list fluxList(const reference::TransportStats& stats);
// The CLI's passes loop (apps/cli/cmd_render_reference.cpp runPasses), GIL released: pass(cb)
// returns whether it was stopped. Returns whether the run is partial.
bool runPasses(int passes, Interruptible& stop,
               const std::function<bool(const reference::ProgressCallback&)>& pass);
void validatePasses(int passes, int threads);

// Validations the CLI makes before tracing (apps/cli/cmd_pathtrace.cpp), with its messages.
uint64_t photonCount(double photons, const char* option = "--photons");

}  // namespace translucent::python
