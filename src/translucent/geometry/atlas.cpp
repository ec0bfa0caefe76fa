// SPDX-License-Identifier: GPL-3.0-or-later
// The surface atlas (atlas.h): chart growing, chart validation and splitting, packing, coverage
// and statistics. The chart maps themselves are CGAL's (atlas_parameterize.cpp); the cache is in
// atlas_io.cpp.
#include "translucent/geometry/atlas.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>
#include <numbers>
#include <numeric>
#include <queue>
#include <unordered_map>

#include <glm/geometric.hpp>

#include "translucent/geometry/atlas_chart.h"

namespace translucent::geometry {
namespace {

// <cmath>'s INFINITY is a float (clang's -Wdouble-promotion flags it in a double).
constexpr double kInf = std::numeric_limits<double>::infinity();

using glm::dvec2;
using glm::dvec3;

double cross2(const dvec2& a, const dvec2& b) { return a.x * b.y - a.y * b.x; }
double orient(const dvec2& a, const dvec2& b, const dvec2& c) { return cross2(b - a, c - a); }

double triangleArea3(const dvec3& a, const dvec3& b, const dvec3& c) {
  return 0.5 * glm::length(glm::cross(b - a, c - a));
}

// ---- Overlaps -------------------------------------------------------------------------------
// Interiors of two counter-clockwise triangles are disjoint iff one of the six edge lines
// separates them (separating axis theorem for convex polygons). Vertices shared by neighbours
// project exactly onto the shared edge's line, so neighbours in a chart are separated with no
// tolerance; `tol` absorbs rounding for coincident but separately stored vertices.
bool separatedByEdgeOf(const dvec2* a, const dvec2* b, double tol) {
  for (int e = 0; e < 3; ++e) {
    const dvec2& p = a[e];
    const dvec2& q = a[(e + 1) % 3];
    const double scale = tol * glm::dot(q - p, q - p);
    if (orient(p, q, b[0]) <= scale && orient(p, q, b[1]) <= scale && orient(p, q, b[2]) <= scale)
      return true;
  }
  return false;
}

bool interiorsOverlap(const dvec2* a, const dvec2* b) {
  constexpr double tol = 1e-9;
  return !separatedByEdgeOf(a, b, tol) && !separatedByEdgeOf(b, a, tol);
}

// Signed UV area (counter-clockwise positive) of the triangles of `corners` (3 per triangle).
double signedArea(const dvec2* c) { return 0.5 * orient(c[0], c[1], c[2]); }

// ---- Mesh topology for chart growing -------------------------------------------------------
struct Topology {
  std::vector<uint32_t> weld;                 // mesh vertex -> welded vertex (same position)
  uint32_t weldedCount = 0;
  std::vector<std::array<int32_t, 3>> across; // face, edge (v[e] -> v[e+1]) -> neighbour or -1
  std::vector<dvec3> normal, centroid;
  std::vector<double> area;
};

Topology buildTopology(const TriangleMesh& mesh) {
  Topology topo;
  // Weld by exact position: files repeat a vertex per normal or UV seam, and a chart must be
  // able to grow across such a seam.
  std::map<std::array<double, 3>, uint32_t> ids;
  topo.weld.assign(mesh.positions.size(), 0u);
  for (size_t i = 0; i < mesh.positions.size(); ++i) {
    const dvec3& p = mesh.positions[i];
    topo.weld[i] = ids.try_emplace({p.x, p.y, p.z}, static_cast<uint32_t>(ids.size())).first->second;
  }
  topo.weldedCount = static_cast<uint32_t>(ids.size());
  const size_t nf = mesh.triangles.size();
  topo.across.assign(nf, {-1, -1, -1});
  topo.normal.resize(nf);
  topo.centroid.resize(nf);
  topo.area.resize(nf);
  // Faces are neighbours across an edge used by exactly two faces in opposite directions
  // (manifold and consistently oriented); any other edge is a cut between charts.
  struct Use {
    uint32_t face;
    int edge;
    bool forward;
    int count;
  };
  std::unordered_map<uint64_t, std::array<Use, 2>> edges;
  std::unordered_map<uint64_t, int> counts;
  edges.reserve(3 * nf);
  counts.reserve(3 * nf);
  for (uint32_t f = 0; f < nf; ++f) {
    const glm::uvec3& t = mesh.triangles[f];
    const dvec3 &a = mesh.positions[t.x], &b = mesh.positions[t.y], &c = mesh.positions[t.z];
    const dvec3 n = glm::cross(b - a, c - a);
    topo.area[f] = 0.5 * glm::length(n);
    topo.normal[f] = glm::length(n) > 0.0 ? n / glm::length(n) : dvec3(0.0);
    topo.centroid[f] = (a + b + c) / 3.0;
    const uint32_t v[3] = {topo.weld[t.x], topo.weld[t.y], topo.weld[t.z]};
    for (int e = 0; e < 3; ++e) {
      const uint32_t p = v[e], q = v[(e + 1) % 3];
      const uint64_t key = (uint64_t{std::min(p, q)} << 32) | std::max(p, q);
      const int k = counts[key]++;
      if (k < 2) edges[key][static_cast<size_t>(k)] = Use{f, e, p < q, 0};
    }
  }
  for (const auto& [key, n] : counts) {
    if (n != 2) continue;
    const auto& u = edges[key];
    if (u[0].forward == u[1].forward || u[0].face == u[1].face) continue;
    topo.across[u[0].face][static_cast<size_t>(u[0].edge)] = static_cast<int32_t>(u[1].face);
    topo.across[u[1].face][static_cast<size_t>(u[1].edge)] = static_cast<int32_t>(u[0].face);
  }
  return topo;
}

// ---- Chart growing -------------------------------------------------------------------------
// Greedy region growing from seed faces (in face order), cheapest candidate first: the cost is
// the normal's deviation from the seed's plus the distance from the seed in units of the radius
// of a disc of the largest chart area, which keeps charts compact (round charts suit a circular
// boundary, and their maps distort less). A face joins only if the chart stays a topological
// disk: sharing one edge, its third vertex must be new; sharing two edges, it closes the fan at
// their common vertex; sharing three, it would close the surface.
class ChartGrower {
 public:
  explicit ChartGrower(const Topology& topo)
      : topo_(topo), label_(topo.area.size(), kNotAllowed), vertexMark_(topo.weldedCount, -1) {}

