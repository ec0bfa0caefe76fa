// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/material/veins.h"

#include "translucent/material/parse_context.h"

#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

#include "translucent/material/noise.h"

namespace translucent::material {

VeinsDesc parseVeins(const ParseContext& c, const json& mat, const std::string& key) {
  const JsonReader& r = c.reader;
  r.onlyKeys(mat, key, materialKeys({"media", "period", "direction", "noise_size", "octaves",
                                     "turbulence", "sharpness"}));
  VeinsDesc d;
  d.media = parseMediaArray(r, mat, "media", key, 2);
  d.period = positive(r, mat, "period", key);
  d.direction = direction(r, mat, "direction", key, d.direction);
  d.noise_size = positive(r, mat, "noise_size", key, d.period);
  d.octaves = r.integer(mat, "octaves", key, 4, 1, 12);
  d.turbulence = r.number(mat, "turbulence", key, 1.0);
  if (!(d.turbulence >= 0.0))
    r.fail(key + ".turbulence", fmt::format("is {}: expected a number >= 0", d.turbulence));
  d.sharpness = r.number(mat, "sharpness", key, 8.0);
  if (!(d.sharpness >= 1.0))
    r.fail(key + ".sharpness", fmt::format("is {}: expected a number >= 1", d.sharpness));
  return d;
}

void writeVeins(const VeinsDesc& d, json& mat) {
  mat["media"] = json::array({toJson(d.media[0]), toJson(d.media[1])});
  mat["period"] = d.period;
  mat["direction"] = vec(d.direction);
  mat["noise_size"] = d.noise_size;
  mat["octaves"] = d.octaves;
  mat["turbulence"] = d.turbulence;
  mat["sharpness"] = d.sharpness;
}

VeinsField::VeinsField(const VeinsDesc& d)
    : d_(d), base_(d.media.at(0).medium), vein_(d.media.at(1).medium) {}

double VeinsField::veinWeight(const glm::dvec3& q) const {
  const double phase = glm::dot(q, d_.direction) / d_.period +
                       d_.turbulence * turbulence(q / d_.noise_size, d_.octaves);
  const double s = std::abs(std::sin(std::numbers::pi * phase));
  const double w = std::pow(std::max(0.0, 1.0 - s), d_.sharpness);
  return std::min(w, 1.0);
}

LocalMedium VeinsField::at(const glm::dvec3& q) const {
  return LocalMedium::mix(base_, vein_, veinWeight(q));
}

Rgb VeinsField::majorant(const glm::dvec3&, const glm::dvec3&) const {
  return padMajorant(maxRgb(base_.sigmaT(), vein_.sigmaT()));
}

}  // namespace translucent::material
