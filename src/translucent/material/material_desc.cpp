// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/material/material_desc.h"

#include "translucent/material/parse_context.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace translucent::material {
namespace {

// The registry: name -> kind and parser. Each parser returns its alternative of FieldDesc.
struct TypeEntry {
  const char* name;
  Material::Kind kind;
  FieldDesc (*parse)(const ParseContext&, const json&, const std::string&);
};

template <auto Parse>
FieldDesc parseAs(const ParseContext& c, const json& mat, const std::string& key) {
  return Parse(c, mat, key);
}

constexpr TypeEntry kTypes[] = {
    {"layers", Material::Kind::Volume, parseAs<parseLayers>},
    {"veins", Material::Kind::Volume, parseAs<parseVeins>},
    {"checker", Material::Kind::Volume, parseAs<parseChecker>},
    {"gradient", Material::Kind::Volume, parseAs<parseGradient>},
    {"voxels", Material::Kind::Volume, parseAs<parseVoxels>},
    {"map", Material::Kind::Surface, parseAs<parseMap>},
    {"rd_map", Material::Kind::Surface, parseAs<parseRdMap>},
    {"surface_checker", Material::Kind::Surface, parseAs<parseSurfaceChecker>},
};

const TypeEntry* findType(const std::string& name) {
  for (const TypeEntry& t : kTypes)
    if (name == t.name) return &t;
  return nullptr;
}

template <class... F>
struct Overloaded : F... {
  using F::operator()...;
};
template <class... F>
Overloaded(F...) -> Overloaded<F...>;  // clang 14 deduces no aggregate's arguments without it

}  // namespace

std::vector<std::string> materialTypes() {
  std::vector<std::string> names = {"homogeneous"};
  for (const TypeEntry& t : kTypes) names.emplace_back(t.name);
  return names;
}

Material::Kind materialKind(const std::string& type) {
  if (type == "homogeneous") return Material::Kind::Homogeneous;
  if (const TypeEntry* t = findType(type)) return t->kind;
  throw ParameterError(fmt::format("'{}': expected one of {}", type, fmt::join(materialTypes(), ", ")));
}

const char* MaterialDesc::type() const {
  return std::visit(Overloaded{[](const HomogeneousDesc&) { return "homogeneous"; },
                               [](const LayersDesc&) { return "layers"; },
                               [](const VeinsDesc&) { return "veins"; },
                               [](const CheckerDesc&) { return "checker"; },
                               [](const GradientDesc&) { return "gradient"; },
                               [](const VoxelsDesc&) { return "voxels"; },
                               [](const MapDesc&) { return "map"; },
                               [](const RdMapDesc&) { return "rd_map"; },
                               [](const SurfaceCheckerDesc&) { return "surface_checker"; }},
                    field);
}

Material::Kind MaterialDesc::kind() const { return materialKind(type()); }

LocalMedium MaterialDesc::representative() const {
  return std::visit(
      Overloaded{[](const HomogeneousDesc&) { return LocalMedium{}; },
                 [](const LayersDesc& d) { return d.layers.at(0).medium.medium; },
                 [](const VeinsDesc& d) { return d.media.at(0).medium; },
                 [](const CheckerDesc& d) { return d.media.at(0).medium; },
                 [](const GradientDesc& d) { return d.media.at(0).medium; },
                 [](const VoxelsDesc& d) { return d.representative(); },
                 [](const MapDesc& d) { return d.data ? d.data->mean() : LocalMedium{}; },
                 [](const RdMapDesc& d) { return d.data ? d.data->mean() : LocalMedium{}; },
                 [](const SurfaceCheckerDesc& d) { return d.media.at(0).medium; }},
      field);
}

MaterialDesc parseMaterialDesc(const ParseContext& c, const json& mat, const std::string& key) {
  const std::string type = c.reader.string(mat, "type", key);
  const TypeEntry* t = findType(type);
  if (!t)
    c.reader.fail(key + ".type", fmt::format("'{}': expected one of {}", type,
                                             fmt::join(materialTypes(), ", ")));
  return {t->parse(c, mat, key)};
}

