// SPDX-License-Identifier: GPL-3.0-or-later
// BSSRDF models by name, their per-channel radial profiles, and translucent.profile().
#include <fmt/format.h>
#include <pybind11/stl.h>

#include <cmath>
#include <limits>
#include <memory>

#include <pybind11/stl/filesystem.h>

#include <filesystem>

#include "translucent/bssrdf/profile_curves.h"
#include "bind.h"
#include "translucent/bssrdf/bssrdf_file.h"
#include "translucent/bssrdf/registry.h"
#include "common.h"
#include "gl_lock.h"
#include "translucent/gpu/bssrdf_kernels.h"
#include "translucent/gpu/bssrdf_profiles.h"
#include "translucent/gpu/context.h"
#include "translucent/optics/inversion.h"

namespace translucent::python {

namespace {

// Radii [scene units] from any array-like (converted once when it is not already float64):
// finite and >= 0, TypeError or ValueError naming the argument `r` otherwise.
py::array_t<double, py::array::c_style | py::array::forcecast> radii(const py::object& r) {
  return checkedArray(r, "r", 0.0, std::numeric_limits<double>::infinity());
}

// apps/cli/bssrdf_models.cpp isBssrdfFile: a name ending in .bssrdf or an existing file.
bool isBssrdfFile(const std::string& entry) { return bssrdf::isPluginFile(entry); }

// A .bssrdf plug-in model, evaluated on the GPU through the module's context.
class BssrdfModel {
 public:
  BssrdfModel(const py::object& path, const py::kwargs& params)
      : path_(pathArgument(path, "path").string()) {
    if (std::error_code ec; !std::filesystem::is_regular_file(path_, ec))
      throw ParameterError(fmt::format("path={}: no such .bssrdf file", reprOf(path)));
    GlLock lock;
    evaluator_ = gpu::openBssrdf(path_);
    try {
      set(params);
    } catch (...) {
      // The evaluator deletes its GL programs: while the context is current (the lock's
      // destructor runs before the members' would).
      evaluator_.reset();
      throw;
    }
  }
  ~BssrdfModel() {
    GlLock lock;  // the evaluator deletes its GL programs
    evaluator_.reset();
  }
  BssrdfModel(const BssrdfModel&) = delete;
  BssrdfModel& operator=(const BssrdfModel&) = delete;
  // Each parameter by its declared type: float, bool, or color (r, g, b).
  // Every value is checked before any is set: a bad one changes nothing.
  void set(const py::kwargs& params) {
    std::vector<std::pair<std::string, gpu::ParameterValue>> values;
    for (const auto& [k, v] : params) {
      const std::string name = k.cast<std::string>();
      const bssrdf::BssrdfParameter* decl = evaluator_->file().findParameter(name);
      if (decl == nullptr)
        throw ParameterError(
            fmt::format("{}={}: {} declares no parameter '{}'", name, reprOf(v), path_, name));
      if (std::holds_alternative<bssrdf::BoolParameter>(decl->spec)) {
        if (!py::isinstance<py::bool_>(v) &&
            !py::isinstance(v, py::module_::import("numpy").attr("bool_")))
          throw py::type_error(
              fmt::format("{}={}: expected True or False (a bool parameter)", name, reprOf(v)));
        values.emplace_back(name, v.cast<bool>());
      } else if (std::holds_alternative<bssrdf::FloatParameter>(decl->spec)) {
        double x = 0.0;
        if (py::isinstance<py::bool_>(v) || py::isinstance<py::str>(v) || v.is_none())
          throw py::type_error(fmt::format("{}={}: expected a number", name, reprOf(v)));
        try {
          x = v.cast<double>();
        } catch (const py::cast_error&) {
          throw py::type_error(fmt::format("{}={}: expected a number", name, reprOf(v)));
        }
        values.emplace_back(name, finiteArgument(x, name.c_str()));
      } else {
        values.emplace_back(name, finiteRgb(v, name));
      }
    }
    for (const auto& [name, value] : values) evaluator_->setParameter(name, value);
  }
  // The evaluator, for a caller that holds a GlLock.
  gpu::BssrdfEvaluator& evaluator() { return *evaluator_; }
  const std::string& path() const { return path_; }
  std::string stem() const { return evaluator_->file().stem(); }
  py::dict parameters() const {
    py::dict d;
    for (const auto& p : evaluator_->file().parameters)
      d[py::str(p.name)] = std::visit([](const auto& x) -> py::object { return py::cast(x); },
                                      evaluator_->parameter(p.name));
    return d;
  }
  // R(r) per channel: gpu::bssrdfCurves, what `translucent profile --model F.bssrdf` writes.
  py::array_t<double> profile(const Medium& medium, const py::object& r) {
    const auto in = radii(r);
    medium.validate();
    std::vector<py::ssize_t> shape(in.shape(), in.shape() + in.ndim());
    shape.push_back(3);
    const std::vector<double> grid(in.data(), in.data() + in.size());
    if (grid.empty()) return ownedArray(std::vector<double>(), shape);
    GlLock lock;
    const auto curves = gpu::bssrdfCurves(
        evaluator(), stem(), medium,
        {analysis::Channel::Red, analysis::Channel::Green, analysis::Channel::Blue}, grid, false);
    std::vector<double> out;
    out.reserve(3 * grid.size());
    for (size_t i = 0; i < grid.size(); ++i)
      for (size_t c = 0; c < 3; ++c) out.push_back(curves[c].value[i]);
    return ownedArray(std::move(out), shape);
  }

