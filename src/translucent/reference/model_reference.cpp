// SPDX-License-Identifier: GPL-3.0-or-later
// Brute-force integration of a BSSRDF model over a mesh for every visible pixel
// (model_reference.h).
#include "translucent/reference/model_reference.h"

#include <fmt/format.h>
#include <tbb/task_arena.h>

#if defined(__x86_64__)
#include <immintrin.h>
#endif

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <numbers>
#include <optional>

#include <glm/geometric.hpp>

#include "translucent/bssrdf/bssrdf_file.h"
#include "translucent/bssrdf/registry.h"
#include "translucent/geometry/ambient_occlusion.h"
#include "translucent/geometry/atlas.h"
#include "translucent/geometry/point_cloud.h"
#include "translucent/geometry/ray_scene.h"
#include "translucent/material/material.h"
#include "translucent/material/point_profiles.h"
#include "translucent/material/surface_uv.h"
#include "translucent/optics/fresnel.h"
#include "translucent/reference/block_driver.h"
#include "translucent/reference/rng.h"
#include "translucent/reference/sampling.h"

namespace translucent::reference {
namespace {

using detail::uniform01;
constexpr double kPi = std::numbers::pi;
constexpr uint64_t kMaxSamples = (uint64_t(1) << 24) - 1;  // geometry::samplePointCloud's limit
constexpr int kMaxSubpixels = 16;
constexpr int kMaxRays = kMaxSubpixels * kMaxSubpixels;

// 2π∫0^r R r' dr' from the profile's cumulative table (8-point Gauss-Legendre panels, ~1e-10):
// the last whole panel below r, then one panel up to r.
double cumulativeAt(const bssrdf::RadialProfile& p, double r) {
  const auto& c = p.cumulative();
  if (r >= c.edges.back()) return c.total();
  const auto it = std::upper_bound(c.edges.begin(), c.edges.end(), r);
  const size_t k = static_cast<size_t>(it - c.edges.begin()) - 1;
  return c.cdf[k] + (r > c.edges[k] ? bssrdf::integratePanel(p, c.edges[k], r) : 0.0);
}

// R_c(r) for the three channels on a grid uniform in s = sqrt(r), s in [s0, s1]: the grid is
// dense at small r, where the profiles are steep, and coarse in the exponential tail.
struct ProfileGrid {
  double s0 = 0.0, s1 = 0.0;
  size_t n = 0;
  std::vector<float> values;  // 4 per node: R_r, R_g, R_b, 0
  double maxRelative = 0.0;   // largest |interpolated - exact| / exact at the interval midpoints
  double integrated = 0.0;    // max_c ∫|interpolated - exact| 2πr dr / Rd_c (midpoint rule)

