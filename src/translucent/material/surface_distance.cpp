// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/material/surface_distance.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "translucent/optics/medium.h"

namespace translucent::material {

glm::dvec3 closestPointOnTriangle(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b,
                                  const glm::dvec3& c) {
  const glm::dvec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0) return a;
  const glm::dvec3 bp = p - b;
  const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= 0.0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return a + (d1 / (d1 - d3)) * ab;
  const glm::dvec3 cp = p - c;
  const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0.0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return a + (d2 / (d2 - d6)) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0)
    return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

SurfaceDistance::SurfaceDistance(std::vector<glm::dvec3> positions,
                                 const std::vector<glm::uvec3>& triangles) {
  if (triangles.empty()) throw ParameterError("surface distance: the mesh has no triangles");
  tris_.reserve(triangles.size());
  for (const glm::uvec3& t : triangles)
    tris_.push_back({positions.at(t.x), positions.at(t.y), positions.at(t.z)});
  nodes_.reserve(2 * tris_.size());
  build(0, static_cast<uint32_t>(tris_.size()));
}

uint32_t SurfaceDistance::build(uint32_t first, uint32_t count) {
  const auto index = static_cast<uint32_t>(nodes_.size());
  nodes_.push_back({});
  glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-lo);
  glm::dvec3 clo = lo, chi = hi;  // bounds of the centroids
  for (uint32_t i = first; i < first + count; ++i) {
    const Tri& t = tris_[i];
    lo = glm::min(lo, glm::min(t.a, glm::min(t.b, t.c)));
    hi = glm::max(hi, glm::max(t.a, glm::max(t.b, t.c)));
    const glm::dvec3 m = (t.a + t.b + t.c) / 3.0;
    clo = glm::min(clo, m);
    chi = glm::max(chi, m);
  }
  nodes_[index].lo = lo;
  nodes_[index].hi = hi;
  if (count <= 4) {
    nodes_[index].first = first;
    nodes_[index].count = count;
    return index;
  }
  // Median split along the longest axis of the centroids.
  const glm::dvec3 e = chi - clo;
  const int axis = e.x >= e.y && e.x >= e.z ? 0 : (e.y >= e.z ? 1 : 2);
  const uint32_t mid = first + count / 2;
  std::nth_element(tris_.begin() + first, tris_.begin() + mid, tris_.begin() + first + count,
                   [axis](const Tri& u, const Tri& v) {
                     return u.a[axis] + u.b[axis] + u.c[axis] < v.a[axis] + v.b[axis] + v.c[axis];
                   });
  const uint32_t left = build(first, mid - first);
  const uint32_t right = build(mid, first + count - mid);
  nodes_[index].left = left;
  nodes_[index].right = right;
  return index;
}

namespace {
double boxDistance2(const glm::dvec3& q, const glm::dvec3& lo, const glm::dvec3& hi) {
  const glm::dvec3 d = glm::max(glm::max(lo - q, q - hi), glm::dvec3(0.0));
  return glm::dot(d, d);
}
}  // namespace

double SurfaceDistance::distance(const glm::dvec3& q) const {
  double best = std::numeric_limits<double>::infinity();
  uint32_t stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& n = nodes_[stack[--top]];
    if (boxDistance2(q, n.lo, n.hi) >= best) continue;
    if (n.count > 0) {
      for (uint32_t i = n.first; i < n.first + n.count; ++i) {
        const Tri& t = tris_[i];
        const glm::dvec3 d = closestPointOnTriangle(q, t.a, t.b, t.c) - q;
        best = std::min(best, glm::dot(d, d));
      }
      continue;
    }
    // Nearer child last, so that it is visited first.
    const Node& l = nodes_[n.left];
    const Node& r = nodes_[n.right];
    const double dl = boxDistance2(q, l.lo, l.hi), dr = boxDistance2(q, r.lo, r.hi);
    if (dl < dr) {
      stack[top++] = n.right;
      stack[top++] = n.left;
    } else {
      stack[top++] = n.left;
      stack[top++] = n.right;
    }
  }
  return std::sqrt(best);
}

}  // namespace translucent::material
