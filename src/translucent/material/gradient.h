// SPDX-License-Identifier: GPL-3.0-or-later
// "gradient": a linear blend of two media along the segment from point a to point b (material
// space, medium units); media[0] at and before a, media[1] at and beyond b:
//   {"type": "gradient", "from": [x, y, z], "to": [x, y, z], "media": [{...}, {...}]}
// t = clamp((q − a)·(b − a) / |b − a|², 0, 1), medium = (1 − t) media[0] + t media[1] (σa, σs, g).
#pragma once

#include <vector>

#include "translucent/material/field_common.h"
#include "translucent/material/medium_desc.h"

namespace translucent::material {

struct GradientDesc {
  glm::dvec3 from{0.0}, to{1.0, 0.0, 0.0};
  std::vector<MediumDesc> media;  // two

  bool operator==(const GradientDesc&) const = default;
};

GradientDesc parseGradient(const ParseContext& c, const json& mat, const std::string& key);
void writeGradient(const GradientDesc& d, json& mat);

class GradientField final : public VolumeField {
 public:
  explicit GradientField(const GradientDesc& d);
  LocalMedium at(const glm::dvec3& q) const override;
  // Exact: t is linear, so its range over the box is that over the corners, and σt is linear in t.
  Rgb majorant(const glm::dvec3& lo, const glm::dvec3& hi) const override;
  double t(const glm::dvec3& q) const;
  // For the GPU twin (reference/gpu/field_gpu.h).
  const glm::dvec3& from() const { return from_; }
  const glm::dvec3& axis() const { return axis_; }
  const LocalMedium& medium(int i) const { return media_[i]; }

 private:
  glm::dvec3 from_, axis_;  // axis_ = (b − a) / |b − a|²
  LocalMedium media_[2];
};

}  // namespace translucent::material