  double node(size_t i) const { return s0 + (s1 - s0) * double(i) / double(n - 1); }
};

ProfileGrid tabulate(const std::vector<std::unique_ptr<bssrdf::RadialProfile>>& profiles,
                     double rho, double rMax, size_t n) {
  ProfileGrid g;
  g.s0 = std::sqrt(rho);
  g.s1 = std::sqrt(rMax);
  g.n = n;
  g.values.assign(4 * n, 0.0f);
  for (size_t i = 0; i < n; ++i) {
    const double s = g.node(i);
    for (size_t c = 0; c < 3; ++c) g.values[4 * i + c] = static_cast<float>(profiles[c]->R(s * s));
  }
  for (size_t c = 0; c < 3; ++c) {
    double err = 0.0;
    const double rd = profiles[c]->Rd();
    for (size_t i = 0; i + 1 < n; ++i) {
      const double a = g.node(i), b = g.node(i + 1), sm = 0.5 * (a + b), rm = sm * sm;
      const double exact = profiles[c]->R(rm);
      const double interp = 0.5 * (double(g.values[4 * i + c]) + double(g.values[4 * (i + 1) + c]));
      const double diff = std::abs(interp - exact);
      if (exact > 0.0) g.maxRelative = std::max(g.maxRelative, diff / exact);
      err += diff * 2.0 * kPi * rm * (b * b - a * a);
    }
    g.integrated = std::max(g.integrated, rd > 0.0 ? err / rd : 0.0);
  }
  return g;
}

// The lights, with unit directions, in the form the irradiance loop reads.
struct LightTerm {
  enum class Kind { Directional, Point, Beam, Environment } kind = Kind::Directional;
  glm::dvec3 direction{0.0};  // towards the light (directional, beam)
  glm::dvec3 position{0.0};   // point light; beam origin
  double radius = 0.0;        // beam
  Rgb value{};                // E·colour, I·colour, P/(π r²)·colour or intensity·colour
  // Environment: the map, its rotation and a luminance sampler (one for all channels).
  std::shared_ptr<const lights::EnvironmentMap> map;
  double rotate = 0.0;
  std::shared_ptr<const lights::EnvironmentSampler> sampler;
};

// The stream family of the environment rays (distinct from the pixels' jitter streams).
uint64_t environmentSeed(uint64_t seed) { return mix64(seed ^ 0x454E5652ull); }

std::vector<LightTerm> lightTerms(std::span<const Light> lights) {
  std::vector<LightTerm> out;
  for (size_t i = 0; i < lights.size(); ++i) {
    const Light l = lights[i].validated(fmt::format("model reference: light {}", i));
    LightTerm t;
    double scale = 1.0;
    if (const auto* d = std::get_if<DirectionalLight>(&l.emitter)) {
      t.kind = LightTerm::Kind::Directional;
      t.direction = d->direction;
      scale = d->irradiance;
    } else if (const auto* p = std::get_if<PointLight>(&l.emitter)) {
      t.kind = LightTerm::Kind::Point;
      t.position = p->position;
      scale = p->intensity;
    } else if (const auto* e = std::get_if<EnvironmentLight>(&l.emitter)) {
      t.kind = LightTerm::Kind::Environment;
      t.map = e->map;
      t.rotate = e->rotate;
      t.sampler = std::make_shared<const lights::EnvironmentSampler>(*e->map, e->rotate);
      scale = e->intensity;
    } else {
      const auto& b = std::get<BeamLight>(l.emitter);
      if (!(b.radius > 0.0))
        throw ParameterError(fmt::format(
            "model reference: light {}: a beam of radius 0 (a pencil beam) has no irradiance to "
            "integrate over the surface: expected radius > 0", i));
      t.kind = LightTerm::Kind::Beam;
      t.direction = -b.direction;  // towards the light
      t.position = b.origin;
      t.radius = b.radius;
      scale = b.power / (kPi * b.radius * b.radius);
    }
    for (size_t c = 0; c < 3; ++c) t.value[c] = scale * l.color[c];
    out.push_back(t);
  }
  return out;
}

// Transmitted irradiance from an environment light at x with normal n,
//   E_c = value_c ∫ L_c(ω) Ft(η, n·ω) max(0, n·ω) V(x, ω) dω,
// by multi-sample importance sampling with the balance heuristic (Veach 1997, §9.2): `pairs`
// directions from the map's luminance sampler (p1) and as many cosine-distributed about n (p2),
// each weighted f / ((p1 + p2) / 2), one shadow ray each. A pair (one of each) is an unbiased
// estimate on its own, so the pairs' spread gives the variance of their mean (added to `var`).
void environmentIrradiance(const glm::dvec3& x, const glm::dvec3& n, const LightTerm& t,
                           const geometry::RayScene& scene, double eps, double eta, bool incoherent,
                           int pairs, Rng& rng, Rgb& e, Rgb& var) {
  glm::dvec3 t1, t2;
  detail::tangentFrame(n, t1, t2);
  Rgb sum{0.0, 0.0, 0.0}, sum2{0.0, 0.0, 0.0};
  auto contribution = [&](const glm::dvec3& w, Rgb& out) {
    const double cosI = glm::dot(n, w);
    if (!(cosI > 0.0)) return;
    const double pMix = 0.5 * (t.sampler->pdf(w) + cosI / kPi);
    if (!(pMix > 0.0)) return;
    if (scene.occluded(x, w, eps, std::numeric_limits<double>::infinity(), incoherent)) return;
    const double ft = eta == 1.0 ? 1.0 : fresnelTransmittance(std::min(cosI, 1.0), eta);
    const glm::vec3 L = t.map->lookup(w, t.rotate);
    for (size_t c = 0; c < 3; ++c) out[c] += t.value[c] * double(L[int(c)]) * ft * cosI / pMix;
  };
  for (int j = 0; j < pairs; ++j) {
    Rgb z{0.0, 0.0, 0.0};
    const double u1 = detail::uniform01(rng), u2 = detail::uniform01(rng);
    contribution(t.sampler->sample({u1, u2}).direction, z);
    // Cosine-weighted about n (Malley's method).
    const double r = std::sqrt(detail::uniform01(rng)), phi = 2.0 * kPi * detail::uniform01(rng);
    const glm::dvec3 w = glm::normalize(r * std::cos(phi) * t1 + r * std::sin(phi) * t2 +
                                        std::sqrt(std::max(0.0, 1.0 - r * r)) * n);
    contribution(w, z);
    for (size_t c = 0; c < 3; ++c) {
      z[c] *= 0.5;
      sum[c] += z[c];
      sum2[c] += z[c] * z[c];
    }
  }
  for (size_t c = 0; c < 3; ++c) {
    const double mean = sum[c] / pairs;
    e[c] += mean;
    if (pairs > 1) var[c] += std::max(0.0, (sum2[c] - pairs * mean * mean) / (pairs - 1.0)) / pairs;
  }
}

// Transmitted irradiance at surface point x with (irradiance) normal n, per channel. Environment
// lights are integrated by `pairs` ray pairs from `rng` (environmentIrradiance), whose variance
// is added to `var`.
Rgb transmittedIrradiance(const glm::dvec3& x, const glm::dvec3& n, std::span<const LightTerm> lights,
                          const geometry::RayScene& scene, double eps, double eta, bool incoherent,
                          int pairs, Rng& rng, Rgb& var) {
  Rgb e{0.0, 0.0, 0.0};
  for (const LightTerm& t : lights) {
    if (t.kind == LightTerm::Kind::Environment) {
      environmentIrradiance(x, n, t, scene, eps, eta, incoherent, pairs, rng, e, var);
      continue;
    }
    glm::dvec3 l = t.direction;
    double tMax = std::numeric_limits<double>::infinity(), falloff = 1.0;
    if (t.kind == LightTerm::Kind::Point) {
      const glm::dvec3 d = t.position - x;
      const double dist = glm::length(d);
      if (!(dist > eps)) continue;
      l = d / dist;
      falloff = 1.0 / (dist * dist);
      tMax = dist - eps;
    } else if (t.kind == LightTerm::Kind::Beam) {
      // Lit only inside the beam's disc and downstream of its origin (the photons start there).
      const glm::dvec3 q = t.position - x;
      const double along = glm::dot(q, l);
      if (!(along > eps)) continue;
      const glm::dvec3 radial = q - along * l;
      if (glm::dot(radial, radial) > t.radius * t.radius) continue;
      tMax = along;
    }
    const double cosI = glm::dot(n, l);
    if (!(cosI > 0.0)) continue;
    const double ft = eta == 1.0 ? 1.0 : fresnelTransmittance(std::min(cosI, 1.0), eta);
    if (scene.occluded(x, l, eps, tMax, incoherent)) continue;
    for (size_t c = 0; c < 3; ++c) e[c] += t.value[c] * falloff * ft * cosI;
  }
  return e;
}

// The lit samples in cells of a uniform grid, structure of arrays (what the inner loop streams).
struct SampleGrid {
  glm::dvec3 origin{0.0};
  double cell = 1.0;
  glm::ivec3 dims{1};
  std::vector<uint32_t> start;  // per cell (x fastest), + 1 sentinel
  std::vector<uint32_t> middle; // per cell: the first sample of odd index (the second half)
  std::vector<float> x, y, z, e0, e1, e2;
  std::vector<uint32_t> tag;    // per slot: tags[k] of its sample, when buildGrid was given tags
  glm::dvec3 lower(const glm::ivec3& c) const { return origin + glm::dvec3(c) * cell; }
};

SampleGrid buildGrid(const geometry::PointCloud& cloud, const std::vector<Rgb>& e, double rMax,
                     const std::vector<uint32_t>* tags = nullptr) {
  SampleGrid g;
  std::vector<uint32_t> lit;
  glm::dvec3 lo(std::numeric_limits<double>::max()), hi(std::numeric_limits<double>::lowest());
  for (size_t k = 0; k < cloud.size(); ++k) {
    if (!(e[k][0] > 0.0 || e[k][1] > 0.0 || e[k][2] > 0.0)) continue;
    lit.push_back(static_cast<uint32_t>(k));
    lo = glm::min(lo, glm::dvec3(cloud.positions[k]));
    hi = glm::max(hi, glm::dvec3(cloud.positions[k]));
  }
  if (lit.empty()) {
    g.start = {0, 0};
    return g;
  }
  // Cells of r_max / 2 (a query visits about 5³ of them), at most 96 per axis.
  const double extent = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z, 1e-30});
  g.cell = std::max(0.5 * rMax, extent / 96.0);
  g.origin = lo;
  for (int a = 0; a < 3; ++a)
    g.dims[a] = std::clamp(static_cast<int>(std::floor((hi[a] - lo[a]) / g.cell)) + 1, 1, 96);
  auto cellOf = [&](const glm::vec3& p) {
    glm::ivec3 c;
    for (int a = 0; a < 3; ++a)
      c[a] = std::clamp(static_cast<int>(std::floor((double(p[a]) - g.origin[a]) / g.cell)), 0,
                        g.dims[a] - 1);
    return static_cast<size_t>((c.z * g.dims.y + c.y) * g.dims.x + c.x);
  };
  const size_t cells = static_cast<size_t>(g.dims.x) * size_t(g.dims.y) * size_t(g.dims.z);
  g.start.assign(cells + 1, 0);
  for (uint32_t k : lit) ++g.start[cellOf(cloud.positions[k]) + 1];
  for (size_t c = 0; c < cells; ++c) g.start[c + 1] += g.start[c];
  // Counting sort: in each cell first the samples of even index, then those of odd index (two
  // independent halves, for the jitter variance), each in index order.
  std::vector<uint32_t> even(cells, 0);
  for (uint32_t k : lit)
    if (k % 2 == 0) ++even[cellOf(cloud.positions[k])];
  g.middle.resize(cells);
  std::vector<uint32_t> fillEven(cells), fillOdd(cells);
  for (size_t c = 0; c < cells; ++c) {
    fillEven[c] = g.start[c];
    fillOdd[c] = g.middle[c] = g.start[c] + even[c];
  }
  const size_t m = lit.size();
  g.x.resize(m), g.y.resize(m), g.z.resize(m), g.e0.resize(m), g.e1.resize(m), g.e2.resize(m);
  if (tags) g.tag.resize(m);
  for (uint32_t k : lit) {
    const size_t cell = cellOf(cloud.positions[k]);
    const uint32_t slot = k % 2 == 0 ? fillEven[cell]++ : fillOdd[cell]++;
    g.x[slot] = cloud.positions[k].x;
    g.y[slot] = cloud.positions[k].y;
    g.z[slot] = cloud.positions[k].z;
    g.e0[slot] = static_cast<float>(e[k][0]);
    g.e1[slot] = static_cast<float>(e[k][1]);
    g.e2[slot] = static_cast<float>(e[k][2]);
    if (tags) g.tag[slot] = (*tags)[k];
  }
  return g;
}

