// SPDX-License-Identifier: GPL-3.0-or-later
// Octree over a point cloud for hierarchical BSSRDF evaluation (seed 2.6.4 "Second Pass", 3.3.1
// construction, 3.3.3 layout; Jensen & Buhler 2002), in flat arrays ready to be uploaded as
// shader storage buffers.
//
// Construction (seed 3.3.1): starting from all points, the centre of the set's bounding box
// splits space into eight octants; every point gets its octant label in [0, 7]
// (bit 0: x >= centre.x, bit 1: y >= centre.y, bit 2: z >= centre.z) and the set is ordered by
// label with a stable counting sort; each non-empty octant becomes a child, subdivided again
// until a set holds at most `maxLeafPoints` points (8, as in the seed). The split point is the
// bounding-box centre, so every split of a set that is not a single location separates at least
// two octants. A set that is still too large at `maxDepth` (only possible for coincident points)
// is split into up to 8 consecutive runs instead, so the tree always ends.
//
// Layout (seed Fig. 3.4): nodes are numbered with the root at 0 and the children of a node in
// consecutive slots, allocated when the node is split (depth first), so a child's index is always
// greater than its parent's. Points are stored in leaf order: the points of a leaf, and indeed
// of every node (a depth-first order of the counting sorts), are consecutive, and
// `pointOrder()[slot]` is the point's index in the PointCloud.
//
// 32-bit child descriptor, one per node (seed Fig. 3.5):
//   bits  0..3   child count   (1..8 for an interior node, 0 for a leaf)
//   bits  4..7   point count   (1..15 for a leaf, 0 for an interior node)
//   bits  8..31  index         interior: descriptor index of the first child
//                              leaf: index in points() of the first point
// A node is a leaf iff its child count is 0. 24 index bits allow up to 2^24 - 1 nodes and
// points; 4 count bits allow up to 15 points per leaf.
//
// Node attributes (std430: four vec4 per node, 64 bytes):
//   powerArea.xyz  Φ_v = Σ E_i A_i, the power incident on the node's points (RGB) [W]
//   powerArea.w    A_v = Σ A_i, the node's area [scene units²]
//   centroid.xyz   P_v = Σ w_i p_i / Σ w_i with w_i = A_i (E_r + E_g + E_b) / 3, the irradiance-
//                  (power-) weighted position; the area-weighted position where Σ w_i = 0
//   lower.xyz, upper.xyz  bounding box of the node's points
// The seed keeps the "total irradiance"; we keep the power Σ E_i A_i because the contribution of
// a cluster is then Rd(|x_o - P_v|) Φ_v, exact in the number of points and their areas even
// when the areas differ (the mean irradiance is Φ_v / A_v).
//
// Irradiance changes every frame when lights move: refit() recomputes Φ_v and P_v bottom-up in
// O(nodes + points) without touching the topology or the bounding boxes.
#pragma once

#include <cstdint>
#include <span>
#include <stdexcept>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "translucent/geometry/point_cloud.h"

namespace translucent::geometry {

// Thrown for options out of range, point clouds the layout cannot hold, and irradiance arrays
// of the wrong size or with negative or non-finite values.
class OctreeError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The 32-bit child descriptor of Fig. 3.5 (see the layout above).
namespace descriptor {
inline constexpr uint32_t kIndexShift = 8;
inline constexpr uint32_t kMaxIndex = (1u << 24) - 1;
inline constexpr uint32_t kMaxCount = 15;
constexpr uint32_t pack(uint32_t index, uint32_t childCount, uint32_t pointCount) {
  return (index << kIndexShift) | ((pointCount & 0xFu) << 4) | (childCount & 0xFu);
}
constexpr uint32_t childCount(uint32_t d) { return d & 0xFu; }
constexpr uint32_t pointCount(uint32_t d) { return (d >> 4) & 0xFu; }
constexpr uint32_t index(uint32_t d) { return d >> kIndexShift; }
constexpr bool isLeaf(uint32_t d) { return childCount(d) == 0; }
}  // namespace descriptor

// One node's attributes, std430-compatible (every member a vec4).
struct alignas(16) OctreeNode {
  glm::vec4 powerArea{0.0f};  // xyz: Φ_v [W] (RGB); w: A_v [scene units²]
  glm::vec4 centroid{0.0f};   // xyz: P_v; w: 0
  glm::vec4 lower{0.0f};      // xyz: bounding box minimum; w: 0
  glm::vec4 upper{0.0f};      // xyz: bounding box maximum; w: 0
};
static_assert(sizeof(OctreeNode) == 64 && alignof(OctreeNode) == 16);

// One point, std430-compatible, in leaf order.
struct alignas(16) OctreePoint {
  glm::vec4 positionArea{0.0f};  // xyz: position; w: area A_i
  glm::vec4 normal{0.0f};        // xyz: unit normal; w: 0
};
static_assert(sizeof(OctreePoint) == 32 && alignof(OctreePoint) == 16);

struct OctreeOptions {
  uint32_t maxLeafPoints = 8;  // 1..15 (the descriptor's 4-bit point count)
  uint32_t maxDepth = 20;      // geometric subdivision levels, 1..24
};

class Octree {
 public:
  Octree() = default;
  // Builds the tree over `cloud` (which must pass validate()); the irradiance is the cloud's,
  // or zero when it has none. Throws OctreeError for options out of range or a cloud of more
  // than 2^24 - 1 points.
  explicit Octree(const PointCloud& cloud, const OctreeOptions& options = {});

  // New irradiance per point, indexed like the PointCloud given to the constructor
  // (E [W / scene unit²], RGB, finite and >= 0). Recomputes every node's Φ_v and P_v.
  void refit(std::span<const glm::vec3> irradiance);

  // Flat arrays for upload (and for the CPU traversal).
  const std::vector<uint32_t>& descriptors() const { return descriptors_; }
  const std::vector<OctreeNode>& nodes() const { return nodes_; }
  const std::vector<OctreePoint>& points() const { return points_; }
  const std::vector<glm::vec4>& pointIrradiance() const { return irradiance_; }  // xyz: E; w: 0
  const std::vector<uint32_t>& pointOrder() const { return order_; }  // slot -> cloud index

  size_t nodeCount() const { return descriptors_.size(); }
  size_t pointCount() const { return points_.size(); }
  size_t leafCount() const;
  // Depth of the deepest leaf (the root alone: 0). A stack-based traversal that does not push
  // the root (Algorithm 2) needs at most max(depth - 1, 0) entries.
  uint32_t depth() const { return depth_; }
  const OctreeOptions& options() const { return options_; }

 private:
  void build(uint32_t node, uint32_t begin, uint32_t end, uint32_t depth,
             const PointCloud& cloud, std::vector<uint32_t>& scratch);
  void computeBounds();

  OctreeOptions options_;
  std::vector<uint32_t> descriptors_;
  std::vector<OctreeNode> nodes_;
  std::vector<OctreePoint> points_;
  std::vector<glm::vec4> irradiance_;
  std::vector<uint32_t> order_;
  uint32_t depth_ = 0;
};

}  // namespace translucent::geometry
