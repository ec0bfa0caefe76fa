// SPDX-License-Identifier: GPL-3.0-or-later
// A uniform grid over a set of points, hashed: neighbour and nearest-point queries in 3D (the
// point sampler's elimination, nearest-neighbour statistics, and the subsurface transfer's exit
// bins and interpolation weights).
//
// The points are copied in cell order (cell key, then index: a total order, so the parallel sort
// is deterministic), and an open-addressing table maps a cell key to its run of slots. Callers
// work on slots, so neighbours are close in memory; memory is O(points) however thin the surface
// is inside its bounding box.
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "translucent/geometry/counter_rng.h"

namespace translucent::geometry {

// The points are copied in cell order (cell key, then index: a total order, so the parallel sort
// is deterministic), and an open-addressing table maps a cell key to its run of slots. Callers
// work on slots, so neighbours are close in memory; memory is O(points) however thin the surface
// is inside its bounding box.
class PointGrid {
 public:
  PointGrid(std::span<const glm::vec3> points, double cellSize) {
    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(std::numeric_limits<double>::lowest());
    for (const auto& p : points) {
      lo = glm::min(lo, glm::dvec3(p));
      hi = glm::max(hi, glm::dvec3(p));
    }
    origin_ = lo;
    // Keys hold 21 bits per axis; coarser cells only cost speed, never correctness, since
    // queries never look farther than the cells next to their own.
    const double extent = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
    cell_ = std::max(cellSize, extent / double(1u << 20));
    if (!(cell_ > 0.0)) cell_ = 1.0;  // all points coincide

    const size_t n = points.size();
    std::vector<std::pair<uint64_t, uint32_t>> entries(n);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n), [&](const auto& r) {
      for (size_t i = r.begin(); i != r.end(); ++i)
        entries[i] = {key(cellOf(points[i])), static_cast<uint32_t>(i)};
    });
    tbb::parallel_sort(entries.begin(), entries.end());
    index_.resize(n);
    position_.resize(n);
    size_t cells = 0;
    for (size_t s = 0; s < n; ++s) {
      index_[s] = entries[s].second;
      position_[s] = points[entries[s].second];
      if (s == 0 || entries[s].first != entries[s - 1].first) ++cells;
    }
    const size_t capacity = std::bit_ceil(std::max<size_t>(2 * cells, 16));
    table_.assign(capacity, Slot{});
    mask_ = capacity - 1;
    for (size_t i = 0; i < n;) {
      size_t j = i + 1;
      while (j < n && entries[j].first == entries[i].first) ++j;
      size_t h = mix64(entries[i].first) & mask_;
      while (table_[h].key != kEmpty) h = (h + 1) & mask_;
      table_[h] = {entries[i].first, static_cast<uint32_t>(i), static_cast<uint32_t>(j)};
      i = j;
    }
  }

  size_t size() const { return index_.size(); }
  double cellSize() const { return cell_; }
  const glm::vec3& position(uint32_t slot) const { return position_[slot]; }
  uint32_t index(uint32_t slot) const { return index_[slot]; }  // the point's input index

  glm::ivec3 cellOf(const glm::vec3& p) const {
    return glm::ivec3(glm::floor((glm::dvec3(p) - origin_) / cell_));
  }
  // Calls f(slot) for every point in cell c, in slot order.
  template <class F>
  void forEachInCell(const glm::ivec3& c, F&& f) const {
    constexpr int kLimit = 1 << 21;
    if (c.x < 0 || c.y < 0 || c.z < 0 || c.x >= kLimit || c.y >= kLimit || c.z >= kLimit) return;
    const uint64_t k = key(c);
    for (size_t h = mix64(k) & mask_; table_[h].key != kEmpty; h = (h + 1) & mask_) {
      if (table_[h].key != k) continue;
      for (uint32_t s = table_[h].begin; s < table_[h].end; ++s) f(s);
      return;
    }
  }
  // Every point in the 27 cells around p's cell, in a fixed order.
  template <class F>
  void forEachNear(const glm::vec3& p, F&& f) const {
    const glm::ivec3 c = cellOf(p);
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) forEachInCell(c + glm::ivec3(dx, dy, dz), f);
  }

  // The k points nearest to p (input indices, nearest first; ties by slot), at most size().
  // Rings of cells grow around p's cell until the k-th distance is provably found (every point
  // outside ring k is farther than k cells); past kMaxRing rings every point is scanned.
  std::vector<std::pair<double, uint32_t>> nearest(const glm::vec3& p, size_t k) const {
    std::vector<std::pair<double, uint32_t>> best;  // (squared distance, slot), sorted
    k = std::min(k, size());
    if (k == 0) return best;
    const auto consider = [&](uint32_t s) {
      const glm::dvec3 d = glm::dvec3(p) - glm::dvec3(position_[s]);
      const std::pair<double, uint32_t> e{glm::dot(d, d), s};
      if (best.size() == k && !(e < best.back())) return;
      best.insert(std::upper_bound(best.begin(), best.end(), e), e);
      if (best.size() > k) best.pop_back();
    };
    const glm::ivec3 c = cellOf(p);
    constexpr int kMaxRing = 8;
    for (int r = 0; r <= kMaxRing; ++r) {
      for (int dz = -r; dz <= r; ++dz)
        for (int dy = -r; dy <= r; ++dy)
          for (int dx = -r; dx <= r; ++dx)
            if (std::max({std::abs(dx), std::abs(dy), std::abs(dz)}) == r)
              forEachInCell(c + glm::ivec3(dx, dy, dz), consider);
      // p lies in its cell, so a point outside rings 0..r is more than r cells away.
      if (best.size() == k && best.back().first <= double(r) * cell_ * double(r) * cell_) break;
      if (r == kMaxRing) {
        best.clear();
        for (uint32_t s = 0; s < size(); ++s) consider(s);
      }
    }
    for (auto& e : best) e.second = index_[e.second];
    return best;
  }

 private:
  static constexpr uint64_t kEmpty = ~uint64_t(0);
  struct Slot {
    uint64_t key = kEmpty;
    uint32_t begin = 0, end = 0;
  };
  static uint64_t key(const glm::ivec3& c) {
    return (uint64_t(uint32_t(c.x)) << 42) | (uint64_t(uint32_t(c.y)) << 21) | uint64_t(uint32_t(c.z));
  }

  glm::dvec3 origin_{0.0};
  double cell_ = 1.0;
  std::vector<uint32_t> index_;
  std::vector<glm::vec3> position_;
  std::vector<Slot> table_;
  size_t mask_ = 0;
};

}  // namespace translucent::geometry
