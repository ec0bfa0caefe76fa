// SPDX-License-Identifier: GPL-3.0-or-later
// Option parsing shared by the subcommands: RGB triples and the medium options.
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "translucent/optics/medium.h"

namespace translucent::cli {

// "0.5" (grey) or "r,g,b"; throws ParameterError naming the option.
Rgb parseRgb(const std::string& text, const std::string& option);
// A count as typed ("1000000", "1e6"): a whole number >= 1; throws ParameterError naming `option`.
uint64_t parseCount(const std::string& text, const char* option);
// "a,b,c" -> {"a","b","c"}
std::vector<std::string> splitList(const std::string& text);

// --preset NAME | --sigma-a r,g,b --sigma-s r,g,b [--g G]; [--eta E] [--scale S].
struct MediumOptions {
  std::string preset;
  std::string sigma_a, sigma_s;
  std::optional<double> g, eta;
  double scale = 1.0;

  void add(CLI::App& cmd, const std::string& default_preset = "Marble");
  // Builds and validates the medium (throws ParameterError).
  Medium medium() const;

 private:
  std::string default_preset_;
};

}  // namespace translucent::cli
