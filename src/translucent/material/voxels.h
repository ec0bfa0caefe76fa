// SPDX-License-Identifier: GPL-3.0-or-later
// "voxels": a voxel grid from an OpenVDB file (Debian's libopenvdb-dev), in one of two forms:
//   {"type": "voxels", "file": "smoke.vdb",
//    "density": "density",             // a float grid (default name "density"), clamped to [0, 1]:
//    "media": [{...}, {...}]}          //   medium = (1 − d) media[0] + d media[1]
//   {"type": "voxels", "file": "jade.vdb",
//    "sigma_a": "sigma_a", "sigma_s": "sigma_s",   // float (grey) or vec3s (RGB) grids
//    "g": 0.0}                                     //   [1/medium unit], every voxel >= 0
// Placement: the grid's own (linear) transform takes index space to material space, so its voxel
// size is in medium units. Values are trilinear between voxel centres (integer index points, as
// OpenVDB's BoxSampler); outside the grid's active bounding box a grid has its background value.
// The file is read when the scene is parsed (errors name the file and grid); the representative
// medium is media[0] (density) or the mean over the grids' active bounding boxes (coefficients).
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/ext/vector_int3.hpp>

#include "translucent/material/field_common.h"
#include "translucent/material/medium_desc.h"

namespace translucent::material {

// A dense copy of one grid over its active bounding box (padded by one voxel of background).
struct DenseGrid {
  glm::ivec3 origin{0};  // index coordinate of the first voxel
  glm::ivec3 dims{0};
  int channels = 1;      // 1 (float) or 3 (vec3s)
  std::vector<float> values;
  Rgb background{0.0, 0.0, 0.0};
  glm::dmat3 index_to_world{1.0};  // world = index_to_world · i + translation
  glm::dvec3 translation{0.0};
  glm::dmat3 world_to_index{1.0};

  Rgb voxel(int x, int y, int z) const;  // background outside
  glm::dvec3 toIndex(const glm::dvec3& q) const {
    return world_to_index * (q - translation);
  }
  Rgb trilinear(const glm::dvec3& q) const;  // q in material (world) space
  // Per channel max and min over the voxels whose trilinear support meets the box.
  void range(const glm::dvec3& lo, const glm::dvec3& hi, Rgb& max, Rgb& min) const;
  Rgb mean() const;  // over the active bounding box (without the padding)
};

struct VoxelsDesc {
  enum class Mode { Density, Coefficients };
  std::filesystem::path file;  // resolved
  Mode mode = Mode::Density;
  std::string density = "density";
  std::vector<MediumDesc> media;  // Density: two
  std::string sigma_a = "sigma_a", sigma_s = "sigma_s";  // Coefficients
  double g = 0.0;
  // The grids, read at parse time (not part of the comparison).
  std::shared_ptr<const DenseGrid> density_grid, sigma_a_grid, sigma_s_grid;

  bool operator==(const VoxelsDesc& o) const {
    return file == o.file && mode == o.mode && density == o.density && media == o.media &&
           sigma_a == o.sigma_a && sigma_s == o.sigma_s && g == o.g;
  }
  LocalMedium representative() const;
};

VoxelsDesc parseVoxels(const ParseContext& c, const json& mat, const std::string& key);
void writeVoxels(const VoxelsDesc& d, json& mat, const PathWriter& written);

// Reads grid `name` of an OpenVDB file as a DenseGrid. Throws ParameterError naming `what`
// (the key), the file and the grid: unreadable file, no such grid (the message lists the grids),
// a type other than float (or vec3s when `allow_vec3`), a non-linear transform, no active voxels,
// more than 2^27 values, a non-finite value (or a negative one when `non_negative`).
DenseGrid readVdbGrid(const std::filesystem::path& file, const std::string& name, bool allow_vec3,
                      bool non_negative, const std::string& what);

class VoxelsField final : public VolumeField {
 public:
  explicit VoxelsField(const VoxelsDesc& d);
  LocalMedium at(const glm::dvec3& q) const override;
  // Max over the voxels whose trilinear support meets the box (density: the blend at the
  // covered range's ends; coefficients: max σa + max σs).
  Rgb majorant(const glm::dvec3& lo, const glm::dvec3& hi) const override;
  const VoxelsDesc& desc() const { return d_; }  // for the GPU twin (reference/gpu/field_gpu.h)

 private:
  VoxelsDesc d_;
  LocalMedium media_[2];
};

}  // namespace translucent::material
