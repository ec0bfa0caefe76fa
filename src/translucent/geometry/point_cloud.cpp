// SPDX-License-Identifier: GPL-3.0-or-later
// Surface sampling (random and Yuksel's sample elimination), uniformity statistics and the mesh
// content hash. PLY input/output and the cache are in point_cloud_io.cpp.
#include "translucent/geometry/point_cloud.h"

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <numbers>
#include <span>
#include <utility>

#include <glm/geometric.hpp>

#include "translucent/geometry/counter_rng.h"
#include "translucent/geometry/point_grid.h"

namespace translucent::geometry {
namespace {

// ---- Area-weighted samples ---------------------------------------------------------------
struct SurfaceSample {
  uint32_t face = 0;
  double b0 = 0.0, b1 = 0.0, b2 = 0.0;  // barycentric coordinates
  glm::dvec3 position{0.0};
};

class AreaSampler {
 public:
  explicit AreaSampler(const TriangleMesh& mesh) : mesh_(mesh) {
    cdf_.reserve(mesh.triangles.size());
    double sum = 0.0;
    for (size_t t = 0; t < mesh.triangles.size(); ++t) {
      sum += triangleArea(t);
      cdf_.push_back(sum);
    }
    area_ = sum;
  }
  double area() const { return area_; }

  // Candidate k: a triangle with probability ∝ its area, then a uniform point on it
  // (b0 = 1 - sqrt(u1), b1 = sqrt(u1)(1 - u2), b2 = sqrt(u1) u2; pbrt's SampleUniformTriangle).
  SurfaceSample draw(uint64_t seed, uint64_t k) const {
    CounterRng rng(seed, k);
    const double target = rng.uniform() * area_;
    const auto it = std::upper_bound(cdf_.begin(), cdf_.end(), target);
    SurfaceSample s;
    s.face = static_cast<uint32_t>(
        std::min<size_t>(static_cast<size_t>(it - cdf_.begin()), cdf_.size() - 1));
    const double su = std::sqrt(rng.uniform()), u2 = rng.uniform();
    s.b0 = 1.0 - su;
    s.b1 = su * (1.0 - u2);
    s.b2 = su * u2;
    const auto& t = mesh_.triangles[s.face];
    s.position = s.b0 * mesh_.positions[t.x] + s.b1 * mesh_.positions[t.y] +
                 s.b2 * mesh_.positions[t.z];
    return s;
  }

  glm::vec3 normal(const SurfaceSample& s) const {
    const auto& t = mesh_.triangles[s.face];
    const glm::dvec3 face = glm::cross(mesh_.positions[t.y] - mesh_.positions[t.x],
                                       mesh_.positions[t.z] - mesh_.positions[t.x]);
    glm::dvec3 n = face;
    if (!mesh_.normals.empty()) {
      n = s.b0 * mesh_.normals[t.x] + s.b1 * mesh_.normals[t.y] + s.b2 * mesh_.normals[t.z];
      // Opposing vertex normals can cancel; the face normal is the only sensible answer then.
      if (!(glm::length(n) > 1e-12)) n = face;
    }
    return glm::vec3(glm::normalize(n));
  }

 private:
  double triangleArea(size_t i) const {
    const auto& t = mesh_.triangles[i];
    return 0.5 * glm::length(glm::cross(mesh_.positions[t.y] - mesh_.positions[t.x],
                                        mesh_.positions[t.z] - mesh_.positions[t.x]));
  }