  // Charts covering `faces` (each face in exactly one).
  std::vector<std::vector<uint32_t>> grow(const TriangleMesh& mesh,
                                          const std::vector<uint32_t>& faces, double maxArea,
                                          double cosMax) {
    for (const uint32_t f : faces) label_[f] = kFree;
    std::vector<std::vector<uint32_t>> charts;
    const double r0 = std::sqrt(maxArea / std::numbers::pi);
    for (const uint32_t seed : faces) {
      if (label_[seed] != kFree) continue;
      const int32_t id = nextMark_++;
      std::vector<uint32_t> chart;
      dvec3 normalSum(0.0);
      double area = 0.0;
      using Candidate = std::pair<double, uint32_t>;
      std::priority_queue<Candidate, std::vector<Candidate>, std::greater<>> heap;
      const dvec3 seedNormal = topo_.normal[seed], seedCentre = topo_.centroid[seed];
      const auto accept = [&](uint32_t f) {
        label_[f] = id;
        chart.push_back(f);
        normalSum += topo_.area[f] * topo_.normal[f];
        area += topo_.area[f];
        const glm::uvec3& t = mesh.triangles[f];
        for (int k = 0; k < 3; ++k) vertexMark_[topo_.weld[t[k]]] = id;
        for (int e = 0; e < 3; ++e) {
          const int32_t g = topo_.across[f][static_cast<size_t>(e)];
          if (g >= 0 && label_[static_cast<size_t>(g)] == kFree) {
            const auto gf = static_cast<uint32_t>(g);
            const double cost = (1.0 - glm::dot(topo_.normal[gf], seedNormal)) +
                                glm::length(topo_.centroid[gf] - seedCentre) / r0;
            heap.emplace(cost, gf);
          }
        }
      };
      accept(seed);
      while (!heap.empty()) {
        const uint32_t f = heap.top().second;
        heap.pop();
        if (label_[f] != kFree) continue;
        const double len = glm::length(normalSum);
        if (len > 0.0 && glm::dot(topo_.normal[f], normalSum / len) < cosMax) continue;
        if (area + topo_.area[f] > maxArea) continue;
        // Round charts: a strip of the same area maps onto a circle with its ends squeezed.
        if (glm::length(topo_.centroid[f] - seedCentre) > 1.5 * r0) continue;
        if (!keepsDisk(mesh, f, id)) continue;
        accept(f);
      }
      charts.push_back(std::move(chart));
    }
    for (const auto& chart : charts)
      for (const uint32_t f : chart) label_[f] = kNotAllowed;
    return charts;
  }

 private:
  static constexpr int32_t kNotAllowed = -2, kFree = -1;

  bool keepsDisk(const TriangleMesh& mesh, uint32_t f, int32_t id) const {
    int shared = 0, sharedEdge = -1;
    for (int e = 0; e < 3; ++e) {
      const int32_t g = topo_.across[f][static_cast<size_t>(e)];
      if (g >= 0 && label_[static_cast<size_t>(g)] == id) {
        ++shared;
        sharedEdge = e;
      }
    }
    if (shared == 1) {
      const uint32_t apex = topo_.weld[mesh.triangles[f][(sharedEdge + 2) % 3]];
      return vertexMark_[apex] != id;
    }
    return shared == 2;
  }

