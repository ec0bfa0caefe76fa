// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/techniques/transfer/transfer_operator.h"

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstring>
#include <fstream>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <system_error>

#include <glm/geometric.hpp>

#include "translucent/geometry/point_grid.h"
#include "translucent/io/output_guard.h"
#include "translucent/optics/medium.h"
#include "translucent/reference/majorant_grid.h"
#include "translucent/reference/mesh_tracer.h"
#include "translucent/reference/surface_transfer.h"

namespace translucent::transfer {
namespace {

constexpr char kMagic[8] = {'T', 'L', 'X', 'F', 'E', 'R', '0', '1'};

// The node of `candidates` (nearest first) nearest to a point with normal n on the same side
// (n_i · n > 0); the nearest overall when none is.
uint32_t sameSideNearest(const std::vector<std::pair<double, uint32_t>>& candidates,
                         const std::vector<glm::vec3>& normals, const glm::dvec3& n) {
  for (const auto& [d2, i] : candidates)
    if (glm::dot(glm::dvec3(normals[i]), n) > 0.0) return i;
  return candidates.front().second;
}

}  // namespace

size_t TransferOperator::bytes() const {
  return matrix.size() * sizeof(float) + vertexNodes.size() * sizeof(uint32_t) +
         vertexWeights.size() * sizeof(float) +
         nodes * (2 * sizeof(glm::vec3) + sizeof(float));
}

std::vector<glm::vec3> TransferOperator::exitance(const std::vector<glm::vec3>& E) const {
  if (E.size() != nodes)
    throw ParameterError(fmt::format("transfer: {} irradiance values for {} nodes", E.size(), nodes));
  std::vector<glm::vec3> B(nodes, glm::vec3(0.0f));
  tbb::parallel_for(tbb::blocked_range<size_t>(0, nodes), [&](const auto& r) {
    for (size_t i = r.begin(); i != r.end(); ++i)
      for (int c = 0; c < 3; ++c) {
        const float* row = &matrix[(size_t(c) * nodes + i) * nodes];
        double s = 0.0;
        for (size_t j = 0; j < nodes; ++j) s += double(row[j]) * double(E[j][c]);
        B[i][c] = float(s);
      }
  });
  return B;
}

std::vector<glm::vec3> TransferOperator::vertexExitance(const std::vector<glm::vec3>& Bn) const {
  const size_t vertices = vertexWeights.size() / kVertexNodes;
  std::vector<glm::vec3> B(vertices, glm::vec3(0.0f));
  for (size_t v = 0; v < vertices; ++v)
    for (int k = 0; k < kVertexNodes; ++k)
      B[v] += vertexWeights[v * kVertexNodes + k] * Bn[vertexNodes[v * kVertexNodes + k]];
  return B;
}

TransferOperator buildTransferOperator(const geometry::TriangleMesh& mesh,
                                       const std::vector<glm::dvec3>& vertexNormals,
                                       const material::Material& material,
                                       const TransferOptions& options,
                                       const reference::ProgressCallback& progress) {
  const auto start = std::chrono::steady_clock::now();
  if (material.kind == material::Material::Kind::Surface)
    throw ParameterError(
        "transfer: a surface-map material (2D maps over the atlas) has no volume for the path "
        "tracer to fill: use the pointcloud technique for it");
  if (options.nodes < 16)
    throw ParameterError(fmt::format("transfer: nodes is {}: expected at least 16", options.nodes));
  if (vertexNormals.size() != mesh.vertexCount())
    throw ParameterError("transfer: expected one normal per vertex");

  TransferOperator op;
  geometry::SamplingOptions sampling;
  sampling.count = static_cast<size_t>(options.nodes);
  sampling.seed = options.seed;
  sampling.method = geometry::SamplingMethod::Elimination;
  const geometry::PointCloud cloud = geometry::samplePointCloud(mesh, sampling);
  const size_t N = cloud.size();
  op.nodes = N;
  op.positions = cloud.positions;
  op.normals = cloud.normals;
  op.areas = cloud.areas;

  // Exit bins: the grid over the nodes, cells about the node spacing.
  const double spacing = std::sqrt(cloud.totalArea() / double(N));
  const geometry::PointGrid grid(cloud.positions, spacing);

  // The walk: the mesh as an Embree body, the material's channels (and its field).
  const reference::MeshBody body(mesh, "transfer mesh");
  material.medium.validate();
  std::vector<ScalarMedium> channels;
  for (int c = 0; c < 3; ++c) channels.push_back(material.medium.channel(c));
  std::optional<reference::VolumeMedium> volume;
  if (material.kind == material::Material::Kind::Volume) {
    const geometry::Bounds b = mesh.bounds();
    const glm::dvec3 pad(1e-6 * (glm::length(b.center()) + b.radius()));
    volume = reference::VolumeMedium::make(material, b.lower - pad, b.upper + pad, {0, 0, 0});
  }
  // The nodes' cells (the surface points each node's bin takes, the rule of sameSideNearest) are
  // not all of area A / N (blue noise spaces the nodes evenly, not exactly): their areas by Monte
  // Carlo, kCellProbes area-uniform random points per node (a relative error of about
  // 1/sqrt(kCellProbes) = 3% per cell, averaging out over neighbouring cells). B_i is the cell's
  // exiting flux over this area, and the entry's flux E_j times it.
  constexpr size_t kCellProbes = 1024;
  {
    geometry::SamplingOptions probes;
    probes.count = std::min<size_t>(kCellProbes * N, (size_t(1) << 24) - 1);
    probes.seed = options.seed ^ 0x9e3779b97f4a7c15ULL;
    probes.method = geometry::SamplingMethod::Random;
    const geometry::PointCloud probe = geometry::samplePointCloud(mesh, probes);
    std::vector<std::atomic<uint32_t>> counts(N);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, probe.size()), [&](const auto& r) {
      for (size_t k = r.begin(); k != r.end(); ++k) {
        const auto near = grid.nearest(probe.positions[k], kExitCandidates);
        counts[sameSideNearest(near, cloud.normals, glm::dvec3(probe.normals[k]))].fetch_add(
            1, std::memory_order_relaxed);
      }
    });
    const double total = cloud.totalArea();
    for (size_t i = 0; i < N; ++i)
      op.areas[i] = float(total * std::max(double(counts[i].load()), 0.5) / double(probe.size()));
  }

  std::vector<reference::SurfaceEntry> entries(N);
  for (size_t j = 0; j < N; ++j)
    entries[j] = {glm::dvec3(cloud.positions[j]), glm::normalize(glm::dvec3(cloud.normals[j])),
                  std::sqrt(double(cloud.areas[j]) / std::numbers::pi)};

  // Exiting flux per entry, column-major while tracing (entry j's column is written only by the
  // thread tracing it): X[(j · 3 + c) · N + i].
  std::vector<float> X(N * 3 * N, 0.0f);
  const reference::SurfaceExitScore score = [&](size_t j, const reference::ExitRecord& e) {
    const auto near = grid.nearest(glm::vec3(e.position), kExitCandidates);
    const uint32_t i = sameSideNearest(near, cloud.normals, e.normal);
    X[(j * 3 + size_t(e.channel)) * N + i] += float(e.weight);
  };
  reference::SurfaceTransferOptions to;
  to.photons = options.photons;
  to.seed = options.seed;
  to.threads = options.threads;
  const reference::SurfaceTransferStats stats = reference::traceSurfaceEntries(
      body, channels, volume ? &*volume : nullptr, entries, to, score, progress);
  if (stats.partial) throw ParameterError("transfer: the preprocessing was stopped");
  op.photons = stats.photons;

  op.matrix.assign(3 * N * N, 0.0f);
  for (size_t j = 0; j < N; ++j) {
    if (!(stats.entered[j][0] > 0.0)) ++op.missedEntries;
    for (size_t c = 0; c < 3; ++c) {
      const double in = stats.entered[j][c];
      if (!(in > 0.0)) continue;
      const float* col = &X[(j * 3 + c) * N];
      for (size_t i = 0; i < N; ++i)
        op.matrix[(c * N + i) * N + j] =
            float(double(col[i]) / in * double(op.areas[j]) / double(op.areas[i]));
    }
  }

  // Vertex weights: Gaussian of the spacing, same side only, normalised.
  const size_t V = mesh.vertexCount();
  op.vertexNodes.assign(V * kVertexNodes, 0);
  op.vertexWeights.assign(V * kVertexNodes, 0.0f);
  const double h2 = spacing * spacing;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, V), [&](const auto& r) {
    for (size_t v = r.begin(); v != r.end(); ++v) {
      const auto near = grid.nearest(glm::vec3(mesh.positions[v]), kVertexNodes);
      double sum = 0.0;
      std::array<double, kVertexNodes> w{};
      for (size_t k = 0; k < near.size(); ++k) {
        const double facing = std::max(0.0, glm::dot(vertexNormals[v], glm::dvec3(cloud.normals[near[k].second])));
        w[k] = std::exp(-0.5 * near[k].first / h2) * facing * facing;
        sum += w[k];
      }
      for (size_t k = 0; k < near.size(); ++k) op.vertexNodes[v * kVertexNodes + k] = near[k].second;
      if (sum > 0.0) {
        for (size_t k = 0; k < near.size(); ++k) op.vertexWeights[v * kVertexNodes + k] = float(w[k] / sum);
      } else {
        op.vertexNodes[v * kVertexNodes] = sameSideNearest(near, cloud.normals, vertexNormals[v]);
        op.vertexWeights[v * kVertexNodes] = 1.0f;
      }
    }
  });
  op.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return op;
}

