// SPDX-License-Identifier: GPL-3.0-or-later
// Scene files of the mesh path tracer (`translucent pathtrace mesh --scene FILE`). There is one
// scene format for every renderer; it lives in scene/scene.h (library translucent::scene), which
// documents the keys. These names remain for the path tracer's callers: a MeshScene is a
// scene::Scene, and scene::referenceLights() gives the lights the path tracer handles.
#pragma once

#include <filesystem>
#include <string>

#include "translucent/scene/scene.h"

namespace translucent::reference {

using MeshScene = scene::Scene;

// Reads and checks a scene file; throws ParameterError naming the file and the offending key.
inline MeshScene loadMeshScene(const std::string& path) { return scene::loadScene(path); }
// The same from JSON text; relative paths are taken relative to `base_dir`.
inline MeshScene parseMeshScene(const std::string& text, const std::filesystem::path& base_dir,
                                const std::string& what) {
  return scene::parseScene(text, base_dir, what);
}
using scene::toJson;

}  // namespace translucent::reference