// One camera ray that hit: where, and what its exit terms are.
struct RayHit {
  float x = 0, y = 0, z = 0;
  float factor = 0;   // L/B at this point (exit convention, Fresnel at the camera direction)
  double near[3]{};   // E_c(x_o) F_c(ρ): the analytic disc
};

// Sums over the samples for one pixel. With v_sck = R_c(|x_s - x_k|) E_c(x_k) (hit s, sample k):
//   ray[s][c] = Σ_k v_sck                      (the per-ray estimates, for the jitter variance)
//   b2[c]     = Σ_k (Σ_s v_sck)²,  l2[c] = Σ_k (Σ_s f_s v_sck)²   (second moments of t_k)
// The first moments follow from ray[][]: Σ_k Σ_s v_sck and Σ_s f_s Σ_k v_sck.
struct PixelSums {
  double b2[3]{}, l2[3]{};
  double ray[2][kMaxRays][3]{};  // [half]: samples of even / odd index
};

// Up to four hits at once (a pixel of 2x2 rays is one group); unused slots lie far away.
struct HitGroup {
  float x[4], y[4], z[4], f[4];
};

struct TableView {
  const float* T;
  float s0, inv, tMax, rho2, rMax2;
};

constexpr uint32_t kChunk = 256;

// R_c(|p - h|) E_c for one sample p and one hit h, from the table (0 outside [ρ, r_max]).
struct Rgbf {
  float r, g, b;
};
[[gnu::always_inline]] inline Rgbf kernel(float px, float py, float pz, float hx, float hy,
                                          float hz, float e0, float e1, float e2,
                                          const TableView& tv) {
  const float dx = px - hx, dy = py - hy, dz = pz - hz;
  const float d2 = dx * dx + dy * dy + dz * dz;
  const float inside = (d2 >= tv.rho2 && d2 <= tv.rMax2) ? 1.0f : 0.0f;
  const float t = std::clamp((std::sqrt(std::sqrt(d2)) - tv.s0) * tv.inv, 0.0f, tv.tMax);
  const int i = static_cast<int>(t);
  const float u = t - static_cast<float>(i);
  const float* T = tv.T;
  const int j = 4 * i;
  return {inside * e0 * (T[j] + u * (T[j + 4] - T[j])),
          inside * e1 * (T[j + 1] + u * (T[j + 5] - T[j + 1])),
          inside * e2 * (T[j + 2] + u * (T[j + 6] - T[j + 2]))};
}

// One group over samples [first, count) of a chunk: R of the four hits, per-ray sums into `ray`, and
// either the second moments directly (kFused: the group is all the pixel's hits) or Σ_s v and
// Σ_s f_s v per sample added into wB / wL for a later pass. (Always inlined, so that
// accumulate's AVX2 build compiles it for AVX2 too.)
template <bool kFused>
[[gnu::always_inline]] inline void groupPass(const float* px, const float* py, const float* pz,
                                             const float* const* e, uint32_t first, uint32_t count,
                                             const HitGroup& g, const TableView& tv,
                                             float (*wB)[kChunk], float (*wL)[kChunk],
                                             float* ray, float* sq) {
  float r00 = 0, r01 = 0, r02 = 0, r10 = 0, r11 = 0, r12 = 0;
  float r20 = 0, r21 = 0, r22 = 0, r30 = 0, r31 = 0, r32 = 0;
  float b0 = 0, b1 = 0, b2 = 0, l0 = 0, l1 = 0, l2 = 0;
  const float* e0 = e[0];
  const float* e1 = e[1];
  const float* e2 = e[2];
  const float x0 = g.x[0], y0 = g.y[0], z0 = g.z[0], f0 = g.f[0];
  const float x1 = g.x[1], y1 = g.y[1], z1 = g.z[1], f1 = g.f[1];
  const float x2 = g.x[2], y2 = g.y[2], z2 = g.z[2], f2 = g.f[2];
  const float x3 = g.x[3], y3 = g.y[3], z3 = g.z[3], f3 = g.f[3];
#pragma omp simd reduction(+ : r00, r01, r02, r10, r11, r12, r20, r21, r22, r30, r31, r32, b0, b1, b2, l0, l1, l2)
  for (uint32_t k = first; k < count; ++k) {
    const Rgbf v0 = kernel(px[k], py[k], pz[k], x0, y0, z0, e0[k], e1[k], e2[k], tv);
    const Rgbf v1 = kernel(px[k], py[k], pz[k], x1, y1, z1, e0[k], e1[k], e2[k], tv);
    const Rgbf v2 = kernel(px[k], py[k], pz[k], x2, y2, z2, e0[k], e1[k], e2[k], tv);
    const Rgbf v3 = kernel(px[k], py[k], pz[k], x3, y3, z3, e0[k], e1[k], e2[k], tv);
    r00 += v0.r, r01 += v0.g, r02 += v0.b;
    r10 += v1.r, r11 += v1.g, r12 += v1.b;
    r20 += v2.r, r21 += v2.g, r22 += v2.b;
    r30 += v3.r, r31 += v3.g, r32 += v3.b;
    const float sbr = v0.r + v1.r + v2.r + v3.r;
    const float sbg = v0.g + v1.g + v2.g + v3.g;
    const float sbb = v0.b + v1.b + v2.b + v3.b;
    const float slr = f0 * v0.r + f1 * v1.r + f2 * v2.r + f3 * v3.r;
    const float slg = f0 * v0.g + f1 * v1.g + f2 * v2.g + f3 * v3.g;
    const float slb = f0 * v0.b + f1 * v1.b + f2 * v2.b + f3 * v3.b;
    if constexpr (kFused) {
      b0 += sbr * sbr, b1 += sbg * sbg, b2 += sbb * sbb;
      l0 += slr * slr, l1 += slg * slg, l2 += slb * slb;
    } else {
      wB[0][k] += sbr, wB[1][k] += sbg, wB[2][k] += sbb;
      wL[0][k] += slr, wL[1][k] += slg, wL[2][k] += slb;
    }
  }
  const float r[12] = {r00, r01, r02, r10, r11, r12, r20, r21, r22, r30, r31, r32};
  for (int j = 0; j < 12; ++j) ray[j] += r[j];
  const float q[6] = {b0, b1, b2, l0, l1, l2};
  for (int j = 0; j < 6; ++j) sq[j] += q[j];
}

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define TRANSLUCENT_MODEL_REFERENCE_AVX2 1
// groupPass with AVX2 + FMA intrinsics, 8 samples at a time (GCC 12 does not emit gathers for
// the table lookups by itself); the remainder of the chunk goes through the portable kernel. Same
// operations, so it agrees with the portable pass to float rounding; the order of the sums is
// fixed, so it is deterministic.
__attribute__((target("avx2,fma"))) inline float horizontalSum(__m256 v) {
  alignas(32) float a[8];
  _mm256_store_ps(a, v);
  return ((a[0] + a[1]) + (a[2] + a[3])) + ((a[4] + a[5]) + (a[6] + a[7]));
}