  const Topology& topo_;
  std::vector<int32_t> label_;       // kNotAllowed, kFree, or the chart's mark
  std::vector<int32_t> vertexMark_;  // welded vertex -> mark of the last chart that used it
  int32_t nextMark_ = 0;
};

// A chart's own vertex numbering (welded vertices in first-use order) and triangles.
struct ChartMesh {
  std::vector<uint32_t> welded;      // chart vertex -> welded vertex
  std::vector<dvec3> positions;
  std::vector<glm::uvec3> triangles; // chart vertices, one per chart face (same order)
};

ChartMesh chartMesh(const TriangleMesh& mesh, const Topology& topo,
                    const std::vector<uint32_t>& faces) {
  ChartMesh cm;
  std::unordered_map<uint32_t, uint32_t> local;
  local.reserve(faces.size() * 2);
  for (const uint32_t f : faces) {
    glm::uvec3 t;
    for (int k = 0; k < 3; ++k) {
      const uint32_t vertex = mesh.triangles[f][k];
      const auto [it, added] =
          local.try_emplace(topo.weld[vertex], static_cast<uint32_t>(cm.welded.size()));
      if (added) {
        cm.welded.push_back(topo.weld[vertex]);
        cm.positions.push_back(mesh.positions[vertex]);
      }
      t[k] = it->second;
    }
    cm.triangles.push_back(t);
  }
  return cm;
}

// Euler characteristic V - E + F = 1 and one boundary loop: a topological disk.
bool isDisk(const ChartMesh& cm) {
  std::unordered_map<uint64_t, int> edges;
  std::unordered_map<uint32_t, int> boundaryDegree;
  for (const auto& t : cm.triangles)
    for (int e = 0; e < 3; ++e) {
      const uint32_t p = t[e], q = t[(e + 1) % 3];
      ++edges[(uint64_t{std::min(p, q)} << 32) | std::max(p, q)];
    }
  size_t boundaryEdges = 0;
  for (const auto& [key, n] : edges) {
    if (n > 2) return false;
    if (n == 1) {
      ++boundaryEdges;
      ++boundaryDegree[static_cast<uint32_t>(key >> 32)];
      ++boundaryDegree[static_cast<uint32_t>(key & 0xffffffffu)];
    }
  }
  const auto euler = static_cast<long long>(cm.positions.size()) -
                     static_cast<long long>(edges.size()) +
                     static_cast<long long>(cm.triangles.size());
  if (euler != 1 || boundaryEdges < 3) return false;
  // A boundary vertex on two boundary loops (a pinch) has degree 4; with every boundary vertex of
  // degree 2, the boundary is a union of loops: follow one and check that it uses every edge.
  for (const auto& [v, d] : boundaryDegree)
    if (d != 2) return false;
  std::unordered_map<uint32_t, uint32_t> next;
  for (const auto& t : cm.triangles)
    for (int e = 0; e < 3; ++e) {
      const uint32_t p = t[e], q = t[(e + 1) % 3];
      if (edges[(uint64_t{std::min(p, q)} << 32) | std::max(p, q)] == 1) next[p] = q;
    }
  const uint32_t start = next.begin()->first;
  uint32_t v = start;
  size_t loop = 0;
  do {
    const auto it = next.find(v);
    if (it == next.end()) return false;
    v = it->second;
    ++loop;
  } while (v != start && loop <= boundaryEdges);
  return loop == boundaryEdges;
}

// Checks a chart's map: finite, every triangle counter-clockwise with positive area, no two
// triangles overlapping (an LSCM boundary can run over itself). Mirrors a clockwise map first.
bool validChartMap(const ChartMesh& cm, std::vector<dvec2>& uv) {
  for (const dvec2& p : uv)
    if (!std::isfinite(p.x) || !std::isfinite(p.y)) return false;
  std::vector<dvec2> corners(3 * cm.triangles.size());
  double total = 0.0;
  for (size_t i = 0; i < cm.triangles.size(); ++i) {
    for (int k = 0; k < 3; ++k) corners[3 * i + static_cast<size_t>(k)] = uv[cm.triangles[i][k]];
    total += signedArea(&corners[3 * i]);
  }
  if (!(std::abs(total) > 0.0)) return false;
  if (total < 0.0) {
    for (dvec2& p : uv) p.x = -p.x;
    for (dvec2& p : corners) p.x = -p.x;
    total = -total;
  }
  // Positive with room to spare for the later float rounding of the packed UVs.
  const double minArea = 1e-12 * total;
  for (size_t i = 0; i < cm.triangles.size(); ++i)
    if (!(signedArea(&corners[3 * i]) > minArea)) return false;
  return countUVOverlaps(corners) == 0;
}

// A chart map distorts area too much when its triangles' area ratios, normalised over the chart,
// spread with an area-weighted RMS of ln above kMaxChartRms or reach a factor e^kMaxChartLog
// shrunk or enlarged anywhere: such a chart is split (Sander et al. 2001 split charts by
// stretch the same way). Shrunk triangles are the undersampled ones of seed Fig. 4.7a, and in a
// strongly shrunk region triangles cannot all own a texel.
constexpr double kMaxChartRms = 0.35, kMaxChartLog = 1.6;

bool tooDistorted(const ChartMesh& cm, const std::vector<dvec2>& uv) {
  double sumS = 0.0, sumT = 0.0;
  std::vector<double> aS(cm.triangles.size()), aT(cm.triangles.size());
  for (size_t i = 0; i < cm.triangles.size(); ++i) {
    const auto& t = cm.triangles[i];
    aS[i] = triangleArea3(cm.positions[t.x], cm.positions[t.y], cm.positions[t.z]);
    const dvec2 c[3] = {uv[t.x], uv[t.y], uv[t.z]};
    aT[i] = signedArea(c);
    sumS += aS[i];
    sumT += aT[i];
  }
  double m2 = 0.0;
  for (size_t i = 0; i < aS.size(); ++i) {
    const double d = std::log((aT[i] / sumT) / (aS[i] / sumS));
    if (std::abs(d) > kMaxChartLog) return true;
    m2 += aS[i] * d * d;
  }
  return std::sqrt(m2 / sumS) > kMaxChartRms;
}

// Isometric layout of one triangle, longest edge along +x, apex above (counter-clockwise).
std::array<dvec2, 3> layoutTriangle(const dvec3* p) {
  int base = 0;
  double longest = -1.0;
  for (int e = 0; e < 3; ++e) {
    const double l = glm::length(p[(e + 1) % 3] - p[e]);
    if (l > longest) {
      longest = l;
      base = e;
    }
  }
  const dvec3 a = p[base], b = p[(base + 1) % 3], c = p[(base + 2) % 3];
  const dvec3 x = (b - a) / longest;
  const double cx = glm::dot(c - a, x);
  const double cy = glm::length((c - a) - cx * x);
  std::array<dvec2, 3> uv;
  uv[static_cast<size_t>(base)] = {0.0, 0.0};
  uv[static_cast<size_t>((base + 1) % 3)] = {longest, 0.0};
  uv[static_cast<size_t>((base + 2) % 3)] = {cx, cy};
  return uv;
}

// ---- Packing ---------------------------------------------------------------------------------
// A chart ready to pack: its vertices in surface units (texel area ∝ surface area once a global
// scale ρ [texels per unit] is applied), rotated to its smallest bounding box and moved to the
// origin; bounding box width × height.
struct PackChart {
  std::vector<dvec2> uv;  // per chart vertex
  double width = 0.0, height = 0.0;
  dvec2 incentre{0.0};    // single-triangle charts: where a texel centre is put when needed
  bool single = false;
};

std::vector<dvec2> convexHull(std::vector<dvec2> p) {
  std::sort(p.begin(), p.end(), [](const dvec2& a, const dvec2& b) {
    return a.x < b.x || (a.x == b.x && a.y < b.y);
  });
  if (p.size() < 3) return p;
  std::vector<dvec2> h(2 * p.size());
  size_t k = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    while (k >= 2 && orient(h[k - 2], h[k - 1], p[i]) <= 0.0) --k;
    h[k++] = p[i];
  }
  for (size_t i = p.size() - 1, t = k + 1; i > 0; --i) {
    while (k >= t && orient(h[k - 2], h[k - 1], p[i - 1]) <= 0.0) --k;
    h[k++] = p[i - 1];
  }
  h.resize(k - 1);
  return h;
}

// Rotates to the minimum-area bounding rectangle (one of its sides is on a hull edge), with the
// longer side along x (shelves are then low), and moves the box to the origin.
void orientChart(std::vector<dvec2>& uv, double& width, double& height) {
  std::vector<dvec2> hull = convexHull(uv);
  double bestArea = std::numeric_limits<double>::infinity();
  dvec2 bestAxis(1.0, 0.0);
  // Hull edges; for very long hulls a subset is as good (the area varies smoothly with angle).
  const size_t stride = std::max<size_t>(1, hull.size() / 256);
  for (size_t i = 0; i < hull.size(); i += stride) {
    dvec2 axis = hull[(i + 1) % hull.size()] - hull[i];
    const double len = glm::length(axis);
    if (!(len > 0.0)) continue;
    axis /= len;
    double lo0 = kInf, hi0 = -kInf, lo1 = kInf, hi1 = -kInf;
    for (const dvec2& q : hull) {
      const double s = glm::dot(q, axis), t = cross2(axis, q);
      lo0 = std::min(lo0, s), hi0 = std::max(hi0, s), lo1 = std::min(lo1, t), hi1 = std::max(hi1, t);
    }
    const double a = (hi0 - lo0) * (hi1 - lo1);
    if (a < bestArea) {
      bestArea = a;
      bestAxis = (hi0 - lo0) >= (hi1 - lo1) ? axis : dvec2(-axis.y, axis.x);
    }
  }
  dvec2 lo(kInf), hi(-kInf);
  for (dvec2& q : uv) {
    q = dvec2(glm::dot(q, bestAxis), cross2(bestAxis, q));
    lo = glm::min(lo, q);
    hi = glm::max(hi, q);
  }
  for (dvec2& q : uv) q -= lo;
  width = hi.x - lo.x;
  height = hi.y - lo.y;
}

// Does the triangle, moved by `shift` (texels) with the scale ρ applied, contain a texel centre?
bool holdsTexelCentre(const std::array<dvec2, 3>& t, double rho, const dvec2& shift) {
  std::array<dvec2, 3> p;
  for (size_t k = 0; k < 3; ++k) p[k] = rho * t[k] + shift;
  const dvec2 lo = glm::min(glm::min(p[0], p[1]), p[2]), hi = glm::max(glm::max(p[0], p[1]), p[2]);
  for (double y = std::floor(lo.y - 0.5) + 0.5; y <= hi.y; y += 1.0)
    for (double x = std::floor(lo.x - 0.5) + 0.5; x <= hi.x; x += 1.0) {
      const dvec2 c(x, y);
      if (orient(p[0], p[1], c) > 0.0 && orient(p[1], p[2], c) > 0.0 && orient(p[2], p[0], c) > 0.0)
        return true;
    }
  return false;
}

struct Placement {
  dvec2 offset{0.0};  // texels: where the chart's origin goes
};

// Shelf packing of boxes ceil(ρ w + g) × ceil(ρ h + g), tallest first; the chart sits g/2 inside
// its box. Single triangles are shifted by a fraction of a texel so that their incentre lands on
// a texel centre when they would otherwise hold none (every triangle then owns a texel centre).
bool shelfPack(const std::vector<PackChart>& charts, const std::vector<std::array<dvec2, 3>>& tris,
               double rho, uint32_t size, uint32_t gutter, std::vector<Placement>* out) {
  const size_t n = charts.size();
  std::vector<uint32_t> w(n), h(n);
  // A fractional offset per chart from the R2 sequence (Roberts 2018): texel centres fall on a
  // chart as on a randomly placed one, so that a triangle owns A_T texels on average (a chart
  // edge on a row of centres would give its triangles a whole row too many or too few).
  std::vector<dvec2> shift(n);
  for (size_t i = 0; i < n; ++i) {
    const double k = static_cast<double>(i + 1);
    shift[i] = dvec2(0.5 * gutter) + dvec2(std::fmod(0.7548776662466927 * k, 1.0),
                                           std::fmod(0.5698402909980532 * k, 1.0));
    const PackChart& c = charts[i];
    if (c.single && !holdsTexelCentre(tris[i], rho, shift[i])) {
      const dvec2 at = rho * c.incentre + shift[i];
      shift[i] += dvec2(std::ceil(at.x - 0.5) + 0.5 - at.x, std::ceil(at.y - 0.5) + 0.5 - at.y);
    }
    const double bw = std::ceil(rho * c.width + shift[i].x + 0.5 * gutter);
    const double bh = std::ceil(rho * c.height + shift[i].y + 0.5 * gutter);
    if (bw > size || bh > size) return false;
    w[i] = static_cast<uint32_t>(bw);
    h[i] = static_cast<uint32_t>(bh);
  }
  std::vector<uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
    return h[a] != h[b] ? h[a] > h[b] : (w[a] != w[b] ? w[a] > w[b] : a < b);
  });
  uint64_t x = 0, y = 0, shelf = 0;
  if (out) out->assign(n, {});
  for (const uint32_t i : order) {
    if (x + w[i] > size) {
      y += shelf;
      x = 0;
      shelf = 0;
    }
    if (shelf == 0) shelf = h[i];
    if (y + h[i] > size) return false;
    if (out) (*out)[i].offset = dvec2(static_cast<double>(x), static_cast<double>(y)) + shift[i];
    x += w[i];
  }
  return true;
}

