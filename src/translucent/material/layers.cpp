// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/material/layers.h"

#include "translucent/material/parse_context.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

namespace translucent::material {

LayersDesc parseLayers(const ParseContext& c, const json& mat, const std::string& key) {
  const JsonReader& r = c.reader;
  r.onlyKeys(mat, key, materialKeys({"from", "normal", "offset", "layers"}));
  LayersDesc d;
  const std::string from = mat.contains("from") ? r.string(mat, "from", key) : "surface";
  if (from == "surface") {
    d.from = LayersDesc::From::Surface;
    for (const char* k : {"normal", "offset"})
      if (mat.contains(k))
        r.fail(key + "." + k, "applies to \"from\": \"plane\" only (depth below the surface here)");
  } else if (from == "plane") {
    d.from = LayersDesc::From::Plane;
    d.normal = direction(r, mat, "normal", key, d.normal);
    d.offset = r.number(mat, "offset", key, 0.0);
  } else {
    r.fail(key + ".from", fmt::format("'{}': expected surface or plane", from));
  }
  const std::string lk = key + ".layers";
  if (!mat.contains("layers")) r.fail(lk, "required (an array of layers, top first)");
  const json& ls = mat["layers"];
  if (!ls.is_array() || ls.empty())
    r.fail(lk, fmt::format("{}: expected a non-empty array of layers", JsonReader::describe(ls)));
  for (size_t i = 0; i < ls.size(); ++i) {
    const std::string k = fmt::format("{}[{}]", lk, i);
    const json& l = ls[i];
    r.onlyKeys(l, k, {"medium", "thickness"});
    if (!l.contains("medium")) r.fail(k + ".medium", "required");
    LayerDesc layer;
    layer.medium = parseMediumDesc(r, l["medium"], k + ".medium");
    const bool last = i + 1 == ls.size();
    const bool given = l.contains("thickness") && !l["thickness"].is_null();
    if (last && given)
      r.fail(k + ".thickness", "the last layer is semi-infinite: expected no thickness (or null)");
    if (!last && !given)
      r.fail(k + ".thickness", "required (a number > 0 [medium units]) for every layer but the last");
    if (!last) layer.thickness = positive(r, l, "thickness", k);
    d.layers.push_back(layer);
  }
  return d;
}

void writeLayers(const LayersDesc& d, json& mat) {
  if (d.from == LayersDesc::From::Surface) {
    mat["from"] = "surface";
  } else {
    mat["from"] = "plane";
    mat["normal"] = vec(d.normal);
    mat["offset"] = d.offset;
  }
  json ls = json::array();
  for (const LayerDesc& l : d.layers) {
    json j = {{"medium", toJson(l.medium)}};
    if (l.thickness) j["thickness"] = *l.thickness;
    ls.push_back(j);
  }
  mat["layers"] = ls;
}

LayersField::LayersField(const LayersDesc& d, std::shared_ptr<const SurfaceDistance> surface)
    : d_(d), surface_(std::move(surface)) {
  if (d_.layers.empty()) throw ParameterError("layers: expected at least one layer");
  if (d_.from == LayersDesc::From::Surface && !surface_)
    throw ParameterError("layers from the surface: the mesh is needed");
  double bottom = 0.0;
  for (size_t i = 0; i < d_.layers.size(); ++i) {
    media_.push_back(d_.layers[i].medium.medium);
    if (i + 1 < d_.layers.size()) {
      bottom += d_.layers[i].thickness.value_or(0.0);
      bottoms_.push_back(bottom);
    }
  }
}

double LayersField::depth(const glm::dvec3& q) const {
  if (d_.from == LayersDesc::From::Plane) return d_.offset - glm::dot(q, d_.normal);
  return surface_->distance(q);
}

size_t LayersField::layerAt(double z) const {
  // The first layer whose bottom lies below z.
  return static_cast<size_t>(std::upper_bound(bottoms_.begin(), bottoms_.end(), z) - bottoms_.begin());
}

LocalMedium LayersField::at(const glm::dvec3& q) const { return media_[layerAt(depth(q))]; }

Rgb LayersField::majorant(const glm::dvec3& lo, const glm::dvec3& hi) const {
  double zmin, zmax;
  if (d_.from == LayersDesc::From::Plane) {
    zmin = std::numeric_limits<double>::infinity();
    zmax = -zmin;
    for (int i = 0; i < 8; ++i) {
      const glm::dvec3 corner((i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z);
      const double z = depth(corner);
      zmin = std::min(zmin, z);
      zmax = std::max(zmax, z);
    }
    // Rounding of the corners' dot products against the points' inside the box.
    const double eps = 1e-12 * (std::abs(d_.offset) + glm::length(glm::max(glm::abs(lo), glm::abs(hi))));
    zmin -= eps;
    zmax += eps;
  } else {
    const double h = 0.5 * glm::length(hi - lo);
    const double z = depth(0.5 * (lo + hi));
    zmin = z - h * (1.0 + 1e-12) - 1e-12;
    zmax = z + h * (1.0 + 1e-12) + 1e-12;
  }
  Rgb m{0.0, 0.0, 0.0};
  for (size_t i = layerAt(zmin); i <= layerAt(zmax); ++i) m = maxRgb(m, media_[i].sigmaT());
  return padMajorant(m);
}

}  // namespace translucent::material
