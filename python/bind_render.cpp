// SPDX-License-Identifier: GPL-3.0-or-later
// The real-time techniques (`translucent render`, apps/cli/cmd_render.cpp): render(scene,
// technique, **settings) and a Renderer that keeps a prepared technique between frames, on a
// headless OpenGL 4.5 context (EGL) made on first use.
#include <fmt/format.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <algorithm>
#include <limits>
#include <memory>
#include <mutex>

#include "bind.h"
#include "common.h"
#include "gl_lock.h"
#include "translucent/gpu/context.h"
#include "translucent/scene/scene.h"
#include "translucent/techniques/registry.h"
#include "translucent/techniques/technique.h"

namespace translucent::python {

namespace {

std::recursive_mutex& glMutex() {
  static std::recursive_mutex m;
  return m;
}
thread_local int glDepth = 0;  // GlLocks of this thread

}  // namespace

GlLock::GlLock() {
  {
    py::gil_scoped_release release;  // another thread may hold the lock and need the GIL
    glMutex().lock();
  }
  try {
    static gpu::Context* context = nullptr;
    if (!context) context = new gpu::Context();
    if (glDepth == 0) context->makeCurrent();
    gl_ = context;
  } catch (...) {
    glMutex().unlock();
    throw;
  }
  ++glDepth;
}

GlLock::~GlLock() {
  if (--glDepth == 0) gl_->release();
  glMutex().unlock();
}

namespace {

// The CLI's option of a technique parameter (its messages name it; pythonMessage turns it back
// into the keyword argument's name).
std::string optionName(const std::string& parameter) {
  std::string s = parameter;
  std::replace(s.begin(), s.end(), '_', '-');
  return "--" + s;
}

// A Python value as a technique parameter: bool, int, float or str (as the CLI's text).
techniques::ParameterValue toValue(const std::string& name, const py::handle& v) {
  if (py::isinstance<py::bool_>(v)) return v.cast<bool>();
  if (py::isinstance<py::int_>(v)) {
    const auto x = v.cast<long long>();  // OverflowError beyond 64 bits
    if (x < std::numeric_limits<int>::min() || x > std::numeric_limits<int>::max())
      throw ParameterError(fmt::format("{}={}: out of the range of an int parameter", name, x));
    return static_cast<int>(x);
  }
  if (py::isinstance<py::float_>(v)) return v.cast<double>();
  if (py::isinstance<py::str>(v)) return v.cast<std::string>();
  throw py::type_error(
      fmt::format("{}={}: expected a bool, int, float or str", name, reprOf(v)));
}

py::object valueToPython(const techniques::ParameterValue& v) {
  return std::visit([](const auto& x) -> py::object { return py::cast(x); }, v);
}

const char* typeName(techniques::ParameterType t) { return techniques::toString(t); }

scene::Scene sceneOf(const py::object& s) {
  if (s.is_none()) return scene::defaultScene();
  if (py::isinstance<scene::Scene>(s)) return s.cast<scene::Scene>();
  if (!py::isinstance<py::str>(s) && !py::isinstance(s, py::module_::import("os").attr("PathLike")))
    throw py::type_error(fmt::format(
        "scene={}: expected a translucent.Scene, a scene file name or None", reprOf(s)));
  return scene::loadScene(pathArgument(s, "scene"));
}

// A technique prepared for a scene, rendered frame after frame (parameters may change between
// frames; the technique redoes only what they invalidate).
class Renderer {
 public:
  Renderer(const py::object& sceneArg, const std::optional<std::string>& technique,
           std::optional<int> width, std::optional<int> height,
           const std::optional<std::string>& model, std::optional<double> time,
           const py::kwargs& settings) {
    // apps/cli/cmd_render.cpp: the scene with the overrides, checked, then the technique.
    scene_ = sceneOf(sceneArg);
    if (technique) {
      if (*technique != scene_.technique) scene_.settings.clear();
      scene_.technique = *technique;
    }
    if (width) scene_.camera.width = *width;
    if (height) scene_.camera.height = *height;
    if (model) scene_.model = *model;
    if (time) {
      if (!std::isfinite(*time))
        throw ParameterError(fmt::format("--time {}: expected a finite time", *time));
      scene_.time = *time;
    }
    scene_.camera.validate();
    (void)techniques::description(scene_.technique);  // an unknown name fails before GPU work
    std::vector<std::pair<std::string, techniques::ParameterValue>> values;
    for (const auto& [k, v] : settings) {
      const std::string name = k.cast<std::string>();
      values.emplace_back(name, toValue(name, v));
    }
    {
      py::gil_scoped_release release;
      scene::requireOutsideMesh(scene_, scene::loadSceneMesh(scene_));
    }
    GlLock lock;
    technique_ = techniques::make(scene_.technique);  // made with the context current
    techniques::applySettings(*technique_, scene_);
    for (const auto& [name, value] : values) set(name, value);
    py::gil_scoped_release release;
    technique_->prepare(scene_, lock.gl());
  }
  ~Renderer() {
    GlLock lock;  // the technique deletes its GL objects
    technique_.reset();
  }
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  void set(const std::string& name, const techniques::ParameterValue& value) {
    try {
      technique_->setParameter(name, value);
    } catch (const ParameterError& e) {
      throw ParameterError(fmt::format("{}: {}", optionName(name), e.what()));
    }
  }

