// SPDX-License-Identifier: GPL-3.0-or-later
// Meshes shared by the point-cloud tests: icospheres and the closed Stanford bunny of Debian's
// glmark2-data (34,835 vertices, 69,666 triangles, genus 0, about 2 units wide).
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>

#include "translucent/geometry/mesh.h"

namespace translucent::geometry::testing {

inline const TriangleMesh& bunny() {
  static const TriangleMesh mesh = [] {
    const std::string path = TRANSLUCENT_BUNNY_OBJ;
    if (!std::filesystem::exists(path))
      throw std::runtime_error("the test mesh " + path +
                               " is missing: install glmark2-data (scripts/install-deps)");
    return loadMesh(path);
  }();
  return mesh;
}

}  // namespace translucent::geometry::testing