// ---- cache ------------------------------------------------------------------------------------

namespace {

template <class T>
void put(std::ofstream& f, const T& v) {
  f.write(reinterpret_cast<const char*>(&v), sizeof(T));
}
template <class T>
void putVector(std::ofstream& f, const std::vector<T>& v) {
  put(f, uint64_t(v.size()));
  f.write(reinterpret_cast<const char*>(v.data()), std::streamsize(v.size() * sizeof(T)));
}
template <class T>
T get(std::ifstream& f, const std::filesystem::path& path) {
  T v{};
  if (!f.read(reinterpret_cast<char*>(&v), sizeof(T)))
    throw std::runtime_error(fmt::format("{}: truncated transfer operator", path.string()));
  return v;
}
template <class T>
std::vector<T> getVector(std::ifstream& f, const std::filesystem::path& path, uint64_t expected) {
  const auto n = get<uint64_t>(f, path);
  if (n != expected)
    throw std::runtime_error(fmt::format("{}: an array of {} values where {} were expected",
                                         path.string(), n, expected));
  std::vector<T> v(n);
  if (!f.read(reinterpret_cast<char*>(v.data()), std::streamsize(n * sizeof(T))))
    throw std::runtime_error(fmt::format("{}: truncated transfer operator", path.string()));
  return v;
}

uint64_t fnv1a(const std::string& s) {
  uint64_t h = 0xcbf29ce484222325ULL;
  for (unsigned char ch : s) h = (h ^ ch) * 0x100000001b3ULL;
  return h;
}

}  // namespace