  const TriangleMesh& mesh_;
  std::vector<double> cdf_;  // inclusive prefix sums of triangle areas
  double area_ = 0.0;
};

double distance2(const glm::vec3& a, const glm::vec3& b) {
  const glm::dvec3 d = glm::dvec3(a) - glm::dvec3(b);
  return glm::dot(d, d);
}

// ---- Sample elimination (Yuksel 2015) ------------------------------------------------------
// Returns the indices (ascending) of the `keep` candidates that survive.
std::vector<uint32_t> eliminate(std::span<const glm::vec3> candidates, size_t keep, double area) {
  const size_t m = candidates.size();
  // Eq. 5 of Yuksel (2D): the largest radius N discs can have on area A.
  const double rMax = std::sqrt(area / (2.0 * std::sqrt(3.0) * double(keep)));
  const double dMax = 2.0 * rMax, dMax2 = dMax * dMax;
  // Weight limiting (Yuksel 2015, Sec. 3.3): distances below dMin count as dMin, so that a tight
  // cluster does not outweigh a candidate with many neighbours at moderate distance.
  const double dMin = dMax * 0.65 * (1.0 - std::pow(double(keep) / double(m), 1.5));
  const auto weight = [&](double d2) {
    const double x = 1.0 - std::max(std::sqrt(d2), dMin) / dMax;  // α = 8
    const double x2 = x * x, x4 = x2 * x2;
    return x4 * x4;
  };

  // Everything below is indexed by grid slot: neighbours are then close in memory. The
  // neighbour lists (within dMax) are kept, so the serial elimination never searches the grid.
  // Fixed chunks of slots each fill their own list; the concatenation is in chunk order, so the
  // result does not depend on the scheduling.
  const PointGrid grid(candidates, dMax);
  std::vector<double> w(m, 0.0);
  constexpr size_t kChunk = 4096;
  const size_t chunks = (m + kChunk - 1) / kChunk;
  std::vector<std::vector<uint32_t>> lists(chunks);
  std::vector<uint64_t> first(m + 1, 0);
  tbb::parallel_for(size_t(0), chunks, [&](size_t chunk) {
    std::vector<uint32_t>& list = lists[chunk];
    for (size_t i = chunk * kChunk; i < std::min(m, (chunk + 1) * kChunk); ++i) {
      const glm::vec3& p = grid.position(static_cast<uint32_t>(i));
      const size_t before = list.size();
      double sum = 0.0;
      grid.forEachNear(p, [&](uint32_t j) {
        const double d2 = distance2(p, grid.position(j));
        if (j != i && d2 < dMax2) {
          sum += weight(d2);
          list.push_back(j);
        }
      });
      w[i] = sum;
      first[i + 1] = list.size() - before;
    }
  });
  for (size_t i = 0; i < m; ++i) first[i + 1] += first[i];
  std::vector<uint32_t> neighbours(first[m]);
  tbb::parallel_for(size_t(0), chunks, [&](size_t chunk) {
    std::copy(lists[chunk].begin(), lists[chunk].end(),
              neighbours.begin() + static_cast<std::ptrdiff_t>(first[chunk * kChunk]));
    std::vector<uint32_t>().swap(lists[chunk]);
  });

  // Indexed 4-ary max-heap on (weight, slot), ties broken by slot so the order is total. The
  // weights live in the entries, so sifting compares adjacent memory; 4-ary halves the levels
  // of a binary heap and a node's children share cache lines. (The elimination itself is
  // inherently serial: each removal changes the weights that choose the next one.)
  struct Entry {
    double w;
    uint32_t id;
  };
  const auto above = [](const Entry& a, const Entry& b) {
    return a.w > b.w || (a.w == b.w && a.id > b.id);
  };
  std::vector<Entry> heap(m);
  std::vector<uint32_t> pos(m);
  for (size_t i = 0; i < m; ++i) {
    heap[i] = {w[i], static_cast<uint32_t>(i)};
    pos[i] = static_cast<uint32_t>(i);
  }
  std::vector<double>().swap(w);
  size_t size = m;
  const auto siftDown = [&](size_t h) {
    const Entry e = heap[h];
    for (;;) {
      const size_t c0 = 4 * h + 1;
      if (c0 >= size) break;
      size_t best = c0;
      for (size_t c = c0 + 1; c < std::min(c0 + 4, size); ++c)
        if (above(heap[c], heap[best])) best = c;
      if (!above(heap[best], e)) break;
      heap[h] = heap[best];
      pos[heap[h].id] = static_cast<uint32_t>(h);
      h = best;
    }
    heap[h] = e;
    pos[e.id] = static_cast<uint32_t>(h);
  };
  for (size_t h = m / 4 + 1; h-- > 0;) siftDown(h);

  // Remove the heaviest candidate until `keep` remain; its neighbours lose its contribution
  // (weights only decrease: sift down).
  std::vector<char> removed(m, 0);
  while (size > keep) {
    const uint32_t top = heap[0].id;
    removed[top] = 1;
    heap[0] = heap[--size];
    if (size > 0) siftDown(0);
    const glm::vec3& p = grid.position(top);
    for (uint64_t k = first[top]; k < first[top + 1]; ++k) {
      const uint32_t j = neighbours[k];
      if (removed[j]) continue;
      heap[pos[j]].w -= weight(distance2(p, grid.position(j)));
      siftDown(pos[j]);
    }
  }

  std::vector<uint32_t> kept;
  kept.reserve(keep);
  for (uint32_t s = 0; s < m; ++s)
    if (!removed[s]) kept.push_back(grid.index(s));
  std::sort(kept.begin(), kept.end());
  return kept;
}

}  // namespace

// ---- PointCloud ----------------------------------------------------------------------------
double PointCloud::totalArea() const {
  double sum = 0.0;
  for (float a : areas) sum += double(a);
  return sum;
}

void PointCloud::validate(const std::string& what) const {
  const size_t n = positions.size();
  if (n == 0) throw PointCloudError(fmt::format("{}: the point cloud is empty: expected points", what));
  if (normals.size() != n)
    throw PointCloudError(fmt::format("{}: {} normals for {} points: expected one per point",
                                      what, normals.size(), n));
  if (areas.size() != n)
    throw PointCloudError(fmt::format("{}: {} areas for {} points: expected one per point", what,
                                      areas.size(), n));
  if (!faces.empty() && faces.size() != n)
    throw PointCloudError(fmt::format("{}: {} face indices for {} points: expected none or one "
                                      "per point", what, faces.size(), n));
  if (!irradiance.empty() && irradiance.size() != n)
    throw PointCloudError(fmt::format("{}: {} irradiance values for {} points: expected none or "
                                      "one per point", what, irradiance.size(), n));
  for (size_t i = 0; i < n; ++i) {
    const auto& p = positions[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      throw PointCloudError(fmt::format("{}: point {} is at ({}, {}, {}): expected finite "
                                        "coordinates", what, i, p.x, p.y, p.z));
    const double len = glm::length(glm::dvec3(normals[i]));
    if (!(std::abs(len - 1.0) < 1e-3))
      throw PointCloudError(fmt::format("{}: normal {} has length {}: expected unit normals",
                                        what, i, len));
    if (!(areas[i] > 0.0f) || !std::isfinite(areas[i]))
      throw PointCloudError(fmt::format("{}: area {} is {}: expected a positive finite area", what,
                                        i, areas[i]));
    if (!irradiance.empty()) {
      const auto& e = irradiance[i];
      if (!(e.x >= 0.0f && e.y >= 0.0f && e.z >= 0.0f) || !std::isfinite(e.x) ||
          !std::isfinite(e.y) || !std::isfinite(e.z))
        throw PointCloudError(fmt::format("{}: irradiance {} is ({}, {}, {}): expected finite "
                                          "non-negative values", what, i, e.x, e.y, e.z));
    }
  }
}

const char* toString(SamplingMethod method) {
  return method == SamplingMethod::Random ? "random" : "elimination";
}

SamplingMethod parseSamplingMethod(const std::string& name) {
  if (name == "random") return SamplingMethod::Random;
  if (name == "elimination") return SamplingMethod::Elimination;
  throw PointCloudError(fmt::format("sampling method '{}' is unknown: expected 'random' or "
                                    "'elimination'", name));
}

// ---- Sampling ------------------------------------------------------------------------------
PointCloud samplePointCloud(const TriangleMesh& mesh, const SamplingOptions& options) {
  constexpr size_t kMaxCount = (size_t(1) << 24) - 1;
  if (options.count == 0 || options.count > kMaxCount)
    throw PointCloudError(fmt::format("point count is {}: expected 1 to {} (24-bit octree "
                                      "indices)", options.count, kMaxCount));
  if (!(options.oversampling >= 2.0 && options.oversampling <= 32.0))
    throw PointCloudError(fmt::format("oversampling is {}: expected 2 to 32 candidates per point",
                                      options.oversampling));
  mesh.validate("point cloud sampling");
  const AreaSampler sampler(mesh);
  const size_t n = options.count;

  // Step 1: which candidates become points.
  std::vector<uint32_t> chosen;
  if (options.method == SamplingMethod::Random) {
    chosen.resize(n);
    for (size_t i = 0; i < n; ++i) chosen[i] = static_cast<uint32_t>(i);
  } else {
    const size_t m = static_cast<size_t>(std::ceil(options.oversampling * double(n)));
    if (m > std::numeric_limits<uint32_t>::max())
      throw PointCloudError(fmt::format("{} candidates ({} points x oversampling {}): expected at "
                                        "most 2^32 - 1", m, n, options.oversampling));
    std::vector<glm::vec3> candidates(m);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, m), [&](const auto& r) {
      for (size_t k = r.begin(); k != r.end(); ++k)
        candidates[k] = glm::vec3(sampler.draw(options.seed, k).position);
    });
    chosen = eliminate(candidates, n, sampler.area());
  }

