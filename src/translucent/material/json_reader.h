// SPDX-License-Identifier: GPL-3.0-or-later
// Strict JSON reading for the scene format (scene/scene.h) and the material descriptions it
// holds (material/material_desc.h): every accessor names the source (`what`, e.g. the scene
// file) and the key path ("material.layers[1].thickness") in its ParameterError, so a bad value
// is always reported where it is. Moved here from scene.cpp so that the material layer (below
// scene) parses its part of the format with the same checks and messages.
#pragma once

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "translucent/optics/medium.h"

namespace translucent::material {

using nlohmann::json;

// Reads JSON values with messages that name the source and the key path.
struct JsonReader {
  std::string what;

  [[noreturn]] void fail(const std::string& key, const std::string& message) const {
    throw ParameterError(fmt::format("{}: {}: {}", what, key, message));
  }
  void onlyKeys(const json& j, const std::string& key, std::initializer_list<const char*> valid) const {
    onlyKeys(j, key, std::vector<std::string>(valid.begin(), valid.end()));
  }
  // Throws naming the first key of `j` not in `valid` (and `j` not an object), listing the valid ones.
  void onlyKeys(const json& j, const std::string& key, const std::vector<std::string>& valid) const {
    if (!j.is_object())
      fail(key.empty() ? "top level" : key, fmt::format("{}: expected an object", describe(j)));
    const std::set<std::string> ok(valid.begin(), valid.end());
    for (const auto& [k, v] : j.items())
      if (!ok.count(k))
        fail(key.empty() ? k : key + "." + k,
             fmt::format("unknown key; valid keys here are {}", fmt::join(valid, ", ")));
  }
  // Every scene number is finite and of magnitude at most kMaxMagnitude: larger values are
  // finite in double but overflow to inf in the float buffers and shaders they reach (an
  // irradiance of 1e308 times a colour or a profile gives inf, then NaN pixels).
  static constexpr double kMaxMagnitude = 1e15;
  double number(const json& j, const std::string& key) const {
    if (!j.is_number()) fail(key, fmt::format("{}: expected a number", describe(j)));
    const double v = j.get<double>();
    if (!std::isfinite(v) || std::abs(v) > kMaxMagnitude)
      fail(key, fmt::format("is {}: expected a finite number of magnitude at most {:g}", v,
                            kMaxMagnitude));
    return v;
  }
  // A value as the message shows it: JSON text, cut short (a whole array would drown the message).
  static std::string describe(const json& j) {
    std::string text = j.dump();
    if (text.size() > 40) text = text.substr(0, 37) + "...";
    return fmt::format("{} {}", j.type_name(), text);
  }
  double number(const json& obj, const char* name, const std::string& key, double fallback) const {
    return obj.contains(name) ? number(obj.at(name), key + "." + name) : fallback;
  }
  bool boolean(const json& obj, const char* name, const std::string& key, bool fallback) const {
    if (!obj.contains(name)) return fallback;
    if (!obj.at(name).is_boolean())
      fail(key + "." + name, fmt::format("{}: expected true or false", describe(obj.at(name))));
    return obj.at(name).get<bool>();
  }
  // A whole number in [lo, hi]. The range is checked on the 64-bit value before narrowing:
  // j.get<int>() would read 4294967360 as 64.
  int integer(const json& obj, const char* name, const std::string& key, int fallback, int lo,
              int hi) const {
    if (!obj.contains(name)) return fallback;
    const json& j = obj.at(name);
    const std::string k = key + "." + name;
    if (!j.is_number_integer())
      fail(k, fmt::format("{}: expected a whole number in [{}, {}]", describe(j), lo, hi));
    // Non-negative integers are stored unsigned (and may exceed int64); compare in that type.
    const bool fits = j.is_number_unsigned()
                          ? j.get<uint64_t>() <= uint64_t(hi) &&
                                (lo <= 0 || j.get<uint64_t>() >= uint64_t(lo))
                          : j.get<int64_t>() >= lo && j.get<int64_t>() <= hi;
    if (!fits) fail(k, fmt::format("is {}: expected a whole number in [{}, {}]", j.dump(), lo, hi));
    return static_cast<int>(j.get<int64_t>());
  }
  glm::dvec3 vec3(const json& j, const std::string& key) const {
    if (!j.is_array() || j.size() != 3)
      fail(key, fmt::format("{}: expected an array of three numbers [x, y, z]", describe(j)));
    return {number(j[0], key + "[0]"), number(j[1], key + "[1]"), number(j[2], key + "[2]")};
  }
  glm::dvec3 vec3(const json& obj, const char* name, const std::string& key,
                  const glm::dvec3& fallback) const {
    return obj.contains(name) ? vec3(obj.at(name), key + "." + name) : fallback;
  }
  glm::dvec3 requiredVec3(const json& obj, const char* name, const std::string& key) const {
    if (!obj.contains(name)) fail(key + "." + name, "required");
    return vec3(obj.at(name), key + "." + name);
  }
  Rgb rgb(const json& j, const std::string& key) const {
    if (j.is_number()) {
      const double v = number(j, key);
      return {v, v, v};
    }
    if (!j.is_array() || j.size() != 3)
      fail(key, fmt::format("{}: expected a number or an array [r, g, b]", describe(j)));
    return {number(j[0], key + "[0]"), number(j[1], key + "[1]"), number(j[2], key + "[2]")};
  }
  std::string string(const json& obj, const char* name, const std::string& key) const {
    if (!obj.contains(name)) fail(key + "." + name, "required");
    const json& j = obj.at(name);
    if (!j.is_string()) fail(key + "." + name, fmt::format("{}: expected a string", describe(j)));
    return j.get<std::string>();
  }
};

inline json vec(const glm::dvec3& v) { return json::array({v.x, v.y, v.z}); }
inline json rgbJson(const Rgb& v) { return json::array({v[0], v[1], v[2]}); }


}  // namespace translucent::material
