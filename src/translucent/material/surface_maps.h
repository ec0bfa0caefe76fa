// SPDX-License-Identifier: GPL-3.0-or-later
// 2D maps over the surface atlas (geometry/atlas.h, UV in [0, 1]²): no volume, the medium of a
// surface point is looked up at its atlas UV.
//   {"type": "map", "sigma_a": "sa.exr", "sigma_s_prime": "ssp.exr",   // [1/medium unit]
//    "g": 0.0}                                                         // σs = σs' / (1 − g)
//   {"type": "rd_map", "rd": "albedo.png" | v | [r, g, b],   // total diffuse reflectance Rd
//    "ld": "ld.exr" | v | [r, g, b],                         // ℓd [medium units] (seed 3.4)
//    "g": 0.0}                 // each texel inverted with the material's model and η
//   {"type": "surface_checker", "cells": 8 | [nu, nv],       // squares across the atlas
//    "media": [{...}, {...}]}                                // the seed's marble chessboard
// Images (EXR, PNG, anything OpenImageIO reads, analysis/image_io.h) are read as stored: no
// sRGB decoding, so a PNG holds values in [0, 1]. Row y of the file (top first) covers
// v ∈ [y, y + 1) / height, column x covers u ∈ [x, x + 1) / width, the atlas's own texel
// convention, so an image the size of the atlas maps texel to texel. Lookups are bilinear
// between texel centres, clamped at the borders. The images are read and (rd_map) inverted when
// the scene is parsed, so a bad texel is a parse error naming the file, texel and channel.
// rd_map inverts Rd(α') of a registered model on a table of 1025 values of s = sqrt(1 − α')
// (linear interpolation: Rd within about 1e-6 of the model's); a .bssrdf model cannot be
// inverted here (the CLI's `translucent invert` does it on the GPU).
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <variant>
#include <vector>

#include <glm/vec2.hpp>

#include "translucent/material/field_common.h"
#include "translucent/material/medium_desc.h"

namespace translucent::material {

// A per-texel medium (σa, σs per medium unit, g).
struct TexelMedia {
  int width = 0, height = 0;
  std::vector<LocalMedium> texels;  // row y (v) first
  LocalMedium at(const glm::dvec2& uv) const;  // bilinear, clamped
  LocalMedium mean() const;
};

// A file, or one value for every texel.
using MapSource = std::variant<std::filesystem::path, Rgb>;

struct MapDesc {
  std::filesystem::path sigma_a, sigma_s_prime;  // resolved
  double g = 0.0;
  std::shared_ptr<const TexelMedia> data;  // read at parse time (not compared)

  bool operator==(const MapDesc& o) const {
    return sigma_a == o.sigma_a && sigma_s_prime == o.sigma_s_prime && g == o.g;
  }
};

struct RdMapDesc {
  MapSource rd, ld;
  double g = 0.0;
  std::shared_ptr<const TexelMedia> data;  // inverted at parse time (not compared)

  bool operator==(const RdMapDesc& o) const { return rd == o.rd && ld == o.ld && g == o.g; }
};

struct SurfaceCheckerDesc {
  glm::dvec2 cells{8.0, 8.0};
  std::vector<MediumDesc> media;  // two

  bool operator==(const SurfaceCheckerDesc&) const = default;
};

MapDesc parseMap(const ParseContext& c, const json& mat, const std::string& key);
RdMapDesc parseRdMap(const ParseContext& c, const json& mat, const std::string& key);
SurfaceCheckerDesc parseSurfaceChecker(const ParseContext& c, const json& mat,
                                       const std::string& key);
void writeMap(const MapDesc& d, json& mat, const PathWriter& written);
void writeRdMap(const RdMapDesc& d, json& mat, const PathWriter& written);
void writeSurfaceChecker(const SurfaceCheckerDesc& d, json& mat);

// Rd -> α' for one model and η, from a table (see above). Throws ParameterError naming `what`
// unless 0 < rd < Rd(α' = 1).
class AlbedoInverter {
 public:
  AlbedoInverter(const std::string& model, double eta);
  double alphaPrime(double rd, const std::string& what) const;
  double maxRd() const { return rd_.front(); }

 private:
  std::vector<double> rd_;  // Rd at s_i = i / (n − 1), decreasing
};

// The media of an rd_map: per texel (Rd, ℓd) -> (σa, σs' by coefficientsFromAlbedo, σs' / (1−g)).
TexelMedia invertRdMap(const AlbedoInverter& inv, int width, int height,
                       const std::vector<float>& rd, const std::vector<float>& ld, double g,
                       const std::string& rd_what, const std::string& ld_what);

class TexelMap final : public SurfaceMap {
 public:
  explicit TexelMap(std::shared_ptr<const TexelMedia> data) : data_(std::move(data)) {}
  LocalMedium at(const glm::dvec2& uv) const override { return data_->at(uv); }

 private:
  std::shared_ptr<const TexelMedia> data_;
};

class SurfaceCheckerMap final : public SurfaceMap {
 public:
  explicit SurfaceCheckerMap(const SurfaceCheckerDesc& d);
  LocalMedium at(const glm::dvec2& uv) const override;

 private:
  glm::dvec2 cells_;
  LocalMedium media_[2];
};

}  // namespace translucent::material