// The largest ρ (bisection) at which the charts fit.
double fitScale(const std::vector<PackChart>& charts,
                const std::vector<std::array<dvec2, 3>>& tris, double surfaceArea,
                uint32_t size, uint32_t gutter) {
  double hi = size / std::sqrt(surfaceArea);  // 100% utilisation: an upper bound
  double lo = 0.0;
  for (int it = 0; it < 48; ++it) {
    const double mid = 0.5 * (lo + hi);
    if (shelfPack(charts, tris, mid, size, gutter, nullptr))
      lo = mid;
    else
      hi = mid;
    if (hi - lo < 1e-4 * hi) break;
  }
  if (!(lo > 0.0) || !shelfPack(charts, tris, lo, size, gutter, nullptr))
    throw AtlasError(fmt::format(
        "atlas: {} charts do not fit into {}² texels with a {}-texel gutter: expected a larger "
        "--size", charts.size(), size, gutter));
  return lo;
}

}  // namespace

void detail::computeAtlasAreas(const TriangleMesh& mesh, Atlas& atlas) {
  const size_t nt = mesh.triangles.size();
  atlas.surfaceArea.resize(nt);
  atlas.texelArea.resize(nt);
  const double s2 = static_cast<double>(atlas.size) * atlas.size;
  for (size_t t = 0; t < nt; ++t) {
    const glm::uvec3& tri = mesh.triangles[t];
    atlas.surfaceArea[t] = triangleArea3(mesh.positions[tri.x], mesh.positions[tri.y],
                                         mesh.positions[tri.z]);
    const dvec2 c[3] = {dvec2(atlas.uvs[3 * t]), dvec2(atlas.uvs[3 * t + 1]),
                        dvec2(atlas.uvs[3 * t + 2])};
    atlas.texelArea[t] = signedArea(c) * s2;
  }
}

