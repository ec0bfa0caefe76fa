// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/material/checker.h"

#include "translucent/material/parse_context.h"

#include <cmath>

namespace translucent::material {

CheckerDesc parseChecker(const ParseContext& c, const json& mat, const std::string& key) {
  const JsonReader& r = c.reader;
  r.onlyKeys(mat, key, materialKeys({"cell", "media"}));
  CheckerDesc d;
  d.cell = positiveVec3(r, mat, "cell", key);
  d.media = parseMediaArray(r, mat, "media", key, 2);
  return d;
}

void writeChecker(const CheckerDesc& d, json& mat) {
  mat["cell"] = vec(d.cell);
  mat["media"] = json::array({toJson(d.media[0]), toJson(d.media[1])});
}

CheckerField::CheckerField(const CheckerDesc& d)
    : cell_(d.cell), media_{d.media.at(0).medium, d.media.at(1).medium} {}

int CheckerField::cellParity(const glm::dvec3& q) const {
  const double s = std::floor(q.x / cell_.x) + std::floor(q.y / cell_.y) + std::floor(q.z / cell_.z);
  return std::fmod(std::abs(s), 2.0) == 1.0 ? 1 : 0;
}

LocalMedium CheckerField::at(const glm::dvec3& q) const { return media_[cellParity(q)]; }

Rgb CheckerField::majorant(const glm::dvec3& lo, const glm::dvec3& hi) const {
  const glm::dvec3 a = glm::floor(lo / cell_), b = glm::floor(hi / cell_);
  if (a == b) return padMajorant(media_[cellParity(lo)].sigmaT());
  return padMajorant(maxRgb(media_[0].sigmaT(), media_[1].sigmaT()));
}

}  // namespace translucent::material
