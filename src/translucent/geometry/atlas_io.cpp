// SPDX-License-Identifier: GPL-3.0-or-later
// The atlas cache (atlas.h): one small binary file per (mesh, options), beside the point clouds
// in defaultCacheDirectory(), written atomically (temporary file, then rename).
//
// Format (little endian): "TLATLAS\n", uint32 format version, uint32 size, uint32 method,
// uint32 gutter, uint64 triangle count, uint32 chart count, uint32 folded and distorted charts, uint32 length
// and bytes of meshUVRejection, float u v per corner (6 per triangle), uint32 chart per triangle,
// then uint64 contentHash of all the bytes before it (version 2: a tampered or truncated file is
// detected and rebuilt, not used). Areas are recomputed from the mesh on reading.
#include <fmt/format.h>
#include <unistd.h>

#include <atomic>
#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <thread>

#include "translucent/geometry/atlas.h"
#include "translucent/geometry/atomic_file.h"
#include "translucent/geometry/atlas_chart.h"
#include "translucent/geometry/counter_rng.h"
#include "translucent/geometry/point_cloud.h"  // meshHash, defaultCacheDirectory

namespace translucent::geometry {
namespace fs = std::filesystem;
namespace {

// Bumped whenever buildAtlas's output for given (mesh, options) changes, or the file format.
constexpr uint32_t kAtlasVersion = 2;
constexpr char kMagic[8] = {'T', 'L', 'A', 'T', 'L', 'A', 'S', '\n'};

uint64_t texcoordHash(const TriangleMesh& mesh) {
  uint64_t h = 0x13198a2e03707344ULL;  // π's fraction bits, further on
  for (const auto& uv : mesh.texcoords) {
    h = mix64(h ^ std::bit_cast<uint64_t>(uv.x));
    h = mix64(h ^ std::bit_cast<uint64_t>(uv.y));
  }
  return h;
}

template <typename T>
void put(std::string& out, const T& v) {
  out.append(reinterpret_cast<const char*>(&v), sizeof(T));
}

class Reader {
 public:
  Reader(const std::string& bytes, const fs::path& file, size_t end)
      : bytes_(bytes), file_(file), end_(end) {}
  template <typename T>
  T get() {
    T v;
    read(&v, sizeof(T));
    return v;
  }
  void read(void* dst, size_t n) {
    if (n > end_ - pos_)
      throw AtlasError(fmt::format("atlas cache file '{}' is truncated", file_.string()));
    if (dst != nullptr) std::memcpy(dst, bytes_.data() + pos_, n);
    pos_ += n;
  }
  bool atEnd() const { return pos_ == end_; }

