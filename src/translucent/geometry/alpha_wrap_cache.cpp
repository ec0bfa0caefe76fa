// SPDX-License-Identifier: GPL-3.0-or-later
// The on-disk cache of alpha wraps (alpha_wrap.h, loadOrAlphaWrap). Kept out of alpha_wrap.cpp so
// that the CGAL translation unit holds only the CGAL call.
//
// File: a text header line "translucent-alpha-wrap <version> <content hash hex> <vertices>
// <triangles>\n", then the payload: vertices × 3 little-endian doubles, triangles × 3 uint32.
// The hash (contentHash, FNV-1a) covers the payload, so a truncated or edited file is detected
// and the wrap recomputed.
#include <fmt/format.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

#include "translucent/geometry/alpha_wrap.h"
#include "translucent/geometry/atomic_file.h"
#include "translucent/geometry/point_cloud.h"  // meshHash

namespace translucent::geometry {
namespace {

// Bumped whenever the wrap of a given input and options changes (CGAL version, conversion).
constexpr int kWrapCacheVersion = 1;

std::string cacheName(const TriangleMesh& mesh, const AlphaWrapOptions& o) {
  return fmt::format("wrap-{:016x}-a{:016x}-o{:016x}-v{}.bin", meshHash(mesh),
                     std::bit_cast<uint64_t>(o.alpha), std::bit_cast<uint64_t>(o.offset),
                     kWrapCacheVersion);
}

std::string payload(const TriangleMesh& m) {
  std::string bytes(m.positions.size() * 3 * sizeof(double) + m.triangles.size() * 3 * sizeof(uint32_t), '\0');
  char* out = bytes.data();
  for (const glm::dvec3& p : m.positions)
    for (int k = 0; k < 3; ++k) {
      std::memcpy(out, &p[k], sizeof(double));
      out += sizeof(double);
    }
  for (const glm::uvec3& t : m.triangles)
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = t[k];
      std::memcpy(out, &v, sizeof(uint32_t));
      out += sizeof(uint32_t);
    }
  return bytes;
}

// The cached wrap, or why it cannot be used.
bool readCache(const std::filesystem::path& file, TriangleMesh& out, std::string& why) {
  std::ifstream f(file, std::ios::binary);
  if (!f) {
    why = "";  // not there yet: no note
    return false;
  }
  std::string header;
  std::getline(f, header);
  std::istringstream h(header);
  std::string magic, hashHex;
  int version = 0;
  size_t nv = 0, nt = 0;
  if (!(h >> magic >> version >> hashHex >> nv >> nt) || magic != "translucent-alpha-wrap" ||
      version != kWrapCacheVersion) {
    why = fmt::format("cache file '{}' has an unexpected header: recomputed", file.string());
    return false;
  }
  // The payload's size from the file's (istreambuf_iterator trips GCC's -Wnull-dereference).
  const std::streamoff start = f.tellg();
  f.seekg(0, std::ios::end);
  const std::streamoff end = f.tellg();
  f.seekg(start);
  const size_t expected = nv * 3 * sizeof(double) + nt * 3 * sizeof(uint32_t);
  std::string bytes(start >= 0 && end >= start ? static_cast<size_t>(end - start) : 0, '\0');
  f.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!f || bytes.size() != expected || fmt::format("{:016x}", contentHash(bytes)) != hashHex) {
    why = fmt::format("cache file '{}' is truncated or edited (content hash mismatch): recomputed",
                      file.string());
    return false;
  }
  out.positions.resize(nv);
  out.triangles.resize(nt);
  const char* in = bytes.data();
  for (glm::dvec3& p : out.positions)
    for (int k = 0; k < 3; ++k) {
      std::memcpy(&p[k], in, sizeof(double));
      in += sizeof(double);
    }
  for (glm::uvec3& t : out.triangles)
    for (int k = 0; k < 3; ++k) {
      uint32_t v = 0;
      std::memcpy(&v, in, sizeof(uint32_t));
      t[k] = v;
      in += sizeof(uint32_t);
    }
  try {
    out.validate(file.string());
  } catch (const MeshError& e) {
    why = fmt::format("{}: recomputed", e.what());
    return false;
  }
  return true;
}

}  // namespace

TriangleMesh loadOrAlphaWrap(const TriangleMesh& mesh, const AlphaWrapOptions& options,
                             const std::string& what, const std::filesystem::path& cacheDir,
                             AlphaWrapStats* stats) {
  AlphaWrapStats local;
  AlphaWrapStats& st = stats ? *stats : local;
  if (cacheDir.empty()) return alphaWrap(mesh, options, what, &st);
  const std::filesystem::path file = cacheDir / cacheName(mesh, options);
  st.cache_file = file;
  TriangleMesh cached;
  std::string why;
  if (readCache(file, cached, why)) {
    st.from_cache = true;
    st.triangles_in = mesh.triangles.size();
    st.triangles_out = cached.triangles.size();
    const glm::dvec3 e = mesh.bounds().upper - mesh.bounds().lower;
    st.diagonal = std::sqrt(e.x * e.x + e.y * e.y + e.z * e.z);
    st.area_in = mesh.area();
    st.area_out = cached.area();
    return cached;
  }
  TriangleMesh wrap = alphaWrap(mesh, options, what, &st);
  st.note = why;
  const std::string bytes = payload(wrap);
  const std::string header = fmt::format("translucent-alpha-wrap {} {:016x} {} {}\n",
                                         kWrapCacheVersion, contentHash(bytes),
                                         wrap.positions.size(), wrap.triangles.size());
  std::error_code ec;
  std::filesystem::create_directories(cacheDir, ec);
  const std::string failed = writeFileAtomically(file, header + bytes);
  if (!failed.empty())
    st.note = fmt::format("{}{}the wrap is not cached: {}", st.note, st.note.empty() ? "" : "; ",
                          failed);
  return wrap;
}

}  // namespace translucent::geometry
