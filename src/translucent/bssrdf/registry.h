// SPDX-License-Identifier: GPL-3.0-or-later
// Name -> model registry. An unknown name is an error that lists the valid names.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "translucent/bssrdf/profile.h"

namespace translucent::bssrdf {

// Thrown for an unknown model name.
class UnknownModelError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

// The registered model with this name, or the tabulated profile a .csv path names (loaded once
// per path, bssrdf/tabulated.h; throws ParameterError naming the file and line). Models live for
// the whole program.
const Model& model(std::string_view name);
// Registered names in registration order.
std::vector<std::string> modelNames();

// One profile per RGB channel of a medium (coefficients per scene unit, see Medium::channel).
using RgbProfiles = std::array<std::unique_ptr<RadialProfile>, 3>;
RgbProfiles profiles(const Model& model, const Medium& medium);

}  // namespace translucent::bssrdf
