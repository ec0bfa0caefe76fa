// SPDX-License-Identifier: GPL-3.0-or-later
// The interface of the OpenVDB module (voxels_openvdb_module.cpp -> libtranslucent_openvdb.so,
// loaded by io/plugins.h on the first .vdb read): what readVdbGrid (voxels.cpp) needs of OpenVDB.
// Header-only types; no function throws. The checks of the grid (type, transform, size, values)
// stay in voxels.cpp, which formats every message naming the file, the grid and the key.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "translucent/io/plugins.h"

namespace translucent::material {

// One grid's header, as read_grid returns it.
struct VdbGridInfo {
  std::string type;           // OpenVDB's name of the value type ("float", "vec3s", ...)
  int channels = 0;           // 1 (float), 3 (vec3s), 0 for any other type
  bool linear = false;        // whether the transform is linear (affine)
  std::string map_type;       // the transform's map type, for messages
  double translation[3] = {};       // index (0, 0, 0) in world space
  double index_to_world[3][3] = {};  // [a]: world offset of index axis a (a column)
  bool empty = true;          // no active voxels
  int bbox_min[3] = {}, bbox_dim[3] = {};  // the active voxels' bounding box (min, extent)
  float background[3] = {};
};

struct VdbApi {
  static constexpr uint32_t kAbiVersion = 1;
  io::PluginHeader header;
  // Reads grid `name` of the file. Returns a handle (for copy_values and close_grid) and fills
  // `info`; nullptr when it fails: with `names` set to the file's grid names and *missing true
  // when the file has no such grid, else with the reason in *error.
  void* (*read_grid)(const char* file, const char* name, VdbGridInfo* info,
                     std::vector<std::string>* names, bool* missing, std::string* error) noexcept;
  // The values of the voxels origin .. origin + dims - 1, x fastest then y then z, `channels`
  // floats each (active or not: the background where none is stored).
  bool (*copy_values)(void* grid, const int* origin, const int* dims, float* out,
                      std::string* error) noexcept;
  void (*close_grid)(void* grid) noexcept;
};

}  // namespace translucent::material
