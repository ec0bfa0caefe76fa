// SPDX-License-Identifier: GPL-3.0-or-later
// Point clouds on disk: a small PLY reader/writer (assimp's PLY exporter cannot store the
// per-point area or float irradiance, see point_cloud.h) and the sampling cache.
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cctype>
#include <charconv>
#include <cmath>
#include <numbers>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <limits>
#include <optional>
#include <sstream>
#include <thread>

#include "translucent/geometry/atomic_file.h"
#include "translucent/geometry/point_cloud.h"

namespace translucent::geometry {
namespace fs = std::filesystem;
namespace {

// Bumped whenever samplePointCloud's output for a given (mesh, options) changes, so stale cache
// files are never returned.
constexpr int kAlgorithmVersion = 1;

// The header comment that holds the content hash of the binary data (writePointCloudPly).
constexpr const char* kHashComment = "content_hash";

PointCloud readPly(const fs::path& path, bool requireHash);

// ---- PLY scalar types ------------------------------------------------------------------------
enum class PlyType { Int8, Uint8, Int16, Uint16, Int32, Uint32, Float32, Float64 };

bool parseType(const std::string& s, PlyType& t) {
  static const std::pair<const char*, PlyType> names[] = {
      {"char", PlyType::Int8},     {"int8", PlyType::Int8},      {"uchar", PlyType::Uint8},
      {"uint8", PlyType::Uint8},   {"short", PlyType::Int16},    {"int16", PlyType::Int16},
      {"ushort", PlyType::Uint16}, {"uint16", PlyType::Uint16},  {"int", PlyType::Int32},
      {"int32", PlyType::Int32},   {"uint", PlyType::Uint32},    {"uint32", PlyType::Uint32},
      {"float", PlyType::Float32}, {"float32", PlyType::Float32}, {"double", PlyType::Float64},
      {"float64", PlyType::Float64}};
  for (const auto& [name, type] : names)
    if (s == name) {
      t = type;
      return true;
    }
  return false;
}

size_t typeSize(PlyType t) {
  switch (t) {
    case PlyType::Int8: case PlyType::Uint8: return 1;
    case PlyType::Int16: case PlyType::Uint16: return 2;
    case PlyType::Int32: case PlyType::Uint32: case PlyType::Float32: return 4;
    case PlyType::Float64: return 8;
  }
  return 0;
}

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::Float32;
  bool isList = false;
  PlyType countType = PlyType::Uint8;
};

struct PlyElement {
  std::string name;
  size_t count = 0;
  std::vector<PlyProperty> properties;
};

enum class PlyFormat { Ascii, BinaryLittle, BinaryBig };

// Reads scalars from the body of a PLY file (ascii tokens or binary values), with bounds checks.
class PlyBody {
 public:
  PlyBody(const std::string& file, std::string data, size_t offset, PlyFormat format)
      : file_(file), data_(std::move(data)), at_(offset), format_(format) {}

  double read(PlyType t) {
    if (format_ == PlyFormat::Ascii) return readToken();
    const size_t n = typeSize(t);
    if (at_ + n > data_.size())
      throw PointCloudError(fmt::format("PLY file '{}' is truncated: expected more vertex data "
                                        "after byte {}", file_, at_));
    std::array<unsigned char, 8> b{};
    std::memcpy(b.data(), data_.data() + at_, n);
    at_ += n;
    const bool swap = (format_ == PlyFormat::BinaryBig) == (std::endian::native == std::endian::little);
    if (swap) std::reverse(b.begin(), b.begin() + static_cast<std::ptrdiff_t>(n));
    switch (t) {
      case PlyType::Int8: return static_cast<int8_t>(b[0]);
      case PlyType::Uint8: return b[0];
      case PlyType::Int16: return value<int16_t>(b);
      case PlyType::Uint16: return value<uint16_t>(b);
      case PlyType::Int32: return value<int32_t>(b);
      case PlyType::Uint32: return value<uint32_t>(b);
      case PlyType::Float32: return double(value<float>(b));
      case PlyType::Float64: return value<double>(b);
    }
    return 0.0;
  }
  size_t remaining() const { return data_.size() - at_; }

