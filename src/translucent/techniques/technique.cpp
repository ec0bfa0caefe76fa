// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/techniques/technique.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace translucent::techniques {

const char* toString(ParameterType type) {
  switch (type) {
    case ParameterType::Float: return "float";
    case ParameterType::Int: return "int";
    case ParameterType::Bool: return "bool";
    case ParameterType::Enum: return "enum";
  }
  return "?";
}

ParameterInfo ParameterInfo::floating(std::string name, double def, double min, double max,
                                      std::string help, std::string unit, bool log) {
  ParameterInfo p;
  p.name = std::move(name);
  p.type = ParameterType::Float;
  p.value = def;
  p.min = min;
  p.max = max;
  p.help = std::move(help);
  p.unit = std::move(unit);
  p.logarithmic = log;
  return p;
}

ParameterInfo ParameterInfo::integer(std::string name, int def, int min, int max, std::string help,
                                     std::string unit) {
  ParameterInfo p;
  p.name = std::move(name);
  p.type = ParameterType::Int;
  p.value = def;
  p.min = min;
  p.max = max;
  p.help = std::move(help);
  p.unit = std::move(unit);
  return p;
}

ParameterInfo ParameterInfo::boolean(std::string name, bool def, std::string help) {
  ParameterInfo p;
  p.name = std::move(name);
  p.type = ParameterType::Bool;
  p.value = def;
  p.min = 0;
  p.max = 1;
  p.help = std::move(help);
  return p;
}

ParameterInfo ParameterInfo::enumeration(std::string name, std::string def,
                                         std::vector<std::string> choices, std::string help) {
  ParameterInfo p;
  p.name = std::move(name);
  p.type = ParameterType::Enum;
  p.value = std::move(def);
  p.choices = std::move(choices);
  p.help = std::move(help);
  return p;
}

ParameterInfo ParameterInfo::withSweep(std::vector<double> values) && {
  sweep = std::move(values);
  return std::move(*this);
}

std::string toString(const ParameterValue& value) {
  return std::visit(
      [](const auto& v) -> std::string {
        using T = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<T, bool>) return v ? "true" : "false";
        else if constexpr (std::is_same_v<T, std::string>) return v;
        else return fmt::format("{}", v);
      },
      value);
}

namespace {

[[noreturn]] void bad(const ParameterInfo& info, const ParameterValue& value, const std::string& expected) {
  throw ParameterError(fmt::format("parameter '{}' is {}: expected {}", info.name,
                                   std::holds_alternative<std::string>(value)
                                       ? "'" + std::get<std::string>(value) + "'"
                                       : toString(value),
                                   expected));
}

bool parseNumber(const std::string& text, double& out) {
  if (text.empty()) return false;
  char* end = nullptr;
  out = std::strtod(text.c_str(), &end);
  return end != text.c_str() && *end == '\0';
}

}  // namespace

ParameterValue checkedValue(const ParameterInfo& info, const ParameterValue& value) {
  switch (info.type) {
    case ParameterType::Float: {
      double v = 0.0;
      if (const auto* d = std::get_if<double>(&value)) v = *d;
      else if (const auto* i = std::get_if<int>(&value)) v = *i;
      else if (const auto* s = std::get_if<std::string>(&value); !(s && parseNumber(*s, v)))
        bad(info, value, "a number");
      if (!std::isfinite(v) || v < info.min || v > info.max)
        bad(info, value, fmt::format("a finite number in [{}, {}]", info.min, info.max));
      return v;
    }
    case ParameterType::Int: {
      double v = 0.0;
      if (const auto* d = std::get_if<double>(&value)) v = *d;
      else if (const auto* i = std::get_if<int>(&value)) v = *i;
      else if (const auto* s = std::get_if<std::string>(&value); !(s && parseNumber(*s, v)))
        bad(info, value, "a whole number");
      if (!std::isfinite(v) || std::floor(v) != v || v < info.min || v > info.max)
        bad(info, value, fmt::format("a whole number in [{}, {}]", info.min, info.max));
      return static_cast<int>(v);
    }
    case ParameterType::Bool: {
      if (const auto* b = std::get_if<bool>(&value)) return *b;
      if (const auto* s = std::get_if<std::string>(&value)) {
        if (*s == "true" || *s == "on" || *s == "1" || *s == "yes") return true;
        if (*s == "false" || *s == "off" || *s == "0" || *s == "no") return false;
      }
      if (const auto* d = std::get_if<double>(&value); d && (*d == 0.0 || *d == 1.0)) return *d == 1.0;
      if (const auto* i = std::get_if<int>(&value); i && (*i == 0 || *i == 1)) return *i == 1;
      bad(info, value, "true or false");
    }
    case ParameterType::Enum: {
      const auto* s = std::get_if<std::string>(&value);
      if (s == nullptr || std::find(info.choices.begin(), info.choices.end(), *s) == info.choices.end())
        bad(info, value, fmt::format("one of {}", fmt::join(info.choices, ", ")));
      return *s;
    }
  }
  bad(info, value, "a known type");
}

ParameterSet::ParameterSet(std::vector<ParameterInfo> infos) : infos_(std::move(infos)) {
  for (const auto& i : infos_) values_[i.name] = checkedValue(i, i.value);
}

const ParameterInfo& ParameterSet::info(std::string_view name) const {
  for (const auto& i : infos_)
    if (i.name == name) return i;
  std::vector<std::string> names;
  for (const auto& i : infos_) names.push_back(i.name);
  throw ParameterError(fmt::format("unknown parameter '{}': valid parameters are {}", name,
                                   fmt::join(names, ", ")));
}

bool ParameterSet::set(std::string_view name, const ParameterValue& value) {
  ParameterValue v = checkedValue(info(name), value);
  auto it = values_.find(name);
  if (it->second == v) return false;
  it->second = std::move(v);
  return true;
}

const ParameterValue& ParameterSet::get(std::string_view name) const {
  auto it = values_.find(name);
  if (it == values_.end()) (void)info(name);  // throws with the valid names
  return it->second;
}

double Frame::totalMs() const {
  double sum = 0.0;
  for (const auto& p : passes)
    if (p.depth == 0) sum += p.ms;
  return sum;
}

void applySettings(Technique& technique, const scene::Scene& scene) {
  for (const auto& [name, setting] : scene.settings) {
    const ParameterValue v = std::visit([](const auto& x) -> ParameterValue { return x; }, setting);
    try {
      technique.setParameter(name, v);
    } catch (const ParameterError& e) {
      throw ParameterError(fmt::format("scene technique.{}: {}", name, e.what()));
    }
  }
}

bssrdf::ExitConvention radianceConvention(const Technique& technique) {
  for (const auto& p : technique.parameters())
    if (p.name == "radiance_convention")
      return bssrdf::parseExitConvention(std::get<std::string>(technique.parameter(p.name)));
  return bssrdf::ExitConvention::Jensen;
}

}  // namespace translucent::techniques