template <bool kFused>
__attribute__((target("avx2,fma"))) void groupPassAvx2(const float* px, const float* py,
                                                       const float* pz, const float* const* e,
                                                       uint32_t first, uint32_t count,
                                                       const HitGroup& g,
                                                       const TableView& tv, float (*wB)[kChunk],
                                                       float (*wL)[kChunk], float* ray, float* sq) {
  __m256 r[12], q[6];
  for (auto& v : r) v = _mm256_setzero_ps();
  for (auto& v : q) v = _mm256_setzero_ps();
  const __m256 rho2 = _mm256_set1_ps(tv.rho2), rMax2 = _mm256_set1_ps(tv.rMax2);
  const __m256 s0 = _mm256_set1_ps(tv.s0), inv = _mm256_set1_ps(tv.inv);
  const __m256 tMax = _mm256_set1_ps(tv.tMax), zero = _mm256_setzero_ps();
  __m256 hx[4], hy[4], hz[4], hf[4];
  for (int h = 0; h < 4; ++h) {
    hx[h] = _mm256_set1_ps(g.x[h]);
    hy[h] = _mm256_set1_ps(g.y[h]);
    hz[h] = _mm256_set1_ps(g.z[h]);
    hf[h] = _mm256_set1_ps(g.f[h]);
  }
  uint32_t k = first;
  for (; k + 8 <= count; k += 8) {
    const __m256 x = _mm256_loadu_ps(px + k), y = _mm256_loadu_ps(py + k), z = _mm256_loadu_ps(pz + k);
    const __m256 ec[3] = {_mm256_loadu_ps(e[0] + k), _mm256_loadu_ps(e[1] + k), _mm256_loadu_ps(e[2] + k)};
    __m256 sb[3] = {zero, zero, zero}, sl[3] = {zero, zero, zero};
    for (int h = 0; h < 4; ++h) {
      const __m256 dx = _mm256_sub_ps(x, hx[h]), dy = _mm256_sub_ps(y, hy[h]), dz = _mm256_sub_ps(z, hz[h]);
      const __m256 d2 = _mm256_fmadd_ps(dz, dz, _mm256_fmadd_ps(dy, dy, _mm256_mul_ps(dx, dx)));
      const __m256 inside = _mm256_and_ps(_mm256_cmp_ps(d2, rho2, _CMP_GE_OQ),
                                          _mm256_cmp_ps(d2, rMax2, _CMP_LE_OQ));
      __m256 t = _mm256_mul_ps(_mm256_sub_ps(_mm256_sqrt_ps(_mm256_sqrt_ps(d2)), s0), inv);
      t = _mm256_min_ps(_mm256_max_ps(t, zero), tMax);
      const __m256i i = _mm256_cvttps_epi32(t);
      const __m256 u = _mm256_sub_ps(t, _mm256_cvtepi32_ps(i));
      const __m256i j = _mm256_slli_epi32(i, 2);
      for (int c = 0; c < 3; ++c) {
        const __m256 a = _mm256_i32gather_ps(tv.T + c, j, 4);
        const __m256 b = _mm256_i32gather_ps(tv.T + 4 + c, j, 4);
        const __m256 v = _mm256_mul_ps(_mm256_and_ps(_mm256_fmadd_ps(u, _mm256_sub_ps(b, a), a), inside), ec[c]);
        r[3 * h + c] = _mm256_add_ps(r[3 * h + c], v);
        sb[c] = _mm256_add_ps(sb[c], v);
        sl[c] = _mm256_fmadd_ps(hf[h], v, sl[c]);
      }
    }
    for (int c = 0; c < 3; ++c) {
      if constexpr (kFused) {
        q[c] = _mm256_fmadd_ps(sb[c], sb[c], q[c]);
        q[3 + c] = _mm256_fmadd_ps(sl[c], sl[c], q[3 + c]);
      } else {
        _mm256_storeu_ps(wB[c] + k, _mm256_add_ps(_mm256_loadu_ps(wB[c] + k), sb[c]));
        _mm256_storeu_ps(wL[c] + k, _mm256_add_ps(_mm256_loadu_ps(wL[c] + k), sl[c]));
      }
    }
  }
  for (int j = 0; j < 12; ++j) ray[j] += horizontalSum(r[j]);
  for (int j = 0; j < 6; ++j) sq[j] += horizontalSum(q[j]);
  if (k < count) groupPass<kFused>(px, py, pz, e, k, count, g, tv, wB, wL, ray, sq);
}
#endif

using GroupPass = void (*)(const float*, const float*, const float*, const float* const*, uint32_t, uint32_t,
                           const HitGroup&, const TableView&, float (*)[kChunk], float (*)[kChunk],
                           float*, float*);
struct GroupPasses {
  GroupPass fused = &groupPass<true>, split = &groupPass<false>;
};

GroupPasses groupPasses(bool portable) {
  GroupPasses p;
#ifdef TRANSLUCENT_MODEL_REFERENCE_AVX2
  if (!portable && __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) {
    p.fused = &groupPassAvx2<true>;
    p.split = &groupPassAvx2<false>;
  }
#else
  (void)portable;
#endif
  return p;
}

// Adds the samples of cells [begin, end) to `sums` for the hits of one pixel (in groups of four).
// Float arithmetic in chunks of kChunk samples (vectorised), chunk sums in double; the order is
// fixed, so the result does not depend on the thread.
void accumulate(const SampleGrid& grid, uint32_t begin, uint32_t end, int half,
                std::span<const HitGroup> groups, const TableView& tv, const GroupPasses& passes,
                PixelSums& sums) {
  alignas(64) float wB[3][kChunk], wL[3][kChunk];
  for (uint32_t first = begin; first < end; first += kChunk) {
    const uint32_t count = std::min(kChunk, end - first);
    const float* px = grid.x.data() + first;
    const float* py = grid.y.data() + first;
    const float* pz = grid.z.data() + first;
    const float* e[3] = {grid.e0.data() + first, grid.e1.data() + first, grid.e2.data() + first};
    float sq[6] = {0, 0, 0, 0, 0, 0};
    if (groups.size() == 1) {
      float ray[12] = {};
      passes.fused(px, py, pz, e, 0, count, groups[0], tv, wB, wL, ray, sq);
      for (int j = 0; j < 12; ++j) sums.ray[half][j / 3][j % 3] += double(ray[j]);
    } else {
      for (int c = 0; c < 3; ++c)
        for (uint32_t k = 0; k < count; ++k) wB[c][k] = wL[c][k] = 0.0f;
      for (size_t gi = 0; gi < groups.size(); ++gi) {
        float ray[12] = {};
        passes.split(px, py, pz, e, 0, count, groups[gi], tv, wB, wL, ray, sq);
        for (int j = 0; j < 12; ++j) sums.ray[half][4 * gi + size_t(j / 3)][j % 3] += double(ray[j]);
      }
      for (int c = 0; c < 3; ++c) {
        float b = 0.0f, l = 0.0f;
#pragma omp simd reduction(+ : b, l)
        for (uint32_t k = 0; k < count; ++k) {
          b += wB[c][k] * wB[c][k];
          l += wL[c][k] * wL[c][k];
        }
        sq[c] += b;
        sq[3 + c] += l;
      }
    }
    for (int c = 0; c < 3; ++c) {
      sums.b2[c] += double(sq[c]);
      sums.l2[c] += double(sq[3 + c]);
    }
  }
}

// ---- Heterogeneous materials (model_reference.h) --------------------------------------------

// ln P nodes of one medium: (n + 1) · 3 doubles, [k · 3 + c] (material::PointProfiles' layout).
using Nodes = std::vector<double>;

// 2π∫0^ρ P r dr of one channel of a representation: 8-point Gauss-Legendre on every piece of
// [0, min(ρ, r_cut)] between the nodes r_k = k r_s / n (ln P is linear on each; beyond r_s the
// tail is smooth), so it is exact to ~1e-10.
double representationCumulative(const double* nodes, int n, double rs, double rho) {
  static constexpr double kX[8] = {-0.9602898564975363, -0.7966664774136267, -0.5255324099163290,
                                   -0.1834346424956498, 0.1834346424956498,  0.5255324099163290,
                                   0.7966664774136267,  0.9602898564975363};
  static constexpr double kW[8] = {0.1012285362903763, 0.2223810344533745, 0.3137066578011563,
                                   0.3626837833783620, 0.3626837833783620, 0.3137066578011563,
                                   0.2223810344533745, 0.1012285362903763};
  const double end = std::min(rho, material::kExtrapolationFactor * rs);
  double sum = 0.0;
  for (int k = 0; k * rs / n < end; ++k) {
    const double a = k * rs / n, b = std::min(end, (k + 1) * rs / n);
    const double half = 0.5 * (b - a), mid = 0.5 * (a + b);
    for (int i = 0; i < 8; ++i) {
      const double r = mid + half * kX[i];
      sum += kW[i] * half * std::exp(material::lnProfileAt(nodes, 3, n, rs, r)) * r;
    }
  }
  return 2.0 * kPi * sum;
}

