// SPDX-License-Identifier: GPL-3.0-or-later
// libFuzzer target for mesh loading (geometry::loadMesh on OBJ, PLY and OFF).
//
// Input: the first byte picks the format (0: .obj, 1: .ply, 2: .off, modulo 3), the rest is the
// file. loadMesh reads files by name (assimp picks its reader by the extension), so the input is
// written to a temporary file first. A MeshError is the expected outcome for a malformed file;
// anything else (a crash, an abort, a sanitizer report, another exception, a hang) is a finding.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "translucent/geometry/mesh.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  static const char* const kExtensions[] = {".obj", ".ply", ".off"};
  static const std::string path =
      (std::filesystem::temp_directory_path() /
       ("translucent_fuzz_mesh_" + std::to_string(::getpid())))
          .string();
  const std::string file = path + kExtensions[data[0] % 3];
  {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data + 1), static_cast<std::streamsize>(size - 1));
  }
  try {
    const auto mesh = translucent::geometry::loadMesh(file);
    // A loaded mesh is a valid one: validate() must hold (loadMesh promises it).
    mesh.validate(file);
  } catch (const translucent::geometry::MeshError&) {
  }
  std::error_code ec;
  std::filesystem::remove(file, ec);
  return 0;
}
