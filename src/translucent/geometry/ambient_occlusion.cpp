// SPDX-License-Identifier: GPL-3.0-or-later
// Per-vertex ambient occlusion by Embree ray casting (ambient_occlusion.h).
#include "translucent/geometry/ambient_occlusion.h"
#include "translucent/geometry/atomic_file.h"

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <limits>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <thread>

#include <glm/geometric.hpp>

#include "translucent/geometry/counter_rng.h"
#include "translucent/geometry/point_cloud.h"  // meshHash, defaultCacheDirectory
#include "translucent/geometry/ray_scene.h"

namespace translucent::geometry {
namespace fs = std::filesystem;
namespace {

// Bump whenever the values a seed produces change, so old cache files are not reused.
constexpr int kAlgorithmVersion = 1;
constexpr char kMagic[8] = {'T', 'L', 'A', 'O', 'C', 'C', '0', '1'};

// Orthonormal basis about a unit n (Duff et al. 2017, "Building an Orthonormal Basis, Revisited").
void basis(const glm::dvec3& n, glm::dvec3& t, glm::dvec3& b) {
  const double s = std::copysign(1.0, n.z);
  const double a = -1.0 / (s + n.z);
  const double c = n.x * n.y * a;
  t = {1.0 + s * n.x * n.x * a, s * c, -s * n.x};
  b = {c, s + n.y * n.y * a, -n.y};
}

void checkOptions(const AmbientOcclusionOptions& options) {
  if (options.rays < 1 || options.rays > 1'000'000)
    throw AmbientOcclusionError(fmt::format(
        "ambient occlusion: rays must be in [1, 1000000], got {}", options.rays));
}

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

std::vector<glm::dvec3> ambientOcclusionNormals(const TriangleMesh& mesh) {
  std::vector<glm::dvec3> normals(mesh.vertexCount(), glm::dvec3(0.0));
  if (!mesh.normals.empty()) {
    if (mesh.normals.size() != mesh.vertexCount())
      throw AmbientOcclusionError(fmt::format(
          "ambient occlusion: the mesh has {} normals for {} vertices", mesh.normals.size(),
          mesh.vertexCount()));
    for (size_t i = 0; i < normals.size(); ++i) {
      const double len = glm::length(mesh.normals[i]);
      if (!std::isfinite(len) || len <= 0.0)
        throw AmbientOcclusionError(fmt::format(
            "ambient occlusion: vertex normal {} is zero or not finite", i));
      normals[i] = mesh.normals[i] / len;
    }
    return normals;
  }
  // Area weighting: the cross product's length is twice the triangle's area.
  for (const glm::uvec3& t : mesh.triangles) {
    const glm::dvec3 n = glm::cross(mesh.positions[t.y] - mesh.positions[t.x],
                                    mesh.positions[t.z] - mesh.positions[t.x]);
    for (int k = 0; k < 3; ++k) normals[t[k]] += n;
  }
  for (glm::dvec3& n : normals) {
    const double len = glm::length(n);
    n = len > 0.0 ? n / len : glm::dvec3(0.0);
  }
  return normals;
}

AmbientOcclusion computeAmbientOcclusion(const TriangleMesh& mesh,
                                         const std::vector<glm::dvec3>& points,
                                         const std::vector<glm::dvec3>& normals,
                                         const AmbientOcclusionOptions& options) {
  checkOptions(options);
  mesh.validate("ambient occlusion mesh");
  if (points.size() != normals.size())
    throw AmbientOcclusionError(fmt::format(
        "ambient occlusion: {} points but {} normals", points.size(), normals.size()));

  AmbientOcclusion result;
  std::optional<RayScene> scene;
  try {
    scene.emplace(mesh, "ambient occlusion");
  } catch (const std::runtime_error& e) {
    throw AmbientOcclusionError(e.what());
  }
  result.deviceSeconds = scene->deviceSeconds();
  result.bvhSeconds = scene->buildSeconds();

  const Bounds bounds = mesh.bounds();
  const double eps = 1e-5 * (glm::length(bounds.center()) + bounds.radius());
  const int rays = options.rays;
  result.values.assign(points.size(), 1.0f);

  const auto start = std::chrono::steady_clock::now();
  tbb::parallel_for(tbb::blocked_range<size_t>(0, points.size(), 64),
                    [&](const tbb::blocked_range<size_t>& range) {
    for (size_t v = range.begin(); v != range.end(); ++v) {
      const glm::dvec3 n = normals[v];
      if (glm::dot(n, n) == 0.0) continue;  // unused vertex: AO = 1
      glm::dvec3 t, b;
      basis(n, t, b);
      const glm::dvec3 o = points[v] + eps * n;
      CounterRng rng(options.seed, v ^ 0x414f414f414f414fULL);  // AO's own streams ("AOAO")
      int visible = 0;
      for (int i = 0; i < rays; ++i) {
        const double u1 = rng.uniform(), u2 = rng.uniform();
        // Uniform: cos θ = u1 (pdf 1/2π). Cosine-weighted: sin θ = sqrt(u1) (pdf cos θ / π).
        const double cosTheta = options.cosineWeighted ? std::sqrt(1.0 - u1) : 1.0 - u1;
        const double sinTheta = std::sqrt(std::max(0.0, 1.0 - cosTheta * cosTheta));
        const double phi = 2.0 * std::numbers::pi * u2;
        const glm::dvec3 d =
            sinTheta * std::cos(phi) * t + sinTheta * std::sin(phi) * b + cosTheta * n;
        if (!scene->occluded(o, d, eps, std::numeric_limits<double>::infinity(), true))
          ++visible;  // Eq. 3.5: V = 1
      }
      result.values[v] = static_cast<float>(static_cast<double>(visible) / rays);
    }
  });
  result.aoSeconds = secondsSince(start);
  return result;
}

AmbientOcclusion computeAmbientOcclusion(const TriangleMesh& mesh,
                                         const AmbientOcclusionOptions& options) {
  checkOptions(options);
  mesh.validate("ambient occlusion mesh");
  return computeAmbientOcclusion(mesh, mesh.positions, ambientOcclusionNormals(mesh), options);
}

std::string ambientOcclusionCacheFileName(const TriangleMesh& mesh,
                                          const AmbientOcclusionOptions& options) {
  return fmt::format("ao-{:016x}-r{}-s{}-{}-v{}.bin", meshHash(mesh), options.rays, options.seed,
                     options.cosineWeighted ? "cosine" : "uniform", kAlgorithmVersion);
}

AmbientOcclusion loadOrComputeAmbientOcclusion(const TriangleMesh& mesh,
                                               const AmbientOcclusionOptions& options,
                                               const fs::path& cacheDir) {
  checkOptions(options);
  const fs::path file = cacheDir / ambientOcclusionCacheFileName(mesh, options);
  std::string note;
  std::error_code ec;
  if (fs::exists(file, ec)) {
    // Layout: magic, uint64 vertex count, int32 rays, then float values.
    std::ifstream in(file, std::ios::binary);
    char magic[8] = {};
    uint64_t count = 0;
    int32_t rays = 0;
    in.read(magic, sizeof magic);
    in.read(reinterpret_cast<char*>(&count), sizeof count);
    in.read(reinterpret_cast<char*>(&rays), sizeof rays);
    bool ok = in && std::memcmp(magic, kMagic, sizeof kMagic) == 0 &&
              count == mesh.vertexCount() && rays == options.rays;
    std::vector<float> values;
    if (ok) {
      values.resize(count);
      in.read(reinterpret_cast<char*>(values.data()),
              static_cast<std::streamsize>(count * sizeof(float)));
      ok = static_cast<bool>(in) && in.peek() == std::char_traits<char>::eof();
      for (size_t i = 0; ok && i < values.size(); ++i)
        ok = values[i] >= 0.0f && values[i] <= 1.0f;
    }
    if (ok) {
      AmbientOcclusion result;
      result.values = std::move(values);
      result.fromCache = true;
      result.file = file;
      return result;
    }
    note = fmt::format("cache file '{}' is corrupt or does not match the mesh; recomputed",
                       file.string());
  }
  AmbientOcclusion result = computeAmbientOcclusion(mesh, options);
  result.file = file;
  result.note = note;
  fs::create_directories(cacheDir, ec);
  const uint64_t count = result.values.size();
  const int32_t rays = options.rays;
  std::string bytes(kMagic, sizeof kMagic);
  bytes.append(reinterpret_cast<const char*>(&count), sizeof count);
  bytes.append(reinterpret_cast<const char*>(&rays), sizeof rays);
  bytes.append(reinterpret_cast<const char*>(result.values.data()), count * sizeof(float));
  if (const std::string why = writeFileAtomically(file, bytes); !why.empty())
    result.note += (result.note.empty() ? "" : "; ") +
                   fmt::format("not cached: '{}' cannot be written: {}", file.string(), why);
  return result;
}

AmbientOcclusion loadOrComputeAmbientOcclusion(const TriangleMesh& mesh,
                                               const AmbientOcclusionOptions& options) {
  return loadOrComputeAmbientOcclusion(mesh, options, defaultCacheDirectory());
}

}  // namespace translucent::geometry