namespace {

void checkOptions(const AtlasOptions& o) {
  if (o.size < 16 || o.size > 16384)
    throw AtlasError(fmt::format("atlas size {}: expected 16 .. 16384 texels per side", o.size));
  if (o.method == AtlasMethod::MeshUVs)
    throw AtlasError("atlas method mesh-uvs: expected authalic, lscm or triangles (the mesh's "
                     "UVs are asked for with useMeshUVs)");
  if (o.gutter > 64)
    throw AtlasError(fmt::format("atlas gutter {}: expected 0 .. 64 texels", o.gutter));
  if (!(o.maxChartAngle >= 10.0 && o.maxChartAngle <= 90.0))
    throw AtlasError(fmt::format("atlas maxChartAngle {}: expected 10 .. 90 degrees",
                                 o.maxChartAngle));
  if (!(o.maxChartArea > 0.0 && o.maxChartArea <= 1.0))
    throw AtlasError(fmt::format("atlas maxChartArea {}: expected a fraction in (0, 1]",
                                 o.maxChartArea));
}

}  // namespace

const char* toString(AtlasMethod method) {
  switch (method) {
    case AtlasMethod::Authalic: return "authalic";
    case AtlasMethod::Lscm: return "lscm";
    case AtlasMethod::Triangles: return "triangles";
    case AtlasMethod::MeshUVs: return "mesh-uvs";
  }
  return "?";
}

AtlasMethod parseAtlasMethod(const std::string& name) {
  for (const AtlasMethod m : {AtlasMethod::Authalic, AtlasMethod::Lscm, AtlasMethod::Triangles})
    if (name == toString(m)) return m;
  throw AtlasError(fmt::format("atlas method '{}': expected authalic, lscm or triangles", name));
}

size_t countUVOverlaps(const std::vector<dvec2>& corners) {
  const size_t n = corners.size() / 3;
  if (n < 2) return 0;
  dvec2 lo(kInf), hi(-kInf);
  for (const dvec2& p : corners) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  // A grid of about one triangle per cell; each pair is tested in the first cell (row-major)
  // that both bounding boxes share, so once.
  const auto g = static_cast<int>(std::clamp(std::sqrt(static_cast<double>(n)), 1.0, 2048.0));
  const dvec2 extent = glm::max(hi - lo, dvec2(1e-300));
  const auto cellOf = [&](double v, double l, double e) {
    return std::clamp(static_cast<int>((v - l) / e * g), 0, g - 1);
  };
  std::vector<std::array<int, 4>> box(n);  // x0 y0 x1 y1 in cells
  std::vector<uint32_t> start(static_cast<size_t>(g) * g + 1, 0);
  for (size_t t = 0; t < n; ++t) {
    const dvec2* c = &corners[3 * t];
    const dvec2 a = glm::min(glm::min(c[0], c[1]), c[2]), b = glm::max(glm::max(c[0], c[1]), c[2]);
    box[t] = {cellOf(a.x, lo.x, extent.x), cellOf(a.y, lo.y, extent.y),
              cellOf(b.x, lo.x, extent.x), cellOf(b.y, lo.y, extent.y)};
    for (int y = box[t][1]; y <= box[t][3]; ++y)
      for (int x = box[t][0]; x <= box[t][2]; ++x) ++start[static_cast<size_t>(y * g + x) + 1];
  }
  std::partial_sum(start.begin(), start.end(), start.begin());
  std::vector<uint32_t> items(start.back()), fill(start.begin(), start.end() - 1);
  for (size_t t = 0; t < n; ++t)
    for (int y = box[t][1]; y <= box[t][3]; ++y)
      for (int x = box[t][0]; x <= box[t][2]; ++x)
        items[fill[static_cast<size_t>(y * g + x)]++] = static_cast<uint32_t>(t);
  std::vector<size_t> perCell(static_cast<size_t>(g) * g, 0);
  tbb::parallel_for(0, g * g, [&](int cell) {
    const int cx = cell % g, cy = cell / g;
    size_t count = 0;
    for (uint32_t i = start[static_cast<size_t>(cell)]; i < start[static_cast<size_t>(cell) + 1]; ++i)
      for (uint32_t j = i + 1; j < start[static_cast<size_t>(cell) + 1]; ++j) {
        const auto& a = box[items[i]];
        const auto& b = box[items[j]];
        if (std::max(a[0], b[0]) != cx || std::max(a[1], b[1]) != cy) continue;
        if (std::min(a[2], b[2]) < cx || std::min(a[3], b[3]) < cy) continue;
        if (interiorsOverlap(&corners[3 * size_t{items[i]}], &corners[3 * size_t{items[j]}]))
          ++count;
      }
    perCell[static_cast<size_t>(cell)] = count;
  });
  return std::accumulate(perCell.begin(), perCell.end(), size_t{0});
}

std::string meshUVProblem(const TriangleMesh& mesh) {
  if (mesh.texcoords.empty()) return "the mesh has no texture coordinates";
  if (mesh.texcoords.size() != mesh.positions.size())
    return fmt::format("{} texture coordinates for {} vertices", mesh.texcoords.size(),
                       mesh.positions.size());
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) {
      const dvec2& p = mesh.texcoords[t[k]];
      if (!(p.x >= 0.0 && p.x <= 1.0 && p.y >= 0.0 && p.y <= 1.0))
        return fmt::format("vertex {} has UV ({}, {}), outside [0, 1]²", t[k], p.x, p.y);
    }
  std::vector<dvec2> corners;
  corners.reserve(3 * mesh.triangles.size());
  for (size_t i = 0; i < mesh.triangles.size(); ++i) {
    const glm::uvec3& t = mesh.triangles[i];
    const dvec2 c[3] = {mesh.texcoords[t.x], mesh.texcoords[t.y], mesh.texcoords[t.z]};
    const double a = signedArea(c);
    if (!(a > 0.0))
      return fmt::format("triangle {} has UV area {:.3g}: expected positive (counter-clockwise) "
                         "UV area for every triangle", i, a);
    corners.insert(corners.end(), c, c + 3);
  }
  if (const size_t overlaps = countUVOverlaps(corners); overlaps != 0)
    return fmt::format("{} pair(s) of triangles overlap in UV space", overlaps);
  return {};
}

