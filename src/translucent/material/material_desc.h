// SPDX-License-Identifier: GPL-3.0-or-later
// The material description of the scene format: what `material` in a scene file says, before it
// is built against the placed mesh into a Material (material.h). The homogeneous form (today's:
// preset or sigma_a/sigma_s, g, eta, scale, model) stays the default and is held by the scene
// itself (Scene::preset, medium, model); `"type"` selects a spatially varying one:
//
//   3D fields in material space (material.h: the mesh's rest pose, medium units)
//     "layers"           layers.h    by depth below the surface or a plane, top layer first
//     "veins"            veins.h     marble: turbulence of 3D gradient noise between two media
//     "checker"          checker.h   a 3D checkerboard of two media
//     "gradient"         gradient.h  a linear blend of two media from point a to point b
//     "voxels"           voxels.h    an OpenVDB grid (density between two media, or σa and σs)
//   2D maps over the surface atlas (surface_maps.h)
//     "map"              images of σa and σs'
//     "rd_map"           images (or values) of Rd and ℓd, inverted per texel with the model
//     "surface_checker"  a checker of two media in UV: the seed's marble chessboard
//
// Every type takes, besides its own keys, "eta" (default 1.3: one η for the whole object, the
// media are index-matched), "scale" (medium units per scene unit, default 1) and "model" (a
// registered model or a .bssrdf file, default "dipole"). A medium inside a field is
// {"preset": ...} or {"sigma_a", "sigma_s", "g"} (medium_desc.h). Coefficients are per medium
// unit, as in the homogeneous form. Parsing is strict: unknown keys list the valid ones, values
// out of range, missing or unreadable files and Rd beyond the model's reach name the key
// ("material.layers[1].thickness") or file and what was expected.
//
// The representative medium (Scene::medium for a heterogeneous material, what techniques without
// heterogeneous support render): the first medium of "media" or the top layer; for "map",
// "rd_map" and coefficient voxels the mean over the texels or voxels.
#pragma once

#include <string>
#include <variant>
#include <vector>

#include "translucent/material/checker.h"
#include "translucent/material/field_common.h"
#include "translucent/material/gradient.h"
#include "translucent/material/layers.h"
#include "translucent/material/surface_maps.h"
#include "translucent/material/veins.h"
#include "translucent/material/voxels.h"

namespace translucent::material {

struct HomogeneousDesc {
  bool operator==(const HomogeneousDesc&) const = default;
};

using FieldDesc = std::variant<HomogeneousDesc, LayersDesc, VeinsDesc, CheckerDesc, GradientDesc,
                               VoxelsDesc, MapDesc, RdMapDesc, SurfaceCheckerDesc>;

struct MaterialDesc {
  FieldDesc field;

  const char* type() const;  // "homogeneous", "layers", ...
  bool homogeneous() const { return std::holds_alternative<HomogeneousDesc>(field); }
  Material::Kind kind() const;
  // See above; for the homogeneous form the caller's medium is the material.
  LocalMedium representative() const;

  bool operator==(const MaterialDesc&) const = default;
};

// The registered types, homogeneous first.
std::vector<std::string> materialTypes();
// Whether `type` names a 2D map (Kind::Surface) or a 3D field (Kind::Volume); throws
// ParameterError listing the valid types when it names neither.
Material::Kind materialKind(const std::string& type);

// Parses the heterogeneous "material" object `mat` (its "type" not "homogeneous"; the common
// keys eta, scale and model are the caller's, given in `c`). Throws ParameterError naming `key`.
MaterialDesc parseMaterialDesc(const ParseContext& c, const json& mat, const std::string& key);
// Writes the type and the type's own keys into `mat` (the caller adds eta, scale and model).
void writeMaterialDesc(const MaterialDesc& d, json& mat, const PathWriter& written);

// Builds the runtime material: `medium` holds η, scale and the representative medium, `model`
// the model; the mesh (placed, scene space) is needed by layers from the surface. Kind::Volume
// sets surface_depth (material.h): the representative medium's smallest diffusion length
// ℓd = 1/σtr over the channels (10 ℓ' when it does not absorb), see Material::surfaceMedium.
Material buildMaterial(const MaterialDesc& d, const Medium& medium, const std::string& model,
                       const BuildContext& b);
// surface_depth's rule on its own.
double surfaceDepth(const LocalMedium& top);

}  // namespace translucent::material