void writeTransferOperator(const TransferOperator& op, const std::string& key,
                           const std::filesystem::path& path) {
  const std::filesystem::path tmp = path.parent_path() / io::temporaryBeside(path, ".part");
  {
    std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
    if (!f) throw std::runtime_error(fmt::format("{}: cannot be written", tmp.string()));
    f.write(kMagic, sizeof(kMagic));
    put(f, uint64_t(key.size()));
    f.write(key.data(), std::streamsize(key.size()));
    put(f, uint64_t(op.nodes));
    put(f, op.seconds);
    put(f, op.photons);
    put(f, op.missedEntries);
    putVector(f, op.positions);
    putVector(f, op.normals);
    putVector(f, op.areas);
    putVector(f, op.matrix);
    putVector(f, op.vertexNodes);
    putVector(f, op.vertexWeights);
    f.flush();
    if (!f) {
      std::error_code ec;
      std::filesystem::remove(tmp, ec);
      throw std::runtime_error(fmt::format("{}: writing failed (disk full?)", tmp.string()));
    }
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    throw std::runtime_error(fmt::format("{}: cannot be written: {}", path.string(), ec.message()));
  }
}

TransferOperator readTransferOperator(const std::filesystem::path& path, const std::string& key) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw std::runtime_error(fmt::format("{}: cannot be read", path.string()));
  char magic[sizeof(kMagic)];
  if (!f.read(magic, sizeof(magic)) || std::memcmp(magic, kMagic, sizeof(kMagic)) != 0)
    throw std::runtime_error(fmt::format("{}: not a transfer operator", path.string()));
  const auto keySize = get<uint64_t>(f, path);
  if (keySize != key.size())
    throw std::runtime_error(fmt::format("{}: made for another scene or settings", path.string()));
  std::string stored(keySize, '\0');
  if (!f.read(stored.data(), std::streamsize(keySize)) || stored != key)
    throw std::runtime_error(fmt::format("{}: made for another scene or settings", path.string()));
  TransferOperator op;
  op.nodes = get<uint64_t>(f, path);
  if (op.nodes == 0 || op.nodes > (1u << 16))
    throw std::runtime_error(fmt::format("{}: {} nodes", path.string(), op.nodes));
  op.seconds = get<double>(f, path);
  op.photons = get<uint64_t>(f, path);
  op.missedEntries = get<uint64_t>(f, path);
  const uint64_t N = op.nodes;
  op.positions = getVector<glm::vec3>(f, path, N);
  op.normals = getVector<glm::vec3>(f, path, N);
  op.areas = getVector<float>(f, path, N);
  op.matrix = getVector<float>(f, path, 3 * N * N);
  const auto vn = get<uint64_t>(f, path);
  if (vn % kVertexNodes != 0 || vn > (uint64_t(1) << 32))
    throw std::runtime_error(fmt::format("{}: corrupt vertex weights", path.string()));
  f.seekg(-std::streamoff(sizeof(uint64_t)), std::ios::cur);
  op.vertexNodes = getVector<uint32_t>(f, path, vn);
  op.vertexWeights = getVector<float>(f, path, vn);
  for (uint32_t i : op.vertexNodes)
    if (i >= N) throw std::runtime_error(fmt::format("{}: corrupt vertex weights", path.string()));
  for (float x : op.matrix)
    if (!std::isfinite(x) || x < 0.0f)
      throw std::runtime_error(fmt::format("{}: corrupt matrix", path.string()));
  return op;
}