Atlas buildAtlas(const TriangleMesh& mesh, const AtlasOptions& options,
                 const AtlasProgress& progress) {
  checkOptions(options);
  const size_t nt = mesh.triangles.size();
  Atlas atlas;
  atlas.size = options.size;
  if (options.useMeshUVs) {
    atlas.meshUVRejection = meshUVProblem(mesh);
    if (atlas.meshUVRejection.empty()) {
      atlas.method = AtlasMethod::MeshUVs;
      atlas.uvs.resize(3 * nt);
      for (size_t t = 0; t < nt; ++t)
        for (int k = 0; k < 3; ++k)
          atlas.uvs[3 * t + static_cast<size_t>(k)] = glm::vec2(mesh.texcoords[mesh.triangles[t][k]]);
      // Charts: triangles connected through shared UV vertices.
      std::vector<uint32_t> parent(mesh.positions.size());
      std::iota(parent.begin(), parent.end(), 0u);
      const auto find = [&](uint32_t v) {
        while (parent[v] != v) v = parent[v] = parent[parent[v]];
        return v;
      };
      for (const auto& t : mesh.triangles) {
        parent[find(t.y)] = find(t.x);
        parent[find(t.z)] = find(t.x);
      }
      std::unordered_map<uint32_t, uint32_t> ids;
      atlas.chart.resize(nt);
      for (size_t t = 0; t < nt; ++t)
        atlas.chart[t] = ids.try_emplace(find(mesh.triangles[t].x),
                                         static_cast<uint32_t>(ids.size())).first->second;
      atlas.chartCount = static_cast<uint32_t>(ids.size());
      detail::computeAtlasAreas(mesh, atlas);
      return atlas;
    }
  }
  atlas.method = options.method;
  atlas.gutter = options.gutter != 0 ? options.gutter
                                     : (options.method == AtlasMethod::Triangles ? 1u : 2u);
  const double totalArea = mesh.area();
  std::vector<PackChart> charts;
  std::vector<std::vector<uint32_t>> chartFaces;
  std::vector<std::vector<uint32_t>> cornerVertex;  // per chart: face corner -> chart vertex
  std::vector<std::array<dvec2, 3>> singles;        // per chart: the layout of a one-face chart

  const auto layoutSingle = [&](uint32_t f) {
    const glm::uvec3& t = mesh.triangles[f];
    const dvec3 p[3] = {mesh.positions[t.x], mesh.positions[t.y], mesh.positions[t.z]};
    PackChart c;
    const auto uv = layoutTriangle(p);
    c.uv.assign(uv.begin(), uv.end());
    c.width = std::max({uv[0].x, uv[1].x, uv[2].x});
    c.height = std::max({uv[0].y, uv[1].y, uv[2].y});
    // Incentre: the vertices weighted by the lengths of the opposite edges.
    const double la = glm::length(uv[1] - uv[2]), lb = glm::length(uv[2] - uv[0]),
                 lc = glm::length(uv[0] - uv[1]);
    c.incentre = (la * uv[0] + lb * uv[1] + lc * uv[2]) / (la + lb + lc);
    c.single = true;
    return std::make_pair(c, uv);
  };

  if (options.method == AtlasMethod::Triangles) {
    charts.reserve(nt);
    for (uint32_t f = 0; f < nt; ++f) {
      auto [c, uv] = layoutSingle(f);
      charts.push_back(std::move(c));
      singles.push_back(uv);
      chartFaces.push_back({f});
      cornerVertex.push_back({0, 1, 2});
    }
    if (progress) progress(1, 2);
  } else {
    // Grow the charts, map each (in parallel), split the ones whose map is not valid, repeat.
    const Topology topo = buildTopology(mesh);
    ChartGrower grower(topo);
    std::vector<uint32_t> all(nt);
    std::iota(all.begin(), all.end(), 0u);
    const double cosMax = std::cos(options.maxChartAngle * std::numbers::pi / 180.0);
    std::vector<std::vector<uint32_t>> pending =
        grower.grow(mesh, all, options.maxChartArea * totalArea, cosMax);
    const detail::ChartMap primary = options.method == AtlasMethod::Lscm
                                         ? detail::ChartMap::Lscm
                                         : detail::ChartMap::Authalic;
    std::atomic<uint64_t> done{0};
    uint64_t total = pending.size();
    std::mutex progressMutex;
    while (!pending.empty()) {
      std::vector<ChartMesh> meshes(pending.size());
      std::vector<std::vector<dvec2>> uvs(pending.size());
      std::vector<uint8_t> ok(pending.size(), 0), folded(pending.size(), 0),
          distorted(pending.size(), 0);
      // A valid (fold-free) map is kept unless it distorts area too much; false: not valid.
      auto accept = [&](size_t i, detail::ChartUV& r) {
        if (!r.error.empty() || !validChartMap(meshes[i], r.uv)) return false;
        if (tooDistorted(meshes[i], r.uv)) {
          distorted[i] = 1;
        } else {
          uvs[i] = std::move(r.uv);
          ok[i] = 1;
        }
        return true;
      };
      tbb::parallel_for(size_t{0}, pending.size(), [&](size_t i) {
        meshes[i] = chartMesh(mesh, topo, pending[i]);
        if (pending[i].size() == 1) {
          ok[i] = 1;  // laid out isometrically below
        } else if (isDisk(meshes[i])) {
          detail::ChartUV r = detail::parameterizeChart(meshes[i].positions, meshes[i].triangles,
                                                        primary);
          if (!accept(i, r)) {
            folded[i] = 1;
            // The authalic weights can be negative and fold the map; mean value coordinates are
            // positive, so with a convex boundary they cannot (Floater 2003).
            if (primary != detail::ChartMap::Lscm) {
              r = detail::parameterizeChart(meshes[i].positions, meshes[i].triangles,
                                            detail::ChartMap::MeanValue);
              accept(i, r);
            }
          }
        }
        const uint64_t d = ++done;
        if (progress) {
          const std::lock_guard lock(progressMutex);
          progress(d, total + 1);
        }
      });
      std::vector<std::vector<uint32_t>> retry;
      for (size_t i = 0; i < pending.size(); ++i) {
        atlas.foldedCharts += folded[i];
        atlas.distortedCharts += distorted[i];
        if (!ok[i]) {
          double area = 0.0;
          for (const uint32_t f : pending[i]) area += topo.area[f];
          auto parts = grower.grow(mesh, pending[i], 0.5 * area, cosMax);
          for (auto& p : parts) retry.push_back(std::move(p));
          continue;
        }
        PackChart c;
        std::vector<uint32_t> corners(3 * pending[i].size());
        for (size_t k = 0; k < pending[i].size(); ++k)
          for (int j = 0; j < 3; ++j)
            corners[3 * k + static_cast<size_t>(j)] = meshes[i].triangles[k][j];
        if (pending[i].size() == 1) {
          auto [single, uv] = layoutSingle(pending[i][0]);
          charts.push_back(std::move(single));
          singles.push_back(uv);
        } else {
          // Scale the chart so that its UV area is its surface area: texel area is then
          // proportional to surface area across charts (seed 3.2.1); inside a chart it is what
          // the map preserves.
          double uvArea = 0.0, sArea = 0.0;
          for (size_t k = 0; k < pending[i].size(); ++k) {
            const auto& t = meshes[i].triangles[k];
            const dvec2 cc[3] = {uvs[i][t.x], uvs[i][t.y], uvs[i][t.z]};
            uvArea += signedArea(cc);
            sArea += topo.area[pending[i][k]];
          }
          const double s = std::sqrt(sArea / uvArea);
          c.uv = std::move(uvs[i]);
          for (dvec2& q : c.uv) q *= s;
          orientChart(c.uv, c.width, c.height);
          charts.push_back(std::move(c));
          singles.push_back({});
        }
        chartFaces.push_back(std::move(pending[i]));
        cornerVertex.push_back(std::move(corners));
      }
      total += retry.size();
      pending = std::move(retry);
    }
  }

  // Pack, then write the corner UVs.
  const double rho = fitScale(charts, singles, totalArea, options.size, atlas.gutter);
  std::vector<Placement> placement;
  shelfPack(charts, singles, rho, options.size, atlas.gutter, &placement);
  atlas.uvs.assign(3 * nt, glm::vec2(0.0f));
  atlas.chart.assign(nt, 0);
  atlas.chartCount = static_cast<uint32_t>(charts.size());
  const double inv = 1.0 / options.size;
  for (size_t c = 0; c < charts.size(); ++c) {
    std::vector<glm::vec2> atlasUV(charts[c].uv.size());
    for (size_t v = 0; v < atlasUV.size(); ++v)
      atlasUV[v] = glm::vec2((placement[c].offset + rho * charts[c].uv[v]) * inv);
    for (size_t k = 0; k < chartFaces[c].size(); ++k) {
      const uint32_t f = chartFaces[c][k];
      atlas.chart[f] = static_cast<uint32_t>(c);
      for (size_t j = 0; j < 3; ++j) atlas.uvs[3 * f + j] = atlasUV[cornerVertex[c][3 * k + j]];
    }
  }
  detail::computeAtlasAreas(mesh, atlas);
  if (progress) progress(1, 1);
  return atlas;
}

