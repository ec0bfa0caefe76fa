// SPDX-License-Identifier: GPL-3.0-or-later
// Media, presets, Fresnel helpers and the (Rd, ℓd) inversion.
#include <fmt/format.h>
#include <pybind11/stl.h>

#include "bind.h"
#include "translucent/bssrdf/registry.h"
#include "common.h"
#include "translucent/optics/inversion.h"
#include "translucent/optics/presets.h"

#include <cmath>

namespace translucent::python {

namespace {
// Applies `set` to a copy of `x` and keeps it if it validates (else ValueError, `x` unchanged).
template <class F>
void setChecked(Medium& x, F&& set) {
  Medium m = x;
  set(m);
  m.validate();
  x = m;
}
}  // namespace

void bindOptics(py::module_& m) {
  py::class_<Medium>(m, "Medium", R"doc(
A homogeneous medium with RGB coefficients.

Medium(sigma_a=(0.0021, 0.0041, 0.0071), sigma_s=(2.19, 2.62, 3.00), g=0.0, eta=1.3, scale=1.0)

sigma_a, sigma_s: absorption and scattering coefficients σa, σs per RGB channel
  [1/mm, or 1/medium unit]; a number means grey. (The default is Jensen 2001 marble.)
g: Henyey-Greenstein mean cosine in (-1, 1).
eta: relative index of refraction n_medium / n_outside.
scale: medium units (mm) per scene unit; lengths of profiles and renders are in scene units,
  the coefficients per scene unit are sigma * scale.
The constructor validates (ValueError naming the parameter and channel).
)doc")
      .def(py::init([](const py::object& sigma_a, const py::object& sigma_s, double g, double eta,
                       double scale) {
             Medium med;
             if (!sigma_a.is_none()) med.sigma_a = toRgb(sigma_a, "sigma_a");
             if (!sigma_s.is_none()) med.sigma_s = toRgb(sigma_s, "sigma_s");
             med.g = g;
             med.eta = eta;
             med.scale = scale;
             med.validate();
             return med;
           }),
           py::arg("sigma_a") = py::none(), py::arg("sigma_s") = py::none(), py::arg("g") = 0.0,
           py::arg("eta") = 1.3, py::arg("scale") = 1.0)
      .def_static(
          "from_reduced",
          [](const py::object& sigma_a, const py::object& sigma_s_prime, double g, double eta,
             double scale) {
            Medium med = Medium::fromReduced(toRgb(sigma_a, "sigma_a"),
                                             toRgb(sigma_s_prime, "sigma_s_prime"), g, eta,
                                             scale);
            med.validate();
            return med;
          },
          py::arg("sigma_a"),
                  py::arg("sigma_s_prime"), py::arg("g") = 0.0, py::arg("eta") = 1.3,
                  py::arg("scale") = 1.0,
                  "Medium from reduced scattering σs' = (1 - g) σs [1/mm], as Jensen 2001 "
                  "tabulates: σs = σs' / (1 - g).")
      // The setters check the medium they leave, as the constructor does (ValueError naming the
      // parameter and channel; the medium keeps its old value): they stored a NaN and read it
      // back silently (tests/python/hostile_check.py).
      .def_property(
          "sigma_a", [](const Medium& x) { return rgbArray(x.sigma_a); },
          [](Medium& x, const py::object& v) {
            setChecked(x, [&](Medium& med) { med.sigma_a = toRgb(v, "sigma_a"); });
          },
          "Absorption coefficient σa per channel [1/mm] (a copy: assign a new triple to change "
          "it)")
      .def_property(
          "sigma_s", [](const Medium& x) { return rgbArray(x.sigma_s); },
          [](Medium& x, const py::object& v) {
            setChecked(x, [&](Medium& med) { med.sigma_s = toRgb(v, "sigma_s"); });
          },
          "Scattering coefficient σs per channel [1/mm]")
      .def_property_readonly(
          "sigma_s_prime",
          [](const Medium& x) {
            Rgb sp{};
            for (size_t c = 0; c < 3; ++c) sp[c] = (1.0 - x.g) * x.sigma_s[c];
            return rgbArray(sp);
          },
          "Reduced scattering coefficient σs' = (1 - g) σs per channel [1/mm]")
      .def_property(
          "g", [](const Medium& x) { return x.g; },
          [](Medium& x, double v) { setChecked(x, [&](Medium& med) { med.g = v; }); },
          "Henyey-Greenstein mean cosine")
      .def_property(
          "eta", [](const Medium& x) { return x.eta; },
          [](Medium& x, double v) { setChecked(x, [&](Medium& med) { med.eta = v; }); },
          "Relative index of refraction")
      .def_property(
          "scale", [](const Medium& x) { return x.scale; },
          [](Medium& x, double v) { setChecked(x, [&](Medium& med) { med.scale = v; }); },
          "Medium units (mm) per scene unit")
      .def("validate", &Medium::validate,
           "Raises ValueError naming the parameter, channel and value unless the medium is valid")
      .def(
          "channel",
          [](const Medium& x, int c) {
            if (c < 0 || c > 2)
              throw ParameterError(fmt::format("channel {}: expected 0, 1 or 2", c));
            const ScalarMedium s = x.channel(c);
            py::dict d;
            d["sigma_a"] = s.sigma_a;
            d["sigma_s"] = s.sigma_s;
            d["g"] = s.g;
            d["eta"] = s.eta;
            d["sigma_tr"] = s.sigmaTr();
            d["albedo"] = s.albedo();
            d["reduced_albedo"] = s.reducedAlbedo();
            d["diffuse_mean_free_path"] = s.diffuseMeanFreePath();
            d["reduced_mean_free_path"] = s.reducedMeanFreePath();
            return result("ChannelProperties", d);
          },
          py::arg("c"),
          "One channel (0 red, 1 green, 2 blue) as a ChannelProperties: coefficients per scene "
          "unit (σ · scale) and the derived quantities: σtr [1/unit], albedo α, reduced albedo α', diffuse "
          "mean free path ℓd = 1/σtr and reduced mean free path ℓ' [scene units]")
      .def("__eq__",
           [](const Medium& a, const Medium& b) {
             return a.sigma_a == b.sigma_a && a.sigma_s == b.sigma_s && a.g == b.g &&
                    a.eta == b.eta && a.scale == b.scale;
           })
      .def("__repr__", [](const Medium& x) {
        return fmt::format("Medium(sigma_a=({}, {}, {}), sigma_s=({}, {}, {}), g={}, eta={}, "
                           "scale={})",
                           x.sigma_a[0], x.sigma_a[1], x.sigma_a[2], x.sigma_s[0], x.sigma_s[1],
                           x.sigma_s[2], x.g, x.eta, x.scale);
      });

  py::class_<Preset>(m, "Preset",
                     "A measured material of Jensen et al. 2001: name, sigma_s_prime and "
                     "sigma_a [1/mm] per RGB channel, g, eta.")
      .def_readonly("name", &Preset::name)
      .def_property_readonly("sigma_s_prime",
                             [](const Preset& p) { return rgbArray(p.sigma_s_prime); })
      .def_property_readonly("sigma_a", [](const Preset& p) { return rgbArray(p.sigma_a); })
      .def_readonly("g", &Preset::g)
      .def_readonly("eta", &Preset::eta)
      .def(
          "medium",
          [](const Preset& p, double scale) {
            const Medium med = p.medium(scale);
            med.validate();
            return med;
          },
          py::arg("scale") = 1.0,
           "The preset as a Medium (σs = σs' / (1 - g)), `scale` mm per scene unit")
      .def("__repr__", [](const Preset& p) { return fmt::format("<Preset {}>", p.name); });

  m.def(
      "presets", [] { return presets(); },
      "The measured materials of Jensen et al. 2001 (data/presets/jensen2001.json), in table "
      "order, as a list of Preset (σs' and σa in 1/mm, g = 0, η = 1.3): what `translucent "
      "presets` prints.");
  m.def(
      "preset", [](const std::string& name) { return preset(name); }, py::arg("name"),
      "The preset of this name (case-insensitive); ValueError listing the names otherwise.");
  m.def(
      "fdr",
      [](double eta) {
        if (!std::isfinite(eta) || eta <= 0.0)
          throw ParameterError(
              fmt::format("eta is {}: expected a positive index of refraction", eta));
        // The fit (Eq. 2.30) is a reflectance only where it lies in [0, 1] (about 1.0 < η < 4.3,
        // and -inf or NaN for η near 0): outside, no value is returned rather than a wrong one.
        const double f = fdrRational(eta);
        if (!(std::isfinite(f) && f >= 0.0 && f <= 1.0))
          throw ParameterError(fmt::format("eta is {}: the Egan & Hilgeman fit gives {} there, not a "
                                           "reflectance in [0, 1] (use η of about 1 to 4)", eta, f));
        return f;
      },
      py::arg("eta"),
        "Average diffuse Fresnel reflectance Fdr(η), the rational fit of Egan & Hilgeman "
        "(Egan & Hilgeman 1979).");

  m.def(
      "invert",
      [](const std::string& model, const py::object& rd, const py::object& ld, double eta) {
        // apps/cli/cmd_invert.cpp, registered models.
        if (!std::isfinite(eta) || eta <= 0.0)
          throw ParameterError(
              fmt::format("--eta is {}: expected a positive index of refraction", eta));
        const Rgb rdv = finiteRgb(rd, "rd"), ldv = finiteRgb(ld, "ld");
        const auto& mod = bssrdf::model(checkNoNul(model, "model"));
        return invertMedium([&](double a) { return mod.totalReflectance(a, eta); }, rdv, ldv,
                            eta);
      },
      py::arg("model"), py::arg("rd"), py::arg("ld"), py::arg("eta") = 1.3, R"doc(
The medium whose total diffuse reflectance is `rd` and diffuse mean free path `ld` per channel
(Jensen & Buhler 2002), for a registered model: `translucent invert`.

model: a registered model name (translucent.model_names()).
rd: total diffuse reflectance Rd per channel (a number or r, g, b), in (0, Rd(α' = 1)).
ld: diffuse mean free path ℓd = 1/σtr per channel [mm].
eta: relative index of refraction.
Returns a Medium (g = 0, so σs = σs'): `.sigma_a` and `.sigma_s_prime` [1/mm] are what the CLI
prints. An unreachable Rd raises ValueError stating the reachable range.
)doc");
}

}  // namespace translucent::python