 private:
  std::string path_;
  std::unique_ptr<gpu::BssrdfEvaluator> evaluator_;
};

// A model's profiles for the three channels of one medium (bssrdf::profiles).
struct Profiles {
  const bssrdf::Model* model;
  Medium medium;
  bssrdf::RgbProfiles rgb;
};

std::shared_ptr<Profiles> makeProfiles(const bssrdf::Model& model, const Medium& medium) {
  medium.validate();
  return std::make_shared<Profiles>(Profiles{&model, medium, bssrdf::profiles(model, medium)});
}

// out[i, c] = f(c, in[i]) for the N values of `in` (any shape, flattened): shape in.shape + (3,).
template <class F>
py::array_t<double> perChannel(
    const py::array_t<double, py::array::c_style | py::array::forcecast>& in, F&& f) {
  std::vector<py::ssize_t> shape(in.shape(), in.shape() + in.ndim());
  shape.push_back(3);
  const size_t n = static_cast<size_t>(in.size());
  std::vector<double> out(3 * n);
  const double* x = in.data();
  {
    py::gil_scoped_release release;  // `in` stays alive (the caller holds it)
    for (size_t i = 0; i < n; ++i)
      for (int c = 0; c < 3; ++c) out[3 * i + static_cast<size_t>(c)] = f(c, x[i]);
  }
  return ownedArray(std::move(out), shape);
}

}  // namespace

void bindBssrdf(py::module_& m) {
  py::class_<bssrdf::Model, std::unique_ptr<bssrdf::Model, py::nodelete>>(m, "Model", R"doc(
A registered BSSRDF model (dipole, better-dipole, ...): translucent.model(name).
Models are stateless; model.profiles(medium) makes the per-channel radial profiles.
)doc")
      .def_property_readonly("name", [](const bssrdf::Model& x) { return std::string(x.name()); })
      .def_property_readonly("description",
                             [](const bssrdf::Model& x) { return std::string(x.description()); })
      .def(
          "total_reflectance",
          [](const bssrdf::Model& x, double alpha_prime, double eta) {
            if (!(alpha_prime >= 0.0 && alpha_prime <= 1.0))
              throw ParameterError(fmt::format(
                  "alpha_prime is {}: expected a reduced albedo in [0, 1]", alpha_prime));
            if (!std::isfinite(eta) || eta <= 0.0)
              throw ParameterError(
                  fmt::format("eta is {}: expected a positive index of refraction", eta));
            return x.totalReflectance(alpha_prime, eta);
          },
          py::arg("alpha_prime"), py::arg("eta"),
           "Total diffuse reflectance Rd as a function of the reduced albedo α' in [0, 1] and η")
      .def(
          "profiles",
          [](const bssrdf::Model& x, const Medium& medium) { return makeProfiles(x, medium); },
          py::arg("medium"), "The model's radial profiles for the RGB channels of `medium`")
      .def("__repr__",
           [](const bssrdf::Model& x) { return fmt::format("<Model {}>", x.name()); });

  m.def(
      "model",
      [](const std::string& name) {
        return std::unique_ptr<bssrdf::Model, py::nodelete>(
            const_cast<bssrdf::Model*>(&bssrdf::model(checkNoNul(name, "name"))));
      },
      py::arg("name"),
      "The registered model of this name, or the tabulated profile a .csv path names (loaded "
      "once per path; .profiles(medium) gives its Rd, sample(u), radius(f)); ValueError listing "
      "the names, or naming the file and line, otherwise.");
  m.def("model_names", &bssrdf::modelNames,
        "Registered model names in registration order (what `--model all` plots).");

  py::class_<Profiles, std::shared_ptr<Profiles>>(m, "Profiles", R"doc(
A model's radial profiles for the three RGB channels of a medium: the searchlight problem, a
pencil beam at normal incidence on a semi-infinite medium. Lengths are in scene units
(coefficients σ · scale). Every method takes an array of any shape and returns that shape + (3,),
float64, the last axis red, green, blue.
)doc")
      .def_property_readonly("model",
                             [](const Profiles& p) { return std::string(p.model->name()); })
      .def_readonly("medium", &Profiles::medium)
      .def(
          "R",
          [](const Profiles& p, const py::object& r) {
            return perChannel(radii(r), [&](int c, double x) {
              return p.rgb[static_cast<size_t>(c)]->R(x);
            });
          },
          py::arg("r"),
          "R(r) [1/unit²]: diffuse reflectance per unit area per unit flux entering the medium, "
          "at radii r [scene units]")
      .def_property_readonly(
          "Rd",
          [](const Profiles& p) {
            return rgbArray({p.rgb[0]->Rd(), p.rgb[1]->Rd(), p.rgb[2]->Rd()});
          },
          "Total diffuse reflectance Rd = 2π ∫ R(r) r dr per channel (shape (3,))")
      .def(
          "sample",
          [](const Profiles& p, const py::object& u) {
            const auto in = checkedArray(u, "u", 0.0, 1.0, true);
            auto r = perChannel(in, [&](int c, double x) {
              return p.rgb[static_cast<size_t>(c)]->sample(x).r;
            });
            auto pdf = perChannel(in, [&](int c, double x) {
              return p.rgb[static_cast<size_t>(c)]->sample(x).pdf;
            });
            return py::make_tuple(r, pdf);
          },
          py::arg("u"),
          "Importance samples of r ∝ r R(r) from u in [0, 1): (r [scene units], pdf [1/unit]), "
          "each of shape u.shape + (3,)")
      .def(
          "pdf",
          [](const Profiles& p, const py::object& r) {
            return perChannel(radii(r), [&](int c, double x) {
              return p.rgb[static_cast<size_t>(c)]->pdf(x);
            });
          },
          py::arg("r"), "Density of sample() at r [1/unit]")
      .def(
          "radius",
          [](const Profiles& p, double fraction) {
            if (!(fraction > 0.0 && fraction < 1.0))
              throw ParameterError(
                  fmt::format("fraction is {}: expected a value in (0, 1)", fraction));
            return rgbArray({p.rgb[0]->radiusForFraction(fraction),
                             p.rgb[1]->radiusForFraction(fraction),
                             p.rgb[2]->radiusForFraction(fraction)});
          },
          py::arg("fraction") = 0.95,
          "Radius [scene units] within which `fraction` of Rd is reflected, per channel (0.95: "
          "the effective scattering range)");

  py::class_<BssrdfModel>(m, "BssrdfModel", R"doc(
A .bssrdf plug-in model, compiled and evaluated on the GPU (the module's
headless OpenGL context, made on first use): BssrdfModel(path, **parameters).

parameters: the file's declared parameters by name (float, bool, or color r, g, b); the others
  keep the file's defaults. .set(**parameters) changes them, .parameters lists them.
.profile(medium, r): R(r) [1/unit²] per channel, shape r.shape + (3,), float64: what
  `translucent profile --model FILE` writes (the GPU computes in float32).
.energy(medium, fraction=0.95): a ProfileEnergy, .Rd and .radius (each (3,)), from GPU values
  of R.
.invert(rd, ld, eta=1.3): the medium through the file's diffuseReflectance section.
Radial sampling is not bound for .bssrdf models (the CPU models have it: Profiles.sample).
)doc")
      .def(py::init<const py::object&, const py::kwargs&>(), py::arg("path"))
      .def_property_readonly("path", &BssrdfModel::path)
      .def_property_readonly("name", &BssrdfModel::stem)
      .def_property_readonly("parameters", &BssrdfModel::parameters)
      .def("set", &BssrdfModel::set)
      .def("profile", &BssrdfModel::profile, py::arg("medium"), py::arg("r"))
      .def(
          "energy",
          [](BssrdfModel& b, const Medium& medium, double fraction) {
            if (!(fraction > 0.0 && fraction < 1.0))
              throw ParameterError(
                  fmt::format("fraction is {}: expected a value in (0, 1)", fraction));
            GlLock lock;
            const auto e = gpu::bssrdfRadiusForFraction(b.evaluator(), medium, fraction);
            py::dict d;
            d["Rd"] = rgbArray(e.rd);
            d["radius"] = rgbArray(e.radius);
            return result("ProfileEnergy", d);
          },
          py::arg("medium"), py::arg("fraction") = 0.95)
      .def(
          "invert",
          [](BssrdfModel& b, const py::object& rd, const py::object& ld, double eta) {
            if (!std::isfinite(eta) || eta <= 0.0)
              throw ParameterError(
                  fmt::format("--eta is {}: expected a positive index of refraction", eta));
            const Rgb rdv = finiteRgb(rd, "rd"), ldv = finiteRgb(ld, "ld");
            GlLock lock;
            return gpu::invertBssrdfMedium(b.evaluator(), rdv, ldv, eta);
          },
          py::arg("rd"), py::arg("ld"), py::arg("eta") = 1.3);

  m.def(
      "profile",
      [](const std::string& model, const py::object& r, const std::optional<std::string>& preset_name,
         const py::object& sigma_a, const py::object& sigma_s, std::optional<double> g,
         std::optional<double> eta, double scale, const std::optional<Medium>& medium,
         const std::optional<std::string>& material_name) {
        const std::optional<std::string> preset =
            materialArgument(material_name, preset_name, "translucent.profile");
        // g and eta default to 0 and 1.3 (the documented signature): with medium= only
        // those defaults are accepted, as for scale.
        if (medium && (preset || !sigma_a.is_none() || !sigma_s.is_none() || g.value_or(0.0) != 0.0 ||
                       eta.value_or(1.3) != 1.3 || scale != 1.0))
          throw ParameterError("medium= excludes material, sigma_a, sigma_s, g, eta and scale");
        checkNoNul(model, "model");
        const auto in = radii(r);
        const Medium med = medium ? *medium : mediumFromArgs(preset, sigma_a, sigma_s, g, eta, scale);
        if (isBssrdfFile(model)) {
          if (std::error_code ec; !std::filesystem::is_regular_file(model, ec))
            throw ParameterError(fmt::format("--model {}: no such .bssrdf file", model));
          BssrdfModel file{py::str(model), py::kwargs()};
          if (!file.evaluator().file().attributes.radial)
            throw ParameterError(fmt::format(
                "--model {}: not a radial BSSRDF (line 1 lacks `radial`): profile plots R(r)",
                model));
          return file.profile(med, in);
        }
        const auto p = makeProfiles(bssrdf::model(model), med);
        return perChannel(in, [&](int c, double x) { return p->rgb[static_cast<size_t>(c)]->R(x); });
      },
      py::arg("model"), py::arg("r"), py::arg("preset") = py::none(),
      py::arg("sigma_a") = py::none(), py::arg("sigma_s") = py::none(), py::arg("g") = 0.0,
      py::arg("eta") = 1.3, py::arg("scale") = 1.0, py::kw_only(),
      py::arg("medium") = py::none(), py::arg("material") = py::none(), R"doc(
Radial diffuse reflectance profile R(r) of a model, per RGB channel: `translucent profile`.

    R = translucent.profile("dipole", r, material="Skin1")    # shape (len(r), 3)

The searchlight problem: a pencil beam at normal incidence on a semi-infinite medium; R(r) is
the diffuse reflectance per unit area at distance r from the beam, per unit flux entering the
medium [1/unit²]. The numbers are those `translucent profile --channel all --out x.csv` writes
(the CSV prints them to 9 significant digits).

model: a registered model name (translucent.model_names()), a .bssrdf file (evaluated on
  the GPU, at its parameters' defaults; translucent.BssrdfModel sets them), or a tabulated
  profile FILE.csv (r,R_r,R_g,R_b with a '# units: mm' line, or what `translucent profile
  --reference --save-profile` writes): a measured R(r) that ignores sigma_a, sigma_s and g;
  scale converts its millimetres to scene units.
r: radii [scene units], any array-like; the result has shape r.shape + (3,), float64,
  C-contiguous, the last axis red, green, blue.
material: a measured material, by preset name (translucent.presets(); default "Marble" unless
  sigma_a and sigma_s are given), as the CLI's --material. preset= is its deprecated spelling
  (a DeprecationWarning; it stays the third positional argument). The presets are reduced coefficients (σs', σa) measured with g = 0 and
  eta = 1.3, the defaults below: a preset with another g has σs = σs' / (1 - g).
sigma_a, sigma_s: absorption and scattering coefficients [1/mm], a number or (r, g, b).
g: Henyey-Greenstein mean cosine (default 0).
eta: relative index of refraction (default 1.3).
scale: mm per scene unit (default 1: r in mm).
medium: a translucent.Medium instead of the arguments above (keyword only).
Errors (unknown model or preset, bad coefficients) raise ValueError with the CLI's message.
)doc");
}

}  // namespace translucent::python