 private:
  template <class T>
  static double value(const std::array<unsigned char, 8>& b) {
    T v;
    std::memcpy(&v, b.data(), sizeof(T));
    return static_cast<double>(v);
  }
  double readToken() {
    while (at_ < data_.size() && std::isspace(static_cast<unsigned char>(data_[at_]))) ++at_;
    size_t end = at_;
    while (end < data_.size() && !std::isspace(static_cast<unsigned char>(data_[end]))) ++end;
    if (end == at_)
      throw PointCloudError(fmt::format("PLY file '{}' is truncated: expected more vertex values",
                                        file_));
    double v = 0.0;
    const auto [ptr, ec] = std::from_chars(data_.data() + at_, data_.data() + end, v);
    if (ec != std::errc() || ptr != data_.data() + end)
      throw PointCloudError(fmt::format("PLY file '{}': '{}' is not a number: expected numeric "
                                        "ascii values", file_, data_.substr(at_, end - at_)));
    at_ = end;
    return v;
  }

  std::string file_;
  std::string data_;
  size_t at_;
  PlyFormat format_;
};

std::string readWholeFile(const fs::path& path) {
  std::error_code ec;
  if (!fs::exists(path, ec))
    throw PointCloudError(fmt::format("PLY file '{}' does not exist", path.string()));
  if (!fs::is_regular_file(path, ec))
    throw PointCloudError(fmt::format("PLY file '{}' is not a regular file", path.string()));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw PointCloudError(fmt::format("PLY file '{}' cannot be opened", path.string()));
  std::ostringstream ss;
  ss << in.rdbuf();
  return std::move(ss).str();
}

template <class T>
void put(std::string& out, T v) {
  if constexpr (std::endian::native == std::endian::big) {
    std::array<char, sizeof(T)> b;
    std::memcpy(b.data(), &v, sizeof(T));
    std::reverse(b.begin(), b.end());
    out.append(b.data(), sizeof(T));
  } else {
    out.append(reinterpret_cast<const char*>(&v), sizeof(T));
  }
}

}  // namespace

// ---- Writing -------------------------------------------------------------------------------
void writePointCloudPly(const PointCloud& cloud, const fs::path& path) {
  cloud.validate(fmt::format("point cloud for '{}'", path.string()));
  const size_t n = cloud.size();
  const bool faces = !cloud.faces.empty(), irradiance = cloud.hasIrradiance();

  std::string body;
  body.reserve(n * (28 + (faces ? 4 : 0) + (irradiance ? 12 : 0)));
  for (size_t i = 0; i < n; ++i) {
    for (int c = 0; c < 3; ++c) put(body, cloud.positions[i][c]);
    for (int c = 0; c < 3; ++c) put(body, cloud.normals[i][c]);
    put(body, cloud.areas[i]);
    if (faces) put(body, cloud.faces[i]);
    if (irradiance)
      for (int c = 0; c < 3; ++c) put(body, cloud.irradiance[i][c]);
  }
  // The content hash covers the whole file with its own 16 digits read as zeros (so that an
  // edited header is detected too); it is checked on reading (readPointCloudCache).
  std::string out = fmt::format(
      "ply\nformat binary_little_endian 1.0\n"
      "comment Translucent point cloud: area-uniform surface samples (area in scene units^2)\n"
      "comment {} {:016x}\n"
      "element vertex {}\n"
      "property float x\nproperty float y\nproperty float z\n"
      "property float nx\nproperty float ny\nproperty float nz\n"
      "property float area\n",
      kHashComment, uint64_t{0}, n);
  if (faces) out += "property uint face\n";
  if (irradiance)
    out += "property float irradiance_r\nproperty float irradiance_g\nproperty float irradiance_b\n";
  out += "end_header\n";
  out += body;
  const size_t digits = out.find(kHashComment) + std::strlen(kHashComment) + 1;
  const std::string hash = fmt::format("{:016x}", contentHash(out));
  out.replace(digits, hash.size(), hash);
  if (const std::string why = writeFileAtomically(path, out); !why.empty())
    throw PointCloudError(fmt::format("PLY file '{}' cannot be written: {}", path.string(), why));
}

// ---- Reading -------------------------------------------------------------------------------
PointCloud readPointCloudPly(const fs::path& path) { return readPly(path, false); }

