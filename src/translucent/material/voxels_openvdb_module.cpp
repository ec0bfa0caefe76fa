// SPDX-License-Identifier: GPL-3.0-or-later
// libtranslucent_openvdb.so: reading OpenVDB grids, behind the table of voxels_openvdb_plugin.h.
// Loaded with dlopen on the first .vdb read (io/plugins.h), so that OpenVDB (26 MiB of its own
// resident pages) and its dependencies are mapped only in processes that read grids. Uses no
// library of ours: only the header-only interface.
#include <openvdb/openvdb.h>

#include <exception>
#include <memory>
#include <mutex>
#include <type_traits>

#include "translucent/material/voxels_openvdb_plugin.h"

namespace {

using translucent::material::VdbApi;
using translucent::material::VdbGridInfo;

void* readGrid(const char* file, const char* name, VdbGridInfo* info,
               std::vector<std::string>* names, bool* missing, std::string* error) noexcept {
  *missing = false;
  try {
    // openvdb::initialize() registers the grid types; it is thread-safe and idempotent.
    openvdb::initialize();
    openvdb::GridBase::Ptr base;
    {
      openvdb::io::File f(file);
      f.open(false);
      if (!f.hasGrid(name)) {
        names->clear();
        for (auto it = f.beginName(); it != f.endName(); ++it) names->push_back(*it);
        f.close();
        *missing = true;
        return nullptr;
      }
      base = f.readGrid(name);
      f.close();
    }
    info->type = base->type();
    const auto fg = openvdb::gridPtrCast<openvdb::FloatGrid>(base);
    const auto vg = openvdb::gridPtrCast<openvdb::Vec3SGrid>(base);
    info->channels = fg ? 1 : vg ? 3 : 0;
    const openvdb::math::Transform& tr = base->transform();
    info->linear = tr.isLinear();
    info->map_type = tr.mapType();
    const openvdb::Vec3d o = tr.indexToWorld(openvdb::Vec3d(0.0, 0.0, 0.0));
    for (int a = 0; a < 3; ++a) {
      info->translation[a] = o[a];
      openvdb::Vec3d e(0.0, 0.0, 0.0);
      e[a] = 1.0;
      const openvdb::Vec3d w = tr.indexToWorld(e) - o;
      for (int r = 0; r < 3; ++r) info->index_to_world[a][r] = w[r];
    }
    const openvdb::CoordBBox bb = base->evalActiveVoxelBoundingBox();
    info->empty = bb.empty();
    if (!info->empty) {
      const openvdb::Coord ext = bb.dim();
      for (int a = 0; a < 3; ++a) {
        info->bbox_min[a] = bb.min()[a];
        info->bbox_dim[a] = ext[a];
      }
    }
    if (fg) {
      const float b = fg->background();
      info->background[0] = info->background[1] = info->background[2] = b;
    } else if (vg) {
      const openvdb::Vec3s b = vg->background();
      for (int c = 0; c < 3; ++c) info->background[c] = b[c];
    }
    // The handle owns a reference to the grid.
    return new openvdb::GridBase::Ptr(std::move(base));
  } catch (const std::exception& e) {
    *error = e.what();
  } catch (...) {
    *error = "unknown error";
  }
  return nullptr;
}

template <typename GridT>
void copy(const GridT& grid, const int* origin, const int* dims, float* out) {
  auto acc = grid.getConstAccessor();
  size_t n = 0;
  for (int z = origin[2]; z < origin[2] + dims[2]; ++z)
    for (int y = origin[1]; y < origin[1] + dims[1]; ++y)
      for (int x = origin[0]; x < origin[0] + dims[0]; ++x) {
        const auto v = acc.getValue(openvdb::Coord(x, y, z));
        if constexpr (std::is_same_v<GridT, openvdb::FloatGrid>) {
          out[n++] = v;
        } else {
          for (int c = 0; c < 3; ++c) out[n++] = v[c];
        }
      }
}

bool copyValues(void* grid, const int* origin, const int* dims, float* out,
                std::string* error) noexcept {
  try {
    const auto& base = *static_cast<openvdb::GridBase::Ptr*>(grid);
    if (const auto fg = openvdb::gridConstPtrCast<openvdb::FloatGrid>(base)) {
      copy(*fg, origin, dims, out);
      return true;
    }
    if (const auto vg = openvdb::gridConstPtrCast<openvdb::Vec3SGrid>(base)) {
      copy(*vg, origin, dims, out);
      return true;
    }
    *error = "the grid is neither float nor vec3s";
  } catch (const std::exception& e) {
    *error = e.what();
  } catch (...) {
    *error = "unknown error";
  }
  return false;
}

void closeGrid(void* grid) noexcept { delete static_cast<openvdb::GridBase::Ptr*>(grid); }

constexpr VdbApi kApi{{VdbApi::kAbiVersion}, readGrid, copyValues, closeGrid};

}  // namespace

extern "C" __attribute__((visibility("default"))) const void* translucent_openvdb_plugin() {
  return &kApi;
}