 private:
  const std::string& bytes_;
  const fs::path& file_;
  size_t end_;  // where the data ends (the content hash follows)
  size_t pos_ = 0;
};

std::string serialize(const Atlas& atlas) {
  std::string out(kMagic, sizeof kMagic);
  put(out, kAtlasVersion);
  put(out, atlas.size);
  put(out, static_cast<uint32_t>(atlas.method));
  put(out, atlas.gutter);
  put(out, static_cast<uint64_t>(atlas.triangleCount()));
  put(out, atlas.chartCount);
  put(out, atlas.foldedCharts);
  put(out, atlas.distortedCharts);
  put(out, static_cast<uint32_t>(atlas.meshUVRejection.size()));
  out += atlas.meshUVRejection;
  for (const glm::vec2& uv : atlas.uvs) {
    put(out, uv.x);
    put(out, uv.y);
  }
  for (const uint32_t c : atlas.chart) put(out, c);
  put(out, contentHash(out));
  return out;
}

// Reads an atlas for `mesh`; throws AtlasError naming the file when it is not one.
Atlas deserialize(const std::string& bytes, const fs::path& file, const TriangleMesh& mesh) {
  constexpr size_t kHead = sizeof kMagic + sizeof(uint32_t);
  if (bytes.size() < sizeof kMagic || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0)
    throw AtlasError(fmt::format("'{}' is not an atlas cache file", file.string()));
  if (bytes.size() < kHead + sizeof(uint64_t))
    throw AtlasError(fmt::format("atlas cache file '{}' is truncated: {} bytes", file.string(),
                                 bytes.size()));
  uint32_t version = 0;
  std::memcpy(&version, bytes.data() + sizeof kMagic, sizeof version);
  if (version != kAtlasVersion)
    throw AtlasError(fmt::format("atlas cache file '{}' has version {}, expected {}",
                                 file.string(), version, kAtlasVersion));
  // The content hash first: a truncated or edited file fails here with what was found, before
  // any of its counts is believed.
  const size_t end = bytes.size() - sizeof(uint64_t);
  uint64_t stored = 0;
  std::memcpy(&stored, bytes.data() + end, sizeof stored);
  if (const uint64_t h = contentHash(std::string_view(bytes).substr(0, end)); h != stored)
    throw AtlasError(fmt::format("atlas cache file '{}': content hash {:016x}: expected {:016x} "
                                 "(stored at its end): the file was changed or truncated",
                                 file.string(), h, stored));
  Reader r(bytes, file, end);
  r.read(nullptr, kHead);
  Atlas atlas;
  atlas.size = r.get<uint32_t>();
  const auto method = r.get<uint32_t>();
  if (method > static_cast<uint32_t>(AtlasMethod::MeshUVs))
    throw AtlasError(fmt::format("atlas cache file '{}' has method {}", file.string(), method));
  atlas.method = static_cast<AtlasMethod>(method);
  atlas.gutter = r.get<uint32_t>();
  const auto nt = r.get<uint64_t>();
  if (nt != mesh.triangleCount())
    throw AtlasError(fmt::format("atlas cache file '{}' has {} triangles, the mesh {}",
                                 file.string(), nt, mesh.triangleCount()));
  atlas.chartCount = r.get<uint32_t>();
  atlas.foldedCharts = r.get<uint32_t>();
  atlas.distortedCharts = r.get<uint32_t>();
  atlas.meshUVRejection.resize(r.get<uint32_t>());
  if (atlas.meshUVRejection.size() > 4096)
    throw AtlasError(fmt::format("atlas cache file '{}' is corrupt", file.string()));
  r.read(atlas.meshUVRejection.data(), atlas.meshUVRejection.size());
  atlas.uvs.resize(3 * nt);
  for (glm::vec2& uv : atlas.uvs) {
    uv.x = r.get<float>();
    uv.y = r.get<float>();
    if (!(uv.x >= 0.0f && uv.x <= 1.0f && uv.y >= 0.0f && uv.y <= 1.0f))
      throw AtlasError(fmt::format("atlas cache file '{}' has a UV outside [0, 1]²",
                                   file.string()));
  }
  atlas.chart.resize(nt);
  for (uint32_t& c : atlas.chart) {
    c = r.get<uint32_t>();
    if (c >= atlas.chartCount)
      throw AtlasError(fmt::format("atlas cache file '{}' has a chart id out of range",
                                   file.string()));
  }
  if (!r.atEnd())
    throw AtlasError(fmt::format("atlas cache file '{}' has trailing bytes", file.string()));
  detail::computeAtlasAreas(mesh, atlas);
  return atlas;
}

}  // namespace

Atlas readAtlasCache(const fs::path& file, const TriangleMesh& mesh) {
  std::error_code ec;
  // The size first: file_size's error value, (uintmax_t)-1, is no size to allocate.
  const auto size = fs::is_regular_file(file, ec) ? fs::file_size(file, ec) : 0;
  if (ec || !fs::is_regular_file(file, ec))
    throw AtlasError(fmt::format("atlas cache file '{}' cannot be read: expected a regular file",
                                 file.string()));
  std::ifstream in(file, std::ios::binary);
  std::string bytes(static_cast<size_t>(size), '\0');
  in.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!in)
    throw AtlasError(fmt::format("atlas cache file '{}' cannot be read", file.string()));
  return deserialize(bytes, file, mesh);
}

std::string atlasCacheFileName(const TriangleMesh& mesh, const AtlasOptions& options) {
  std::string name = fmt::format("atlas-{:016x}", meshHash(mesh));
  if (options.useMeshUVs) name += fmt::format("-uv{:016x}", texcoordHash(mesh));
  name += fmt::format("-n{}-{}-g{}", options.size, toString(options.method), options.gutter);
  if (options.method != AtlasMethod::Triangles)
    name += fmt::format("-a{}-c{}", options.maxChartAngle, options.maxChartArea);
  return name + fmt::format("-v{}.bin", kAtlasVersion);
}

CachedAtlas loadOrBuildAtlas(const TriangleMesh& mesh, const AtlasOptions& options,
                             const fs::path& cacheDir, const AtlasProgress& progress) {
  CachedAtlas result;
  result.file = cacheDir / atlasCacheFileName(mesh, options);
  std::error_code ec;
  if (fs::exists(result.file, ec)) {
    try {
      result.atlas = readAtlasCache(result.file, mesh);
      if (result.atlas.size == options.size) {
        result.fromCache = true;
        return result;
      }
      result.note = fmt::format("cache file '{}' does not match the options; rebuilt",
                                result.file.string());
    } catch (const AtlasError& e) {
      result.note = fmt::format("cache file unreadable ({}); rebuilt", e.what());
    }
  }
  result.atlas = buildAtlas(mesh, options, progress);
  fs::create_directories(cacheDir, ec);
  if (const std::string why = writeFileAtomically(result.file, serialize(result.atlas)); !why.empty())
    result.note += (result.note.empty() ? "" : "; ") +
                   fmt::format("not cached: atlas cache file '{}' cannot be written: {}",
                               result.file.string(), why);
  return result;
}

CachedAtlas loadOrBuildAtlas(const TriangleMesh& mesh, const AtlasOptions& options,
                             const AtlasProgress& progress) {
  return loadOrBuildAtlas(mesh, options, defaultCacheDirectory(), progress);
}

}  // namespace translucent::geometry
