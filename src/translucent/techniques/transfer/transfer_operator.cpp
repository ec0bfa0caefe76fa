// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/techniques/transfer/transfer_operator.h"

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string_view>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <system_error>

#include <glm/geometric.hpp>

#include "translucent/geometry/atomic_file.h"
#include "translucent/geometry/point_grid.h"
#include "translucent/optics/medium.h"
#include "translucent/reference/majorant_grid.h"
#include "translucent/reference/mesh_tracer.h"
#include "translucent/reference/surface_transfer.h"

namespace translucent::transfer {
namespace {

constexpr char kMagic[8] = {'T', 'L', 'X', 'F', 'E', 'R', '0', '2'};

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
         nodes * (3 * sizeof(glm::vec3) + sizeof(float)) +
         (samplePositions.size() + sampleNormals.size()) * sizeof(glm::vec3);
}

std::vector<glm::vec3> TransferOperator::exitance(const std::vector<glm::vec3>& E,
                                                  const std::vector<glm::vec3>& Eu,
                                                  const std::vector<glm::vec3>& Ev) const {
  const bool tilted = !Eu.empty() || !Ev.empty();
  if (E.size() != nodes || (tilted && (matrices < 3 || Eu.size() != nodes || Ev.size() != nodes)))
    throw ParameterError(fmt::format("transfer: {} irradiance values ({} and {} tilted) for {} "
                                     "nodes and {} matrices", E.size(), Eu.size(), Ev.size(),
                                     nodes, matrices));
  std::vector<glm::vec3> B(nodes, glm::vec3(0.0f));
  const auto K = [&](size_t c, size_t m, size_t i) {
    return &matrix[((c * matrices + m) * nodes + i) * nodes];
  };
  tbb::parallel_for(tbb::blocked_range<size_t>(0, nodes), [&](const auto& r) {
    for (size_t i = r.begin(); i != r.end(); ++i)
      for (size_t c = 0; c < 3; ++c) {
        const int ch = int(c);
        double s = 0.0;
        if (tilted && matrices == incidenceMatrices(Incidence::Secant)) {
          // One-sided: the beam tilted towards the light's side, weighted by the tilt over kTilt
          // (the sign of the channels' sum, as apply.comp).
          for (size_t j = 0; j < nodes; ++j) {
            const double e = double(E[j].x) + double(E[j].y) + double(E[j].z);
            if (e == 0.0) continue;
            const size_t mu = Eu[j].x + Eu[j].y + Eu[j].z >= 0.0f ? 1 : 2;
            const size_t mv = Ev[j].x + Ev[j].y + Ev[j].z >= 0.0f ? 3 : 4;
            // The tilt clamped to the tilted beams' (|t_u| + |t_v| <= 1), as apply.comp.
            double t = 0.0;
            for (int k = 0; k < 3; ++k) t += std::abs(double(Eu[j][k])) + std::abs(double(Ev[j][k]));
            const double clamp = std::max(1.0, t / (kTilt * e));
            const double wu = std::abs(double(Eu[j][ch])) / kTilt / clamp;
            const double wv = std::abs(double(Ev[j][ch])) / kTilt / clamp;
            s += double(K(c, 0, i)[j]) * (double(E[j][ch]) - wu - wv) +
                 double(K(c, mu, i)[j]) * wu + double(K(c, mv, i)[j]) * wv;
          }
        } else {
          const std::vector<glm::vec3>* inputs[3] = {&E, &Eu, &Ev};
          for (size_t m = 0; m < (tilted ? 3u : 1u); ++m) {
            const float* row = K(c, m, i);
            const std::vector<glm::vec3>& in = *inputs[m];
            for (size_t j = 0; j < nodes; ++j) s += double(row[j]) * double(in[j][ch]);
          }
        }
        B[i][ch] = float(s);
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
    std::vector<uint32_t> owner(probe.size());
    tbb::parallel_for(tbb::blocked_range<size_t>(0, probe.size()), [&](const auto& r) {
      for (size_t k = r.begin(); k != r.end(); ++k)
        owner[k] = sameSideNearest(grid.nearest(probe.positions[k], kExitCandidates),
                                   cloud.normals, glm::dvec3(probe.normals[k]));
    });
    std::vector<uint32_t> counts(N, 0);
    for (uint32_t i : owner) ++counts[i];
    const double total = cloud.totalArea();
    for (size_t i = 0; i < N; ++i)
      op.areas[i] = float(total * std::max(double(counts[i]), 0.5) / double(probe.size()));
    // The cells' irradiance samples: each cell's first kCellSamples probes (uniform over the
    // cell, as the probes are over the surface); a cell with fewer is filled up with its node.
    op.samplePositions.assign(N * kCellSamples, glm::vec3(0.0f));
    op.sampleNormals.assign(N * kCellSamples, glm::vec3(0.0f));
    std::vector<uint32_t> taken(N, 0);
    for (size_t k = 0; k < probe.size(); ++k) {
      const uint32_t i = owner[k];
      if (taken[i] == kCellSamples) continue;
      op.samplePositions[i * kCellSamples + taken[i]] = probe.positions[k];
      op.sampleNormals[i * kCellSamples + taken[i]] = probe.normals[k];
      ++taken[i];
    }
    for (size_t i = 0; i < N; ++i)
      for (uint32_t t = taken[i]; t < kCellSamples; ++t) {
        op.samplePositions[i * kCellSamples + t] = cloud.positions[i];
        op.sampleNormals[i * kCellSamples + t] = cloud.normals[i];
      }
  }

  // The beams: per node the normal one and, with the tilted modes, four tilted ones (+u, -u, +v,
  // -v) on the same random numbers (stream j). Entry e = j · beams + b.
  const size_t beams = incidenceBeams(options.incidence);
  op.matrices = incidenceMatrices(options.incidence);
  op.tangents.resize(N);
  std::vector<reference::SurfaceEntry> entries(N * beams);
  for (size_t j = 0; j < N; ++j) {
    const glm::dvec3 n = glm::normalize(glm::dvec3(cloud.normals[j]));
    // Any unit tangent: the frame only has to be the same here and in the GPU pass (which gets u
    // and rebuilds v = n × u).
    const glm::dvec3 u = glm::normalize(glm::cross(n, std::abs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0)));
    const glm::dvec3 v = glm::cross(n, u);
    op.tangents[j] = glm::vec3(u);
    const double radius = std::sqrt(double(cloud.areas[j]) / std::numbers::pi);
    for (size_t b = 0; b < beams; ++b) {
      reference::SurfaceEntry& e = entries[j * beams + b];
      e = {glm::dvec3(cloud.positions[j]), n, radius, glm::dvec3(0.0), j};
      if (b == 0) continue;
      // The direction outside whose refraction leans by kTilt towards ±u or ±v: Snell, the
      // tangential part of the direction scales by η from inside to outside.
      const glm::dvec3 lean = (b == 1 ? u : b == 2 ? -u : b == 3 ? v : -v);
      const double sinOut = std::min(kTilt * material.medium.eta, 0.99);
      e.direction = glm::normalize(sinOut * lean - std::sqrt(1.0 - sinOut * sinOut) * n);
    }
  }
  if (beams > 1 && kTilt * material.medium.eta > 0.99)
    throw ParameterError(fmt::format("transfer: tilted beams with η = {}: a refracted direction "
                                     "leaning by {} cannot be reached from outside; use "
                                     "incidence normal", material.medium.eta, kTilt));

  // Exiting flux per entry, column-major while tracing (entry e's column is written only by the
  // thread tracing it): X[(e · 3 + c) · N + i].
  std::vector<float> X(entries.size() * 3 * N, 0.0f);
  const reference::SurfaceExitScore score = [&](size_t e, const reference::ExitRecord& x) {
    // The per-pixel term follows the light straight to the scattering point and on to the
    // view ray's exit: single scattering with an internal reflection stays in the operator.
    if (options.exclude_single && x.order == reference::ScatteringOrder::Single && !x.reflected)
      return;
    const auto near = grid.nearest(glm::vec3(x.position), kExitCandidates);
    const uint32_t i = sameSideNearest(near, cloud.normals, x.normal);
    X[(e * 3 + size_t(x.channel)) * N + i] += float(x.weight);
  };
  reference::SurfaceTransferOptions to;
  to.photons = options.photons;
  to.seed = options.seed;
  to.threads = options.threads;
  const reference::SurfaceTransferStats stats = reference::traceSurfaceEntries(
      body, channels, volume ? &*volume : nullptr, entries, to, score, progress);
  if (stats.partial) throw ParameterError("transfer: the preprocessing was stopped");
  op.photons = stats.photons;

  // K per beam: exiting flux per unit entered flux, times A_j / A_i; 0 for a beam that missed.
  const auto column = [&](size_t e, size_t c, size_t i) {
    const double in = stats.entered[e][c];
    return in > 0.0 ? double(X[(e * 3 + c) * N + i]) / in * double(op.areas[e / beams]) /
                          double(op.areas[i])
                    : 0.0;
  };
  op.matrix.assign(3 * op.matrices * N * N, 0.0f);
  for (size_t j = 0; j < N; ++j) {
    if (!(stats.entered[j * beams][0] > 0.0)) ++op.missedEntries;
    for (size_t c = 0; c < 3; ++c)
      for (size_t i = 0; i < N; ++i) {
        const size_t e = j * beams;
        op.matrix[((c * op.matrices) * N + i) * N + j] = float(column(e, c, i));
        if (beams == 1) continue;
        if (options.incidence == Incidence::Secant) {
          for (size_t b = 1; b < 5; ++b)
            op.matrix[((c * op.matrices + b) * N + i) * N + j] = float(column(e + b, c, i));
          continue;
        }
        op.matrix[((c * op.matrices + 1) * N + i) * N + j] =
            float((column(e + 1, c, i) - column(e + 2, c, i)) / (2.0 * kTilt));
        op.matrix[((c * op.matrices + 2) * N + i) * N + j] =
            float((column(e + 3, c, i) - column(e + 4, c, i)) / (2.0 * kTilt));
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
// Layout: magic, the key (length + bytes), N, seconds, photons, missed entries, then the arrays
// (count + values), and last the content hash of everything before it (geometry::contentHash, as
// the other caches: a truncated or edited file is rebuilt, not used).

namespace {

template <class T>
void put(std::string& out, const T& v) {
  out.append(reinterpret_cast<const char*>(&v), sizeof(T));
}
template <class T>
void putVector(std::string& out, const std::vector<T>& v) {
  put(out, uint64_t(v.size()));
  out.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
}

// Reads the file's fields in order; every read past the end throws naming the file.
class Reader {
 public:
  Reader(std::string_view bytes, const std::filesystem::path& path) : bytes_(bytes), path_(path) {}
  template <class T>
  T get() {
    T v{};
    std::memcpy(&v, take(sizeof(T)).data(), sizeof(T));
    return v;
  }
  template <class T>
  std::vector<T> getVector(uint64_t expected) {
    const auto n = get<uint64_t>();
    if (n != expected)
      throw std::runtime_error(fmt::format("{}: an array of {} values where {} were expected",
                                           path_.string(), n, expected));
    std::vector<T> v(n);
    if (n > 0) std::memcpy(v.data(), take(n * sizeof(T)).data(), n * sizeof(T));
    return v;
  }
  std::string_view take(uint64_t n) {
    if (n > bytes_.size() - pos_)
      throw std::runtime_error(fmt::format("{}: truncated transfer operator", path_.string()));
    const std::string_view out = bytes_.substr(pos_, n);
    pos_ += n;
    return out;
  }

 private:
  std::string_view bytes_;
  const std::filesystem::path& path_;
  size_t pos_ = 0;
};

}  // namespace

void writeTransferOperator(const TransferOperator& op, const std::string& key,
                           const std::filesystem::path& path) {
  std::string out(kMagic, sizeof(kMagic));
  put(out, uint64_t(key.size()));
  out += key;
  put(out, uint64_t(op.nodes));
  put(out, uint64_t(op.matrices));
  put(out, op.seconds);
  put(out, op.photons);
  put(out, op.missedEntries);
  putVector(out, op.samplePositions);
  putVector(out, op.sampleNormals);
  putVector(out, op.positions);
  putVector(out, op.normals);
  putVector(out, op.tangents);
  putVector(out, op.areas);
  putVector(out, op.matrix);
  putVector(out, op.vertexNodes);
  putVector(out, op.vertexWeights);
  put(out, geometry::contentHash(out));
  if (const std::string why = geometry::writeFileAtomically(path, out); !why.empty())
    throw std::runtime_error(fmt::format("{}: {}", path.string(), why));
}

TransferOperator readTransferOperator(const std::filesystem::path& path, const std::string& key) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw std::runtime_error(fmt::format("{}: cannot be read", path.string()));
  std::ostringstream ss;
  ss << f.rdbuf();
  const std::string bytes = std::move(ss).str();
  if (bytes.size() < sizeof(kMagic) + sizeof(uint64_t) ||
      bytes.compare(0, sizeof(kMagic), kMagic, sizeof(kMagic)) != 0)
    throw std::runtime_error(fmt::format("{}: not a transfer operator", path.string()));
  const std::string_view body(bytes.data(), bytes.size() - sizeof(uint64_t));
  uint64_t stored = 0;
  std::memcpy(&stored, bytes.data() + body.size(), sizeof(stored));
  if (stored != geometry::contentHash(body))
    throw std::runtime_error(fmt::format("{}: truncated or altered transfer operator (its content "
                                         "hash does not match)", path.string()));
  Reader r(body, path);
  (void)r.take(sizeof(kMagic));
  if (r.take(r.get<uint64_t>()) != key)
    throw std::runtime_error(fmt::format("{}: made for another scene or settings", path.string()));
  TransferOperator op;
  op.nodes = r.get<uint64_t>();
  if (op.nodes == 0 || op.nodes > (1u << 16))
    throw std::runtime_error(fmt::format("{}: {} nodes", path.string(), op.nodes));
  op.matrices = r.get<uint64_t>();
  if (op.matrices != 1 && op.matrices != 3 && op.matrices != 5)
    throw std::runtime_error(fmt::format("{}: {} matrices", path.string(), op.matrices));
  op.seconds = r.get<double>();
  op.photons = r.get<uint64_t>();
  op.missedEntries = r.get<uint64_t>();
  op.samplePositions = r.getVector<glm::vec3>(op.nodes * kCellSamples);
  op.sampleNormals = r.getVector<glm::vec3>(op.nodes * kCellSamples);
  const uint64_t N = op.nodes;
  op.positions = r.getVector<glm::vec3>(N);
  op.normals = r.getVector<glm::vec3>(N);
  op.tangents = r.getVector<glm::vec3>(N);
  op.areas = r.getVector<float>(N);
  op.matrix = r.getVector<float>(3 * op.matrices * N * N);
  Reader peek = r;
  const auto vn = peek.get<uint64_t>();
  if (vn % kVertexNodes != 0)
    throw std::runtime_error(fmt::format("{}: corrupt vertex weights", path.string()));
  op.vertexNodes = r.getVector<uint32_t>(vn);
  op.vertexWeights = r.getVector<float>(vn);
  for (uint32_t i : op.vertexNodes)
    if (i >= N) throw std::runtime_error(fmt::format("{}: corrupt vertex weights", path.string()));
  return op;
}

CachedTransfer loadOrBuildTransferOperator(const geometry::TriangleMesh& mesh,
                                           const std::vector<glm::dvec3>& vertexNormals,
                                           const material::Material& material,
                                           const TransferOptions& options, const std::string& key,
                                           const std::filesystem::path& cacheDir,
                                           const reference::ProgressCallback& progress) {
  CachedTransfer out;
  out.file = cacheDir / fmt::format("transfer-{:016x}.bin", geometry::contentHash(key));
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