// ---- Coverage --------------------------------------------------------------------------------
namespace {

// Edge function of p against a → b, computed from the endpoints in a fixed (lexicographic) order
// so that the two triangles sharing an edge get exactly opposite values.
double edgeFunction(const dvec2& a, const dvec2& b, const dvec2& p) {
  const bool swap = b.x < a.x || (b.x == a.x && b.y < a.y);
  const double e = swap ? orient(b, a, p) : orient(a, b, p);
  return swap ? -e : e;
}

// Inside test with the tie rule of the perturbation p + (ε, ε²): a centre on the edge a → b of a
// counter-clockwise triangle is inside iff the edge points down, or exactly right.
bool insideEdge(const dvec2& a, const dvec2& b, double e) {
  if (e != 0.0) return e > 0.0;
  const dvec2 d = b - a;
  return d.y < 0.0 || (d.y == 0.0 && d.x > 0.0);
}

dvec2 closestPointOnTriangle(const dvec2* t, const dvec2& p) {
  bool inside = true;
  for (int e = 0; e < 3; ++e)
    if (orient(t[e], t[(e + 1) % 3], p) < 0.0) inside = false;
  if (inside) return p;
  double best = kInf;
  dvec2 q = t[0];
  for (int e = 0; e < 3; ++e) {
    const dvec2 a = t[e], d = t[(e + 1) % 3] - a;
    const double len2 = glm::dot(d, d);
    const double s = len2 > 0.0 ? std::clamp(glm::dot(p - a, d) / len2, 0.0, 1.0) : 0.0;
    const dvec2 c = a + s * d;
    if (const double dist = glm::dot(p - c, p - c); dist < best) {
      best = dist;
      q = c;
    }
  }
  return q;
}

}  // namespace

AtlasCoverage rasterizeCoverage(const Atlas& atlas) {
  AtlasCoverage cov;
  const uint32_t n = atlas.size;
  cov.size = n;
  cov.owner.assign(size_t{n} * n, -1);
  const size_t nt = atlas.triangleCount();
  cov.texels.assign(nt, 0);
  const auto corners = [&](size_t t, dvec2* c) {
    for (size_t k = 0; k < 3; ++k) c[k] = dvec2(atlas.uvs[3 * t + k]) * static_cast<double>(n);
  };
  // Texel centres inside each triangle, in triangle order (a texel already taken by an earlier
  // triangle is an overlap and stays with it).
  for (size_t t = 0; t < nt; ++t) {
    dvec2 c[3];
    corners(t, c);
    const dvec2 lo = glm::min(glm::min(c[0], c[1]), c[2]), hi = glm::max(glm::max(c[0], c[1]), c[2]);
    const int x0 = std::max(0, static_cast<int>(std::ceil(lo.x - 0.5)));
    const int y0 = std::max(0, static_cast<int>(std::ceil(lo.y - 0.5)));
    const int x1 = std::min(static_cast<int>(n) - 1, static_cast<int>(std::floor(hi.x - 0.5)));
    const int y1 = std::min(static_cast<int>(n) - 1, static_cast<int>(std::floor(hi.y - 0.5)));
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const dvec2 p(x + 0.5, y + 0.5);
        bool in = true;
        for (int e = 0; e < 3 && in; ++e)
          in = insideEdge(c[e], c[(e + 1) % 3], edgeFunction(c[e], c[(e + 1) % 3], p));
        if (!in) continue;
        int32_t& o = cov.owner[static_cast<size_t>(y) * n + static_cast<size_t>(x)];
        if (o >= 0) {
          ++cov.conflicts;
          continue;
        }
        o = static_cast<int32_t>(t);
        ++cov.texels[t];
      }
  }
  // Conservative coverage for the triangles without a centre: the nearest texel whose square the
  // triangle touches, empty first, else one whose owner keeps another.
  for (size_t t = 0; t < nt; ++t) {
    if (cov.texels[t] != 0) continue;
    dvec2 c[3];
    corners(t, c);
    const dvec2 lo = glm::min(glm::min(c[0], c[1]), c[2]), hi = glm::max(glm::max(c[0], c[1]), c[2]);
    const int x0 = std::max(0, static_cast<int>(std::floor(lo.x)));
    const int y0 = std::max(0, static_cast<int>(std::floor(lo.y)));
    const int x1 = std::min(static_cast<int>(n) - 1, static_cast<int>(std::floor(hi.x)));
    const int y1 = std::min(static_cast<int>(n) - 1, static_cast<int>(std::floor(hi.y)));
    double bestEmpty = kInf, bestShared = kInf;
    size_t empty = SIZE_MAX, shared = SIZE_MAX;
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const dvec2 p(x + 0.5, y + 0.5);
        const dvec2 q = closestPointOnTriangle(c, p);
        // Touching the square: the closest point lies within the texel.
        if (std::abs(q.x - p.x) > 0.5 || std::abs(q.y - p.y) > 0.5) continue;
        const double d = glm::dot(q - p, q - p);
        const size_t idx = static_cast<size_t>(y) * n + static_cast<size_t>(x);
        const int32_t o = cov.owner[idx];
        if (o < 0) {
          if (d < bestEmpty) bestEmpty = d, empty = idx;
        } else if (cov.texels[static_cast<size_t>(o)] >= 2 && d < bestShared) {
          bestShared = d, shared = idx;
        }
      }
    const size_t idx = empty != SIZE_MAX ? empty : shared;
    if (idx == SIZE_MAX) {
      ++cov.uncovered;
      continue;
    }
    if (cov.owner[idx] >= 0) --cov.texels[static_cast<size_t>(cov.owner[idx])];
    cov.owner[idx] = static_cast<int32_t>(t);
    cov.texels[t] = 1;
    ++cov.conservative;
  }
  for (const int32_t o : cov.owner) cov.ownedTexels += o >= 0 ? 1 : 0;
  return cov;
}