void writeMaterialDesc(const MaterialDesc& d, json& mat, const PathWriter& written) {
  mat["type"] = d.type();
  std::visit(Overloaded{[](const HomogeneousDesc&) {},
                        [&](const LayersDesc& x) { writeLayers(x, mat); },
                        [&](const VeinsDesc& x) { writeVeins(x, mat); },
                        [&](const CheckerDesc& x) { writeChecker(x, mat); },
                        [&](const GradientDesc& x) { writeGradient(x, mat); },
                        [&](const VoxelsDesc& x) { writeVoxels(x, mat, written); },
                        [&](const MapDesc& x) { writeMap(x, mat, written); },
                        [&](const RdMapDesc& x) { writeRdMap(x, mat, written); },
                        [&](const SurfaceCheckerDesc& x) { writeSurfaceChecker(x, mat); }},
             d.field);
}

double surfaceDepth(const LocalMedium& top) {
  double depth = std::numeric_limits<double>::infinity();
  double reduced = std::numeric_limits<double>::infinity();
  for (size_t c = 0; c < 3; ++c) {
    const ScalarMedium m{top.sigma_a[c], top.sigma_s[c], top.g, 1.0};
    if (m.sigmaTPrime() > 0.0) reduced = std::min(reduced, m.reducedMeanFreePath());
    if (m.sigma_a > 0.0 && m.sigmaTPrime() > 0.0) depth = std::min(depth, m.diffuseMeanFreePath());
  }
  if (!std::isfinite(depth)) depth = std::isfinite(reduced) ? 10.0 * reduced : 0.0;
  return depth;
}

Material buildMaterial(const MaterialDesc& d, const Medium& medium, const std::string& model,
                       const BuildContext& b) {
  Material m;
  m.medium = medium;
  m.model = model;
  m.frame = b.frame;
  m.kind = d.kind();
  auto surfaceDistance = [&]() {
    if (!b.placed_mesh) throw ParameterError("material.layers: the placed mesh is needed");
    std::vector<glm::dvec3> q;
    q.reserve(b.placed_mesh->positions.size());
    for (const glm::dvec3& x : b.placed_mesh->positions) q.push_back(b.frame.toMaterial(x));
    return std::make_shared<const SurfaceDistance>(std::move(q), b.placed_mesh->triangles);
  };
  std::visit(
      Overloaded{[](const HomogeneousDesc&) {},
                 [&](const LayersDesc& x) {
                   m.volume = std::make_shared<const LayersField>(
                       x, x.from == LayersDesc::From::Surface ? surfaceDistance() : nullptr);
                 },
                 [&](const VeinsDesc& x) { m.volume = std::make_shared<const VeinsField>(x); },
                 [&](const CheckerDesc& x) { m.volume = std::make_shared<const CheckerField>(x); },
                 [&](const GradientDesc& x) { m.volume = std::make_shared<const GradientField>(x); },
                 [&](const VoxelsDesc& x) { m.volume = std::make_shared<const VoxelsField>(x); },
                 [&](const MapDesc& x) {
                   if (!x.data) throw ParameterError("material: the map's images are not loaded");
                   m.surface = std::make_shared<const TexelMap>(x.data);
                 },
                 [&](const RdMapDesc& x) {
                   if (!x.data) throw ParameterError("material: the rd_map is not inverted");
                   m.surface = std::make_shared<const TexelMap>(x.data);
                 },
                 [&](const SurfaceCheckerDesc& x) {
                   m.surface = std::make_shared<const SurfaceCheckerMap>(x);
                 }},
      d.field);
  if (m.kind == Material::Kind::Volume) m.surface_depth = surfaceDepth(LocalMedium::of(medium));
  return m;
}

}  // namespace translucent::material
