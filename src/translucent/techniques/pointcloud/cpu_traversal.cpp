// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/techniques/pointcloud/cpu_traversal.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <glm/exponential.hpp>
#include <glm/geometric.hpp>

namespace translucent::pointcloud {
namespace desc = geometry::descriptor;

TraversalStats& TraversalStats::operator+=(const TraversalStats& o) {
  nodesVisited += o.nodesVisited;
  clusterEvaluations += o.clusterEvaluations;
  pointEvaluations += o.pointEvaluations;
  maxStack = std::max(maxStack, o.maxStack);
  return *this;
}

RgbKernel RgbKernel::fromTables(const std::array<bssrdf::ProfileTable, 3>& tables) {
  RgbKernel k;
  k.eval_ = [t = tables](double r) {
    return glm::dvec3(t[0].lookup(r), t[1].lookup(r), t[2].lookup(r));
  };
  return k;
}

RgbKernel RgbKernel::fromTable(const bssrdf::ProfileTable& table) {
  RgbKernel k;
  k.eval_ = [t = table](double r) { return glm::dvec3(t.lookup(r)); };
  return k;
}

RgbKernel RgbKernel::fromProfiles(const std::array<const bssrdf::RadialProfile*, 3>& profiles) {
  for (size_t c = 0; c < 3; ++c)
    if (profiles[c] == nullptr)
      throw std::invalid_argument(fmt::format("RgbKernel: the {} profile is null: expected three "
                                              "profiles", kChannelNames[c]));
  RgbKernel k;
  k.eval_ = [p = profiles](double r) { return glm::dvec3(p[0]->R(r), p[1]->R(r), p[2]->R(r)); };
  return k;
}

namespace {

// Squared distance from x to the box [lo, hi] (0 inside).
double distance2ToBox(const glm::dvec3& x, const glm::vec4& lo, const glm::vec4& hi) {
  const glm::dvec3 d = glm::max(glm::max(glm::dvec3(lo) - x, x - glm::dvec3(hi)), glm::dvec3(0.0));
  return glm::dot(d, d);
}

bool dark(const geometry::OctreeNode& n) {
  return n.powerArea.x == 0.0f && n.powerArea.y == 0.0f && n.powerArea.z == 0.0f;
}

}  // namespace

namespace {

// Algorithm 2 with the terms of a point (pointTerm(slot, r) · E_i A_i) and of a cluster
// (nodeTerm(node, r) · Φ_v).
template <class PointTerm, class NodeTerm>
glm::dvec3 traverse(const geometry::Octree& octree, const glm::dvec3& x, const PointTerm& pointTerm,
                    const NodeTerm& nodeTerm, const TraversalOptions& options,
                    TraversalStats* stats) {
  if (!(options.epsilon > 0.0) || !std::isfinite(options.epsilon))
    throw std::invalid_argument(fmt::format("epsilon is {}: expected a positive finite solid "
                                            "angle", options.epsilon));
  if (octree.nodeCount() == 0)
    throw geometry::OctreeError("radiant exitance on an empty octree: expected a built octree");
  if (octree.depth() > kMaxStack + 1)
    throw geometry::OctreeError(fmt::format("octree depth {}: expected at most {} for the "
                                            "traversal stack", octree.depth(), kMaxStack + 1));
  const auto& descriptors = octree.descriptors();
  const auto& nodes = octree.nodes();
  const auto& points = octree.points();
  const auto& irradiance = octree.pointIrradiance();
  const bool boxDistance = options.criterion == Criterion::BoundingBox;
  TraversalStats local;

  // subdivide(node): interior, lit, and Δω = A_v / d² >= ε.
  const auto subdivide = [&](uint32_t node) {
    if (desc::isLeaf(descriptors[node])) return false;
    const geometry::OctreeNode& n = nodes[node];
    if (dark(n)) return false;
    const double d2 = boxDistance ? distance2ToBox(x, n.lower, n.upper)
                                  : glm::dot(glm::dvec3(n.centroid) - x, glm::dvec3(n.centroid) - x);
    return double(n.powerArea.w) >= options.epsilon * d2;
  };
  // point contributions(node) / node contribution(node); a dark node adds exactly 0.
  glm::dvec3 radiance(0.0);
  const auto contribute = [&](uint32_t node) {
    const uint32_t d = descriptors[node];
    const geometry::OctreeNode& n = nodes[node];
    if (dark(n)) return;
    if (desc::isLeaf(d)) {
      for (uint32_t p = desc::index(d), e = p + desc::pointCount(d); p < e; ++p) {
        const glm::dvec3 pos(points[p].positionArea);
        const double r = glm::length(x - pos);
        radiance += pointTerm(p, r) * glm::dvec3(irradiance[p]) * double(points[p].positionArea.w);
        ++local.pointEvaluations;
      }
    } else {
      const double r = glm::length(x - glm::dvec3(n.centroid));
      radiance += nodeTerm(node, r) * glm::dvec3(n.powerArea);
      ++local.clusterEvaluations;
    }
  };

  // Algorithm 2.
  uint32_t stack[kMaxStack];
  uint32_t sp = 0;
  uint32_t node = 0, childnum = 0;
  for (;;) {
    ++local.nodesVisited;
    if (subdivide(node)) {
      // recurse(node, childnum): remember where we are, continue with the last child.
      if (node != 0) {
        stack[sp++] = packStackEntry(node, childnum);
        local.maxStack = std::max(local.maxStack, sp);
      }
      const uint32_t d = descriptors[node];
      childnum = desc::childCount(d) - 1;
      node = desc::index(d) + childnum;
      continue;
    }
    contribute(node);
    // next node(node, childnum): the previous sibling, or unrecurse (pop) and try again.
    for (;;) {
      if (childnum > 0) {
        --node;
        --childnum;
        break;
      }
      if (sp == 0) {
        if (stats != nullptr) *stats += local;
        return radiance;
      }
      const uint32_t entry = stack[--sp];
      node = entry >> 8;
      childnum = entry & 0xFFu;
    }
  }
}

}  // namespace

glm::dvec3 radiantExitance(const geometry::Octree& octree, const glm::dvec3& x,
                           const RgbKernel& kernel, const TraversalOptions& options,
                           TraversalStats* stats) {
  const auto term = [&kernel](uint32_t, double r) { return kernel(r); };
  return traverse(octree, x, term, term, options, stats);
}

glm::dvec3 radiantExitanceBruteForce(const geometry::PointCloud& cloud, const glm::dvec3& x,
                                     const RgbKernel& kernel) {
  if (!cloud.hasIrradiance() || cloud.irradiance.size() != cloud.size())
    throw geometry::PointCloudError("brute-force radiant exitance: the point cloud has no "
                                    "irradiance: expected one value per point");
  glm::dvec3 sum(0.0);
  for (size_t i = 0; i < cloud.size(); ++i) {
    const double r = glm::length(x - glm::dvec3(cloud.positions[i]));
    sum += kernel(r) * glm::dvec3(cloud.irradiance[i]) * double(cloud.areas[i]);
  }
  return sum;
}

// ---- heterogeneous -------------------------------------------------------------------------

namespace {

// (k, w) of Eq. 9 at r and, in the extrapolated tail (t = n r / r_s > n), what the tail needs:
// ln P = v_n + (t − n) (v_n − v_{n−1} + c) − l, c = 2 ln(n / (n − 1)), l = 2 ln(t / n) (the last
// segment of ln(r² P) extended; material/point_profiles.h). Beyond the cut: P = 0.
struct Segment {
  int k = 0;
  double w = 0.0;
  bool tail = false, cut = false;
  double c = 0.0, l = 0.0;
};
Segment segmentAt(int n, double radius, double r) {
  const double t = r / radius * n;
  Segment s;
  s.k = std::min(static_cast<int>(t), n - 1);
  s.w = t - s.k;
  s.tail = t > double(n);
  s.cut = t > material::kExtrapolationFactor * n;
  if (s.tail && n > 1) {
    s.c = 2.0 * std::log(double(n) / double(n - 1));
    s.l = 2.0 * std::log(t / double(n));
  }
  return s;
}

// ln P of one channel on a segment: the linear interpolation, or the tail (−∞ where its slope is
// >= 0 or beyond the cut).
double lnOnSegment(double a, double b, const Segment& s) {
  if (!s.tail) return a + s.w * (b - a);
  const double slope = b - a + s.c;
  if (s.cut || !(slope < 0.0)) return -std::numeric_limits<double>::infinity();
  return b + (s.w - 1.0) * slope - s.l;
}

glm::dvec3 lnOnSegment(const glm::vec4* nodes, const Segment& s) {
  const glm::vec4 a = nodes[s.k], b = nodes[s.k + 1];
  const auto ln = [&](float x, float y) {
    return lnOnSegment(static_cast<double>(x), static_cast<double>(y), s);
  };
  return {ln(a.x, b.x), ln(a.y, b.y), ln(a.z, b.z)};
}

void checkProfiles(const HeteroProfiles& p, const geometry::Octree& octree, bool needNodes) {
  if (p.segments < 1 || !(p.radius > 0.0))
    throw std::invalid_argument(fmt::format("heterogeneous profiles: {} segments, r_s {}: expected "
                                            ">= 1 and > 0", p.segments, p.radius));
  if (p.points.size() != p.stride() * octree.pointCount())
    throw std::invalid_argument(fmt::format("heterogeneous profiles: {} point nodes: expected {} "
                                            "((n + 1) per point)", p.points.size(),
                                            p.stride() * octree.pointCount()));
  if (needNodes && p.nodes.size() != p.stride() * octree.nodeCount())
    throw std::invalid_argument(fmt::format("heterogeneous profiles: {} node entries: expected {} "
                                            "(refitNodeProfiles)", p.nodes.size(),
                                            p.stride() * octree.nodeCount()));
}

}  // namespace

glm::dvec3 lnProfileAt(const glm::vec4* nodes, int segments, double radius, double r) {
  return lnOnSegment(nodes, segmentAt(segments, radius, r));
}

std::vector<glm::vec4> profileNodes(const material::PointProfiles& profiles, size_t p) {
  std::vector<glm::vec4> out(size_t(profiles.segments()) + 1);
  for (int k = 0; k <= profiles.segments(); ++k)
    for (int c = 0; c < 3; ++c) out[size_t(k)][c] = static_cast<float>(profiles.node(p, c, k));
  return out;
}

HeteroProfiles heteroProfiles(const geometry::Octree& octree, const material::PointProfiles& cloud) {
  const auto& order = octree.pointOrder();
  if (cloud.size() != order.size())
    throw std::invalid_argument(fmt::format("heterogeneous profiles: {} profiles for {} points: "
                                            "expected one per point", cloud.size(), order.size()));
  HeteroProfiles out;
  out.segments = cloud.segments();
  out.radius = cloud.radius();
  out.points.resize(out.stride() * order.size());
  for (size_t slot = 0; slot < order.size(); ++slot)
    for (int k = 0; k <= out.segments; ++k)
      for (int c = 0; c < 3; ++c)
        out.points[slot * out.stride() + size_t(k)][c] =
            static_cast<float>(cloud.node(order[slot], c, k));
  return out;
}

void refitNodeProfiles(const geometry::Octree& octree, HeteroProfiles& profiles) {
  checkProfiles(profiles, octree, false);
  const auto& descriptors = octree.descriptors();
  const auto& nodes = octree.nodes();
  const auto& points = octree.points();
  const auto& irradiance = octree.pointIrradiance();
  const size_t m = profiles.stride();
  profiles.nodes.assign(m * octree.nodeCount(), glm::vec4(0.0f));
  // Children have larger indices than their parent: the reverse order is bottom-up.
  std::vector<glm::dvec3> s(m), sa(m);
  for (size_t v = octree.nodeCount(); v-- > 0;) {
    const uint32_t d = descriptors[v];
    std::fill(s.begin(), s.end(), glm::dvec3(0.0));
    std::fill(sa.begin(), sa.end(), glm::dvec3(0.0));
    glm::dvec3 power(0.0);
    double area = 0.0;
    const auto add = [&](const glm::vec4* ln, const glm::dvec3& phi, double a) {
      power += phi;
      area += a;
      for (size_t k = 0; k < m; ++k) {
        const glm::dvec3 root = glm::exp(0.5 * glm::dvec3(ln[k]));
        s[k] += phi * root;
        sa[k] += a * root;
      }
    };
    if (desc::isLeaf(d)) {
      for (uint32_t p = desc::index(d), e = p + desc::pointCount(d); p < e; ++p) {
        const double a = static_cast<double>(points[p].positionArea.w);
        add(&profiles.points[p * m], glm::dvec3(irradiance[p]) * a, a);
      }
    } else {
      for (uint32_t c = desc::index(d), e = c + desc::childCount(d); c < e; ++c)
        add(&profiles.nodes[c * m], glm::dvec3(nodes[c].powerArea), static_cast<double>(nodes[c].powerArea.w));
    }
    for (size_t k = 0; k < m; ++k)
      for (int c = 0; c < 3; ++c) {
        const double mean = power[c] > 0.0 ? s[k][c] / power[c] : sa[k][c] / area;
        profiles.nodes[v * m + k][c] = static_cast<float>(
            mean > 0.0 ? std::max(2.0 * std::log(mean), material::kLnFloor) : material::kLnFloor);
      }
  }
}

std::vector<glm::vec4> shadingProfile(const geometry::TriangleMesh& mesh,
                                      const material::PointProfiles& vertices, uint32_t triangle,
                                      const glm::dvec3& x) {
  if (triangle >= mesh.triangleCount() || vertices.size() != mesh.vertexCount())
    throw std::invalid_argument(fmt::format("shading profile: triangle {} of {}, {} vertex profiles "
                                            "for {} vertices", triangle, mesh.triangleCount(),
                                            vertices.size(), mesh.vertexCount()));
  const glm::uvec3 t = mesh.triangles[triangle];
  const glm::dvec3 a = mesh.positions[t[0]], b = mesh.positions[t[1]], c = mesh.positions[t[2]];
  // Barycentrics of the projection of x onto the triangle's plane, clamped and renormalised.
  const glm::dvec3 e0 = b - a, e1 = c - a, e2 = x - a;
  const double d00 = glm::dot(e0, e0), d01 = glm::dot(e0, e1), d11 = glm::dot(e1, e1);
  const double d20 = glm::dot(e2, e0), d21 = glm::dot(e2, e1);
  const double den = d00 * d11 - d01 * d01;
  double v = den > 0.0 ? (d11 * d20 - d01 * d21) / den : 1.0 / 3.0;
  double w = den > 0.0 ? (d00 * d21 - d01 * d20) / den : 1.0 / 3.0;
  v = std::max(v, 0.0);
  w = std::max(w, 0.0);
  double u = std::max(1.0 - v - w, 0.0);
  const double sum = u + v + w;
  u /= sum;
  v /= sum;
  w /= sum;
  std::vector<glm::vec4> out(size_t(vertices.segments()) + 1);
  for (int k = 0; k <= vertices.segments(); ++k)
    for (int ch = 0; ch < 3; ++ch)
      out[size_t(k)][ch] = static_cast<float>(u * vertices.node(t[0], ch, k) +
                                              v * vertices.node(t[1], ch, k) +
                                              w * vertices.node(t[2], ch, k));
  return out;
}

glm::dvec3 radiantExitance(const geometry::Octree& octree, const glm::dvec3& x,
                           const HeteroProfiles& profiles, std::span<const glm::vec4> shading,
                           const TraversalOptions& options, TraversalStats* stats) {
  checkProfiles(profiles, octree, true);
  if (shading.size() != profiles.stride())
    throw std::invalid_argument(fmt::format("shading profile of {} nodes: expected {}",
                                            shading.size(), profiles.stride()));
  const size_t m = profiles.stride();
  const int n = profiles.segments;
  const double rs = profiles.radius;
  const auto term = [&](const glm::vec4* source, double r) {
    const Segment seg = segmentAt(n, rs, r);
    return glm::exp(0.5 * (lnOnSegment(source, seg) + lnOnSegment(shading.data(), seg)));
  };
  const auto pointTerm = [&](uint32_t slot, double r) { return term(&profiles.points[slot * m], r); };
  const auto nodeTerm = [&](uint32_t node, double r) { return term(&profiles.nodes[node * m], r); };
  return traverse(octree, x, pointTerm, nodeTerm, options, stats);
}

glm::dvec3 radiantExitanceBruteForce(const geometry::PointCloud& cloud, const glm::dvec3& x,
                                     const material::PointProfiles& cloudProfiles,
                                     std::span<const glm::vec4> shading) {
  if (!cloud.hasIrradiance() || cloud.irradiance.size() != cloud.size())
    throw geometry::PointCloudError("brute-force radiant exitance: the point cloud has no "
                                    "irradiance: expected one value per point");
  if (cloudProfiles.size() != cloud.size() ||
      shading.size() != size_t(cloudProfiles.segments()) + 1)
    throw std::invalid_argument(fmt::format("brute-force Eq. 8: {} profiles for {} points, shading "
                                            "profile of {} nodes", cloudProfiles.size(),
                                            cloud.size(), shading.size()));
  const int n = cloudProfiles.segments();
  const double rs = cloudProfiles.radius();
  glm::dvec3 sum(0.0);
  for (size_t i = 0; i < cloud.size(); ++i) {
    const double r = glm::length(x - glm::dvec3(cloud.positions[i]));
    const Segment seg = segmentAt(n, rs, r);
    glm::dvec3 lnI;
    for (int c = 0; c < 3; ++c)
      lnI[c] = lnOnSegment(cloudProfiles.node(i, c, seg.k), cloudProfiles.node(i, c, seg.k + 1), seg);
    const glm::dvec3 kernel = glm::exp(0.5 * (lnI + lnOnSegment(shading.data(), seg)));
    sum += kernel * glm::dvec3(cloud.irradiance[i]) * double(cloud.areas[i]);
  }
  return sum;
}

}  // namespace translucent::pointcloud
