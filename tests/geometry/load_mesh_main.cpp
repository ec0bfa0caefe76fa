// SPDX-License-Identifier: GPL-3.0-or-later
// translucent_load_mesh FILE: loads FILE with geometry::loadMesh and prints its counts, or the
// MeshError on stderr with exit status 1. The malformed-mesh corpus test (malformed_meshes.cmake)
// runs it on each file, so that a crash shows as a signal, not as a failed expectation.
#include <cstdio>

#include "translucent/geometry/mesh.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: translucent_load_mesh FILE\n");
    return 2;
  }
  try {
    const auto mesh = translucent::geometry::loadMesh(argv[1]);
    std::printf("%zu vertices, %zu triangles\n", mesh.vertexCount(), mesh.triangleCount());
  } catch (const translucent::geometry::MeshError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
