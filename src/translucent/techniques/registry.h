// SPDX-License-Identifier: GPL-3.0-or-later
// Name -> technique registry. Adding a technique: one folder under src/techniques/ and one line in
// registry.cpp. An unknown name is an error that lists the valid names.
#pragma once

#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "translucent/techniques/technique.h"

namespace translucent::techniques {

class UnknownTechniqueError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

// A new instance of the technique with this name (parameters at their defaults).
std::unique_ptr<Technique> make(std::string_view name);
// Registered names in registration order.
std::vector<std::string> names();
// One-line description of a registered technique (UnknownTechniqueError otherwise).
std::string description(std::string_view name);

}  // namespace translucent::techniques
