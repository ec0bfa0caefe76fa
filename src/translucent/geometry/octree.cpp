// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/geometry/octree.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>

#include <glm/common.hpp>

namespace translucent::geometry {

Octree::Octree(const PointCloud& cloud, const OctreeOptions& options) : options_(options) {
  if (options.maxLeafPoints < 1 || options.maxLeafPoints > descriptor::kMaxCount)
    throw OctreeError(fmt::format("maxLeafPoints is {}: expected 1 to {} (4-bit point count)",
                                  options.maxLeafPoints, descriptor::kMaxCount));
  if (options.maxDepth < 1 || options.maxDepth > 24)
    throw OctreeError(fmt::format("maxDepth is {}: expected 1 to 24", options.maxDepth));
  cloud.validate("octree input");
  const size_t n = cloud.size();
  if (n > descriptor::kMaxIndex)
    throw OctreeError(fmt::format("{} points: expected at most {} (24-bit descriptor indices)", n,
                                  descriptor::kMaxIndex));

  // Topology: recursive octant splits of the index array (the points stay where they are).
  order_.resize(n);
  std::iota(order_.begin(), order_.end(), 0u);
  std::vector<uint32_t> scratch(n);
  descriptors_.assign(1, 0u);
  build(0, 0, static_cast<uint32_t>(n), 0, cloud, scratch);
  if (descriptors_.size() > descriptor::kMaxIndex)
    throw OctreeError(fmt::format("{} nodes: expected at most {} (24-bit descriptor indices)",
                                  descriptors_.size(), descriptor::kMaxIndex));

  // Points in leaf order.
  points_.resize(n);
  for (size_t s = 0; s < n; ++s) {
    const uint32_t i = order_[s];
    points_[s].positionArea = glm::vec4(cloud.positions[i], cloud.areas[i]);
    points_[s].normal = glm::vec4(cloud.normals[i], 0.0f);
  }
  nodes_.assign(descriptors_.size(), OctreeNode{});
  computeBounds();
  if (cloud.hasIrradiance()) {
    refit(cloud.irradiance);
  } else {
    const std::vector<glm::vec3> zero(n, glm::vec3(0.0f));
    refit(zero);
  }
}

void Octree::build(uint32_t node, uint32_t begin, uint32_t end, uint32_t depth,
                   const PointCloud& cloud, std::vector<uint32_t>& scratch) {
  depth_ = std::max(depth_, depth);
  const uint32_t count = end - begin;
  if (count <= options_.maxLeafPoints) {
    descriptors_[node] = descriptor::pack(begin, 0, count);
    return;
  }

  // Groups of the set, as [start, end) runs of order_ (at most 8).
  std::array<uint32_t, 9> bounds{};
  uint32_t groups = 0;
  glm::dvec3 lo(std::numeric_limits<double>::max()), hi(std::numeric_limits<double>::lowest());
  for (uint32_t s = begin; s < end; ++s) {
    const glm::dvec3 p(cloud.positions[order_[s]]);
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  const bool separable = lo.x < hi.x || lo.y < hi.y || lo.z < hi.z;
  if (depth < options_.maxDepth && separable) {
    // Label each point with its octant about the box centre; counting sort by label (stable).
    const glm::dvec3 centre = 0.5 * (lo + hi);
    const auto label = [&](uint32_t i) {
      const glm::dvec3 p(cloud.positions[i]);
      return uint32_t(p.x >= centre.x) | uint32_t(p.y >= centre.y) << 1 |
             uint32_t(p.z >= centre.z) << 2;
    };
    std::array<uint32_t, 8> counts{};
    for (uint32_t s = begin; s < end; ++s) ++counts[label(order_[s])];
    std::array<uint32_t, 8> next{};
    uint32_t at = begin;
    for (uint32_t o = 0; o < 8; ++o) {
      next[o] = at;
      if (counts[o] > 0) bounds[groups++] = at;
      at += counts[o];
    }
    bounds[groups] = end;
    for (uint32_t s = begin; s < end; ++s) scratch[next[label(order_[s])]++] = order_[s];
    std::copy(scratch.begin() + begin, scratch.begin() + end, order_.begin() + begin);
  } else {
    // Coincident points (or the depth limit): up to 8 runs of (nearly) equal length.
    groups = std::min<uint32_t>(8, (count + options_.maxLeafPoints - 1) / options_.maxLeafPoints);
    for (uint32_t g = 0; g <= groups; ++g)
      bounds[g] = begin + static_cast<uint32_t>(uint64_t(count) * g / groups);
  }

  // Children in consecutive slots, allocated now, then built one after another.
  const auto first = static_cast<uint32_t>(descriptors_.size());
  if (uint64_t(first) + groups > descriptor::kMaxIndex)
    throw OctreeError(fmt::format("more than {} nodes: expected at most that many (24-bit "
                                  "descriptor indices)", descriptor::kMaxIndex));
  descriptors_.resize(first + groups, 0u);
  descriptors_[node] = descriptor::pack(first, groups, 0);
  for (uint32_t g = 0; g < groups; ++g)
    build(first + g, bounds[g], bounds[g + 1], depth + 1, cloud, scratch);
}

void Octree::computeBounds() {
  // Children have larger indices than their parents: one pass from the back is bottom-up.
  for (size_t v = descriptors_.size(); v-- > 0;) {
    const uint32_t d = descriptors_[v];
    glm::vec3 lo(std::numeric_limits<float>::max()), hi(std::numeric_limits<float>::lowest());
    if (descriptor::isLeaf(d)) {
      for (uint32_t s = descriptor::index(d), e = s + descriptor::pointCount(d); s < e; ++s) {
        const glm::vec3 p(points_[s].positionArea);
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
      }
    } else {
      for (uint32_t c = descriptor::index(d), e = c + descriptor::childCount(d); c < e; ++c) {
        lo = glm::min(lo, glm::vec3(nodes_[c].lower));
        hi = glm::max(hi, glm::vec3(nodes_[c].upper));
      }
    }
    nodes_[v].lower = glm::vec4(lo, 0.0f);
    nodes_[v].upper = glm::vec4(hi, 0.0f);
  }
}

void Octree::refit(std::span<const glm::vec3> irradiance) {
  const size_t n = points_.size();
  if (irradiance.size() != n)
    throw OctreeError(fmt::format("{} irradiance values for an octree of {} points: expected one "
                                  "per point", irradiance.size(), n));
  irradiance_.resize(n);
  for (size_t s = 0; s < n; ++s) {
    const glm::vec3& e = irradiance[order_[s]];
    if (!(e.x >= 0.0f && e.y >= 0.0f && e.z >= 0.0f) || !std::isfinite(e.x) ||
        !std::isfinite(e.y) || !std::isfinite(e.z))
      throw OctreeError(fmt::format("irradiance of point {} is ({}, {}, {}): expected finite "
                                    "non-negative values", order_[s], e.x, e.y, e.z));
    irradiance_[s] = glm::vec4(e, 0.0f);
  }

  // Double-precision sums per node, bottom-up; each node's float attributes from its own sums.
  struct Sums {
    glm::dvec3 power{0.0};     // Σ E_i A_i
    double area = 0.0;         // Σ A_i
    double weight = 0.0;       // Σ w_i
    glm::dvec3 weighted{0.0};  // Σ w_i p_i
    glm::dvec3 areaPos{0.0};   // Σ A_i p_i
  };
  std::vector<Sums> sums(descriptors_.size());
  for (size_t v = descriptors_.size(); v-- > 0;) {
    const uint32_t d = descriptors_[v];
    Sums& s = sums[v];
    if (descriptor::isLeaf(d)) {
      for (uint32_t p = descriptor::index(d), e = p + descriptor::pointCount(d); p < e; ++p) {
        const glm::dvec3 pos(points_[p].positionArea);
        const double a = static_cast<double>(points_[p].positionArea.w);
        const glm::dvec3 power = glm::dvec3(irradiance_[p]) * a;
        const double w = (power.x + power.y + power.z) / 3.0;
        s.power += power;
        s.area += a;
        s.weight += w;
        s.weighted += w * pos;
        s.areaPos += a * pos;
      }
    } else {
      for (uint32_t c = descriptor::index(d), e = c + descriptor::childCount(d); c < e; ++c) {
        s.power += sums[c].power;
        s.area += sums[c].area;
        s.weight += sums[c].weight;
        s.weighted += sums[c].weighted;
        s.areaPos += sums[c].areaPos;
      }
    }
    const glm::dvec3 centroid = s.weight > 0.0 ? s.weighted / s.weight : s.areaPos / s.area;
    nodes_[v].powerArea = glm::vec4(glm::vec3(s.power), static_cast<float>(s.area));
    nodes_[v].centroid = glm::vec4(glm::vec3(centroid), 0.0f);
  }
}

size_t Octree::leafCount() const {
  return static_cast<size_t>(
      std::count_if(descriptors_.begin(), descriptors_.end(), descriptor::isLeaf));
}

}  // namespace translucent::geometry