CachedTransfer loadOrBuildTransferOperator(const geometry::TriangleMesh& mesh,
                                           const std::vector<glm::dvec3>& vertexNormals,
                                           const material::Material& material,
                                           const TransferOptions& options, const std::string& key,
                                           const std::filesystem::path& cacheDir,
                                           const reference::ProgressCallback& progress) {
  CachedTransfer out;
  out.file = cacheDir / fmt::format("transfer-{:016x}.bin", fnv1a(key));
  std::error_code ec;
  if (std::filesystem::is_regular_file(out.file, ec)) {
    try {
      out.op = readTransferOperator(out.file, key);
      if (out.op.vertexWeights.size() == mesh.vertexCount() * kVertexNodes) {
        out.fromCache = true;
        return out;
      }
      out.note = fmt::format("{}: made for another mesh; rebuilt", out.file.string());
    } catch (const std::exception& e) {
      out.note = fmt::format("{}; rebuilt", e.what());
    }
  }
  out.op = buildTransferOperator(mesh, vertexNormals, material, options, progress);
  try {
    std::filesystem::create_directories(cacheDir, ec);
    writeTransferOperator(out.op, key, out.file);
  } catch (const std::exception& e) {
    out.note = fmt::format("not cached: {}", e.what());
  }
  return out;
}

}  // namespace translucent::transfer
