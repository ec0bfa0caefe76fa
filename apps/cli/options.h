// SPDX-License-Identifier: GPL-3.0-or-later
// Option parsing shared by the subcommands: RGB triples, the material options, --param.
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "translucent/optics/medium.h"

namespace translucent::scene {
struct Scene;
}

namespace translucent::cli {

// "0.5" (grey) or "r,g,b"; throws ParameterError naming the option.
Rgb parseRgb(const std::string& text, const std::string& option);
// A count as typed ("1000000", "1e6"): a whole number >= 1; throws ParameterError naming `option`.
uint64_t parseCount(const std::string& text, const char* option);
// "a,b,c" -> {"a","b","c"}
std::vector<std::string> splitList(const std::string& text);

// The material options, one spelling and one meaning in every command that uses a material:
//   --material PRESET | --sigma-a r,g,b --sigma-s r,g,b;  --g G;  --eta E;  --scale S;  --model M
// add(): the medium of a command that has no scene (profile, pathtrace sphere, integrate sphere),
// PRESET by default; --preset is the deprecated spelling of --material there (a warning on
// stderr). addOverrides(): for commands that read a scene (render, compare, pathtrace mesh,
// integrate mesh), each option given overrides the scene's material (apply()): the medium options
// a homogeneous material, --eta, --scale and --model any material.
struct MediumOptions {
  std::string preset;  // --material
  std::string sigma_a, sigma_s;
  std::optional<double> g, eta, scale;
  std::optional<std::string> model;  // --model (addOverrides with the model only)

  void add(CLI::App& cmd, const std::string& default_preset = "Marble");
  void addOverrides(CLI::App& cmd, bool with_model = true);
  // Builds and validates the medium (throws ParameterError).
  Medium medium() const;
  // Whether any option was given (addOverrides).
  bool overrides() const;
  // The options given, over the scene's material (throws ParameterError naming the option).
  void apply(scene::Scene& s) const;
  // The options given, as they would be typed again (" --material Skin1 --eta 1.4"; "" for none).
  std::string commandLine() const;

 private:
  void addCommon(CLI::App& cmd, const std::string& material_help);
  void applyMedium(scene::Scene& s) const;
  std::string default_preset_;
};

// A deprecated spelling kept for one release: `old_name` still works as `new_name` does, with a
// warning on stderr when it is given ("translucent: warning: render --sigma is deprecated: ...").
void warnDeprecated(const std::string& command, const std::string& old_name,
                    const std::string& instead);

// --param NAME=VALUE (repeatable): split at the first '='; throws ParameterError naming the option
// when there is none or the name is empty.
std::pair<std::string, std::string> parseParam(const std::string& text, const std::string& option);

}  // namespace translucent::cli
