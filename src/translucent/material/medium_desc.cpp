// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/material/medium_desc.h"

#include "translucent/material/parse_context.h"

#include "translucent/optics/presets.h"

namespace translucent::material {

MediumDesc parseMediumDesc(const JsonReader& r, const json& j, const std::string& key) {
  r.onlyKeys(j, key, {"preset", "sigma_a", "sigma_s", "g"});
  const bool explicitCoefficients = j.contains("sigma_a") || j.contains("sigma_s");
  if (j.contains("preset") && explicitCoefficients)
    r.fail(key, "give either \"preset\" or \"sigma_a\" and \"sigma_s\", not both");
  MediumDesc d;
  Medium m;
  if (j.contains("preset")) {
    d.preset = r.string(j, "preset", key);
    const Preset* p = nullptr;
    try {
      p = &preset(d.preset);
    } catch (const ParameterError& e) {
      r.fail(key + ".preset", e.what());
    }
    const double g = r.number(j, "g", key, p->g);
    try {
      m = Medium::fromReduced(p->sigma_a, p->sigma_s_prime, g, p->eta);
    } catch (const ParameterError& e) {
      r.fail(key, e.what());
    }
  } else if (explicitCoefficients) {
    if (!j.contains("sigma_a") || !j.contains("sigma_s"))
      r.fail(key, "\"sigma_a\" and \"sigma_s\" must be given together");
    m.sigma_a = r.rgb(j["sigma_a"], key + ".sigma_a");
    m.sigma_s = r.rgb(j["sigma_s"], key + ".sigma_s");
    m.g = r.number(j, "g", key, 0.0);
  } else {
    r.fail(key, "expected \"preset\" or \"sigma_a\" and \"sigma_s\"");
  }
  m.eta = 1.3;  // checked with the material's η elsewhere; here only the coefficients and g
  m.scale = 1.0;
  try {
    m.validate();
  } catch (const ParameterError& e) {
    r.fail(key, e.what());
  }
  d.medium = LocalMedium::of(m);
  return d;
}

json toJson(const MediumDesc& m) {
  json j;
  if (!m.preset.empty()) {
    j["preset"] = m.preset;
  } else {
    j["sigma_a"] = rgbJson(m.medium.sigma_a);
    j["sigma_s"] = rgbJson(m.medium.sigma_s);
  }
  j["g"] = m.medium.g;
  return j;
}

MediumDesc mediumDesc(const Rgb& sigma_a, const Rgb& sigma_s, double g) {
  return {"", {sigma_a, sigma_s, g}};
}

std::vector<MediumDesc> parseMediaArray(const JsonReader& r, const json& obj, const char* name,
                                        const std::string& key, size_t n) {
  const std::string k = key + "." + name;
  if (!obj.contains(name)) r.fail(k, fmt::format("required (an array of {} media)", n));
  const json& a = obj.at(name);
  if (!a.is_array() || a.size() != n)
    r.fail(k, fmt::format("{}: expected an array of {} media", JsonReader::describe(a), n));
  std::vector<MediumDesc> out;
  for (size_t i = 0; i < n; ++i) out.push_back(parseMediumDesc(r, a[i], fmt::format("{}[{}]", k, i)));
  return out;
}

}  // namespace translucent::material
