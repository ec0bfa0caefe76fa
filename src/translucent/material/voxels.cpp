// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/material/voxels.h"

#include "translucent/material/parse_context.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>
#include <glm/common.hpp>
#include <glm/matrix.hpp>

#include "translucent/io/plugins.h"
#include "translucent/material/voxels_openvdb_plugin.h"

namespace translucent::material {

Rgb DenseGrid::voxel(int x, int y, int z) const {
  const int i = x - origin.x, j = y - origin.y, k = z - origin.z;
  if (i < 0 || j < 0 || k < 0 || i >= dims.x || j >= dims.y || k >= dims.z) return background;
  const size_t n = (static_cast<size_t>(k) * static_cast<size_t>(dims.y) + static_cast<size_t>(j)) *
                       static_cast<size_t>(dims.x) + static_cast<size_t>(i);
  if (channels == 1) {
    const double v = static_cast<double>(values[n]);
    return {v, v, v};
  }
  return {static_cast<double>(values[3 * n]), static_cast<double>(values[3 * n + 1]),
          static_cast<double>(values[3 * n + 2])};
}

Rgb DenseGrid::trilinear(const glm::dvec3& q) const {
  const glm::dvec3 p = toIndex(q);
  const glm::dvec3 f = glm::floor(p);
  const glm::dvec3 t = p - f;
  // Far outside (or non-finite): the background, without converting huge values to int.
  constexpr double kFar = 1e9;
  if (!(std::abs(f.x) < kFar && std::abs(f.y) < kFar && std::abs(f.z) < kFar)) return background;
  const int x = static_cast<int>(f.x), y = static_cast<int>(f.y), z = static_cast<int>(f.z);
  Rgb out{0.0, 0.0, 0.0};
  for (int c = 0; c < 8; ++c) {
    const int dx = c & 1, dy = (c >> 1) & 1, dz = (c >> 2) & 1;
    const double w = (dx ? t.x : 1.0 - t.x) * (dy ? t.y : 1.0 - t.y) * (dz ? t.z : 1.0 - t.z);
    if (w == 0.0) continue;
    const Rgb v = voxel(x + dx, y + dy, z + dz);
    for (size_t ch = 0; ch < 3; ++ch) out[ch] += w * v[ch];
  }
  return out;
}

void DenseGrid::range(const glm::dvec3& lo, const glm::dvec3& hi, Rgb& mx, Rgb& mn) const {
  glm::dvec3 plo(std::numeric_limits<double>::infinity()), phi(-plo);
  for (int i = 0; i < 8; ++i) {
    const glm::dvec3 corner((i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z);
    const glm::dvec3 p = toIndex(corner);
    plo = glm::min(plo, p);
    phi = glm::max(phi, p);
  }
  // Voxels floor(plo) .. floor(phi) + 1 carry weight somewhere in the box (one more on each side
  // against rounding of the transform), clamped to the stored voxels; the background counts
  // when the range reaches beyond them.
  const glm::dvec3 first = glm::floor(plo) - 1.0, last = glm::floor(phi) + 2.0;
  const glm::dvec3 a(origin), b = glm::dvec3(origin + dims) - 1.0;
  mx = {-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
        -std::numeric_limits<double>::infinity()};
  mn = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
        std::numeric_limits<double>::infinity()};
  auto take = [&](const Rgb& v) {
    for (size_t c = 0; c < 3; ++c) {
      mx[c] = std::max(mx[c], v[c]);
      mn[c] = std::min(mn[c], v[c]);
    }
  };
  const bool nan = !(std::isfinite(plo.x) && std::isfinite(plo.y) && std::isfinite(plo.z) &&
                     std::isfinite(phi.x) && std::isfinite(phi.y) && std::isfinite(phi.z));
  if (nan || first.x < a.x || first.y < a.y || first.z < a.z || last.x > b.x || last.y > b.y ||
      last.z > b.z)
    take(background);
  if (nan) {  // everything
    for (size_t n = 0; n < values.size() / static_cast<size_t>(channels); ++n)
      take(channels == 1 ? Rgb{static_cast<double>(values[n]), static_cast<double>(values[n]),
                               static_cast<double>(values[n])}
                         : Rgb{static_cast<double>(values[3 * n]),
                               static_cast<double>(values[3 * n + 1]),
                               static_cast<double>(values[3 * n + 2])});
    return;
  }
  const glm::dvec3 s = glm::max(first, a), e = glm::min(last, b);
  if (s.x > e.x || s.y > e.y || s.z > e.z) return;
  for (int z = static_cast<int>(s.z); z <= static_cast<int>(e.z); ++z)
    for (int y = static_cast<int>(s.y); y <= static_cast<int>(e.y); ++y)
      for (int x = static_cast<int>(s.x); x <= static_cast<int>(e.x); ++x) take(voxel(x, y, z));
}

Rgb DenseGrid::mean() const {
  Rgb sum{0.0, 0.0, 0.0};
  size_t n = 0;
  for (int z = origin.z + 1; z < origin.z + dims.z - 1; ++z)
    for (int y = origin.y + 1; y < origin.y + dims.y - 1; ++y)
      for (int x = origin.x + 1; x < origin.x + dims.x - 1; ++x) {
        const Rgb v = voxel(x, y, z);
        for (size_t c = 0; c < 3; ++c) sum[c] += v[c];
        ++n;
      }
  for (double& v : sum) v /= static_cast<double>(std::max<size_t>(n, 1));
  return sum;
}

namespace {

// A grid read by the OpenVDB module, released when it goes out of scope.
struct GridHandle {
  GridHandle(const VdbApi& a, void* g) : api(a), grid(g) {}
  ~GridHandle() {
    if (grid != nullptr) api.close_grid(grid);
  }
  GridHandle(const GridHandle&) = delete;
  GridHandle& operator=(const GridHandle&) = delete;
  const VdbApi& api;
  void* grid;
};

}  // namespace

// OpenVDB is reached through its module (voxels_openvdb_plugin.h), loaded on the first grid read
// (io/plugins.h): a process that reads no .vdb file does not map OpenVDB.
DenseGrid readVdbGrid(const std::filesystem::path& file, const std::string& name, bool allow_vec3,
                      bool non_negative, const std::string& what) {
  const std::string where = fmt::format("{}: '{}' grid '{}'", what, file.string(), name);
  const VdbApi* api = nullptr;
  try {
    api = &io::plugin<VdbApi>("openvdb");
  } catch (const io::PluginError& e) {
    throw ParameterError(fmt::format("{}: cannot be read: {}", where, e.what()));
  }
  VdbGridInfo info;
  std::vector<std::string> names;
  bool missing = false;
  std::string error;
  const GridHandle grid{*api, api->read_grid(file.string().c_str(), name.c_str(), &info, &names,
                                             &missing, &error)};
  if (grid.grid == nullptr && missing)
    throw ParameterError(fmt::format("{}: no such grid; the file holds {}", where,
                                     names.empty() ? std::string("none")
                                                   : fmt::format("{}", fmt::join(names, ", "))));
  if (grid.grid == nullptr)
    throw ParameterError(fmt::format("{}: cannot be read as OpenVDB: {}", where, error));
  DenseGrid d;
  if (!(info.channels == 1 || (allow_vec3 && info.channels == 3)))
    throw ParameterError(fmt::format("{}: is of type {}: expected float{}", where, info.type,
                                     allow_vec3 ? " or vec3s" : ""));
  if (!info.linear)
    throw ParameterError(fmt::format("{}: its transform ({}) is not linear: expected an affine "
                                     "index-to-world map", where, info.map_type));
  d.translation = {info.translation[0], info.translation[1], info.translation[2]};
  for (int a = 0; a < 3; ++a)  // column a
    d.index_to_world[a] = glm::dvec3(info.index_to_world[a][0], info.index_to_world[a][1],
                                     info.index_to_world[a][2]);
  const double det = glm::determinant(d.index_to_world);
  if (!(std::abs(det) > 0.0) || !std::isfinite(det))
    throw ParameterError(fmt::format("{}: its transform is singular", where));
  d.world_to_index = glm::inverse(d.index_to_world);
  if (info.empty) throw ParameterError(fmt::format("{}: has no active voxels", where));
  d.origin = glm::ivec3(info.bbox_min[0] - 1, info.bbox_min[1] - 1, info.bbox_min[2] - 1);
  d.dims = glm::ivec3(info.bbox_dim[0] + 2, info.bbox_dim[1] + 2, info.bbox_dim[2] + 2);
  d.channels = info.channels;
  const double count = static_cast<double>(d.dims.x) * d.dims.y * d.dims.z * d.channels;
  constexpr double kMaxValues = 134217728.0;  // 2^27 floats: 512 MiB
  if (count > kMaxValues)
    throw ParameterError(fmt::format("{}: its active bounding box ({} x {} x {} voxels) holds more "
                                     "than 2^27 values: expected a smaller grid", where,
                                     info.bbox_dim[0], info.bbox_dim[1], info.bbox_dim[2]));
  d.values.resize(static_cast<size_t>(count));
  d.background = {static_cast<double>(info.background[0]), static_cast<double>(info.background[1]),
                  static_cast<double>(info.background[2])};
  const int origin[3] = {d.origin.x, d.origin.y, d.origin.z};
  const int dims[3] = {d.dims.x, d.dims.y, d.dims.z};
  if (!api->copy_values(grid.grid, origin, dims, d.values.data(), &error))
    throw ParameterError(fmt::format("{}: cannot be read as OpenVDB: {}", where, error));
  // Every value finite (and >= 0 when asked), the first offender named by its index.
  const size_t nc = static_cast<size_t>(d.channels);
  size_t n = 0;
  for (int z = d.origin.z; z < d.origin.z + d.dims.z; ++z)
    for (int y = d.origin.y; y < d.origin.y + d.dims.y; ++y)
      for (int x = d.origin.x; x < d.origin.x + d.dims.x; ++x, ++n)
        for (size_t c = 0; c < nc; ++c) {
          const float f = d.values[nc * n + c];
          if (!std::isfinite(f) || (non_negative && f < 0.0f))
            throw ParameterError(fmt::format(
                "{}: voxel ({}, {}, {}) is {}: expected a finite value{}", where, x, y, z, f,
                non_negative ? " >= 0" : ""));
        }
  for (size_t c = 0; c < 3; ++c)
    if (!std::isfinite(d.background[c]) || (non_negative && d.background[c] < 0.0))
      throw ParameterError(fmt::format("{}: background is {}: expected a finite value{}", where,
                                       d.background[c], non_negative ? " >= 0" : ""));
  return d;
}

namespace {

// σa + σs' (σs' = (1 - g) σs) must be > 0 wherever the grids are sampled, as for a homogeneous
// medium (ScalarMedium::validate): where both are 0 a photon neither scatters nor is absorbed
// and, inside a mesh of index > 1, may be reflected totally at its surface forever. Checked at
// every voxel of each grid (the other one interpolated there) and for the backgrounds, which
// hold wherever the mesh reaches beyond the grids' active voxels.
void requireExtinction(const DenseGrid& a, const DenseGrid& s, double g, const std::string& where) {
  const double sp = 1.0 - g;
  auto fail = [&](const std::string& at, size_t c, double va, double vs) {
    throw ParameterError(fmt::format(
        "{}: sigma_a is {} and sigma_s' is {} in channel {} at {}: the medium neither absorbs nor "
        "scatters there (need sigma_a + sigma_s' > 0 everywhere, the background outside the "
        "active voxels included)", where, va, vs * sp, kChannelNames[c], at));
  };
  for (size_t c = 0; c < 3; ++c)
    if (!(a.background[c] + sp * s.background[c] > 0.0))
      fail("the background (outside the active voxels)", c, a.background[c], s.background[c]);
  auto sweep = [&](const DenseGrid& own, const DenseGrid& other, bool ownIsA, const char* name) {
    for (int z = own.origin.z; z < own.origin.z + own.dims.z; ++z)
      for (int y = own.origin.y; y < own.origin.y + own.dims.y; ++y)
        for (int x = own.origin.x; x < own.origin.x + own.dims.x; ++x) {
          const Rgb v = own.voxel(x, y, z);
          if (v[0] > 0.0 && v[1] > 0.0 && v[2] > 0.0 && (ownIsA || sp > 0.0)) continue;
          const glm::dvec3 q = own.index_to_world * glm::dvec3(x, y, z) + own.translation;
          const Rgb w = other.trilinear(q);
          for (size_t c = 0; c < 3; ++c) {
            const double va = ownIsA ? v[c] : w[c], vs = ownIsA ? w[c] : v[c];
            if (!(va + sp * vs > 0.0))
              fail(fmt::format("voxel ({}, {}, {}) of grid '{}' (position ({}, {}, {}))", x, y, z,
                               name, q.x, q.y, q.z),
                   c, va, vs);
          }
        }
  };
  sweep(a, s, true, "sigma_a");
  sweep(s, a, false, "sigma_s");
}

}  // namespace

LocalMedium VoxelsDesc::representative() const {
  if (mode == Mode::Density) return media.at(0).medium;
  LocalMedium m;
  m.sigma_a = sigma_a_grid ? sigma_a_grid->mean() : Rgb{0.0, 0.0, 0.0};
  m.sigma_s = sigma_s_grid ? sigma_s_grid->mean() : Rgb{0.0, 0.0, 0.0};
  m.g = g;
  return m;
}

VoxelsDesc parseVoxels(const ParseContext& c, const json& mat, const std::string& key) {
  const JsonReader& r = c.reader;
  r.onlyKeys(mat, key, materialKeys({"file", "density", "media", "sigma_a", "sigma_s", "g"}));
  VoxelsDesc d;
  d.file = c.resolve(r.string(mat, "file", key), key + ".file");
  const bool coefficients = mat.contains("sigma_a") || mat.contains("sigma_s") || mat.contains("g");
  const bool density = mat.contains("density") || mat.contains("media");
  if (coefficients && density)
    r.fail(key, "give either \"density\" and \"media\", or \"sigma_a\", \"sigma_s\" and \"g\", "
                "not both");
  if (!coefficients && !density)
    r.fail(key, "expected \"media\" (and \"density\", a grid name), or the grid names "
                "\"sigma_a\" and \"sigma_s\"");
  try {
    if (density) {
      d.mode = VoxelsDesc::Mode::Density;
      if (mat.contains("density")) d.density = r.string(mat, "density", key);
      d.media = parseMediaArray(r, mat, "media", key, 2);
      d.density_grid = std::make_shared<const DenseGrid>(
          readVdbGrid(d.file, d.density, false, false, r.what + ": " + key + ".density"));
    } else {
      d.mode = VoxelsDesc::Mode::Coefficients;
      d.sigma_a = r.string(mat, "sigma_a", key);
      d.sigma_s = r.string(mat, "sigma_s", key);
      d.g = r.number(mat, "g", key, 0.0);
      if (!(std::abs(d.g) < 1.0)) r.fail(key + ".g", fmt::format("is {}: expected |g| < 1", d.g));
      d.sigma_a_grid = std::make_shared<const DenseGrid>(
          readVdbGrid(d.file, d.sigma_a, true, true, r.what + ": " + key + ".sigma_a"));
      d.sigma_s_grid = std::make_shared<const DenseGrid>(
          readVdbGrid(d.file, d.sigma_s, true, true, r.what + ": " + key + ".sigma_s"));
      requireExtinction(*d.sigma_a_grid, *d.sigma_s_grid, d.g,
                        fmt::format("{}: {} ('{}', grids '{}' and '{}')", r.what, key,
                                    d.file.string(), d.sigma_a, d.sigma_s));
    }
  } catch (const std::bad_alloc&) {
    r.fail(key + ".file", fmt::format("'{}': not enough memory for its grids", d.file.string()));
  }
  return d;
}

void writeVoxels(const VoxelsDesc& d, json& mat, const PathWriter& written) {
  mat["file"] = written(d.file);
  if (d.mode == VoxelsDesc::Mode::Density) {
    mat["density"] = d.density;
    mat["media"] = json::array({toJson(d.media[0]), toJson(d.media[1])});
  } else {
    mat["sigma_a"] = d.sigma_a;
    mat["sigma_s"] = d.sigma_s;
    mat["g"] = d.g;
  }
}

VoxelsField::VoxelsField(const VoxelsDesc& d) : d_(d) {
  if (d_.mode == VoxelsDesc::Mode::Density) {
    media_[0] = d_.media.at(0).medium;
    media_[1] = d_.media.at(1).medium;
    if (!d_.density_grid) throw ParameterError("voxels: the density grid is not loaded");
  } else if (!d_.sigma_a_grid || !d_.sigma_s_grid) {
    throw ParameterError("voxels: the sigma_a and sigma_s grids are not loaded");
  }
}

LocalMedium VoxelsField::at(const glm::dvec3& q) const {
  if (d_.mode == VoxelsDesc::Mode::Density) {
    const double v = std::clamp(d_.density_grid->trilinear(q)[0], 0.0, 1.0);
    return LocalMedium::mix(media_[0], media_[1], v);
  }
  LocalMedium m;
  m.sigma_a = d_.sigma_a_grid->trilinear(q);
  m.sigma_s = d_.sigma_s_grid->trilinear(q);
  m.g = d_.g;
  return m;
}

Rgb VoxelsField::majorant(const glm::dvec3& lo, const glm::dvec3& hi) const {
  Rgb mx, mn;
  if (d_.mode == VoxelsDesc::Mode::Density) {
    d_.density_grid->range(lo, hi, mx, mn);
    const double a = std::clamp(mn[0], 0.0, 1.0), b = std::clamp(mx[0], 0.0, 1.0);
    return padMajorant(maxRgb(LocalMedium::mix(media_[0], media_[1], a).sigmaT(),
                              LocalMedium::mix(media_[0], media_[1], b).sigmaT()));
  }
  Rgb amx, smx;
  d_.sigma_a_grid->range(lo, hi, amx, mn);
  d_.sigma_s_grid->range(lo, hi, smx, mn);
  return padMajorant({amx[0] + smx[0], amx[1] + smx[1], amx[2] + smx[2]});
}

}  // namespace translucent::material
