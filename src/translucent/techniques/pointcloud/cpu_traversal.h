// SPDX-License-Identifier: GPL-3.0-or-later
// Hierarchical evaluation of the multiple-scattering term on a point cloud (seed 2.6.4 "Second
// Pass", 3.3.3 and Algorithm 2; Jensen & Buhler 2002): the CPU reference ("oracle") of the GPU
// traversal.
//
// Computes the radiant exitance due to subsurface transport at a surface point x_o,
//     B(x_o) = Σ_c Rd(|x_o - x_c|) Φ_c,      Φ_c = E_c A_c   [W / scene unit²], per RGB channel,
// where c runs over single points (x_c = p_i, Φ_c = E_i A_i) and clusters (octree nodes:
// x_c = P_v, Φ_c = Φ_v; geometry/octree.h), and Rd(r) is the radial diffuse reflectance profile
// R(r) [1 / scene unit²] of each channel (bssrdf/profile.h). The exit radiance is B times the
// exit Fresnel factor over π; that belongs to the renderer.
//
// Traversal (Algorithm 2, stack-bounded, no recursion), starting at the root:
//   - a node is *subdivided* iff it is interior, it carries power (Φ_v ≠ 0; a dark node adds 0
//     whatever is done with it) and its solid angle is not small enough:
//         A_v >= ε d²            (Δω = A_v / d² >= ε, Eq. 2.40, written without a division)
//     with d the distance from x_o to the node's bounding box (0 inside it: the seed's
//     conservative fix, default) or, as in Jensen & Buhler, to its centroid P_v;
//   - a leaf that is not subdivided sums its points; an interior node adds Rd(|x_o - P_v|) Φ_v.
//   Children are visited from the last to the first (the seed's `node ← last child`,
//   `node ← node - 1`). A stack entry packs (node index << 8 | remaining sibling count), one
//   32-bit word per level; the root is never pushed. Algorithm 2 as printed re-tests the popped
//   node; the popped node has been handled already, so we advance to its previous sibling
//   (popping again when it was the first).
//
// Arithmetic: node and point data are the float values of the octree's upload arrays; distances,
// kernel values and sums are in double, in traversal order. A float GPU implementation of the
// same order differs only by float rounding (relative ~1e-6 per term).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "translucent/bssrdf/profile.h"
#include "translucent/bssrdf/profile_table.h"
#include "translucent/geometry/mesh.h"
#include "translucent/geometry/octree.h"
#include "translucent/geometry/point_cloud.h"
#include "translucent/material/point_profiles.h"

namespace translucent::pointcloud {

// Default ε of the solid-angle criterion with the bounding-box distance. Study (BENCHMARKS.md of commit 91fe617,
// "Point cloud"; bench_pointcloud BM_EpsilonStudy): relative RMS error of B against the brute-
// force sum at 150 surface points of the bunny (30k points, lit by a directional light), for the
// dipole of Marble, Skin1, Ketchup and Skimmilk at 20-50 mm per unit. The error grows about
// linearly with ε; ε = 0.1 is the largest value of the grid 0.02, 0.05, 0.1, 0.2, 0.5, 1, 2 whose
// worst case (Ketchup red, 0.35%) leaves a 3x margin to the 1% budget, at 19x fewer evaluations
// than brute force for 30k points (more for more points: the work grows about as log N).
inline constexpr double kDefaultEpsilon = 0.1;

enum class Criterion {
  BoundingBox,  // d = distance to the node's bounding box (seed 2.6.4's conservative fix)
  Centroid,     // d = |x_o - P_v| (Jensen & Buhler 2002, Eq. 2.40 as printed)
};

struct TraversalOptions {
  double epsilon = kDefaultEpsilon;  // maximum solid angle Δω of a cluster [sr], > 0
  Criterion criterion = Criterion::BoundingBox;
};

// Work done by one evaluation.
struct TraversalStats {
  uint64_t nodesVisited = 0;        // descriptors read (each tested once)
  uint64_t clusterEvaluations = 0;  // interior nodes evaluated as one point
  uint64_t pointEvaluations = 0;    // single points summed in leaves
  uint32_t maxStack = 0;            // deepest stack used
  TraversalStats& operator+=(const TraversalStats& o);
};

// Rd(r) per RGB channel [1 / scene unit²], r in scene units.
class RgbKernel {
 public:
  // Linear interpolation of three tables (bssrdf::ProfileTable::lookup; copied, 0 beyond r_max).
  static RgbKernel fromTables(const std::array<bssrdf::ProfileTable, 3>& tables);
  // One table for all three channels.
  static RgbKernel fromTable(const bssrdf::ProfileTable& table);
  // Exact R(r) of three profiles (not owned: they must outlive the kernel).
  static RgbKernel fromProfiles(const std::array<const bssrdf::RadialProfile*, 3>& profiles);

  glm::dvec3 operator()(double r) const { return eval_(r); }

