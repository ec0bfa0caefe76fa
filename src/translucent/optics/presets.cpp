// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/optics/presets.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cctype>
#include <nlohmann/json.hpp>

namespace translucent {
namespace optics::detail {
extern const std::string_view kPresetsJson;
}

namespace {

struct Table {
  std::vector<Preset> presets;
  std::string source, units;
};

const Table& table() {
  static const Table t = [] {
    Table out;
    const auto j = nlohmann::json::parse(optics::detail::kPresetsJson);
    out.source = j.at("source").get<std::string>();
    out.units = j.at("units").get<std::string>();
    const double g = j.at("g").get<double>();
    const double eta = j.at("eta").get<double>();
    for (const auto& m : j.at("materials")) {
      Preset p;
      p.name = m.at("name").get<std::string>();
      p.sigma_s_prime = m.at("sigma_s_prime").get<Rgb>();
      p.sigma_a = m.at("sigma_a").get<Rgb>();
      p.g = g;
      p.eta = eta;
      out.presets.push_back(std::move(p));
    }
    return out;
  }();
  return t;
}

bool equalsIgnoreCase(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::tolower(static_cast<unsigned char>(x)) ==
                  std::tolower(static_cast<unsigned char>(y));
         });
}

}  // namespace

const std::vector<Preset>& presets() { return table().presets; }

const Preset& preset(std::string_view name) {
  for (const auto& p : presets())
    if (equalsIgnoreCase(p.name, name)) return p;
  std::vector<std::string> names;
  for (const auto& p : presets()) names.push_back(p.name);
  throw ParameterError(
      fmt::format("unknown preset '{}': valid presets are {}", name, fmt::join(names, ", ")));
}

std::string presetsSource() { return table().source; }
std::string presetsUnits() { return table().units; }

}  // namespace translucent