  // Step 2: the points, redrawn from their candidate index (cheaper than keeping all candidates).
  PointCloud cloud;
  cloud.positions.resize(n);
  cloud.normals.resize(n);
  cloud.faces.resize(n);
  cloud.areas.assign(n, static_cast<float>(sampler.area() / double(n)));
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n), [&](const auto& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      const SurfaceSample s = sampler.draw(options.seed, chosen[i]);
      cloud.positions[i] = glm::vec3(s.position);
      cloud.normals[i] = sampler.normal(s);
      cloud.faces[i] = s.face;
    }
  });
  return cloud;
}

// ---- Uniformity ----------------------------------------------------------------------------
NearestNeighbourStats nearestNeighbourStats(const PointCloud& cloud) {
  const size_t n = cloud.size();
  if (n < 2)
    throw PointCloudError(fmt::format("nearest-neighbour statistics of {} point(s): expected at "
                                      "least 2", n));
  double area = cloud.totalArea();
  if (!(area > 0.0)) area = 1.0;
  // Cells about the expected spacing; rings grow until the nearest point is provably found.
  const PointGrid grid(cloud.positions, std::sqrt(area / double(n)));
  const double cell = grid.cellSize();
  std::vector<double> nn(n);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n), [&](const auto& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      const auto slot = static_cast<uint32_t>(i);
      const glm::vec3& p = grid.position(slot);
      const glm::ivec3 c = grid.cellOf(p);
      double best2 = std::numeric_limits<double>::infinity();
      // After the rings 0..k of cells around p's cell, every point not yet seen is farther than
      // k cells. Past a few rings (an isolated point) a scan of all points is cheaper.
      constexpr int kMaxRing = 6;
      for (int k = 0; k <= kMaxRing; ++k) {
        for (int dz = -k; dz <= k; ++dz)
          for (int dy = -k; dy <= k; ++dy)
            for (int dx = -k; dx <= k; ++dx) {
              if (std::max({std::abs(dx), std::abs(dy), std::abs(dz)}) != k) continue;
              grid.forEachInCell(c + glm::ivec3(dx, dy, dz), [&](uint32_t j) {
                if (j != slot) best2 = std::min(best2, distance2(p, grid.position(j)));
              });
            }
        if (best2 <= double(k) * cell * double(k) * cell) break;
        if (k == kMaxRing)
          for (uint32_t j = 0; j < n; ++j)
            if (j != slot) best2 = std::min(best2, distance2(p, grid.position(j)));
      }
      nn[i] = std::sqrt(best2);  // in slot order: the statistics do not depend on the order
    }
  });
  NearestNeighbourStats s;
  s.min = std::numeric_limits<double>::infinity();
  double sum = 0.0;
  for (double d : nn) {
    sum += d;
    s.min = std::min(s.min, d);
    s.max = std::max(s.max, d);
  }
  s.mean = sum / double(n);
  double var = 0.0;
  for (double d : nn) var += (d - s.mean) * (d - s.mean);
  s.stddev = std::sqrt(var / double(n - 1));
  s.cv = s.mean > 0.0 ? s.stddev / s.mean : 0.0;
  return s;
}

// ---- Content hash --------------------------------------------------------------------------
uint64_t meshHash(const TriangleMesh& mesh) {
  uint64_t h = 0x243f6a8885a308d3ULL;  // π's fraction bits
  const auto add = [&h](uint64_t word) { h = std::rotl(h ^ mix64(word), 27) * 0x9e3779b97f4a7c15ULL + 0x632be59bd9b4e019ULL; };
  add(mesh.positions.size());
  add(mesh.triangles.size());
  add(mesh.normals.size());
  for (const auto& p : mesh.positions) {
    add(std::bit_cast<uint64_t>(p.x));
    add(std::bit_cast<uint64_t>(p.y));
    add(std::bit_cast<uint64_t>(p.z));
  }
  for (const auto& t : mesh.triangles) {
    add(t.x);
    add(t.y);
    add(t.z);
  }
  for (const auto& n : mesh.normals) {
    add(std::bit_cast<uint64_t>(n.x));
    add(std::bit_cast<uint64_t>(n.y));
    add(std::bit_cast<uint64_t>(n.z));
  }
  return h;
}

}  // namespace translucent::geometry