bool isPointCloudPly(const fs::path& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return false;
  std::ifstream in(path, std::ios::binary);
  std::string header(64 * 1024, '\0');
  in.read(header.data(), static_cast<std::streamsize>(header.size()));
  header.resize(static_cast<size_t>(in.gcount()));
  const size_t end = header.find("end_header");
  if (header.rfind("ply", 0) != 0 || end == std::string::npos) return false;
  std::istringstream lines(header.substr(0, end));
  std::string line, element;
  bool vertexHasArea = false, faces = false;
  while (std::getline(lines, line)) {
    std::istringstream ls(line);
    std::string word;
    ls >> word;
    if (word == "element") {
      long long count = 0;
      ls >> element >> count;
      if (element == "face" && count > 0) faces = true;
    } else if (word == "property" && element == "vertex") {
      std::string type, name;
      ls >> type >> name;
      if (type != "list" && (name == "area" || name == "radius")) vertexHasArea = true;
    }
  }
  return vertexHasArea && !faces;
}

PointCloud readPointCloudCache(const fs::path& path) { return readPly(path, true); }

namespace {
PointCloud readPly(const fs::path& path, bool requireHash) {
  const std::string file = path.string();
  std::string data = readWholeFile(path);

  // Header.
  const size_t headerEnd = data.find("end_header");
  if (data.rfind("ply", 0) != 0 || headerEnd == std::string::npos)
    throw PointCloudError(fmt::format("PLY file '{}' has no PLY header: expected 'ply' ... "
                                      "'end_header'", file));
  size_t bodyStart = data.find('\n', headerEnd);
  bodyStart = bodyStart == std::string::npos ? data.size() : bodyStart + 1;
  std::istringstream header(data.substr(0, headerEnd));
  std::string line;
  PlyFormat format = PlyFormat::Ascii;
  bool haveFormat = false;
  std::vector<PlyElement> elements;
  std::optional<uint64_t> storedHash;
  size_t hashAt = 0;  // where its 16 digits are in the file
  while (std::getline(header, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream ls(line);
    std::string word;
    ls >> word;
    if (word == "comment") {
      std::string tag, hex;
      ls >> tag >> hex;
      if (tag == kHashComment) {
        uint64_t h = 0;
        const auto [ptr, ec] = std::from_chars(hex.data(), hex.data() + hex.size(), h, 16);
        if (ec != std::errc() || ptr != hex.data() + hex.size() || hex.size() != 16)
          throw PointCloudError(fmt::format("PLY file '{}': header line '{}': expected '{} "
                                            "<16 hex digits>'", file, line, kHashComment));
        storedHash = h;
        const std::string tagged = fmt::format("comment {} ", kHashComment);
        hashAt = data.find(tagged) + tagged.size();
      }
    } else if (word == "format") {
      std::string f;
      ls >> f;
      if (f == "ascii") format = PlyFormat::Ascii;
      else if (f == "binary_little_endian") format = PlyFormat::BinaryLittle;
      else if (f == "binary_big_endian") format = PlyFormat::BinaryBig;
      else
        throw PointCloudError(fmt::format("PLY file '{}' has format '{}': expected ascii, "
                                          "binary_little_endian or binary_big_endian", file, f));
      haveFormat = true;
    } else if (word == "element") {
      PlyElement e;
      long long count = -1;
      ls >> e.name >> count;
      if (!ls || count < 0)
        throw PointCloudError(fmt::format("PLY file '{}': header line '{}': expected 'element "
                                          "<name> <count>'", file, line));
      e.count = static_cast<size_t>(count);
      elements.push_back(std::move(e));
    } else if (word == "property") {
      if (elements.empty())
        throw PointCloudError(fmt::format("PLY file '{}': property before any element: expected "
                                          "'element' first", file));
      PlyProperty p;
      std::string type;
      ls >> type;
      if (type == "list") {
        std::string countType, itemType;
        ls >> countType >> itemType >> p.name;
        p.isList = true;
        if (!parseType(countType, p.countType) || !parseType(itemType, p.type))
          throw PointCloudError(fmt::format("PLY file '{}': header line '{}': unknown list type",
                                            file, line));
      } else {
        ls >> p.name;
        if (!parseType(type, p.type))
          throw PointCloudError(fmt::format("PLY file '{}': property type '{}' is unknown: "
                                            "expected char, uchar, short, ushort, int, uint, "
                                            "float or double", file, type));
      }
      elements.back().properties.push_back(std::move(p));
    }
    // "ply", "comment", "obj_info" and blank lines carry nothing we need.
  }
  if (!haveFormat)
    throw PointCloudError(fmt::format("PLY file '{}' has no 'format' line", file));
  if (requireHash && !storedHash)
    throw PointCloudError(fmt::format("PLY file '{}' has no '{}' header comment: expected a "
                                      "cache file written by this version", file, kHashComment));
  if (storedHash) {
    std::string zeroed = data;
    zeroed.replace(hashAt, 16, 16, '0');
    const uint64_t h = contentHash(zeroed);
    if (h != *storedHash)
      throw PointCloudError(fmt::format("PLY file '{}': its content hash is {:016x}: expected "
                                        "{:016x} (its header): the file was changed or truncated",
                                        file, h, *storedHash));
  }

  PlyBody body(file, std::move(data), bodyStart, format);
  PointCloud cloud;
  for (const auto& e : elements) {
    if (e.name != "vertex") {
      // Skip an element that precedes the vertices (after them we stop reading).
      for (size_t i = 0; i < e.count; ++i)
        for (const auto& p : e.properties) {
          if (!p.isList) {
            body.read(p.type);
            continue;
          }
          const double items = body.read(p.countType);
          if (!(items >= 0.0) || items > double(body.remaining()))
            throw PointCloudError(fmt::format("PLY file '{}': list '{}' has {} items: expected a "
                                              "count the file can hold", file, p.name, items));
          for (size_t k = 0; k < static_cast<size_t>(items); ++k) body.read(p.type);
        }
      continue;
    }

    // The vertex element: map property names to fields.
    enum Field { X, Y, Z, NX, NY, NZ, AREA, FACE, ER, EG, EB, RADIUS, NONE };
    static const char* fieldNames[] = {"x", "y", "z", "nx", "ny", "nz", "area", "face",
                                       "irradiance_r", "irradiance_g", "irradiance_b", "radius"};
    std::vector<int> field(e.properties.size(), NONE);
    std::array<bool, NONE> present{};
    for (size_t k = 0; k < e.properties.size(); ++k)
      for (int f = 0; f < NONE; ++f)
        if (e.properties[k].name == fieldNames[f] && !e.properties[k].isList) {
          field[k] = f;
          present[static_cast<size_t>(f)] = true;
        }
    // Surfel files give a disc radius instead of an area: p_a = π r² (an area wins if both).
    const bool areaFromRadius = !present[AREA] && present[RADIUS];
    if (areaFromRadius) present[AREA] = true;
    for (int f = X; f <= AREA; ++f)
      if (!present[static_cast<size_t>(f)])
        throw PointCloudError(fmt::format("PLY file '{}' has no vertex property '{}': expected "
                                          "x, y, z, nx, ny, nz and area (or radius)", file,
                                          fieldNames[f]));
    const bool haveFaces = present[FACE];
    const bool haveIrradiance = present[ER] || present[EG] || present[EB];
    if (haveIrradiance && !(present[ER] && present[EG] && present[EB]))
      throw PointCloudError(fmt::format("PLY file '{}' has only some of irradiance_r, "
                                        "irradiance_g, irradiance_b: expected all three or none",
                                        file));
    if (format != PlyFormat::Ascii) {
      size_t stride = 0;
      for (const auto& p : e.properties) stride += p.isList ? 0 : typeSize(p.type);
      if (stride > 0 && e.count > body.remaining() / stride)
        throw PointCloudError(fmt::format("PLY file '{}' is truncated: {} vertices declared, "
                                          "expected {} bytes of data", file, e.count,
                                          e.count * stride));
    }
    cloud.positions.resize(e.count);
    cloud.normals.resize(e.count);
    cloud.areas.resize(e.count);
    if (haveFaces) cloud.faces.resize(e.count);
    if (haveIrradiance) cloud.irradiance.resize(e.count);
    for (size_t i = 0; i < e.count; ++i) {
      for (size_t k = 0; k < e.properties.size(); ++k) {
        const auto& p = e.properties[k];
        if (p.isList) {
          const double items = body.read(p.countType);
          if (!(items >= 0.0) || items > double(body.remaining()))
            throw PointCloudError(fmt::format("PLY file '{}': list '{}' has {} items", file,
                                              p.name, items));
          for (size_t j = 0; j < static_cast<size_t>(items); ++j) body.read(p.type);
          continue;
        }
        const double v = body.read(p.type);
        const auto f = static_cast<float>(v);
        switch (field[k]) {
          case X: cloud.positions[i].x = f; break;
          case Y: cloud.positions[i].y = f; break;
          case Z: cloud.positions[i].z = f; break;
          case NX: cloud.normals[i].x = f; break;
          case NY: cloud.normals[i].y = f; break;
          case NZ: cloud.normals[i].z = f; break;
          case AREA: cloud.areas[i] = f; break;
          case RADIUS:
            if (!areaFromRadius) break;
            if (!(v > 0.0) || !std::isfinite(v))
              throw PointCloudError(fmt::format("PLY file '{}': vertex {} has radius {}: expected "
                                                "a positive finite radius", file, i, v));
            cloud.areas[i] = static_cast<float>(std::numbers::pi * v * v);
            break;
          case FACE:
            if (!(v >= 0.0 && v <= double(std::numeric_limits<uint32_t>::max())) ||
                v != std::floor(v))
              throw PointCloudError(fmt::format("PLY file '{}': vertex {} has face {}: expected "
                                                "a non-negative integer", file, i, v));
            cloud.faces[i] = static_cast<uint32_t>(v);
            break;
          case ER: cloud.irradiance[i].x = f; break;
          case EG: cloud.irradiance[i].y = f; break;
          case EB: cloud.irradiance[i].z = f; break;
          default: break;
        }
      }
    }
    cloud.validate(fmt::format("PLY file '{}'", file));
    return cloud;
  }
  throw PointCloudError(fmt::format("PLY file '{}' has no 'vertex' element: expected the points "
                                    "as vertices", file));
}
}  // namespace

// ---- Cache ---------------------------------------------------------------------------------
fs::path defaultCacheDirectory() {
  if (const char* dir = std::getenv("TRANSLUCENT_CACHE_DIR"); dir != nullptr && *dir != '\0')
    return fs::path(dir);
  // The XDG base-directory spec ignores relative paths.
  if (const char* xdg = std::getenv("XDG_CACHE_HOME");
      xdg != nullptr && *xdg != '\0' && fs::path(xdg).is_absolute())
    return fs::path(xdg) / "translucent";
  if (const char* home = std::getenv("HOME"); home != nullptr && *home != '\0')
    return fs::path(home) / ".cache" / "translucent";
  std::error_code ec;
  return fs::temp_directory_path(ec) / "translucent-cache";
}

std::string cacheFileName(const TriangleMesh& mesh, const SamplingOptions& options) {
  std::string name = fmt::format("pointcloud-{:016x}-n{}-s{}-{}", meshHash(mesh), options.count,
                                 options.seed, toString(options.method));
  if (options.method == SamplingMethod::Elimination)
    name += fmt::format("-o{}", options.oversampling);
  return name + fmt::format("-v{}.ply", kAlgorithmVersion);
}

CachedPointCloud loadOrSamplePointCloud(const TriangleMesh& mesh, const SamplingOptions& options,
                                        const fs::path& cacheDir) {
  CachedPointCloud result;
  result.file = cacheDir / cacheFileName(mesh, options);
  std::error_code ec;
  if (fs::exists(result.file, ec)) {
    try {
      PointCloud cloud = readPointCloudCache(result.file);
      // The name says which sampling it is; check that the content agrees before trusting it.
      const double area = mesh.area();
      bool ok = cloud.size() == options.count && cloud.faces.size() == cloud.size() &&
                std::abs(cloud.totalArea() - area) <= 1e-4 * area;
      for (size_t i = 0; ok && i < cloud.faces.size(); ++i)
        ok = cloud.faces[i] < mesh.triangles.size();
      if (ok) {
        result.cloud = std::move(cloud);
        result.fromCache = true;
        return result;
      }
      result.note = fmt::format("cache file '{}' does not match the mesh or point count; "
                                "resampled", result.file.string());
    } catch (const PointCloudError& e) {
      result.note = fmt::format("cache file unreadable ({}); resampled", e.what());
    }
  }
  result.cloud = samplePointCloud(mesh, options);
  fs::create_directories(cacheDir, ec);
  try {
    writePointCloudPly(result.cloud, result.file);
  } catch (const PointCloudError& e) {
    result.note += (result.note.empty() ? "" : "; ") +
                   fmt::format("not cached: {}", e.what());
  }
  return result;
}

CachedPointCloud loadOrSamplePointCloud(const TriangleMesh& mesh, const SamplingOptions& options) {
  return loadOrSamplePointCloud(mesh, options, defaultCacheDirectory());
}

}  // namespace translucent::geometry