  void setAll(const py::kwargs& settings) {
    for (const auto& [k, v] : settings) {
      const std::string name = k.cast<std::string>();
      set(name, toValue(name, v));
    }
  }

  // One frame rendered until converged (FrameRequest::converge, as the CLI), Ctrl-C checked
  // between the renders of a progressive technique.
  py::object render() {
    GlLock lock;
    techniques::Frame f;
    {
      py::gil_scoped_release release;
      for (int tries = 0; tries < 100000; ++tries) {
        techniques::FrameRequest request;
        request.converge = true;
        f = technique_->render(request);
        if (f.converged) break;
        py::gil_scoped_acquire gil;
        if (PyErr_CheckSignals() != 0) throw py::error_already_set();
      }
    }
    py::dict d;
    const std::vector<py::ssize_t> shape{f.height, f.width, 3};
    d["image"] = ownedArray(std::move(f.rgb), shape);
    py::dict layers;
    for (auto& [name, data] : f.layers) layers[py::str(name)] = ownedArray(std::move(data), shape);
    d["layers"] = layers;
    py::list passes;
    for (const auto& p : f.passes) {
      py::dict pd;
      pd["name"] = p.name;
      pd["ms"] = p.ms;
      pd["depth"] = p.depth;
      passes.append(result("RenderPass", pd));
    }
    d["passes"] = passes;
    d["total_ms"] = f.totalMs();
    d["converged"] = f.converged;
    d["notes"] = f.notes;
    d["technique"] = std::string(technique_->name());
    return result("Frame", d);
  }

  py::dict parameters() const {
    py::dict d;
    for (const auto& p : technique_->parameters())
      d[py::str(p.name)] = valueToPython(technique_->parameter(p.name));
    return d;
  }

  const scene::Scene& scene() const { return scene_; }

 private:
  scene::Scene scene_;
  std::unique_ptr<techniques::Technique> technique_;
};

constexpr const char* kRenderDoc = R"doc(
Renders a scene with a real-time technique on the GPU: `translucent render`.

