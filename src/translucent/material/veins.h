// SPDX-License-Identifier: GPL-3.0-or-later
// "veins": marble, after Perlin (1985): bands of a vein medium through a base medium along a
// direction, their phase distorted by turbulence of 3D gradient noise (noise.h).
//   {"type": "veins",
//    "media": [{base}, {vein}],
//    "period": 10.0,          // distance between veins along "direction" [medium units], > 0
//    "direction": [1, 0, 0],  // across the veins (normalised)
//    "noise_size": 10.0,      // feature size of the noise [medium units], > 0 (default: period)
//    "octaves": 4,            // turbulence octaves, 1 .. 12
//    "turbulence": 1.0,       // phase distortion [periods per unit of turbulence], >= 0
//    "sharpness": 8.0}        // >= 1: larger gives thinner veins
// Per point: φ = q·d / period + turbulence · T(q / noise_size), w = (1 − |sin πφ|)^sharpness ∈
// [0, 1], medium = (1 − w) base + w vein (σa, σs and g blended alike), so every coefficient lies
// between the two media's.
#pragma once

#include <vector>

#include "translucent/material/field_common.h"
#include "translucent/material/medium_desc.h"

namespace translucent::material {

struct VeinsDesc {
  std::vector<MediumDesc> media;  // base, vein
  double period = 10.0;
  glm::dvec3 direction{1.0, 0.0, 0.0};
  double noise_size = 10.0;
  int octaves = 4;
  double turbulence = 1.0;
  double sharpness = 8.0;

  bool operator==(const VeinsDesc&) const = default;
};

VeinsDesc parseVeins(const ParseContext& c, const json& mat, const std::string& key);
void writeVeins(const VeinsDesc& d, json& mat);

class VeinsField final : public VolumeField {
 public:
  explicit VeinsField(const VeinsDesc& d);
  LocalMedium at(const glm::dvec3& q) const override;
  // The larger σt of the two media (the blend is convex).
  Rgb majorant(const glm::dvec3& lo, const glm::dvec3& hi) const override;
  // w ∈ [0, 1]: the vein medium's weight at q.
  double veinWeight(const glm::dvec3& q) const;
  const VeinsDesc& desc() const { return d_; }  // for the GPU twin (reference/gpu/field_gpu.h)

 private:
  VeinsDesc d_;
  LocalMedium base_, vein_;
};

}  // namespace translucent::material