// What the heterogeneous path needs besides the homogeneous set-up.
struct Hetero {
  const material::Material* material = nullptr;
  int n = 0;
  double rs = 0.0, rCut = 0.0;
  std::vector<double> sampleNodes;  // per distinct sample medium u: (n + 1) · 3 at u (n + 1) 3
  std::vector<double> sampleSlopes; // per distinct sample medium u: tailSlopes, 3 at 3 u
  std::vector<uint32_t> mediumOf;   // per sample: its distinct medium u
  std::optional<geometry::Atlas> atlas;  // Kind::Surface
  const double* nodesOf(uint32_t u) const { return sampleNodes.data() + size_t(u) * size_t(n + 1) * 3; }
  const double* slopesOf(uint32_t u) const { return sampleSlopes.data() + size_t(u) * 3; }
};

// Per channel, the slope s of the extrapolated tail of one representation (lnProfileAt:
// ln P = v_n + (t − n) s − 2 ln(t / n) beyond r_s, t = n r / r_s), or +∞ where it has none
// (s >= 0: P = 0 beyond r_s).
void tailSlopes(const double* nodes, int n, double out[3]) {
  const double c = n > 1 ? 2.0 * std::log(double(n) / double(n - 1)) : 0.0;
  for (int ch = 0; ch < 3; ++ch) {
    const double s = nodes[size_t(n) * 3 + size_t(ch)] - nodes[size_t(n - 1) * 3 + size_t(ch)] + c;
    out[ch] = s < 0.0 ? s : std::numeric_limits<double>::infinity();
  }
}

// Eq. 8 at t = n r / r_s for two representations on the same grid (a, b: (n + 1) · 3 nodes; sa,
// sb: their tailSlopes): sqrt(P_a P_b) per channel, what exp((lnProfileAt(a) + lnProfileAt(b)) / 2)
// gives, with one (k, w) for both and, in the tail, the r² factor as (n / t)² instead of a log.
[[gnu::always_inline]] inline void eq8(const double* a, const double* b, const double* sa,
                                       const double* sb, int n, double t, double out[3]) {
  if (t <= double(n)) {
    const int k = std::min(static_cast<int>(t), n - 1);
    const double w = t - k;
    const double* a0 = a + size_t(k) * 3;
    const double* b0 = b + size_t(k) * 3;
    for (int c = 0; c < 3; ++c)
      out[c] = std::exp(0.5 * ((1.0 - w) * (a0[c] + b0[c]) + w * (a0[c + 3] + b0[c + 3])));
    return;
  }
  if (t > material::kExtrapolationFactor * n) {
    out[0] = out[1] = out[2] = 0.0;
    return;
  }
  const double q = double(n) / t, r2 = n > 1 ? q * q : 1.0;
  const double* an = a + size_t(n) * 3;
  const double* bn = b + size_t(n) * 3;
  for (int c = 0; c < 3; ++c) {
    const double s = 0.5 * (sa[c] + sb[c]);  // +∞ when either has no tail
    out[c] = s < 0.0 ? std::exp(0.5 * (an[c] + bn[c]) + (t - n) * s) * r2 : 0.0;
  }
}

using MediumKey = std::array<double, 7>;
MediumKey keyOf(const material::LocalMedium& m) {
  return {m.sigma_a[0], m.sigma_a[1], m.sigma_a[2], m.sigma_s[0], m.sigma_s[1], m.sigma_s[2], m.g};
}

// A camera hit's profile, by medium (one map per image row: deterministic whatever the thread).
struct HitProfile {
  Nodes nodes;
  double slopes[3]{};  // tailSlopes
  double near[3]{};    // F_c(ρ) of the representation
};
using HitProfiles = std::map<MediumKey, HitProfile>;

const HitProfile& hitProfile(const Hetero& het, const material::LocalMedium& m, double rho,
                             HitProfiles& cache) {
  const MediumKey key = keyOf(m);
  auto it = cache.find(key);
  if (it != cache.end()) return it->second;
  const material::PointProfiles p =
      material::PointProfiles::build(*het.material, std::span(&m, 1), {het.n, het.rs});
  HitProfile h;
  h.nodes = p.nodes();
  tailSlopes(h.nodes.data(), het.n, h.slopes);
  for (int c = 0; c < 3; ++c) h.near[c] = representationCumulative(h.nodes.data() + c, het.n, het.rs, rho);
  return cache.emplace(key, std::move(h)).first->second;
}

// The heterogeneous counterpart of accumulate: samples [begin, end) of the grid against the
// pixel's hits, Eq. 8 per pair in double, the same sums (per-ray, and the second moments of the
// per-sample terms). Fixed order: deterministic.
void accumulateHetero(const SampleGrid& grid, uint32_t begin, uint32_t end, int half,
                      std::span<const RayHit> hits, std::span<const HitProfile* const> hitProfiles,
                      const Hetero& het, double rho, PixelSums& sums) {
  const double rho2 = rho * rho, cut2 = het.rCut * het.rCut, scale = het.n / het.rs;
  for (uint32_t k = begin; k < end; ++k) {
    const double px = static_cast<double>(grid.x[k]), py = static_cast<double>(grid.y[k]),
                 pz = static_cast<double>(grid.z[k]);
    const double e[3] = {static_cast<double>(grid.e0[k]), static_cast<double>(grid.e1[k]),
                        static_cast<double>(grid.e2[k])};
    const double* nk = het.nodesOf(grid.tag[k]);
    const double* sk = het.slopesOf(grid.tag[k]);
    double vb[3] = {0.0, 0.0, 0.0}, vl[3] = {0.0, 0.0, 0.0};
    bool any = false;
    for (size_t s = 0; s < hits.size(); ++s) {
      const double dx = px - double(hits[s].x), dy = py - double(hits[s].y), dz = pz - double(hits[s].z);
      const double d2 = dx * dx + dy * dy + dz * dz;
      if (d2 < rho2 || d2 > cut2) continue;
      double kernel[3];
      eq8(nk, hitProfiles[s]->nodes.data(), sk, hitProfiles[s]->slopes, het.n, std::sqrt(d2) * scale, kernel);
      const double f = double(hits[s].factor);
      for (int c = 0; c < 3; ++c) {
        const double v = kernel[c] * e[c];
        sums.ray[half][s][c] += v;
        vb[c] += v;
        vl[c] += f * v;
      }
      any = true;
    }
    if (!any) continue;
    for (int c = 0; c < 3; ++c) {
      sums.b2[c] += vb[c] * vb[c];
      sums.l2[c] += vl[c] * vl[c];
    }
  }
}

}  // namespace

