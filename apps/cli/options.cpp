// SPDX-License-Identifier: GPL-3.0-or-later
#include "options.h"

#include <fmt/format.h>

#include <cmath>
#include <cstdlib>

#include "translucent/optics/presets.h"

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

void MediumOptions::add(CLI::App& cmd, const std::string& default_preset) {
  default_preset_ = default_preset;
  auto* p = cmd.add_option("--preset", preset,
                           "Measured material of Jensen et al. 2001 (see `translucent presets`); "
                           "default " + default_preset + " unless --sigma-a/--sigma-s are given");
  auto* a = cmd.add_option("--sigma-a", sigma_a, "Absorption coefficient σa, 'v' or 'r,g,b' [1/mm]");
  auto* s = cmd.add_option("--sigma-s", sigma_s,
                           "Scattering coefficient σs, 'v' or 'r,g,b' [1/mm] (σs' = (1-g)σs)");
  a->needs(s);
  s->needs(a);
  p->excludes(a)->excludes(s);
  cmd.add_option("--g", g, "Henyey-Greenstein mean cosine g in (-1, 1) (default 0)");
  cmd.add_option("--eta", eta, "Relative index of refraction η (default 1.3)");
  cmd.add_option("--scale", scale, "Medium units (mm) per scene unit (default 1)");
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
  m.scale = scale;
  m.validate();
  return m;
}

}  // namespace translucent::cli
