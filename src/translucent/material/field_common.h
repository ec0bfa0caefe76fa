// SPDX-License-Identifier: GPL-3.0-or-later
// What the field types of material_desc.h share: the build context, how paths are written back,
// and helpers for conservative majorants. Light on purpose (scene/scene.h includes the field
// headers through material_desc.h): the JSON parsing side is in parse_context.h, for .cpp files.
#pragma once

#include <algorithm>
#include <filesystem>
#include <functional>
#include <nlohmann/json_fwd.hpp>
#include <string>

#include "translucent/geometry/mesh.h"
#include "translucent/material/material.h"

namespace translucent::material {

using nlohmann::json;
struct JsonReader;    // json_reader.h
struct ParseContext;  // parse_context.h

// How toJson writes a resolved path back (the name given when it came from the search path).
using PathWriter = std::function<std::string(const std::filesystem::path& path)>;

struct BuildContext {
  const geometry::TriangleMesh* placed_mesh = nullptr;  // scene space (loadSceneMesh)
  MaterialFrame frame;                                  // scene -> material space
};

inline Rgb maxRgb(const Rgb& a, const Rgb& b) {
  return {std::max(a[0], b[0]), std::max(a[1], b[1]), std::max(a[2], b[2])};
}
// A majorant computed from the same numbers as the field, raised by a relative 1e-12 so that
// rounding in the field's interpolation (a + t (b − a) can exceed b by an ulp) never puts the
// field above it.
inline Rgb padMajorant(const Rgb& m) {
  constexpr double kSlack = 1.0 + 1e-12;
  return {m[0] * kSlack, m[1] * kSlack, m[2] * kSlack};
}

}  // namespace translucent::material