void ModelReferenceOptions::validate() const {
  if (samples == 0 || samples > kMaxSamples)
    throw ParameterError(fmt::format("model reference: samples is {}: expected 1 to {}", samples,
                                     kMaxSamples));
  if (subpixels < 1 || subpixels > kMaxSubpixels)
    throw ParameterError(fmt::format("model reference: subpixels is {}: expected 1 to {} rays per "
                                     "pixel per axis", subpixels, kMaxSubpixels));
  if (threads < 0)
    throw ParameterError(fmt::format("model reference: threads is {}: expected >= 0 (0: all)", threads));
  if (!(near_field > 0.0 && std::isfinite(near_field)))
    throw ParameterError(fmt::format("model reference: near_field is {}: expected a radius > 0 in "
                                     "sample spacings", near_field));
  if (!(tail > 0.0 && tail <= 0.01))
    throw ParameterError(fmt::format("model reference: tail is {}: expected a fraction of Rd in "
                                     "(0, 0.01]", tail));
  if (environment_rays < 2 || environment_rays > 4096 || environment_rays % 2 != 0)
    throw ParameterError(fmt::format("model reference: environment_rays is {}: expected an even "
                                     "number from 2 to 4096", environment_rays));
  if (profile_segments < 1 || profile_segments > 1024)
    throw ParameterError(fmt::format("model reference: profile_segments is {}: expected 1 to 1024 "
                                     "segments of ln P", profile_segments));
}