    out = translucent.render("data/scenes/cube.json", "pointcloud", points=20000)
    out.image        # (height, width, 3) float32, linear radiance [W/(unit² sr)], rows from top
    out.layers       # {"exitance": (height, width, 3) float32, ...} (the EXR's layers)
    out.passes       # [RenderPass(name, ms, depth)]: GPU time of every pass; out.total_ms

scene: a translucent.Scene, a scene file name, or None (the built-in bunny).
technique: a name of translucent.techniques() (default: the scene's; another one starts from its
  own defaults, not the scene's settings).
width, height [pixels], model (a registered name or .bssrdf file), time (of the deformations):
  override the scene's, as the CLI's options.
**settings: technique parameters by name (translucent.technique_parameters(name)), e.g.
  points=20000, epsilon=0.1; bool, int, float or str (as typed on the command line).
The headless OpenGL 4.5 context (EGL; Mesa llvmpipe without a GPU) is made on the first call.
Progressive techniques render until converged. The GIL is released while preparing and rendering.
Returns a Frame. A bad argument or setting raises ValueError naming it (TypeError for a wrong
type).
)doc";

}  // namespace

void bindRender(py::module_& m) {
  m.def(
      "techniques",
      [] {
        py::dict d;
        for (const auto& n : techniques::names()) d[py::str(n)] = techniques::description(n);
        return d;
      },
      "The registered techniques: {name: one-line description}, in registration order.");
  m.def(
      "technique_parameters",
      [](const std::string& name) {
        const auto t = techniques::make(name);
        py::list out;
        for (const auto& p : t->parameters()) {
          py::dict d;
          d["name"] = p.name;
          d["type"] = typeName(p.type);
          d["default"] = valueToPython(p.value);
          if (p.type == techniques::ParameterType::Float ||
              p.type == techniques::ParameterType::Int) {
            d["min"] = p.min;
            d["max"] = p.max;
          }
          if (!p.choices.empty()) d["choices"] = p.choices;
          d["unit"] = p.unit;
          d["help"] = p.help;
          d["sweep"] = p.sweep;
          out.append(result("TechniqueParameter", d));
        }
        return out;
      },
      py::arg("name"),
      "A technique's parameters: name, type, default, range (min, max), choices, unit, help and "
      "sweep (the values `compare --sweep` renders; empty: not a quality parameter).");
  m.def(
      "gl_info",
      [] {
        GlLock lock;
        const auto& i = lock.gl().info();
        py::dict d;
        d["renderer"] = i.renderer;
        d["version"] = i.version;
        d["vendor"] = i.vendor;
        d["platform"] = i.platform;
        d["software"] = i.software;
        return result("GlInfo", d);
      },
      "The module's OpenGL context (made on first use): renderer, version, vendor, platform, "
      "software (True for Mesa's llvmpipe).");

  py::class_<Renderer>(m, "Renderer", R"doc(
A technique prepared for a scene, for frame after frame (a parameter sweep re-renders without
preparing again): Renderer(scene=None, technique=None, *, width=None, height=None, model=None,
time=None, **settings) takes render()'s arguments; .set(**settings) changes parameters,
.render() returns render()'s Frame, .parameters the current values.
)doc")
      .def(py::init<const py::object&, const std::optional<std::string>&, std::optional<int>,
                    std::optional<int>, const std::optional<std::string>&,
                    std::optional<double>, const py::kwargs&>(),
           py::arg("scene") = py::none(), py::arg("technique") = py::none(), py::kw_only(),
           py::arg("width") = py::none(), py::arg("height") = py::none(),
           py::arg("model") = py::none(), py::arg("time") = py::none())
      .def("set", &Renderer::setAll, "Sets technique parameters by name")
      .def("render", &Renderer::render, "Renders one frame (until converged)")
      .def_property_readonly("parameters", &Renderer::parameters)
      .def_property_readonly("scene", &Renderer::scene);

  m.def(
      "render",
      [](const py::object& scene, const std::optional<std::string>& technique,
         std::optional<int> width, std::optional<int> height,
         const std::optional<std::string>& model, std::optional<double> time,
         const py::kwargs& settings) {
        Renderer r(scene, technique, width, height, model, time, settings);
        return r.render();
      },
      py::arg("scene") = py::none(), py::arg("technique") = py::none(), py::kw_only(),
      py::arg("width") = py::none(), py::arg("height") = py::none(),
      py::arg("model") = py::none(), py::arg("time") = py::none(), kRenderDoc);
}

}  // namespace translucent::python
