// SPDX-License-Identifier: GPL-3.0-or-later
// The reference path tracers: the slab (MCML's one- and multi-layer modes) and the lit sphere.
// Each call builds its inputs as the CLI's subcommand does (apps/cli/cmd_pathtrace.cpp,
// cmd_render_reference.cpp), with the same checks and messages, and returns a dict with the
// keys of the subcommand's JSON (arrays as NumPy arrays), images as H×W×3 float32 arrays.
#include <fmt/format.h>
#include <pybind11/stl.h>

#include <cmath>
#include <filesystem>
#include <optional>
#include <nlohmann/json.hpp>
#include <numbers>

#include "bind.h"
#include "common.h"
#include "json_py.h"
#include "translucent/optics/presets.h"
#include "translucent/reference/camera_paths.h"
#include "translucent/reference/gpu/device.h"
#include "translucent/reference/layered_slab.h"
#include "translucent/reference/slab_request.h"
#include "translucent/bssrdf/registry.h"
#include "translucent/reference/sphere.h"
#include "translucent/reference/sphere_integration.h"
#include "translucent/reference/gpu/sphere_integration_gpu.h"
#include "translucent/gpu/bssrdf_profiles.h"
#include "gl_lock.h"
#include "translucent/bssrdf/bssrdf_file.h"
#include "translucent/bssrdf/tabulated.h"

