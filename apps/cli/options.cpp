// SPDX-License-Identifier: GPL-3.0-or-later
#include "options.h"

#include <fmt/format.h>

#include <cmath>
#include <cstdlib>

#include "safe_print.h"
#include "translucent/optics/presets.h"
#include "translucent/scene/scene.h"

namespace translucent::cli {

std::vector<std::string> splitList(const std::string& text) {
  std::vector<std::string> out;
  size_t start = 0;
  while (start <= text.size()) {
    const size_t end = text.find(',', start);
    const std::string item = text.substr(start, end == std::string::npos ? end : end - start);
    if (!item.empty()) out.push_back(item);
    if (end == std::string::npos) break;
    start = end + 1;
  }
  return out;
}

uint64_t parseCount(const std::string& text, const char* option) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (end == text.c_str() || *end != '\0' || !(v >= 1.0) || v > 1e18 || std::floor(v) != v)
    throw ParameterError(
        fmt::format("{} '{}': expected a whole number >= 1 (e.g. 1000000 or 1e6)", option, text));
  return static_cast<uint64_t>(v);
}

Rgb parseRgb(const std::string& text, const std::string& option) {
  const auto parts = splitList(text);
  if (parts.size() != 1 && parts.size() != 3)
    throw ParameterError(fmt::format("{} '{}': expected one value or three comma-separated values r,g,b",
                                     option, text));
  Rgb v{};
  for (size_t i = 0; i < 3; ++i) {
    const std::string& s = parts[parts.size() == 1 ? 0 : i];
    char* end = nullptr;
    v[i] = std::strtod(s.c_str(), &end);
    if (end == s.c_str() || *end != '\0')
      throw ParameterError(fmt::format("{} '{}': '{}' is not a number", option, text, s));
  }
  return v;
}

void warnDeprecated(const std::string& command, const std::string& old_name,
                    const std::string& instead) {
  printStderr("translucent: warning: {} {} is deprecated and will be removed in the next release: "
              "{}\n", command, old_name, instead);
}

std::pair<std::string, std::string> parseParam(const std::string& text, const std::string& option) {
  const size_t eq = text.find('=');
  if (eq == std::string::npos || eq == 0)
    throw ParameterError(fmt::format("{} '{}': expected NAME=VALUE", option, text));
  return {text.substr(0, eq), text.substr(eq + 1)};
}

// The options both forms share: the medium (--sigma-a, --sigma-s, --g, --eta, --scale) with
// --material, whose Option is returned.
void MediumOptions::addCommon(CLI::App& cmd, const std::string& material_help) {
  auto* m = cmd.add_option("--material", preset, material_help);
  auto* a = cmd.add_option("--sigma-a", sigma_a, "Absorption coefficient σa, 'v' or 'r,g,b' [1/mm]");
  auto* s = cmd.add_option("--sigma-s", sigma_s,
                           "Scattering coefficient σs, 'v' or 'r,g,b' [1/mm] (σs' = (1-g)σs)");
  a->needs(s);
  s->needs(a);
  m->excludes(a)->excludes(s);
  cmd.add_option("--g", g, "Henyey-Greenstein mean cosine g in (-1, 1)" +
                               std::string(default_preset_.empty() ? "" : " (default 0, or the preset's)"));
  cmd.add_option("--eta", eta, "Relative index of refraction η" +
                                   std::string(default_preset_.empty() ? "" : " (default 1.3, or the preset's)"));
  cmd.add_option("--scale", scale, "Medium units (mm) per scene unit" +
                                       std::string(default_preset_.empty() ? "" : " (default 1)"));
}

void MediumOptions::add(CLI::App& cmd, const std::string& default_preset) {
  default_preset_ = default_preset;
  addCommon(cmd, "Measured material of Jensen et al. 2001 (see `translucent presets`); default " +
                     default_preset + " unless --sigma-a/--sigma-s are given");
  // The old spelling of --material (render's --preset was the empirical technique's survey
  // preset: one name, two meanings).
  const std::string command = cmd.get_parent() && !cmd.get_parent()->get_name().empty()
                                  ? cmd.get_parent()->get_name() + " " + cmd.get_name()
                                  : cmd.get_name();
  auto* old = cmd.add_option_function<std::string>(
      "--preset",
      [this, command](const std::string& v) {
        warnDeprecated(command, "--preset", "use --material " + v);
        preset = v;
      },
      "Deprecated: --material");
  old->excludes(cmd.get_option("--material"))
      ->excludes(cmd.get_option("--sigma-a"))
      ->excludes(cmd.get_option("--sigma-s"));
}