std::optional<TexelSurfacePoint> texelSurfacePoint(const TriangleMesh& mesh, const Atlas& atlas,
                                                   const AtlasCoverage& coverage, uint32_t x,
                                                   uint32_t y) {
  if (x >= coverage.size || y >= coverage.size) return std::nullopt;
  const int32_t o = coverage.at(x, y);
  if (o < 0) return std::nullopt;
  const auto t = static_cast<size_t>(o);
  dvec2 c[3];
  for (size_t k = 0; k < 3; ++k) c[k] = dvec2(atlas.uvs[3 * t + k]) * static_cast<double>(coverage.size);
  const dvec2 p = closestPointOnTriangle(c, dvec2(x + 0.5, y + 0.5));
  const double area = orient(c[0], c[1], c[2]);
  TexelSurfacePoint s;
  s.triangle = static_cast<uint32_t>(t);
  s.barycentric = {orient(c[1], c[2], p) / area, orient(c[2], c[0], p) / area, 0.0};
  s.barycentric.z = 1.0 - s.barycentric.x - s.barycentric.y;
  const glm::uvec3& tri = mesh.triangles[t];
  s.position = s.barycentric.x * mesh.positions[tri.x] + s.barycentric.y * mesh.positions[tri.y] +
               s.barycentric.z * mesh.positions[tri.z];
  dvec3 n = mesh.normals.empty()
                ? glm::cross(mesh.positions[tri.y] - mesh.positions[tri.x],
                             mesh.positions[tri.z] - mesh.positions[tri.x])
                : s.barycentric.x * mesh.normals[tri.x] + s.barycentric.y * mesh.normals[tri.y] +
                      s.barycentric.z * mesh.normals[tri.z];
  s.normal = glm::length(n) > 0.0 ? n / glm::length(n) : n;
  return s;
}

// ---- Statistics ------------------------------------------------------------------------------
std::vector<double> areaDistortion(const Atlas& atlas) {
  const double sumS = std::accumulate(atlas.surfaceArea.begin(), atlas.surfaceArea.end(), 0.0);
  const double sumT = std::accumulate(atlas.texelArea.begin(), atlas.texelArea.end(), 0.0);
  std::vector<double> d(atlas.triangleCount());
  for (size_t t = 0; t < d.size(); ++t)
    d[t] = std::log((atlas.texelArea[t] / sumT) / (atlas.surfaceArea[t] / sumS));
  return d;
}

AtlasStatistics atlasStatistics(const Atlas& atlas, const AtlasCoverage& coverage) {
  AtlasStatistics s;
  const size_t nt = atlas.triangleCount();
  s.triangles = nt;
  s.charts = atlas.chartCount;
  const std::vector<double> d = areaDistortion(atlas);
  const double sumS = std::accumulate(atlas.surfaceArea.begin(), atlas.surfaceArea.end(), 0.0);
  const double sumT = std::accumulate(atlas.texelArea.begin(), atlas.texelArea.end(), 0.0);
  double m1 = 0.0, m2 = 0.0;
  s.distortionMin = kInf;
  s.distortionMax = -kInf;
  for (size_t t = 0; t < nt; ++t) {
    m1 += atlas.surfaceArea[t] * d[t];
    m2 += atlas.surfaceArea[t] * d[t] * d[t];
    s.distortionMin = std::min(s.distortionMin, d[t]);
    s.distortionMax = std::max(s.distortionMax, d[t]);
    if (atlas.texelArea[t] < 1.0) ++s.trianglesBelowOneTexel;
  }
  s.distortionMean = m1 / sumS;
  s.distortionRms = std::sqrt(m2 / sumS);
  std::vector<uint32_t> order(nt);
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return d[a] < d[b]; });
  double acc = 0.0;
  double* targets[3] = {&s.distortionP05, &s.distortionP50, &s.distortionP95};
  const double levels[3] = {0.05, 0.5, 0.95};
  int next = 0;
  for (const uint32_t t : order) {
    acc += atlas.surfaceArea[t];
    while (next < 3 && acc >= levels[next] * sumS) *targets[next++] = d[t];
  }
  const double texels = static_cast<double>(atlas.size) * atlas.size;
  s.utilisation = sumT / texels;
  s.coveredFraction = static_cast<double>(coverage.ownedTexels) / texels;
  double recovered = 0.0;
  for (const int32_t o : coverage.owner)
    if (o >= 0)
      recovered += atlas.surfaceArea[static_cast<size_t>(o)] / atlas.texelArea[static_cast<size_t>(o)];
  s.recoveredAreaRatio = recovered / sumS;
  return s;
}

}  // namespace translucent::geometry