 private:
  std::function<glm::dvec3(double)> eval_;
};

// Stack size of the CPU traversal; octrees deeper than kMaxStack + 1 are rejected.
inline constexpr uint32_t kMaxStack = 64;
constexpr uint32_t packStackEntry(uint32_t node, uint32_t childnum) { return node << 8 | childnum; }

// B(x_o) by Algorithm 2. Throws geometry::OctreeError for an empty octree or one too deep, and
// std::invalid_argument for ε <= 0 or not finite.
glm::dvec3 radiantExitance(const geometry::Octree& octree, const glm::dvec3& x,
                           const RgbKernel& kernel, const TraversalOptions& options = {},
                           TraversalStats* stats = nullptr);

// B(x_o) = Σ_i Rd(|x_o - p_i|) E_i A_i over every point of the cloud (in index order), from the
// PointCloud itself, independently of the octree. Throws geometry::PointCloudError when the
// cloud has no irradiance.
glm::dvec3 radiantExitanceBruteForce(const geometry::PointCloud& cloud, const glm::dvec3& x,
                                     const RgbKernel& kernel);

// ---- Heterogeneous materials (SubEdit Eqs. 8-9; material/point_profiles.h) -------------------
//
// With a spatially varying material every point p_i carries its own profile P_i (n + 1 nodes of
// ln P per channel on [0, r_s]) and the shading point x_o its own P_o, and a term of B is Eq. 8:
//     R(x_o, x_c) = sqrt(P_c(r) P_o(r)) = exp((ln P_c(r) + ln P_o(r)) / 2),  r = |x_o − x_c|.
// Both profiles share the grid, so one (k, w) per term serves both (lnAt below; the GPU's
// pcHeteroPoint and pcHeteroNode, shaders/pointcloud/hetero.glsl, are the same arithmetic in
// float).
//
// A cluster (octree node) v needs a representative P_v. We use the *power-weighted mean of
// sqrt P* of its points, per channel and node k:
//     sqrt(P_v^k) = Σ_i Φ_i sqrt(P_i^k) / Σ_i Φ_i        (Φ_i = E_i A_i; area weights where Σ Φ = 0)
// built bottom-up (a child's Φ and sqrt P_v stand for its points), stored as ln P_v^k. Why: the
// exact sum over the cluster is sqrt(P_o(r)) Σ_i Φ_i sqrt(P_i(r_i)); with the cluster's one
// distance r_i ≈ r (the approximation the homogeneous traversal already makes) it equals
// Φ_v sqrt(P_v(r)) exactly at every node r_k. The area-weighted mean of ln P (a geometric mean)
// is biased low where media mix and ignores where the light falls (a cluster straddling a lit
// and an unlit medium), and the profile of the mean medium needs the model on the GPU and is
// biased too (P is not linear in σ). Cost: the weights follow the irradiance, so the
// representatives are refit every frame with the power (refit.comp on the GPU).

// Per-point and per-node ln P nodes in the layout the GPU reads: (n + 1) vec4 per entry, xyz =
// ln P (RGB), w = 0; points in the octree's slot order (Octree::points()).
struct HeteroProfiles {
  int segments = material::kDefaultProfileSegments;  // n
  double radius = 0.0;                                // r_s [scene units]
  std::vector<glm::vec4> points;  // (n + 1) · octree.pointCount()
  std::vector<glm::vec4> nodes;   // (n + 1) · octree.nodeCount(), from refitNodeProfiles
  size_t stride() const { return size_t(segments) + 1; }
};

// The point profiles (indexed like the PointCloud the octree was built from) in slot order; the
// node representatives are left empty until refitNodeProfiles.
HeteroProfiles heteroProfiles(const geometry::Octree& octree, const material::PointProfiles& cloud);
// The node representatives (see above) from the octree's current irradiance (Octree::refit).
void refitNodeProfiles(const geometry::Octree& octree, HeteroProfiles& profiles);

// ln P at r of one profile (n + 1 float nodes, xyz = RGB): Eq. 9 with the extrapolation and the
// cut of material/point_profiles.h (−∞: P = 0).
glm::dvec3 lnProfileAt(const glm::vec4* nodes, int segments, double radius, double r);
// One profile (n + 1 nodes) as floats, from PointProfiles entry p.
std::vector<glm::vec4> profileNodes(const material::PointProfiles& profiles, size_t p);
// The shading point's profile on a triangle: the barycentric interpolation (of ln P) of its
// vertices' profiles (`vertices`: PointProfiles indexed like mesh.positions), at the point of the
// triangle's plane nearest to x (barycentrics clamped to the triangle) — what the GPU does from
// the G-buffer's triangle index.
std::vector<glm::vec4> shadingProfile(const geometry::TriangleMesh& mesh,
                                      const material::PointProfiles& vertices, uint32_t triangle,
                                      const glm::dvec3& x);

// B(x_o) with Eq. 8: Algorithm 2 as above, the kernel exp((ln P_c + ln P_o) / 2) with the
// shading point's profile `shading` (n + 1 nodes) and the points' and nodes' profiles.
// `profiles.nodes` must be refit (refitNodeProfiles) for the octree's irradiance.
glm::dvec3 radiantExitance(const geometry::Octree& octree, const glm::dvec3& x,
                           const HeteroProfiles& profiles, std::span<const glm::vec4> shading,
                           const TraversalOptions& options = {}, TraversalStats* stats = nullptr);
// The brute-force Eq. 8 sum over every point of the cloud (index order): Σ_i sqrt(P_i P_o) E_i A_i
// with the double nodes of `cloudProfiles` (indexed like the cloud).
glm::dvec3 radiantExitanceBruteForce(const geometry::PointCloud& cloud, const glm::dvec3& x,
                                     const material::PointProfiles& cloudProfiles,
                                     std::span<const glm::vec4> shading);

}  // namespace translucent::pointcloud