void MediumOptions::addOverrides(CLI::App& cmd, bool with_model) {
  default_preset_.clear();
  addCommon(cmd, "Measured material of Jensen et al. 2001 (see `translucent presets`) instead of "
                 "the scene's homogeneous material");
  if (with_model)
    cmd.add_option("--model", model,
                   "BSSRDF model name, .bssrdf file or tabulated profile .csv (default: the "
                   "scene's)");
}

bool MediumOptions::overrides() const {
  return !preset.empty() || !sigma_a.empty() || g || eta || scale || model;
}

std::string MediumOptions::commandLine() const {
  std::string out;
  if (!preset.empty()) out += " --material " + preset;
  if (!sigma_a.empty()) out += fmt::format(" --sigma-a {} --sigma-s {}", sigma_a, sigma_s);
  if (g) out += fmt::format(" --g {}", *g);
  if (eta) out += fmt::format(" --eta {}", *eta);
  if (scale) out += fmt::format(" --scale {}", *scale);
  if (model) out += " --model " + *model;
  return out;
}

Medium MediumOptions::medium() const {
  Medium m;
  if (!sigma_a.empty()) {
    m.sigma_a = parseRgb(sigma_a, "--sigma-a");
    m.sigma_s = parseRgb(sigma_s, "--sigma-s");
    m.g = g.value_or(0.0);
    m.eta = eta.value_or(1.3);
  } else {
    const auto& pr = translucent::preset(preset.empty() ? default_preset_ : preset);
    m = pr.medium();
    if (g) m = Medium::fromReduced(pr.sigma_a, pr.sigma_s_prime, *g, m.eta);
    if (eta) m.eta = *eta;
  }
  m.scale = scale.value_or(1.0);
  m.validate();
  return m;
}

void MediumOptions::apply(scene::Scene& s) const {
  if (model) {
    if (model->empty()) throw ParameterError("--model '': expected a model name or a file");
    s.model = *model;
  }
  const bool medium = !preset.empty() || !sigma_a.empty() || g.has_value();
  if (medium && !s.material.homogeneous()) {
    const char* option = !preset.empty() ? "--material" : !sigma_a.empty() ? "--sigma-a" : "--g";
    throw ParameterError(fmt::format(
        "{}: the scene's material is of type '{}': the medium options replace a homogeneous "
        "material only (--eta, --scale and --model apply to any)", option, s.material.type()));
  }
  try {
    applyMedium(s);
  } catch (const ParameterError& e) {
    throw ParameterError(fmt::format("the material options ({}): {}", commandLine().substr(1),
                                     e.what()));
  }
}

void MediumOptions::applyMedium(scene::Scene& s) const {
  Medium m = s.medium;
  if (!preset.empty()) {
    const Preset& pr = translucent::preset(preset);
    m = Medium::fromReduced(pr.sigma_a, pr.sigma_s_prime, g.value_or(pr.g), eta.value_or(pr.eta));
    s.preset = preset;
  } else if (!sigma_a.empty()) {
    m.sigma_a = parseRgb(sigma_a, "--sigma-a");
    m.sigma_s = parseRgb(sigma_s, "--sigma-s");
    if (g) m.g = *g;
    s.preset.clear();
  } else if (g) {
    if (!s.preset.empty()) {
      // As the scene file's "g" beside a preset: the preset's reduced coefficients kept.
      const Preset& pr = translucent::preset(s.preset);
      m = Medium::fromReduced(pr.sigma_a, pr.sigma_s_prime, *g, m.eta);
    } else {
      m.g = *g;
    }
  }
  if (eta) m.eta = *eta;
  m.scale = scale.value_or(s.medium.scale);
  m.validate();
  s.medium = m;
}

}  // namespace translucent::cli