namespace {

// Both paths: `material` null for the homogeneous one (`model` and `medium`), else heterogeneous
// (`medium`: material->medium, `model` unused).
ModelReferenceImages render(const geometry::TriangleMesh& meshIn, const Medium& medium,
                            const bssrdf::Model* model, const material::Material* material,
                            std::span<const Light> lights, const Camera& camera,
                            const ModelReferenceOptions& options, const ProgressCallback& progress) {
  const auto start = std::chrono::steady_clock::now();
  // Check the set-up before any work.
  options.validate();
  medium.validate();
  camera.validate();
  const std::vector<LightTerm> terms = lightTerms(lights);
  meshIn.validate("model reference mesh");
  meshIn.requireClosed("model reference mesh");
  geometry::TriangleMesh mesh = meshIn;
  mesh.orientOutwards();  // face normals point out (the technique does the same)

  std::vector<std::unique_ptr<bssrdf::RadialProfile>> profiles;
  if (!material)
    for (int c = 0; c < 3; ++c) profiles.push_back(model->profile(medium.channel(c)));
  const double eta = medium.eta;
  const double norm = bssrdf::diffuseTransmittanceFromOutside(eta);
  const int threads = detail::resolveThreads(options.threads, std::numeric_limits<uint64_t>::max());
  tbb::task_arena arena(threads);

  ModelReferenceImages out;
  out.width = camera.width;
  out.height = camera.height;
  out.samples = options.samples;
  out.threads = threads;

  // Radii: ρ from the sample spacing, r_max from the profiles' tails.
  const double area = mesh.area();
  out.area = area;
  const double rho = options.near_field * std::sqrt(area / double(options.samples));
  out.near_radius = rho;
  // Homogeneous: the model's profile, its table and r_max (heterogeneous: after the samples).
  double rMax = 0.0;
  double nearF[3]{};
  ProfileGrid table;
  if (!material) {
    for (const auto& p : profiles) rMax = std::max(rMax, p->radiusForFraction(1.0 - options.tail));
    if (!(rho < rMax))
      throw ParameterError(fmt::format(
          "model reference: samples is {}: the near-field radius ρ = {:.4g} (near_field {} sample "
          "spacings) reaches the profile's pruning radius {:.4g}: expected more samples",
          options.samples, rho, options.near_field, rMax));
    out.prune_radius = rMax;
    for (size_t c = 0; c < 3; ++c) {
      const double rd = profiles[c]->Rd();
      nearF[c] = cumulativeAt(*profiles[c], rho);
      out.near_fraction[c] = rd > 0.0 ? nearF[c] / rd : 0.0;
      out.tail_fraction[c] = rd > 0.0 ? std::max(0.0, 1.0 - cumulativeAt(*profiles[c], rMax) / rd) : 0.0;
    }

    // Profile table: refined until linear interpolation is within 1e-4 of R at the midpoints.
    for (size_t n = 2048;; n *= 2) {
      table = tabulate(profiles, rho, rMax, n);
      if (table.maxRelative <= 1e-4 || n >= 65536) break;
    }
    out.table_size = table.n;
    out.table_error = table.integrated;
  }

  // Geometry: ray queries, smooth (G-buffer) normals, the samples and their irradiance.
  const geometry::RayScene scene(mesh, "model reference mesh", geometry::RayScene::Quality::High);
  const geometry::Bounds bounds = mesh.bounds();
  const double eps = 1e-5 * (glm::length(bounds.center()) + bounds.radius());  // as MeshBody
  const std::vector<glm::dvec3> smooth = geometry::ambientOcclusionNormals(mesh);
  geometry::SamplingOptions so;
  so.count = static_cast<size_t>(options.samples);
  so.seed = options.seed;
  so.method = geometry::SamplingMethod::Random;
  const geometry::PointCloud cloud = arena.execute([&] { return geometry::samplePointCloud(mesh, so); });
  std::vector<Rgb> irradiance(cloud.size());
  const uint64_t envSeed = environmentSeed(options.seed);
  const int samplePairs = std::max(1, options.environment_rays / 2);
  // At the camera hits E multiplies the near field's share of Rd directly (not averaged over
  // many samples): 4x the rays there.
  const int hitPairs = 4 * samplePairs;
  {
    constexpr uint64_t kBlock = 4096;
    const uint64_t blocks = (cloud.size() + kBlock - 1) / kBlock;
    struct None {};
    detail::runBlocks<None>(
        0, blocks, threads, [] { return None{}; },
        [&](uint64_t b, None&, const std::atomic<bool>&) {
          const size_t end = std::min<size_t>(cloud.size(), (b + 1) * kBlock);
          for (size_t k = b * kBlock; k < end; ++k) {
            Rng rng(envSeed, k);
            Rgb var{};  // part of the per-sample terms' spread (the standard error's estimate)
            irradiance[k] = transmittedIrradiance(glm::dvec3(cloud.positions[k]),
                                                  glm::dvec3(cloud.normals[k]), terms, scene, eps,
                                                  eta, true, samplePairs, rng, var);
          }
          return true;
        },
        [](uint64_t, None&) {}, {});
  }
  // Heterogeneous: the samples' local media, deduplicated, and their profiles (which fix r_s).
  Hetero het;
  if (material) {
    het.material = material;
    het.n = options.profile_segments;
    if (material->kind == material::Material::Kind::Surface)
      het.atlas = geometry::loadOrBuildAtlas(mesh, geometry::AtlasOptions{}).atlas;
    std::vector<glm::vec2> uvs;
    if (het.atlas) {
      if (cloud.faces.size() != cloud.size())
        throw ParameterError("model reference: a surface-map material needs the triangle of every "
                             "sample: the point cloud has none");
      uvs = material::atlasUvs(mesh, *het.atlas, cloud.faces, cloud.positions);
    }
    const std::vector<material::LocalMedium> media =
        material::PointProfiles::surfaceMedia(*material, cloud.positions, cloud.normals, uvs);
    std::map<MediumKey, uint32_t> index;
    std::vector<material::LocalMedium> distinct;
    het.mediumOf.resize(media.size());
    for (size_t k = 0; k < media.size(); ++k) {
      auto [it, inserted] = index.try_emplace(keyOf(media[k]), static_cast<uint32_t>(distinct.size()));
      if (inserted) distinct.push_back(media[k]);
      het.mediumOf[k] = it->second;
    }
    const material::PointProfiles p = material::PointProfiles::build(*material, distinct, {het.n, 0.0});
    het.rs = p.radius();
    het.rCut = p.cutRadius();
    het.sampleNodes = p.nodes();
    het.sampleSlopes.resize(3 * distinct.size());
    for (size_t u = 0; u < distinct.size(); ++u)
      tailSlopes(het.nodesOf(static_cast<uint32_t>(u)), het.n, &het.sampleSlopes[3 * u]);
    rMax = het.rCut;
    if (!(rho < rMax))
      throw ParameterError(fmt::format(
          "model reference: samples is {}: the near-field radius ρ = {:.4g} (near_field {} sample "
          "spacings) reaches the profiles' cut radius {:.4g}: expected more samples",
          options.samples, rho, options.near_field, rMax));
    out.heterogeneous = true;
    out.profile_segments = het.n;
    out.profile_radius = het.rs;
    out.sample_media = distinct.size();
    out.prune_radius = rMax;
    for (size_t u = 0; u < distinct.size(); ++u)
      for (int c = 0; c < 3; ++c) {
        const double* nodes = het.nodesOf(static_cast<uint32_t>(u)) + c;
        const double total = representationCumulative(nodes, het.n, het.rs, het.rCut);
        if (total > 0.0)
          out.near_fraction[size_t(c)] = std::max(out.near_fraction[size_t(c)],
                                                  representationCumulative(nodes, het.n, het.rs, rho) / total);
      }
  }
  const SampleGrid grid = buildGrid(cloud, irradiance, rMax, material ? &het.mediumOf : nullptr);
  out.lit_samples = grid.x.size();

  // Per pixel.
  const CameraModel cam(camera);
  const int w = camera.width, h = camera.height, S = options.subpixels, M = S * S;
  const size_t npix = size_t(w) * size_t(h);
  out.exitance.assign(3 * npix, 0.0f);
  out.exitance_se.assign(3 * npix, 0.0f);
  out.radiance.assign(3 * npix, 0.0f);
  out.radiance_se.assign(3 * npix, 0.0f);
  out.coverage.assign(npix, 0.0f);
  const double N = double(options.samples);
  const GroupPasses passes = groupPasses(options.portable);
  TableView tv{};
  if (!material) {
    tv.T = table.values.data();
    tv.s0 = static_cast<float>(table.s0);
    tv.inv = static_cast<float>(double(table.n - 1) / (table.s1 - table.s0));
    tv.tMax = static_cast<float>(table.n - 1) * (1.0f - 1e-6f);  // keeps i + 1 inside the table
    tv.rho2 = static_cast<float>(rho * rho);
    tv.rMax2 = static_cast<float>(rMax * rMax);
  }

  struct Row {
    std::vector<float> b, bse, l, lse, cov;
    size_t media = 0;  // heterogeneous: hit profiles evaluated
  };
  auto work = [&](uint64_t j, Row& row, const std::atomic<bool>& stop) {
    row.b.assign(3 * size_t(w), 0.0f);
    row.bse = row.l = row.lse = row.b;
    row.cov.assign(size_t(w), 0.0f);
    auto sums = std::make_unique<PixelSums>();
    std::vector<RayHit> hits;
    std::vector<HitGroup> groups;
    HitProfiles hitProfiles;              // heterogeneous: the row's hit media
    std::vector<const HitProfile*> hitNodes;  // heterogeneous: per hit, its profile
    for (int i = 0; i < w; ++i) {
      if (stop.load(std::memory_order_relaxed)) return false;
      // Camera rays: stratified over the pixel, at the strata's centres or jittered from the
      // pixel's own stream.
      hits.clear();
      hitNodes.clear();
      Rng rng(options.seed, uint64_t(j) * uint64_t(w) + uint64_t(i));
      std::vector<int> rayOf;  // hit index -> ray index (misses have none)
      double rayNearB[kMaxRays][3]{}, rayNearL[kMaxRays][3]{};
      double nearVarB[3]{}, nearVarL[3]{};  // Σ_r of the near terms' variance (environment rays)
      for (int sy = 0; sy < S; ++sy)
        for (int sx = 0; sx < S; ++sx) {
          const double ux = options.jitter ? uniform01(rng) : 0.5;
          const double uy = options.jitter ? uniform01(rng) : 0.5;
          glm::dvec3 o, d;
          cam.ray(i + (sx + ux) / S, double(j) + (sy + uy) / S, o, d);
          geometry::RayHit hit;
          if (!scene.intersect(o, d, 0.0, std::numeric_limits<double>::infinity(), hit)) continue;
          const glm::dvec3 x = o + hit.t * d;
          const glm::uvec3 tri = mesh.triangles[hit.triangle];
          const glm::dvec3 p0 = mesh.positions[tri.x], e1 = mesh.positions[tri.y] - p0,
                           e2 = mesh.positions[tri.z] - p0, q = x - p0;
          // Barycentrics of x on its triangle (for the interpolated normals).
          const double d11 = glm::dot(e1, e1), d12 = glm::dot(e1, e2), d22 = glm::dot(e2, e2);
          const double q1 = glm::dot(q, e1), q2 = glm::dot(q, e2), den = d11 * d22 - d12 * d12;
          const double b1 = (d22 * q1 - d12 * q2) / den, b2 = (d11 * q2 - d12 * q1) / den,
                       b0 = 1.0 - b1 - b2;
          const bool back = glm::dot(hit.normal, d) > 0.0;
          glm::dvec3 ns = b0 * smooth[tri.x] + b1 * smooth[tri.y] + b2 * smooth[tri.z];
          ns = glm::length(ns) > 1e-12 ? glm::normalize(ns) : hit.normal;
          if (back) ns = -ns;
          // The irradiance normal, as the point cloud's (geometry/point_cloud.h).
          glm::dvec3 ne = hit.normal;
          if (!mesh.normals.empty()) {
            const glm::dvec3 v = b0 * mesh.normals[tri.x] + b1 * mesh.normals[tri.y] +
                                 b2 * mesh.normals[tri.z];
            if (glm::length(v) > 1e-12) ne = glm::normalize(v);
          }
          // The near disc's share of the profile: the model's (homogeneous) or x_o's own
          // representation (heterogeneous: the local homogeneous approximation).
          const double* nf = nearF;
          if (material) {
            const glm::dvec2 uv = het.atlas ? material::atlasUvAt(mesh, *het.atlas, hit.triangle, x)
                                            : glm::dvec2(0.0);
            const HitProfile& hp = hitProfile(het, material->surfaceMedium(x, ne, uv), rho, hitProfiles);
            nf = hp.near;
            hitNodes.push_back(&hp);
          }
          const double cosO = glm::dot(ns, -d);
          RayHit rh;
          rh.x = static_cast<float>(x.x);
          rh.y = static_cast<float>(x.y);
          rh.z = static_cast<float>(x.z);
          const double factor =
              cosO > 0.0 ? bssrdf::exitRadianceFactor(options.convention, eta, std::min(cosO, 1.0), norm)
                         : 0.0;
          rh.factor = static_cast<float>(factor);
          const int r = sy * S + sx;
          Rng envRng(envSeed, cloud.size() + (uint64_t(j) * uint64_t(w) + uint64_t(i)) * kMaxRays + uint64_t(r));
          Rgb e0Var{};
          const Rgb e0 = transmittedIrradiance(x, ne, terms, scene, eps, eta, false, hitPairs, envRng, e0Var);
          for (size_t c = 0; c < 3; ++c) {
            nearVarB[c] += e0Var[c] * nf[c] * nf[c];
            nearVarL[c] += e0Var[c] * nf[c] * nf[c] * factor * factor;
            rh.near[c] = e0[c] * nf[c];
            rayNearB[r][c] = rh.near[c];
            rayNearL[r][c] = double(rh.factor) * rh.near[c];
          }
          hits.push_back(rh);
          rayOf.push_back(r);
        }
      row.cov[size_t(i)] = float(hits.size()) / float(M);
      if (hits.empty()) continue;

      // The samples within r_max of any hit: cells whose box is closer than r_max to the hits'
      // bounding box.
      *sums = PixelSums{};
      glm::dvec3 lo(hits[0].x, hits[0].y, hits[0].z), hi = lo;
      for (const RayHit& rh : hits) {
        lo = glm::min(lo, glm::dvec3(rh.x, rh.y, rh.z));
        hi = glm::max(hi, glm::dvec3(rh.x, rh.y, rh.z));
      }
      glm::ivec3 c0, c1;
      for (int a = 0; a < 3; ++a) {
        c0[a] = std::clamp(int(std::floor((lo[a] - rMax - grid.origin[a]) / grid.cell)), 0, grid.dims[a] - 1);
        c1[a] = std::clamp(int(std::floor((hi[a] + rMax - grid.origin[a]) / grid.cell)), 0, grid.dims[a] - 1);
      }
      groups.assign((hits.size() + 3) / 4, HitGroup{});
      for (size_t k = 0; k < 4 * groups.size(); ++k) {
        HitGroup& g = groups[k / 4];
        const bool used = k < hits.size();
        // An unused slot lies so far away that every sample is beyond r_max.
        g.x[k % 4] = used ? hits[k].x : 1e30f;
        g.y[k % 4] = used ? hits[k].y : 1e30f;
        g.z[k % 4] = used ? hits[k].z : 1e30f;
        g.f[k % 4] = used ? hits[k].factor : 0.0f;
      }
      for (int cz = c0.z; cz <= c1.z; ++cz)
        for (int cy = c0.y; cy <= c1.y; ++cy)
          for (int cx = c0.x; cx <= c1.x; ++cx) {
            const size_t cell = size_t((cz * grid.dims.y + cy) * grid.dims.x + cx);
            const uint32_t b = grid.start[cell], e = grid.start[cell + 1];
            if (b == e) continue;
            const glm::dvec3 cl = grid.lower({cx, cy, cz}), cu = cl + glm::dvec3(grid.cell);
            const glm::dvec3 gap = glm::max(glm::max(cl - hi, lo - cu), glm::dvec3(0.0));
            if (glm::dot(gap, gap) > rMax * rMax) continue;
            if (material) {
              accumulateHetero(grid, b, grid.middle[cell], 0, hits, hitNodes, het, rho, *sums);
              accumulateHetero(grid, grid.middle[cell], e, 1, hits, hitNodes, het, rho, *sums);
              continue;
            }
            accumulate(grid, b, grid.middle[cell], 0, groups, tv, passes, *sums);
            accumulate(grid, grid.middle[cell], e, 1, groups, tv, passes, *sums);
          }

      // Estimates: near field + (1/N) Σ t_k with t_k = A (1/M) Σ_s R E, and standard errors.
      for (size_t c = 0; c < 3; ++c) {
        auto estimate = [&](bool radiance, double s2, float& value, float& se) {
          // Per-ray values from each half of the samples (misses 0): the near field plus
          // A/N_half Σ_{k in half} (f_s) v_sk.
          double half[2][kMaxRays]{};
          const double nHalf[2] = {std::ceil(0.5 * N), std::floor(0.5 * N)};
          double s = 0.0;  // Σ_k Σ_s (f_s) v_sk
          for (int hf = 0; hf < 2; ++hf) {
            for (int r = 0; r < M; ++r) half[hf][r] = radiance ? rayNearL[r][c] : rayNearB[r][c];
            for (size_t k = 0; k < hits.size(); ++k) {
              const double f = radiance ? double(hits[k].factor) : 1.0;
              s += f * sums->ray[hf][k][c];
              if (nHalf[hf] > 0.0) half[hf][rayOf[k]] += area / nHalf[hf] * f * sums->ray[hf][k][c];
            }
          }
          double near = 0.0;
          for (int r = 0; r < M; ++r) near += radiance ? rayNearL[r][c] : rayNearB[r][c];
          near /= M;
          // Σ t_k and Σ t_k² with t_k = (A/M) Σ_s (f_s) v_sk.
          const double tSum = area * s / M, tSum2 = area * area * s2 / (double(M) * M);
          const double mean = tSum / N;
          const double var = N > 1.0 ? std::max(0.0, (tSum2 - N * mean * mean) / (N - 1.0)) : 0.0;
          // The near field's own noise where E came from environment rays (independent of the
          // samples'): the mean of M rays' terms.
          double v = var / N + (radiance ? nearVarL[c] : nearVarB[c]) / (double(M) * M);
          value = static_cast<float>(near + mean);
          if (options.jitter && M > 1 && N > 1.0) {
            // The spread of the true per-ray values, from the product of the two halves'
            // deviations: their noises are independent, so it has no noise term in expectation
            // (the spread of one half's values would add the decorrelated part of the noise).
            double m0 = 0.0, m1 = 0.0, q = 0.0;
            for (int r = 0; r < M; ++r) m0 += half[0][r], m1 += half[1][r];
            m0 /= M;
            m1 /= M;
            for (int r = 0; r < M; ++r) q += (half[0][r] - m0) * (half[1][r] - m1);
            v += std::max(0.0, q) / (double(M - 1) * M);
          }
          se = static_cast<float>(std::sqrt(v));
        };
        estimate(false, sums->b2[c], row.b[3 * size_t(i) + c], row.bse[3 * size_t(i) + c]);
        estimate(true, sums->l2[c], row.l[3 * size_t(i) + c], row.lse[3 * size_t(i) + c]);
      }
    }
    row.media = hitProfiles.size();
    return true;
  };
  auto merge = [&](uint64_t j, Row& row) {
    out.hit_media += row.media;
    const size_t o = 3 * size_t(j) * size_t(w);
    std::copy(row.b.begin(), row.b.end(), out.exitance.begin() + long(o));
    std::copy(row.bse.begin(), row.bse.end(), out.exitance_se.begin() + long(o));
    std::copy(row.l.begin(), row.l.end(), out.radiance.begin() + long(o));
    std::copy(row.lse.begin(), row.lse.end(), out.radiance_se.begin() + long(o));
    std::copy(row.cov.begin(), row.cov.end(), out.coverage.begin() + long(size_t(j) * size_t(w)));
  };
  std::function<bool(uint64_t, double)> tick;
  const uint64_t total = npix;
  if (progress)
    tick = [&](uint64_t rows, double seconds) {
      return progress(TraceProgress{rows * uint64_t(w), total, seconds});
    };
  const detail::BlockRun run = detail::runBlocks<Row>(0, uint64_t(h), threads, [] { return Row{}; },
                                                      work, merge, tick);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (progress) progress(TraceProgress{run.blocks_done * uint64_t(w), total, out.seconds});
  out.partial = run.stopped;
  return out;
}

}  // namespace

