// SPDX-License-Identifier: GPL-3.0-or-later
// Measured materials of Jensen et al. 2001 (data/presets/jensen2001.json, embedded at build time).
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "translucent/optics/medium.h"

namespace translucent {

struct Preset {
  std::string name;
  Rgb sigma_s_prime;  // reduced scattering coefficient σs' [1/mm]
  Rgb sigma_a;        // absorption coefficient σa [1/mm]
  double g = 0.0;
  double eta = 1.3;

  Medium medium(double scale = 1.0) const {
    return Medium::fromReduced(sigma_a, sigma_s_prime, g, eta, scale);
  }
};

// All presets in table order.
const std::vector<Preset>& presets();
// Case-insensitive lookup; throws ParameterError listing the valid names.
const Preset& preset(std::string_view name);
// The preset table's source line and units, for printing.
std::string presetsSource();
std::string presetsUnits();

}  // namespace translucent
