// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/material/gradient.h"

#include "translucent/material/parse_context.h"

#include <algorithm>

#include <glm/geometric.hpp>

namespace translucent::material {

GradientDesc parseGradient(const ParseContext& c, const json& mat, const std::string& key) {
  const JsonReader& r = c.reader;
  r.onlyKeys(mat, key, materialKeys({"from", "to", "media"}));
  GradientDesc d;
  d.from = r.requiredVec3(mat, "from", key);
  d.to = r.requiredVec3(mat, "to", key);
  if (!(glm::length(d.to - d.from) > 0.0))
    r.fail(key + ".to", "equals \"from\": expected two distinct points");
  d.media = parseMediaArray(r, mat, "media", key, 2);
  return d;
}

void writeGradient(const GradientDesc& d, json& mat) {
  mat["from"] = vec(d.from);
  mat["to"] = vec(d.to);
  mat["media"] = json::array({toJson(d.media[0]), toJson(d.media[1])});
}

GradientField::GradientField(const GradientDesc& d)
    : from_(d.from),
      axis_((d.to - d.from) / glm::dot(d.to - d.from, d.to - d.from)),
      media_{d.media.at(0).medium, d.media.at(1).medium} {}

double GradientField::t(const glm::dvec3& q) const {
  return std::clamp(glm::dot(q - from_, axis_), 0.0, 1.0);
}

LocalMedium GradientField::at(const glm::dvec3& q) const {
  return LocalMedium::mix(media_[0], media_[1], t(q));
}

Rgb GradientField::majorant(const glm::dvec3& lo, const glm::dvec3& hi) const {
  double tmin = 1.0, tmax = 0.0;
  for (int i = 0; i < 8; ++i) {
    const glm::dvec3 corner((i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z);
    const double v = t(corner);
    tmin = std::min(tmin, v);
    tmax = std::max(tmax, v);
  }
  return padMajorant(maxRgb(LocalMedium::mix(media_[0], media_[1], tmin).sigmaT(),
                            LocalMedium::mix(media_[0], media_[1], tmax).sigmaT()));
}

}  // namespace translucent::material