namespace translucent::python {
namespace {

using reference::SlabResult;

// The CLI's JSON (reference::slabResultJson, what `pathtrace slab --json` writes) as a dict; the
// radial and angular arrays become NumPy arrays.
// The radial and angular tallies of `d` (the JSON's lists) as float64 arrays.
void profileArrays(py::dict& d, const reference::TraceOptions& o, reference::RadialProfileTally&& rad,
                   reference::AngularTally&& ang) {
  auto vec = [](std::vector<double>&& v) {
    const auto n = static_cast<py::ssize_t>(v.size());
    return ownedArray(std::move(v), {n});
  };
  if (o.radial_bins > 0) {
    py::dict radial = d["radial"];
    radial["r"] = vec(std::move(rad.r));
    radial["rd"] = vec(std::move(rad.rd));
    radial["rd_stderr"] = vec(std::move(rad.rd_stderr));
  }
  if (o.angle_bins > 0) {
    py::dict angular = d["angular"];
    std::vector<double> deg;
    for (double t : ang.theta) deg.push_back(t * 180.0 / std::numbers::pi);
    angular["theta_deg"] = vec(std::move(deg));
    angular["rd"] = vec(std::move(ang.rd));
    angular["rd_stderr"] = vec(std::move(ang.rd_stderr));
    if (o.radial_bins > 0) {
      const auto rows = static_cast<py::ssize_t>(o.radial_bins);
      const auto cols = static_cast<py::ssize_t>(o.angle_bins);
      angular["rd_r_theta"] = ownedArray(std::move(ang.rd_r_theta), {rows, cols});
      angular["rd_r_theta_stderr"] = ownedArray(std::move(ang.rd_r_theta_stderr), {rows, cols});
    }
  }
}

py::dict slabDict(const reference::SlabRun& run, SlabResult&& r) {
  py::dict d = toPython(reference::slabResultJson(run, r));
  const reference::TraceOptions& o = run.options;
  profileArrays(d, o, std::move(r.radial), std::move(r.angular));
  py::dict orders = d["scattering_orders"];
  for (reference::ScatteringOrder k : reference::kAllScatteringOrders) {
    py::dict part = orders[reference::toString(k)];
    auto& ord = r.orders[static_cast<size_t>(k)];
    profileArrays(part, o, std::move(ord.radial), std::move(ord.angular));
  }
  return d;
}

py::object pathtraceSlab(const reference::SlabRequest& request, const py::object& layersArg,
                       std::optional<double> time_limit) {
  // Layers: a file name (what --layers takes), or the list itself (the file's JSON array).
  std::optional<std::vector<reference::SlabLayer>> layers;
  std::string what = "layers";
  if (!layersArg.is_none()) {
    if (py::isinstance<py::str>(layersArg) ||
        py::isinstance(layersArg, py::module_::import("os").attr("PathLike"))) {
      what = pathArgument(layersArg, "layers").string();
      layers = reference::loadSlabLayers(what);
    } else {
      if (!py::isinstance<py::list>(layersArg) && !py::isinstance<py::tuple>(layersArg))
        throw py::type_error(fmt::format(
            "layers={}: expected a list of dicts (one per layer, top first) or a file name",
            reprOf(layersArg)));
      std::string text;
      try {
        text = fromPython(layersArg, "layers").dump();
      } catch (const py::error_already_set& e) {
        throw py::type_error(fmt::format("layers: {}", e.what()));
      }
      layers = reference::parseSlabLayers(text, "layers");
    }
  }
  const reference::SlabRun run = reference::makeSlabRun(request, layers, what);
  // The GL context (device "gpu", or "auto" on a hardware GPU) is current on this thread, which
  // traces with the GIL released.
  const reference::TraceDevice device = reference::openTraceDevice(run.device, "device");
  Interruptible stop(time_limit);
  SlabResult r;
  {
    py::gil_scoped_release release;
    r = reference::traceSlabRun(device, run, stop.callback());
  }
  stop.finish();
  py::dict d = slabDict(run, std::move(r));
  if (run.layered) d["layers_file"] = py::isinstance<py::str>(layersArg) ? what : std::string();
  py::object out = result("SlabResult", d);
  stop.rethrow(out);
  return out;
}

// apps/cli/cmd_render_reference.cpp parseVec3, for a sequence of three numbers.
glm::dvec3 toVec3(const py::handle& value, const char* option) {
  std::vector<double> v;
  const std::string text = reprOf(value);
  auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(value);
  if (value.is_none() || py::isinstance<py::str>(value) || !a || a.ndim() != 1)
    throw py::type_error(fmt::format("{}={}: expected three numbers x, y, z", option, text));
  v.assign(a.data(), a.data() + a.size());
  if (v.size() != 3)
    throw ParameterError(fmt::format("{} {}: expected three numbers x, y, z", option, text));
  for (double x : v)
    if (!std::isfinite(x))
      throw ParameterError(fmt::format("{} {}: '{}' is not a finite number", option, text, x));
  const glm::dvec3 d(v[0], v[1], v[2]);
  if (!(glm::length(d) > 0.0))
    throw ParameterError(fmt::format("{} {}: expected a non-zero vector", option, text));
  return d;
}

}  // namespace

py::dict imageDict(const reference::CameraImages& images, const std::string& suffix) {
  py::dict d;
  const std::pair<const char*, const reference::McImage*> all[] = {
      {"exitance", &images.exitance},
      {"radiance", &images.radiance},
      {"cone_radiance", &images.cone_radiance}};
  for (const auto& [name, img] : all) {
    const std::vector<py::ssize_t> shape{img->height(), img->width(), 3};
    const std::string key = name + suffix;
    d[key.c_str()] = ownedArray(img->rgb(), shape);
    d[(key + "_stderr").c_str()] = ownedArray(img->rgbStdError(), shape);
  }
  return d;
}

template <class Tracer>
py::dict tracerImageDict(const Tracer& tracer) {
  py::dict d = imageDict(tracer.images());
  // "exitance_single", "exitance_single_stderr", ...: the CLI's EXR layers with --split-orders.
  if (tracer.splitsOrders())
    for (reference::ScatteringOrder o : reference::kAllScatteringOrders)
      for (const auto& [key, value] : imageDict(tracer.orderImages(o), std::string("_") + reference::toString(o)))
        d[key] = value;
  return d;
}
template py::dict tracerImageDict(const reference::SpherePathTracer&);
template py::dict tracerImageDict(const reference::MeshPathTracer&);
template py::dict tracerImageDict(const reference::CameraPathTracer&);

py::list fluxList(const reference::TransportStats& s) {
  return toPython(reference::fluxPerChannelJson(s));
}

bool runPasses(int passes, Interruptible& stop,
               const std::function<bool(const reference::ProgressCallback&)>& pass) {
  // apps/cli/cmd_render_reference.cpp runPasses: the passes until one is stopped; between
  // passes a pending Ctrl-C or the time limit stops too.
  bool partial = false;
  for (int k = 0; k < passes && !partial; ++k) {
    partial = pass([&](const reference::TraceProgress& p) {
      const uint64_t total = p.photons_total * static_cast<uint64_t>(passes);
      return stop.poll(static_cast<uint64_t>(k) * p.photons_total + p.photons_done, total);
    });
    if (!partial && k + 1 < passes) partial = !stop.poll(0, 0);
  }
  return partial;
}

static reference::SphereScene sphereScene(double radius, const py::object& light_dir,
                                          const py::object& view_dir, int width, int height,
                                          double cone_angle) {
  reference::SphereScene scene;
  scene.radius = radius;
  scene.light_direction = toVec3(light_dir, "light_dir");
  scene.view_direction = toVec3(view_dir, "view_dir");
  scene.width = width;
  scene.height = height;
  scene.cone_half_angle = cone_angle;
  scene.validate();
  return scene;
}

void validatePasses(int passes, int threads) {
  if (passes < 1) throw ParameterError(fmt::format("--passes is {}: expected >= 1", passes));
  if (threads < 0) throw ParameterError(fmt::format("--threads is {}: expected >= 0", threads));
}

void bindReference(py::module_& m) {
  m.def(
      "pathtrace_slab",
      [](std::optional<double> sigma_a, std::optional<double> sigma_s, std::optional<double> g,
         std::optional<double> eta, std::optional<std::string> preset_name,
         std::optional<std::string> channel, double eta_above, double eta_below,
         std::optional<double> thickness, double theta, double phi, double photons,
         uint64_t seed, int threads, int radial_bins, std::optional<double> radial_max,
         int angle_bins, uint64_t long_path_roulette, const std::string& absorption,
         const std::string& kernel, const std::string& device, const py::object& layers,
         std::optional<double> time_limit,
         const std::optional<std::string>& material_name) {
        const std::optional<std::string> preset =
            materialArgument(material_name, preset_name, "translucent.pathtrace_slab");
        // What the CLI's option parser says in its own words, in the arguments' names.
        if (layers.is_none() && !preset && !sigma_a && !sigma_s)
          throw ParameterError(
              "give the medium: sigma_a=, sigma_s= and eta=; or material= and channel= ('r', 'g' "
              "or 'b'); or layers=");
        if (preset && !channel && !sigma_a && !sigma_s && layers.is_none())
          throw ParameterError(
              "channel=None: expected 'r', 'g' or 'b' with material= (the slab traces one channel)");
        finiteArgument(phi, "phi");
        if (radial_max && !(std::isfinite(*radial_max) && *radial_max > 0.0))
          throw ParameterError(fmt::format("radial_max is {}: expected a positive length", *radial_max));
        if (angle_bins < 0)
          throw ParameterError(fmt::format("angle_bins is {}: expected >= 0", angle_bins));
        for (const auto& [v, name] : {std::pair{eta_above, "eta_above"}, {eta_below, "eta_below"}})
          if (!(std::isfinite(v) && v > 0.0))
            throw ParameterError(
                fmt::format("{} is {}: expected a positive index of refraction", name, v));
        validatePasses(1, threads);
        reference::SlabRequest a;
        a.sigma_a = sigma_a;
        a.sigma_s = sigma_s;
        a.g = g;
        a.eta = eta;
        a.preset = preset.value_or("");
        a.channel = channel.value_or("");
        a.eta_above = eta_above;
        a.eta_below = eta_below;
        a.thickness = thickness;
        a.theta = theta;
        a.phi = phi;
        a.photons = photonCount(photons);
        a.seed = seed;
        a.threads = threads;
        a.radial_bins = radial_bins;
        a.radial_max = radial_max;
        a.angle_bins = angle_bins;
        a.long_path_roulette = long_path_roulette;
        a.absorption = absorption;
        a.kernel = kernel;
        a.device = device;
        a.time_limited = time_limit.has_value();  // a long estimated run is traced up to it
        return pathtraceSlab(a, layers, time_limit);
      },
      py::kw_only(), py::arg("sigma_a") = py::none(), py::arg("sigma_s") = py::none(),
      py::arg("g") = py::none(), py::arg("eta") = py::none(), py::arg("preset") = py::none(),
      py::arg("channel") = py::none(), py::arg("eta_above") = 1.0, py::arg("eta_below") = 1.0,
      py::arg("thickness") = py::none(), py::arg("theta") = 0.0, py::arg("phi") = 0.0,
      py::arg("photons") = 1e6, py::arg("seed") = 1, py::arg("threads") = 0,
      py::arg("radial_bins") = 0, py::arg("radial_max") = py::none(), py::arg("angle_bins") = 0,
      py::arg("long_path_roulette") = 0, py::arg("absorption") = "auto",
      py::arg("kernel") = "lanes", py::arg("device") = "auto", py::arg("layers") = py::none(),
      py::arg("time_limit") = py::none(), py::arg("material") = py::none(), R"doc(
The reference: Monte Carlo photon transport in a slab lit by a pencil beam (MCML's one-layer
setting; Wang, Jacques & Zheng 1995): `translucent pathtrace slab`. Keyword arguments only.

Medium: sigma_a, sigma_s [1/length], g, eta (required with sigma_a), or material (a preset of
Jensen 2001, in mm, as the CLI's --material; preset= is its deprecated spelling) with channel "r",
"g" or "b". thickness [length]: None for a semi-infinite medium.
eta_above, eta_below: indices around the slab. theta, phi: incidence [degrees].
layers: a layered slab (MCML's multi-layer mode) instead of the medium and thickness: a list of
dicts {"thickness": t or None (last layer only), "sigma_a", "sigma_s", "g"}, top first, or the
name of such a JSON file; every layer at index eta.
photons, seed, threads (0: all cores): the same seed gives the same result on any thread count.
radial_bins, radial_max: the radial profile Rd(r) in annuli on [0, radial_max]; angle_bins: the
exit angle tally. long_path_roulette, absorption ("auto" | "analog" | "weighted"; auto: weighted for slabs of reduced optical thickness <= 2), kernel ("lanes" |
"portable" | "scalar"): as the CLI's options of the same names.
device: "cpu", "gpu" (the GL compute-shader tracer, any GL 4.5 context; Philox streams, so it
agrees with the CPU within the standard errors, not bit for bit) or "auto" (the GPU on a
hardware GPU, else the CPU); "device" in the result names what traced.
time_limit [s]: stop then and return what was traced, "partial": True.

Returns a SlabResult with the fields of the CLI's --json output: specular_reflectance,
diffuse_reflectance, transmittance, diffuse_transmittance, unscattered_transmittance, absorbed
(per incident photon), each with <key>_stderr (its standard error); "radial" with "r", "rd",
"rd_stderr" as float64 arrays (Rd(r) per unit area per incident photon); "scattering_orders"
with "unscattered", "single" and "multiple", each holding diffuse_reflectance, transmittance
and "radial" (and "angular") of that light alone (they add up to the totals);
photons, seconds, photons_per_second, threads, seed, partial, medium, ... The GIL is released
while tracing;
Ctrl-C raises KeyboardInterrupt with the partial result as its `partial_result`.
)doc");

  m.def(
      "integrate_sphere",
      [](const std::string& model, const std::optional<std::string>& preset_name,
         const py::object& sigma_a, const py::object& sigma_s, std::optional<double> g,
         std::optional<double> eta, double scale, double radius, const py::object& light_dir,
         const py::object& view_dir, int width, int height, double samples, int passes,
         const std::string& sampling, double defensive, uint64_t seed, int threads,
         std::optional<double> time_limit,
         const std::optional<std::string>& material_name) {
        const std::optional<std::string> preset =
            materialArgument(material_name, preset_name, "translucent.integrate_sphere");
        // apps/cli/cmd_render_reference.cpp runIntegrateSphere.
        checkNoNul(model, "model");
        validatePasses(passes, threads);
        Interruptible stop(time_limit);
        const Medium medium = mediumFromArgs(preset, sigma_a, sigma_s, g, eta, scale);
        const reference::SphereScene scene =
            sphereScene(radius, light_dir, view_dir, width, height, 5.0);
        const uint64_t n = photonCount(samples, "--samples");
        if (sampling != "uniform" && sampling != "importance")
          throw ParameterError(
              fmt::format("--sampling '{}': expected uniform or importance", sampling));
        reference::IntegrationOptions o;
        o.sampling = sampling == "uniform" ? reference::SurfaceSampling::Uniform
                                           : reference::SurfaceSampling::Importance;
        if (!(defensive >= 0.0 && defensive <= 1.0))
          throw ParameterError(
              fmt::format("defensive is {}: expected a fraction in [0, 1]", defensive));
        o.defensive = defensive;
        o.seed = seed;
        o.threads = threads;
        // A .bssrdf file (the CLI's choice): radial, through its GPU values tabulated for the
        // medium and integrated on the CPU; directional, on the GPU with the light's direction
        // (reference::GpuSphereIntegrator, uniform sampling), the module's context held meanwhile.
        std::optional<GlLock> gl;
        std::unique_ptr<gpu::BssrdfEvaluator> evaluator;
        std::unique_ptr<bssrdf::TabulatedModel> table;
        std::string used = sampling;
        if (bssrdf::isPluginFile(model)) {
          if (std::error_code ec; !std::filesystem::is_regular_file(model, ec))
            throw ParameterError(fmt::format("--model {}: no such .bssrdf file", model));
          gl.emplace();
          evaluator = gpu::openBssrdf(model);
          if (evaluator->file().attributes.radial) {
            table = gpu::bssrdfTabulatedModel(*evaluator, medium, model);
            evaluator.reset();
            gl.reset();
          } else {
            used = "uniform";
          }
        }
        reference::IntegrationImages images;
        reference::IntegrationStats st;
        auto run = [&](auto& integrator) {
          {
            py::gil_scoped_release release;
            runPasses(passes, stop, [&](const reference::ProgressCallback& cb) {
              return integrator.addPass(n, cb).partial;
            });
          }
          images = integrator.images();
          st = integrator.stats();
        };
        if (evaluator) {
          reference::GpuSphereIntegrator integrator(*evaluator, scene, medium, seed);
          run(integrator);
          evaluator.reset();
          gl.reset();
        } else {
          reference::SphereIntegrator integrator(table ? *table : bssrdf::model(model), scene,
                                                 medium, o);
          run(integrator);
        }
        stop.finish();
        py::dict d;
        const std::pair<const char*, const reference::McImage*> all[] = {
            {"exitance", &images.exitance}, {"radiance", &images.radiance}};
        for (const auto& [name, img] : all) {
          const std::vector<py::ssize_t> shape{img->height(), img->width(), 3};
          d[name] = ownedArray(img->rgb(), shape);
          d[(std::string(name) + "_stderr").c_str()] = ownedArray(img->rgbStdError(), shape);
        }
        d["model"] = model;
        d["sampling"] = used;
        d["defensive"] = used == "uniform" ? 1.0 : defensive;
        d["samples_per_pixel"] = st.samples;
        d["seconds"] = st.seconds;
        d["threads"] = st.threads;
        d["partial"] = st.partial || stop.interrupted() || stop.timedOut();
        d["seed"] = seed;
        d["medium"] = medium;
        py::object out = result("SphereIntegration", d);
        stop.rethrow(out);
        return out;
      },
      py::arg("model") = "dipole", py::kw_only(), py::arg("preset") = py::none(),
      py::arg("sigma_a") = py::none(), py::arg("sigma_s") = py::none(), py::arg("g") = py::none(),
      py::arg("eta") = py::none(), py::arg("scale") = 1.0, py::arg("radius") = 1.0,
      py::arg("light_dir") = std::vector<double>{1.0, 1.0, 1.0},
      py::arg("view_dir") = std::vector<double>{0.0, 0.0, 1.0}, py::arg("width") = 256,
      py::arg("height") = 256, py::arg("samples") = 64, py::arg("passes") = 1,
      py::arg("sampling") = "importance", py::arg("defensive") = 0.1, py::arg("seed") = 1,
      py::arg("threads") = 0, py::arg("time_limit") = py::none(),
      py::arg("material") = py::none(), R"doc(
A BSSRDF model integrated over the lit sphere, B(x_o) = ∫ R(|x_o − x_i|) Ft(η, θi) cos θi dA by
Monte Carlo over the surface: `translucent integrate sphere`, the same scene and
pixels as pathtrace_sphere (whose arguments it takes, without cone_angle).

model: a registered model name, a tabulated profile FILE.csv, or a .bssrdf file (radial: its GPU
  values tabulated for the medium; directional, e.g. data/bssrdf/directional-dipole.bssrdf: on
  the GPU with the light's direction, uniform sampling, said in "sampling"). A directional model
  (directional-dipole) is integrated with its kernel and the light's true direction.
samples per pixel and channel per pass, passes.
sampling: "importance" (probe rays from the model's radial sampler along three axes, with a
  fraction `defensive` of uniform samples) or "uniform" (points uniform on the lit hemisphere).
Returns a SphereIntegration: "exitance" B [W/unit²] and "radiance" Ft(η, ω_o) B / π [W/(unit² sr)], each an
(height, width, 3) float32 array with "<name>_stderr"; samples_per_pixel, seconds, threads,
partial, seed, medium. GIL released; Ctrl-C: KeyboardInterrupt with `partial_result`.
)doc");

  m.def(
      "pathtrace_sphere",
      [](const std::optional<std::string>& preset_name, const py::object& sigma_a,
         const py::object& sigma_s, std::optional<double> g, std::optional<double> eta,
         double scale, double radius, const py::object& light_dir, const py::object& view_dir,
         int width, int height, double cone_angle, double photons, int passes, uint64_t seed,
         int threads, const std::string& device, std::optional<double> time_limit,
         bool split_orders,
         const std::optional<std::string>& material_name) {
        const std::optional<std::string> preset =
            materialArgument(material_name, preset_name, "translucent.pathtrace_sphere");
        validatePasses(passes, threads);
        Interruptible stop(time_limit);
        const Medium medium = mediumFromArgs(preset, sigma_a, sigma_s, g, eta, scale);
        const reference::SphereScene scene =
            sphereScene(radius, light_dir, view_dir, width, height, cone_angle);
        const uint64_t n = photonCount(photons);
        // Before the tracer: the context outlives the walker the tracer holds.
        const reference::TraceDevice dev = reference::openTraceDevice(device, "device");
        reference::TracerOptions options{seed, threads};
        options.split_orders = split_orders;
        reference::SpherePathTracer tracer(scene, medium, options);
        reference::useDevice(dev, tracer);
        {
          py::gil_scoped_release release;
          runPasses(passes, stop, [&](const reference::ProgressCallback& cb) {
            return tracer.addPass(n, cb).partial;
          });
        }
        stop.finish();
        const auto& st = tracer.stats();
        py::dict d = tracerImageDict(tracer);
        d["photons_per_channel"] = st.photons.empty() ? 0 : st.photons[0];
        d["passes"] = tracer.passes();
        d["seconds"] = st.seconds;
        d["photons_per_second"] = st.photonsPerSecond();
        d["threads"] = st.threads;
        d["cone_angle"] = cone_angle;
        d["device"] = tracer.device();
        d["flux_per_channel"] = fluxList(st);
        d["partial"] = st.partial || stop.interrupted() || stop.timedOut();
        d["seed"] = seed;
        d["medium"] = medium;
        py::object out = result("SphereTrace", d);
        stop.rethrow(out);
        return out;
      },
      py::kw_only(), py::arg("preset") = py::none(), py::arg("sigma_a") = py::none(),
      py::arg("sigma_s") = py::none(), py::arg("g") = py::none(), py::arg("eta") = py::none(),
      py::arg("scale") = 1.0, py::arg("radius") = 1.0,
      py::arg("light_dir") = std::vector<double>{1.0, 1.0, 1.0},
      py::arg("view_dir") = std::vector<double>{0.0, 0.0, 1.0}, py::arg("width") = 256,
      py::arg("height") = 256, py::arg("cone_angle") = 5.0, py::arg("photons") = 1e6,
      py::arg("passes") = 1, py::arg("seed") = 1, py::arg("threads") = 0,
      py::arg("device") = "auto", py::arg("time_limit") = py::none(),
      py::arg("split_orders") = false, py::arg("material") = py::none(), R"doc(
The lit sphere reference: a sphere of the medium under a directional light of unit irradiance,
seen by an orthographic camera, by photon tracing: `translucent pathtrace sphere`. Keyword
arguments only.

Medium: material (a preset, default "Marble"; preset= is its deprecated spelling) or sigma_a,
sigma_s [1/mm] (numbers or r, g, b), g, eta, scale (mm per scene unit), as translucent.profile
takes them.
radius [scene units]; light_dir, view_dir: directions towards the light and the camera (x, y, z);
width, height [pixels] (the sphere fills 1/1.05 of the height); cone_angle: half-angle of the
cone of the cone-averaged true radiance [degrees].
photons per channel per pass, passes (accumulated), seed, threads (0: all cores): the same seed
gives the same images on any thread count. time_limit [s]: stop then, "partial": True.
device: "cpu", "gpu" (the GL compute-shader walk, any GL 4.5 context; Philox streams, so it
agrees with the CPU within the standard errors, not bit for bit) or "auto" (the GPU on a
hardware GPU, else the CPU); "device" in the result names what traced.

Returns a SphereTrace: "exitance" (radiant exitance B [W/unit²], pixel averages), "radiance" (the
diffusion models' radiance Ft(η, ω_o) B / π [W/(unit² sr)]), "cone_radiance" (true radiance
towards the camera, cone-averaged), each an (height, width, 3) float32 array, rows from the
top, with "<name>_stderr" its per-pixel standard error (the layers of the CLI's EXR); with
split_orders, the same per scattering order ("exitance_unscattered", "exitance_single",
"exitance_multiple", ..., each with "_stderr"; they add up to "exitance"); and
photons_per_channel, passes, seconds, photons_per_second, threads, flux_per_channel (emitted,
entered, exited, escaped per channel with standard errors, and exited_by_order), partial, seed,
medium.
The GIL is released while tracing; Ctrl-C raises KeyboardInterrupt with the partial result as its
`partial_result`.
)doc");
}

}  // namespace translucent::python