ModelReferenceImages renderModelReference(const geometry::TriangleMesh& mesh, const Medium& medium,
                                          const bssrdf::Model& model, std::span<const Light> lights,
                                          const Camera& camera, const ModelReferenceOptions& options,
                                          const ProgressCallback& progress) {
  return render(mesh, medium, &model, nullptr, lights, camera, options, progress);
}

ModelReferenceImages renderModelReference(const geometry::TriangleMesh& mesh,
                                          const material::Material& material,
                                          std::span<const Light> lights, const Camera& camera,
                                          const ModelReferenceOptions& options,
                                          const ProgressCallback& progress) {
  if (bssrdf::hasBssrdfExtension(material.model))
    throw ParameterError(fmt::format(
        "model reference: the material's model is the .bssrdf file '{}'; the model reference "
        "integrates a registered model", material.model));
  if (!material.heterogeneous())
    return render(mesh, material.medium, &bssrdf::model(material.model), nullptr, lights, camera,
                  options, progress);
  if (material.kind == material::Material::Kind::Volume && !material.volume)
    throw ParameterError("model reference: a volume material without its field");
  if (material.kind == material::Material::Kind::Surface && !material.surface)
    throw ParameterError("model reference: a surface-map material without its map");
  return render(mesh, material.medium, nullptr, &material, lights, camera, options, progress);
}

}  // namespace translucent::reference
