// SPDX-License-Identifier: GPL-3.0-or-later
// libFuzzer target for scene files (scene::parseScene on JSON text, issue #15).
//
// The input is the scene text. Relative file names resolve against a temporary folder that holds
// one mesh file, "m.obj", so that inputs get past "mesh.file" (the seeds name it); the mesh is
// not loaded (fuzz_mesh covers that). A ParameterError is the expected outcome for a malformed
// scene; anything else (a crash, a sanitizer report, another exception, a hang) is a finding. A
// scene that parses must write and read back (toJson, parseScene) without an error.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "translucent/optics/medium.h"  // ParameterError
#include "translucent/scene/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::filesystem::path dir = [] {
    const auto d = std::filesystem::temp_directory_path() /
                   ("translucent_fuzz_scene_" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    std::ofstream(d / "m.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    return d;
  }();
  const std::string text(reinterpret_cast<const char*>(data), size);
  translucent::scene::Scene s;
  try {
    s = translucent::scene::parseScene(text, dir, "fuzz scene");
  } catch (const translucent::ParameterError&) {
    return 0;
  }
  // Round trip: what was accepted is written back to a scene that is accepted again.
  (void)translucent::scene::parseScene(translucent::scene::toJson(s), dir, "fuzz scene (written)");
  return 0;
}
