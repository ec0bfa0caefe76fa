// SPDX-License-Identifier: GPL-3.0-or-later
// Where a technique's error against the physical reference comes from, per region of the picture.
// T − P = (T − M) + (M − P): the technique's part is its distance from the model reference M
// (the model it approximates, evaluated exactly on the mesh), the model's part is the model's own
// distance from the physical truth P. Each is measured as compare's relative RMSE (noise taken
// out, divided by the mean of P over the region) in regions where diffusion on a half-space is
// known to break (Donner & Jensen 2005; Frisvad, Hachisuka & Kjeldsen 2014 for light at grazing
// angles; the thin parts where the body is no half-space):
//   silhouettes        interior pixels seen at |n·v| < 0.3
//   thin parts         the body is thinner than the medium's diffuse mean free path ℓd along −n
//                      (the mean of the three channels' ℓd = 1/σtr, in scene units)
//   shadow boundaries  within 2 pixels of a change of the directional and point lights' direct
//                      visibility (n·l > 0 and an unoccluded shadow ray), cast and attached
//   elsewhere          interior pixels in none of the above
// The regions overlap (a silhouette can be thin); each is measured on its own.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "translucent/compare/compare.h"

namespace translucent::analysis {

struct ErrorRegions {
  int width = 0, height = 0;
  std::vector<std::string> names;              // the four regions above, in that order
  std::vector<std::vector<uint8_t>> masks;     // per region, per pixel (inside the interior)
  std::string definition;                      // the thresholds as used, one sentence
  double thin_threshold = 0.0;                 // ℓd in scene units
};

// The regions of the scene's camera picture, inside `interior` (compareMasks().interior).
// Lights other than directional and point lights add no shadow boundary (the definition says so).
ErrorRegions errorRegions(const scene::Scene& scene, const geometry::TriangleMesh& mesh,
                          std::span<const uint8_t> interior);

// errorRegions when `references` hold a model and a physical reference (what the split needs),
// else empty regions (no names): what compare's report takes.
ErrorRegions reportRegions(const scene::Scene& scene, const geometry::TriangleMesh& mesh,
                           std::span<const Reference> references, std::span<const uint8_t> interior);

struct RegionSplit {
  std::string region;
  uint64_t pixels = 0;
  double vs_physical = 0.0;     // T against P
  double technique_part = 0.0;  // T against M
  double model_part = 0.0;      // M against P
};

// Per region (and "interior" first: the whole compared picture), the three relative RMSEs.
// Sizes must agree (ParameterError otherwise). A region without pixels gets NaN.
std::vector<RegionSplit> splitError(const CompareImage& technique, const CompareImage& model,
                                    const CompareImage& physical, const ErrorRegions& regions,
                                    std::span<const uint8_t> interior);

// The split as a picture (8-bit RGB, rows from the top): black outside `interior`; inside, the
// brightness is |T − P| / P (full at `full_scale`, 0.5 = 50%) and the hue the share of the model's
// part: orange where the technique's part |T − M| dominates, blue where the model's |M − P| does.
std::vector<uint8_t> splitMap(const CompareImage& technique, const CompareImage& model,
                              const CompareImage& physical, std::span<const uint8_t> interior,
                              double full_scale = 0.5);

// The regions as a picture (8-bit RGB): grey interior, silhouettes red, thin parts green, shadow
// boundaries blue (added where they overlap), black outside.
std::vector<uint8_t> regionMap(const ErrorRegions& regions, std::span<const uint8_t> interior);

}  // namespace translucent::analysis
