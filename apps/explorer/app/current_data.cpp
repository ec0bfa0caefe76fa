// SPDX-License-Identifier: GPL-3.0-or-later
// "Print current data" of the explorer (current_data.h).
#include "app/current_data.h"

#include <fmt/format.h>

#include <exception>
#include <string>
#include <variant>

#include "translucent/techniques/registry.h"

namespace translucent::explorer {

QString currentDataText(const scene::Scene& s) {
  std::string text = "current data: scene\n" + scene::toJson(s) + "\n";
  try {
    const auto technique = techniques::make(s.technique);
    text += fmt::format("technique {} ({}), parameters:\n", s.technique, technique->description());
    for (const auto& p : technique->parameters()) {
      const auto it = s.settings.find(p.name);
      std::string value;
      if (it != s.settings.end())
        value = std::visit([](const auto& v) { return fmt::format("{}", v); }, it->second);
      else
        value = std::visit([](const auto& v) { return fmt::format("{}", v); }, p.value) + " (default)";
      text += fmt::format("  {} = {}\n", p.name, value);
    }
  } catch (const std::exception& e) {
    text += fmt::format("technique {}: {}\n", s.technique, e.what());
  }
  return QString::fromStdString(text);
}

}  // namespace translucent::explorer
