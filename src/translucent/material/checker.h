// SPDX-License-Identifier: GPL-3.0-or-later
// "checker": a 3D checkerboard of two media in material space.
//   {"type": "checker", "cell": 5.0 | [x, y, z],   // cell size [medium units], each > 0
//    "media": [{...}, {...}]}                       // media[0] where ⌊x/cx⌋+⌊y/cy⌋+⌊z/cz⌋ is even
#pragma once

#include <vector>

#include "translucent/material/field_common.h"
#include "translucent/material/medium_desc.h"

namespace translucent::material {

struct CheckerDesc {
  glm::dvec3 cell{1.0};
  std::vector<MediumDesc> media;  // two

  bool operator==(const CheckerDesc&) const = default;
};

CheckerDesc parseChecker(const ParseContext& c, const json& mat, const std::string& key);
void writeChecker(const CheckerDesc& d, json& mat);

class CheckerField final : public VolumeField {
 public:
  explicit CheckerField(const CheckerDesc& d);
  LocalMedium at(const glm::dvec3& q) const override;
  // Exact: the cell's σt when the box lies in one cell, the larger of the two otherwise.
  Rgb majorant(const glm::dvec3& lo, const glm::dvec3& hi) const override;
  // 0 or 1: which medium holds q.
  int cellParity(const glm::dvec3& q) const;
  // For the GPU twin (reference/gpu/field_gpu.h).
  const glm::dvec3& cell() const { return cell_; }
  const LocalMedium& medium(int i) const { return media_[i]; }

 private:
  glm::dvec3 cell_;
  LocalMedium media_[2];
};

}  // namespace translucent::material
