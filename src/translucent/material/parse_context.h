// SPDX-License-Identifier: GPL-3.0-or-later
// The parsing side of the material descriptions (material_desc.h): the context a type's parser
// gets and the checked readers the types share. For .cpp files (it brings in nlohmann/json).
#pragma once

#include <cmath>
#include <initializer_list>
#include <optional>
#include <string>
#include <vector>

#include "translucent/material/field_common.h"
#include "translucent/material/json_reader.h"

namespace translucent::material {

// Finds a file a material names (scene/data_path.h: beside the scene, then the data search
// path); `key` ("material.file") goes into the message when it is nowhere. The scene supplies it.
using FileResolver =
    std::function<std::filesystem::path(const std::string& name, const std::string& key)>;
struct ParseContext {
  JsonReader reader;
  FileResolver resolve;
  double eta = 1.3;              // the material's η (rd_map inverts with it)
  std::string model = "dipole";  // the material's model (resolved .bssrdf path or a name)
};

// The keys valid in a heterogeneous "material" object: the type's own and those every type takes.
inline std::vector<std::string> materialKeys(std::initializer_list<const char*> own) {
  std::vector<std::string> keys = {"type", "eta", "scale", "model"};
  keys.insert(keys.end(), own.begin(), own.end());
  return keys;
}
// A positive finite number at obj[name] (required when no fallback is given).
inline double positive(const JsonReader& r, const json& obj, const char* name,
                       const std::string& key, std::optional<double> fallback = std::nullopt) {
  if (!obj.contains(name)) {
    if (!fallback) r.fail(key + "." + name, "required (a number > 0)");
    return *fallback;
  }
  const double v = r.number(obj.at(name), key + "." + name);
  if (!(v > 0.0)) r.fail(key + "." + name, fmt::format("is {}: expected a number > 0", v));
  return v;
}
// A number or an array of three, each > 0.
inline glm::dvec3 positiveVec3(const JsonReader& r, const json& obj, const char* name,
                               const std::string& key) {
  const std::string k = key + "." + name;
  if (!obj.contains(name)) r.fail(k, "required (a number or [x, y, z], each > 0)");
  const json& j = obj.at(name);
  const glm::dvec3 v = j.is_number() ? glm::dvec3(r.number(j, k)) : r.vec3(j, k);
  if (!(v.x > 0.0 && v.y > 0.0 && v.z > 0.0))
    r.fail(k, fmt::format("is [{}, {}, {}]: expected each > 0", v.x, v.y, v.z));
  return v;
}
// A non-zero direction, normalised (kept bit for bit when already unit, for the round trip).
inline glm::dvec3 direction(const JsonReader& r, const json& obj, const char* name,
                            const std::string& key, const glm::dvec3& fallback) {
  glm::dvec3 d = r.vec3(obj, name, key, fallback);
  const double n = std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
  if (!(n > 0.0))
    r.fail(key + "." + name, fmt::format("is [{}, {}, {}]: expected a non-zero direction", d.x,
                                         d.y, d.z));
  if (std::abs(n - 1.0) > 1e-12) d /= n;
  return d;
}

}  // namespace translucent::material
