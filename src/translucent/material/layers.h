// SPDX-License-Identifier: GPL-3.0-or-later
// "layers": media stacked by depth, top layer first, the last one semi-infinite. Depth is either
// the distance below the mesh surface (material space, medium units: a skin-like coat that
// follows the shape) or the distance below a plane:
//   {"type": "layers",
//    "from": "surface" | "plane",   // default "surface"
//    "normal": [0, 1, 0],           // "plane" only: the plane's normal, pointing out of the top
//    "offset": 0.0,                 // "plane" only: the top plane is {q : q·normal = offset}
//    "layers": [{"medium": {...}, "thickness": 0.2},   // [medium units], > 0
//               {"medium": {...}, "thickness": 1.0},
//               {"medium": {...}}]}                    // the last: no thickness (semi-infinite)
// Surface depth is the unsigned distance to the nearest triangle of the placed mesh taken to
// material space (surface_distance.h), so it is right inside the object (where it is queried);
// plane depth is offset − q·normal, and points above the top plane are in the top layer.
// Layer i holds depths [Σ_{j<i} t_j, Σ_{j≤i} t_j).
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "translucent/material/field_common.h"
#include "translucent/material/medium_desc.h"
#include "translucent/material/surface_distance.h"

namespace translucent::material {

struct LayerDesc {
  MediumDesc medium;
  std::optional<double> thickness;  // none: the last, semi-infinite layer

  bool operator==(const LayerDesc&) const = default;
};

struct LayersDesc {
  enum class From { Surface, Plane };
  From from = From::Surface;
  glm::dvec3 normal{0.0, 1.0, 0.0};
  double offset = 0.0;
  std::vector<LayerDesc> layers;

  bool operator==(const LayersDesc&) const = default;
};

LayersDesc parseLayers(const ParseContext& c, const json& mat, const std::string& key);
void writeLayers(const LayersDesc& d, json& mat);

class LayersField final : public VolumeField {
 public:
  // `surface`: required for From::Surface (the mesh in material space), ignored otherwise.
  LayersField(const LayersDesc& d, std::shared_ptr<const SurfaceDistance> surface);
  LocalMedium at(const glm::dvec3& q) const override;
  // The larger σt of the layers whose depth range meets the box's: plane depth is exact over
  // the box's corners; surface depth is 1-Lipschitz, so it lies within the box's half-diagonal
  // of its value at the centre.
  Rgb majorant(const glm::dvec3& lo, const glm::dvec3& hi) const override;
  double depth(const glm::dvec3& q) const;
  size_t layerAt(double depth) const;
  // For the GPU twin (reference/gpu/field_gpu.h).
  const LayersDesc& desc() const { return d_; }
  const std::vector<double>& bottoms() const { return bottoms_; }
  const std::vector<LocalMedium>& media() const { return media_; }
  const SurfaceDistance* surface() const { return surface_.get(); }

 private:
  LayersDesc d_;
  std::vector<double> bottoms_;  // bottom depth of each layer but the last
  std::vector<LocalMedium> media_;
  std::shared_ptr<const SurfaceDistance> surface_;
};

}  // namespace translucent::material
