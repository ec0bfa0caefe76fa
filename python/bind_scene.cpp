// SPDX-License-Identifier: GPL-3.0-or-later
// Scenes (the one JSON format of every renderer: src/scene/scene.h) and the mesh path tracer
// (`translucent pathtrace mesh`, apps/cli/cmd_render_reference.cpp runPathtraceMesh).
#include <fmt/format.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <algorithm>
#include <cmath>
#include <utility>
#include <nlohmann/json.hpp>

#include "translucent/compare/compare.h"
#include "bind.h"
#include "common.h"
#include "translucent/geometry/mesh.h"
#include "translucent/io/json.h"
#include "json_py.h"
#include "translucent/scene/mesh_scene.h"
#include "translucent/reference/camera_paths.h"
#include "translucent/reference/gpu/device.h"
#include "translucent/reference/mesh_tracer.h"
#include "translucent/scene/scene.h"

namespace translucent::python {
namespace {

// apps/cli/cmd_render_reference.cpp medianRelativeError: per channel, the median of se / value
// over the pixels with value > 0.
std::vector<double> medianRelativeError(const reference::McImage& img) {
  const std::vector<float> value = img.rgb(), se = img.rgbStdError();
  std::vector<double> out;
  for (size_t c = 0; c < 3; ++c) {
    std::vector<double> rel;
    for (size_t p = 0; 3 * p + c < value.size(); ++p)
      if (value[3 * p + c] > 0.0f) rel.push_back(double(se[3 * p + c]) / double(value[3 * p + c]));
    if (rel.empty()) {
      out.push_back(0.0);
      continue;
    }
    std::nth_element(rel.begin(), rel.begin() + long(rel.size() / 2), rel.end());
    out.push_back(rel[rel.size() / 2]);
  }
  return out;
}

// An image side for the width and height setters: the range of the scene file's camera.width.
int imageSide(int pixels, const char* what) {
  if (pixels < 1 || pixels > 16384)
    throw ParameterError(fmt::format("{} is {}: expected pixels in [1, 16384]", what, pixels));
  return pixels;
}

scene::Scene sceneFromDict(const py::handle& d, const std::filesystem::path& base_dir) {
  return scene::parseScene(fromPython(d, "d").dump(), base_dir, "scene dict");
}

}  // namespace

void bindScene(py::module_& m) {
  py::class_<scene::Scene>(m, "Scene", R"doc(
A scene: mesh and placement, material, lights, camera, technique with its settings, display
(the JSON format of `translucent render` and `translucent pathtrace mesh --scene`; see
src/scene/scene.h for every key).

    s = translucent.Scene.load("data/scenes/cube.json")
    d = s.to_dict(); d["material"]["preset"] = "Skin1"
    s = translucent.Scene.from_dict(d)       # parsed and checked as a file would be
    s.save("skin_cube.json")                 # the same JSON as the CLI writes

Parsing is strict: an unknown key or a bad value raises ValueError naming it. Relative file
names are found beside the scene file (from_dict, from_json: in base_dir), else on the data
search path ($TRANSLUCENT_DATA).
)doc")
      .def_static(
          "load", [](const std::filesystem::path& p) { return scene::loadScene(p); },
          py::arg("path"), "Reads and checks a scene file")
      .def_static(
          "from_json",
          [](const std::string& text, const std::filesystem::path& base_dir) {
            return scene::parseScene(text, base_dir, "scene JSON");
          },
          py::arg("text"), py::arg("base_dir") = std::filesystem::path("."),
          "A scene from JSON text; relative file names are taken relative to base_dir")
      .def_static("from_dict", &sceneFromDict, py::arg("d"),
                  py::arg("base_dir") = std::filesystem::path("."),
                  "A scene from a dict with the file's keys (what to_dict returns)")
      .def_static("default", &scene::defaultScene,
                  "The built-in scene: glmark2's closed bunny in Marble, lit from behind and "
                  "above (what `translucent render` renders without --scene)")
      .def("to_json", &scene::toJson,
           "The scene as JSON text (Scene.from_json(s.to_json()) is the same scene)")
      .def(
          "to_dict",
          [](const scene::Scene& s) { return toPython(io::parseJson(scene::toJson(s), "the scene")); },
          "The scene as a dict with the file's keys")
      .def(
          "save", [](const scene::Scene& s, const std::filesystem::path& p) { scene::saveScene(s, p); },
          py::arg("path"), "Writes to_json() to `path` (ValueError naming the file when it cannot)")
      .def_readwrite("technique", &scene::Scene::technique, "Technique name (translucent.techniques())")
      .def_property(
          "settings", [](const scene::Scene& s) { return s.settings; },
          [](scene::Scene& s, const py::dict& d) {
            // Explicitly by type: pybind11's variant caster would take an int for a bool.
            std::map<std::string, scene::Setting> out;
            for (const auto& [k, v] : d) {
              const std::string name = k.cast<std::string>();
              if (py::isinstance<py::bool_>(v))
                out[name] = v.cast<bool>();
              else if (py::isinstance<py::int_>(v) || py::isinstance<py::float_>(v))
                // A NaN or an infinity would be written as null by to_json (not read back).
                out[name] = finiteArgument(v.cast<double>(), ("technique." + name).c_str());
              else if (py::isinstance<py::str>(v))
                out[name] = v.cast<std::string>();
              else
                throw ParameterError(fmt::format("technique.{}: {} is not a bool, number or str",
                                                 name, reprOf(v)));
            }
            s.settings = std::move(out);
          },
          "Technique settings {name: bool | float | str} (a copy: assign a dict to change them; "
          "validated by the technique when rendering)")
      .def_property(
          "model", [](const scene::Scene& s) { return s.model; },
          [](scene::Scene& s, const std::string& model) {
            // As the scene file's material.model (an empty name does not read back).
            if (model.empty())
              throw ParameterError("model is '': expected a model name or a .bssrdf file");
            s.model = checkNoNul(model, "model");
          },
          "BSSRDF model of the material: a registered name or a .bssrdf file")
      // The numbers are checked as the scene file's reader checks them (scene.cpp), so that a
      // scene edited through them is one that to_json() writes and from_json() reads back: a
      // NaN was stored and read back silently, and written as null (tests/python/hostile_check.py).
      .def_property(
          "time", [](const scene::Scene& s) { return s.time; },
          [](scene::Scene& s, double t) {
            // The scene file's limit (scene.cpp), so that to_json() reads back.
            if (!(std::fabs(finiteArgument(t, "time")) <= 1e15))
              throw ParameterError(fmt::format("time is {}: expected a finite number of magnitude "
                                               "at most 1e15", t));
            s.time = t;
          },
          "Time of the mesh deformations [s]")
      .def_property(
          "exposure", [](const scene::Scene& s) { return s.exposure; },
          [](scene::Scene& s, double e) {
            if (!(std::fabs(e) <= 64.0))
              throw ParameterError(fmt::format("exposure is {}: expected stops in [-64, 64]", e));
            s.exposure = e;
          },
          "Display exposure [stops], in [-64, 64]")
      .def_property(
          "gamma", [](const scene::Scene& s) { return s.gamma; },
          [](scene::Scene& s, double g) {
            if (!(g >= 0.01 && g <= 100.0))
              throw ParameterError(
                  fmt::format("gamma is {}: expected a display gamma in [0.01, 100]", g));
            s.gamma = g;
          },
          "Display gamma, in [0.01, 100]")
      .def_property(
          "tonemap", [](const scene::Scene& s) { return std::string(analysis::toString(s.tonemap)); },
          [](scene::Scene& s, const std::string& op) {
            if (op != "clamp" && op != "reinhard")
              throw ParameterError(fmt::format("tonemap '{}': expected clamp or reinhard", op));
            s.tonemap = analysis::parseToneOperator(op, "tonemap");
          },
          "Display tone map: 'clamp' (exposure, clamped to white) or 'reinhard' (s/(1+s), s = "
          "key x exposure / the rendered pixels' average; Reinhard et al. 2002)")
      .def_property(
          "tonemap_key", [](const scene::Scene& s) { return s.tonemap_key; },
          [](scene::Scene& s, double k) {
            if (!(k > 0.0 && k <= 100.0))
              throw ParameterError(fmt::format("tonemap_key is {}: expected a key in (0, 100]", k));
            s.tonemap_key = k;
          },
          "Reinhard tone map: the rendered pixels' average displays as key/(1+key), in (0, 100]")
      .def_property(
          "cone_angle", [](const scene::Scene& s) { return s.cone_angle; },
          [](scene::Scene& s, double a) {
            if (!(a > 0.0 && a <= 90.0))
              throw ParameterError(fmt::format("cone_angle is {}: expected degrees in (0, 90]", a));
            s.cone_angle = a;
          },
          "Path tracer: half-angle of the cone-averaged radiance [degrees], in (0, 90]")
      .def_property(
          "width", [](const scene::Scene& s) { return s.camera.width; },
          [](scene::Scene& s, int w) { s.camera.width = imageSide(w, "width"); },
          "Image width [pixels], 1 to 16384")
      .def_property(
          "height", [](const scene::Scene& s) { return s.camera.height; },
          [](scene::Scene& s, int h) { s.camera.height = imageSide(h, "height"); },
          "Image height [pixels], 1 to 16384")
      .def_property_readonly(
          "medium", [](const scene::Scene& s) { return s.medium; },
          "The material's medium (a copy; edit the material through to_dict/from_dict)")
      .def_property_readonly(
          "mesh_file", [](const scene::Scene& s) { return s.mesh_file; }, "The mesh file, resolved")
      .def("__repr__", [](const scene::Scene& s) {
        return fmt::format("<Scene {} {}x{} technique {}>", s.mesh_file.filename().string(),
                           s.camera.width, s.camera.height, s.technique);
      });

  m.def(
      "pathtrace_mesh",
      [](const py::object& sceneArg, std::optional<double> photons, int passes, uint64_t seed,
         int threads, std::optional<double> time, const std::string& device,
         std::optional<double> time_limit, bool split_orders, const std::string& method,
         std::optional<double> samples) {
        validatePasses(passes, threads);
        if (method != "light" && method != "camera")
          throw ParameterError(
              fmt::format("method='{}': expected \"light\" or \"camera\"", method));
        if (method == "camera" && photons)
          throw ParameterError("photons: the camera method traces camera paths per pixel "
                               "(samples=), not photons");
        if (method == "light" && samples)
          throw ParameterError("samples: camera paths per pixel are the camera method's "
                               "(method=\"camera\"); the light method takes photons=");
        Interruptible stop(time_limit);
        scene::Scene scene = py::isinstance<scene::Scene>(sceneArg)
                                 ? sceneArg.cast<scene::Scene>()
                                 : scene::loadScene(pathArgument(sceneArg, "scene"));
        if (time) {
          if (!std::isfinite(*time))
            throw ParameterError(fmt::format("--time {}: expected a finite time", *time));
          scene.time = *time;
        }
        // Loading (and hole filling, alpha wrapping) the mesh and building the tracer's BVH can
        // take seconds: without the GIL, as the passes. `make(mesh)` builds the tracer (either
        // method), `count` per pass.
        int passesRun = 0;
        auto trace = [&](auto&& make, uint64_t count) {
          decltype(make(std::declval<const geometry::TriangleMesh&>())) tracer;
          {
            py::gil_scoped_release release;
            const geometry::TriangleMesh mesh = scene::loadSceneMesh(scene);
            scene::requireOutsideMesh(scene, mesh);
            tracer = make(mesh);
            stop.restart();  // the CLI's time limit counts the tracing, not the loading
            runPasses(passes, stop, [&](const reference::ProgressCallback& cb) {
              ++passesRun;
              return tracer->addPass(count, cb).partial;
            });
          }
          stop.finish();
          return tracer;
        };
        // The keys both methods' results share (the CLI's --json).
        auto common = [&](const auto& tracer, py::dict& d) {
          const auto& st = tracer.stats();
          d["scene"] = toPython(io::parseJson(scene::toJson(scene), "the scene"));
          d["triangles"] = tracer.body().triangleCount();
          d["passes"] = passesRun;
          d["seconds"] = st.seconds;
          d["scattering_events"] = st.scattering_events;
          d["median_relative_stderr"] = medianRelativeError(tracer.images().exitance);
          d["majorant_violations"] = tracer.majorantViolations();
          d["threads"] = st.threads;
          d["partial"] = st.partial || stop.interrupted() || stop.timedOut();
          d["seed"] = seed;
        };
        // Before the tracer, on this thread: the context outlives the walker the tracer holds.
        const reference::TraceDevice dev = reference::openTraceDevice(device, "device");
        if (method == "camera") {
          // `pathtrace mesh --method camera` (reference/camera_paths.h).
          const uint64_t spp = photonCount(samples.value_or(64.0), "samples");
          const auto tracer = trace(
              [&](const geometry::TriangleMesh& mesh) {
                reference::CameraPathOptions o;
                o.seed = seed;
                o.threads = threads;
                o.split_orders = split_orders;
                auto t = std::make_unique<reference::CameraPathTracer>(
                    mesh, scene::sceneMaterial(scene, mesh), scene::referenceLights(scene),
                    scene.camera, o);
                reference::useDevice(dev, device, *t, mesh, scene.mesh_file.string(), "device");
                return t;
              },
              spp);
          const auto& st = tracer->stats();
          py::dict d = tracerImageDict(*tracer);
          common(*tracer, d);
          d["method"] = "camera";
          d["samples_per_pixel"] = st.samples;
          d["paths"] = st.paths;
          d["shadow_rays"] = st.shadow_rays;
          d["complement_photons"] = st.complement_photons;
          d["complement_cone_angle"] = tracer->complementCone();
          d["device"] = tracer->device();
          py::object out = result("MeshTrace", d);
          stop.rethrow(out);
          return out;
        }
        const uint64_t n = photonCount(photons.value_or(1e6));
        const auto tracer = trace(
            [&](const geometry::TriangleMesh& mesh) {
              reference::TracerOptions o{seed, threads};
              o.split_orders = split_orders;
              auto t = std::make_unique<reference::MeshPathTracer>(
                  mesh, scene::sceneMaterial(scene, mesh), scene::referenceLights(scene),
                  scene.camera, scene.cone_angle, o);
              reference::useDevice(dev, device, *t, mesh, scene.mesh_file.string(), "device");
              return t;
            },
            n);
        const auto& st = tracer->stats();
        py::dict d = tracerImageDict(*tracer);
        common(*tracer, d);
        d["method"] = "light";
        d["photons_per_channel"] = st.photons.empty() ? 0 : st.photons[0];
        d["photons_per_second"] = st.photonsPerSecond();
        d["photons_in_several_pixels"] = tracer->severalPixelPhotons();
        d["device"] = tracer->device();
        d["flux_per_channel"] = fluxList(st);
        analysis::ReferenceRequest req;
        req.kind = analysis::ReferenceKind::Physical;
        req.count = st.photons.empty() ? 0 : st.photons[0];
        req.seed = seed;
        req.device = tracer->device() == "cpu" ? "cpu" : "gpu";  // as pathtrace mesh keys it
        d["reference_key"] = analysis::referenceKey(scene, req);
        py::object out = result("MeshTrace", d);
        stop.rethrow(out);
        return out;
      },
      py::arg("scene"), py::kw_only(), py::arg("photons") = py::none(), py::arg("passes") = 1,
      py::arg("seed") = 1, py::arg("threads") = 0, py::arg("time") = py::none(),
      py::arg("device") = "auto", py::arg("time_limit") = py::none(),
      py::arg("split_orders") = false, py::arg("method") = "light",
      py::arg("samples") = py::none(), R"doc(
Photon tracing in the scene's closed triangle mesh under its lights, seen by its camera:
`translucent pathtrace mesh --scene FILE`.

scene: a translucent.Scene or a scene file name. method: "light" (photons from the lights,
`photons` per channel per pass, default 1e6) or "camera" (paths from the camera with next-event
estimation, `samples` per pixel and channel per pass, default 64: `pathtrace mesh --method
camera`; its "cone_radiance" is the true radiance, cone half-angle 0). passes
(accumulated), seed, threads (0: all cores): the same seed gives the same images on any thread
count. time: the deformations' time (the scene's when None). time_limit [s]: stop then,
"partial": True. device: "cpu", "gpu" (the GL compute-shader walk against a BVH; homogeneous
materials and 3D fields, deformed or not: others are a ValueError naming why) or "auto" (the
GPU on a hardware GPU where the walk can trace the scene, else the CPU), as `pathtrace mesh
--device`; "device" in the result names what traced.

Returns a MeshTrace: "exitance" (radiant exitance B [W/unit²]), "radiance" (Ft(η, ω_o) B / π),
"cone_radiance" (true radiance towards the camera, cone-averaged [W/(unit² sr)]), each a
(height, width, 3) float32 array, rows from the top, with "<name>_stderr"; with split_orders,
the same per scattering order ("exitance_unscattered", "exitance_single", "exitance_multiple",
..., each with "_stderr"; they add up to "exitance"); and the keys of the
CLI's --json: scene, triangles, photons_per_channel, seconds, photons_per_second,
scattering_events, photons_in_several_pixels, median_relative_stderr, majorant_violations,
threads, flux_per_channel, partial, seed, reference_key (what compare's --reference-from checks);
the camera method's: method, samples_per_pixel, paths, shadow_rays, complement_photons and
complement_cone_angle (the light-traced complement at eta != 1) instead of the photon counts.
The GIL is released while loading and tracing; Ctrl-C raises KeyboardInterrupt with the partial
result as its `partial_result`.
)doc");
}

}  // namespace translucent::python
