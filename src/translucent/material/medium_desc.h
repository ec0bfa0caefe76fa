// SPDX-License-Identifier: GPL-3.0-or-later
// A medium inside a heterogeneous material description: a preset of Jensen et al. 2001
// (optics/presets.h; its own g unless given) or explicit coefficients, per medium unit:
//   {"preset": "Skin1"}  |  {"preset": "Marble", "g": 0.5}  |
//   {"sigma_a": [r, g, b] | v, "sigma_s": [r, g, b] | v, "g": 0.0}
// η and scale are the material's own (one η per object: the media of a field are index-matched).
#pragma once

#include <string>

#include <vector>

#include "translucent/material/field_common.h"
#include "translucent/material/material.h"

namespace translucent::material {

struct MediumDesc {
  std::string preset;  // the name as given; empty: explicit coefficients
  LocalMedium medium;  // per medium unit (a preset's σs = σs' / (1 − g))

  bool operator==(const MediumDesc&) const = default;
};

// Parses the object at `key` ("material.layers[0].medium"); throws ParameterError naming the
// key (an unknown preset lists the valid ones, a coefficient out of range names its channel).
MediumDesc parseMediumDesc(const JsonReader& r, const json& j, const std::string& key);
json toJson(const MediumDesc& m);
// Explicit coefficients (no preset), e.g. for tests.
MediumDesc mediumDesc(const Rgb& sigma_a, const Rgb& sigma_s, double g = 0.0);

// Requires `n` (≥ 2) media in the array at obj[name]; `key` is the object's key.
std::vector<MediumDesc> parseMediaArray(const JsonReader& r, const json& obj, const char* name,
                                        const std::string& key, size_t n);

}  // namespace translucent::material
