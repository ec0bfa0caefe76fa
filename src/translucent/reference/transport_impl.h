// SPDX-License-Identifier: GPL-3.0-or-later
// Internal to src/reference: the photon walk of transport.h as a template on the body type, so
// that a final body class (the analytic sphere) gets its ray queries inlined. transport.cpp
// instantiates it for the abstract Body; sphere.cpp for SphereBody.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "translucent/optics/fresnel.h"
#include "translucent/reference/block_driver.h"
#include "translucent/reference/majorant_grid.h"
#include "translucent/reference/phase.h"
#include "translucent/reference/rng.h"
#include "translucent/reference/sampling.h"
#include "translucent/reference/transport.h"
#include "translucent/reference/walk.h"

namespace translucent::reference::detail {

// Everything one channel's walk needs, precomputed.
struct ChannelWalk {
  double sigmaT = 1.0;
  double absorbProbability = 0.0;  // 1 - α
  float g = 0.0f;
  double eta = 1.0;  // n_inside / n_outside
  bool matched = true;
  bool afterSpecularOnly = false;  // TransportOptions::after_specular_only
  std::vector<double> lightCdf;  // light selection, ∝ flux in this channel
  double totalFlux = 0.0;        // what every photon of this channel carries
};

// Per-block counters (per channel).
struct BlockCounters {
  std::vector<Moments> emitted, entered, exited, escaped;
  std::array<std::vector<Moments>, kScatteringOrders> exitedByOrder;
  uint64_t events = 0;
  explicit BlockCounters(size_t channels)
      : emitted(channels), entered(channels), exited(channels), escaped(channels),
        exitedByOrder{std::vector<Moments>(channels), std::vector<Moments>(channels),
                      std::vector<Moments>(channels)} {}
  // One photon's exits of channel c summed by order (before squaring: transport.h).
  void addExitedByOrder(size_t c, const std::array<double, kScatteringOrders>& byOrder) {
    for (size_t k = 0; k < kScatteringOrders; ++k) exitedByOrder[k][c].add(byOrder[k]);
  }
};

// A block's counters into the run's statistics (every channel traced kBlockPhotons photons).
inline void addBlock(TransportStats& stats, const BlockCounters& k) {
  for (size_t c = 0; c < k.emitted.size(); ++c) {
    stats.photons[c] += kBlockPhotons;
    stats.emitted[c].add(k.emitted[c].s, k.emitted[c].s2);
    stats.entered[c].add(k.entered[c].s, k.entered[c].s2);
    stats.exited[c].add(k.exited[c].s, k.exited[c].s2);
    stats.escaped[c].add(k.escaped[c].s, k.escaped[c].s2);
    for (size_t o = 0; o < kScatteringOrders; ++o)
      stats.exited_by_order[o][c].add(k.exitedByOrder[o][c].s, k.exitedByOrder[o][c].s2);
  }
  stats.scattering_events += k.events;
}

// Whether the body type declares itself convex (transport.h: `static constexpr bool kConvex`):
// then an exit ray cannot meet the body again and the re-entry query is skipped.
template <class BodyT>
constexpr bool convexBody() {
  if constexpr (requires { BodyT::kConvex; })
    return BodyT::kConvex;
  else
    return false;
}

// Refraction of unit `d` through a surface with unit normal `n` on the transmitted side
// (d·n > 0), cos_t from refractedCosine and ratio = n_incident / n_transmitted.
inline glm::dvec3 refract(const glm::dvec3& d, const glm::dvec3& n, double ratio, double cos_t) {
  const double cos_i = glm::dot(d, n);
  return glm::normalize(ratio * d + (cos_t - ratio * cos_i) * n);
}

// A photon's emission: ray origin, direction (unit).
struct Emission {
  glm::dvec3 origin, direction;
};

inline Emission emit(const Light& light, const BoundingSphere& b, int channel, Rng& rng) {
  Emission e;
  if (const auto* el = std::get_if<EnvironmentLight>(&light.emitter)) {
    // A direction by the channel's radiance, then a point of the disc covering the bounding
    // sphere perpendicular to it, outside the sphere (transport.h, EnvironmentLight). A channel
    // without radiance is never chosen (its flux is 0) unless every light is black in it, and
    // then its photons carry 0 whatever they do: any direction will do.
    const auto& sampler = el->samplers[static_cast<size_t>(channel)];
    glm::dvec3 toEnv{0.0, 1.0, 0.0};
    if (sampler) {
      const double u = uniform01(rng), v = uniform01(rng);
      toEnv = sampler->sample({u, v}).direction;
    }
    glm::dvec3 t1, t2;
    tangentFrame(toEnv, t1, t2);
    double x, y;
    sampleDisc(rng, b.radius, x, y);
    e.origin = b.center + 2.0 * b.radius * toEnv + x * t1 + y * t2;
    e.direction = -toEnv;
  } else if (const auto* dl = std::get_if<DirectionalLight>(&light.emitter)) {
    // A point on the disc that covers the bounding sphere, far enough out to be outside it.
    glm::dvec3 t1, t2;
    tangentFrame(dl->direction, t1, t2);
    double x, y;
    sampleDisc(rng, b.radius, x, y);
    e.origin = b.center + 2.0 * b.radius * dl->direction + x * t1 + y * t2;
    e.direction = -dl->direction;
  } else if (const auto* pl = std::get_if<PointLight>(&light.emitter)) {
    // Uniform within the cone that holds the bounding sphere (or over all directions when the
    // light is inside it).
    const glm::dvec3 toCenter = b.center - pl->position;
    const double dist = glm::length(toCenter);
    double cosMax = -1.0;
    glm::dvec3 axis{0.0, 0.0, 1.0};
    if (dist > b.radius) {
      axis = toCenter / dist;
      cosMax = std::sqrt(std::max(0.0, 1.0 - (b.radius / dist) * (b.radius / dist)));
    }
    const double cosT = 1.0 - uniform01(rng) * (1.0 - cosMax);
    const double sinT = std::sqrt(std::max(0.0, 1.0 - cosT * cosT));
    const double phi = 2.0 * std::numbers::pi * uniform01(rng);
    glm::dvec3 t1, t2;
    tangentFrame(axis, t1, t2);
    e.direction = glm::normalize(sinT * std::cos(phi) * t1 + sinT * std::sin(phi) * t2 + cosT * axis);
    // The ray starts at t0 = dist - 2R from the light (about 2R from the centre), not at the
    // light: no point of the ray with t <= t0 lies in the bounding sphere (|p + t d - c| >=
    // dist - t >= 2R), so the photon's path is the same, but the ray queries see an origin of the
    // size of the body, as the directional light's (2R from the centre).
    // Embree intersects in single precision, with errors of about |origin| 2^-24 in the hit
    // distance: from a light 1000 radii away that is several times the surface epsilon
    // (mesh_tracer.h), the entry point then lands off the surface, the first flight "leaves"
    // through the triangle it entered by, and the walk goes astray (measured: 92% of the
    // entering flux exited instead of the 60% of the equivalent sun).
    e.origin = pl->position;
    if (dist > 2.0 * b.radius) e.origin += (dist - 2.0 * b.radius) * e.direction;
  } else {
    const auto& bl = std::get<BeamLight>(light.emitter);
    glm::dvec3 t1, t2;
    tangentFrame(bl.direction, t1, t2);
    double x = 0.0, y = 0.0;
    if (bl.radius > 0.0) sampleDisc(rng, bl.radius, x, y);
    e.origin = bl.origin + x * t1 + y * t2;
    e.direction = bl.direction;
  }
  return e;
}

// The flight in air of a photon that left the body at x along d (transport.h): true if it meets
// the body again and is refracted in, with x, d the re-entry point and the inward direction;
// false if it escapes. At each hit the outside Fresnel reflectance F decides, with probability F,
// a mirror reflection that keeps the photon in air (traced, not dropped: transport.h says why);
// `mirrored` (when given) says whether one happened. The camera method's paths fly in air by it
// too (camera_paths.cpp: crossFromInside), so both methods see one boundary.
template <class BodyT>
bool reenter(const BodyT& body, const ChannelWalk& W, double eps, glm::dvec3& x, glm::dvec3& d,
             Rng& rng, bool* mirrored = nullptr) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  SurfaceHit hit;
  for (;;) {
    if (!body.intersect(x, d, eps, kInf, hit)) return false;
    x += hit.t * d;
    if (W.matched) return true;
    const glm::dvec3 inward = glm::dot(hit.normal, d) > 0.0 ? hit.normal : -hit.normal;
    const double cosI = glm::dot(d, inward);
    const double F = fresnelReflectance(cosI, W.eta);
    if (uniform01(rng) < F) {
      d = glm::normalize(d - 2.0 * cosI * inward);
      if (mirrored) *mirrored = true;
      continue;
    }
    d = refract(d, inward, 1.0 / W.eta, refractedCosine(cosI, W.eta));
    return true;
  }
}

// A photon's start: the light (probability ∝ its flux, so every photon carries the total),
// emission, and the entry at the first hit with the Fresnel transmittance as a weight and Snell
// refraction. False (and the photon's zero scores recorded) when the ray misses the body.
template <class BodyT>
bool launch(const BodyT& body, const BoundingSphere& bounds, std::span<const Light> lights,
            const ChannelWalk& W, int c, Rng& rng, BlockCounters& k, ExitTally::Block& tally,
            double& w, glm::dvec3& x, glm::dvec3& d) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const size_t ci = static_cast<size_t>(c);
  w = W.totalFlux;
  k.emitted[ci].add(w);
  size_t li = 0;
  if (lights.size() > 1) {
    const double u = uniform01(rng) * W.lightCdf.back();
    li = static_cast<size_t>(std::upper_bound(W.lightCdf.begin(), W.lightCdf.end(), u) -
                             W.lightCdf.begin());
    li = std::min(li, lights.size() - 1);
  }
  const Emission em = emit(lights[li], bounds, c, rng);
  SurfaceHit hit;
  if (!body.intersect(em.origin, em.direction, 0.0, kInf, hit)) {
    k.entered[ci].add(0.0);
    k.exited[ci].add(0.0);
    k.escaped[ci].add(0.0);
    k.addExitedByOrder(ci, {});
    tally.endPhoton();
    return false;
  }
  x = em.origin + hit.t * em.direction;
  const glm::dvec3 inward = glm::dot(hit.normal, em.direction) > 0.0 ? hit.normal : -hit.normal;
  d = em.direction;
  if (!W.matched) {
    const double cosI = glm::dot(d, inward);
    w *= 1.0 - fresnelReflectance(cosI, W.eta);
    d = refract(d, inward, 1.0 / W.eta, refractedCosine(cosI, W.eta));
  }
  k.entered[ci].add(w);
  return true;
}

// What happened to a photon at the boundary point x (reached along d, surface normal n).
enum class AtBoundary { Reflected, Reentered, Escaped };

// Line 6: leave with probability Ft = 1 - F, else reflect (line 7) and go on (line 8). A photon
// that leaves is scored, flies on in air and may re-enter (x, d: the re-entry point and inward
// direction).
template <class BodyT>
AtBoundary crossBoundary(const BodyT& body, const ChannelWalk& W, double eps, int c, double w,
                         const glm::dvec3& normal, glm::dvec3& x, glm::dvec3& d, Rng& rng,
                         ExitTally::Block& tally, uint64_t scatters, double& exitedSum,
                         std::array<double, kScatteringOrders>& exitedByOrder, bool score = true,
                         bool reflected = false) {
  const glm::dvec3 outward = glm::dot(normal, d) > 0.0 ? normal : -normal;
  const double cosIn = glm::dot(d, outward);
  const double F = W.matched ? 0.0 : fresnelReflectance(cosIn, 1.0 / W.eta);
  if (F > 0.0 && uniform01(rng) < F) {
    d = glm::normalize(d - 2.0 * cosIn * outward);
    return AtBoundary::Reflected;
  }
  ExitRecord e;
  e.position = x;
  e.normal = outward;
  e.direction = W.matched ? d : refract(d, outward, W.eta, refractedCosine(cosIn, 1.0 / W.eta));
  e.weight = w;
  e.channel = c;
  e.order = scatteringOrder(scatters);
  e.reflected = reflected;
  if (score) {
    tally.record(e);
    exitedSum += w;
    exitedByOrder[static_cast<size_t>(e.order)] += w;
  }
  if constexpr (!convexBody<BodyT>()) {
    d = e.direction;
    if (reenter(body, W, eps, x, d, rng)) return AtBoundary::Reentered;
  }
  return AtBoundary::Escaped;
}

// crossBoundary with TransportOptions::after_specular_only's bookkeeping: the exit is scored
// unless the photon has neither scattered nor met the boundary since its entry, and a reflection
// or re-entry before its first scattering counts in `specular`; `reflected` records whether the
// photon has been reflected inside since its entry (ExitRecord::reflected).
template <class BodyT>
AtBoundary crossCounted(const BodyT& body, const ChannelWalk& W, double eps, int c, double w,
                        const glm::dvec3& normal, glm::dvec3& x, glm::dvec3& d, Rng& rng,
                        ExitTally::Block& tally, uint64_t scatters, double& exitedSum,
                        std::array<double, kScatteringOrders>& exitedByOrder, uint64_t& specular,
                        bool& reflected) {
  const AtBoundary b =
      crossBoundary(body, W, eps, c, w, normal, x, d, rng, tally, scatters, exitedSum,
                    exitedByOrder, !(W.afterSpecularOnly && scatters == 0 && specular == 0),
                    reflected);
  if (b != AtBoundary::Escaped && scatters == 0) ++specular;
  if (b == AtBoundary::Reflected) reflected = true;
  return b;
}

// Henyey-Greenstein scattering (line 16) and the seed's long-path roulette (section 3.2); false
// when the roulette ends the walk.
inline bool scatter(float g, uint64_t longPath, Rng& rng, glm::dvec3& d, uint64_t& scatters,
                    double& w) {
  const double mu = static_cast<double>(sampleHgCosine(g, rng.uniform()));
  const double phi = 2.0 * std::numbers::pi * uniform01(rng);
  const double sinT = std::sqrt(std::max(0.0, 1.0 - mu * mu));
  glm::dvec3 t1, t2;
  tangentFrame(d, t1, t2);
  d = glm::normalize(sinT * std::cos(phi) * t1 + sinT * std::sin(phi) * t2 + mu * d);
  ++scatters;
  if (longPath != 0 && scatters > longPath) {
    if (rng.next() >= kSurviveThreshold) return false;
    w *= kSurviveBoost;
  }
  return true;
}

// One photon of channel `c` in the homogeneous body: emission, entry, walk, exits and re-entries
// (Algorithm 1).
template <class BodyT>
void tracePhoton(const BodyT& body, const BoundingSphere& bounds, std::span<const Light> lights,
                 const ChannelWalk& W, int c, uint64_t longPath, Rng& rng, BlockCounters& k,
                 ExitTally::Block& tally) {
  const size_t ci = static_cast<size_t>(c);
  const double eps = body.epsilon();
  double w = 0.0;
  glm::dvec3 x, d;
  if (!launch(body, bounds, lights, W, c, rng, k, tally, w, x, d)) return;
  SurfaceHit hit;
  bool onSurface = true;  // the next ray starts on the boundary: ignore hits closer than eps
  uint64_t scatters = 0;
  double exitedSum = 0.0;  // this photon's exits, summed before squaring (transport.h)
  std::array<double, kScatteringOrders> exitedByOrder{};  // the same by scattering order
  double escapedWeight = 0.0;
  // Boundary events (reflections, re-entries) between the entry and the first scattering: with
  // after_specular_only, the light of a photon that scatters (or leaves) before any is not scored.
  uint64_t specular = 0;
  bool reflected = false;  // reflected inside since the entry (ExitRecord::reflected)

  for (;;) {
    // Free flight (line 3), then advance or meet the boundary (lines 4-14).
    double s = -std::log(1.0 - uniform01(rng)) / W.sigmaT;
    bool escaped = false;
    for (;;) {
      if (!body.intersect(x, d, onSurface ? eps : 0.0, s, hit)) {
        x += s * d;
        onSurface = false;
        break;
      }
      x += hit.t * d;
      s = std::max(0.0, s - hit.t);
      onSurface = true;
      // The rest of the free path s goes on after a reflection or from the re-entry point
      // (memoryless flights, transport.h).
      const AtBoundary b = crossCounted(body, W, eps, c, w, hit.normal, x, d, rng, tally,
                                        scatters, exitedSum, exitedByOrder, specular, reflected);
      if (b != AtBoundary::Escaped) continue;
      escaped = true;
      escapedWeight = w;
      break;
    }
    if (escaped) break;
    if (W.afterSpecularOnly && scatters == 0 && specular == 0) break;
    // Absorption (line 15).
    if (uniform01(rng) < W.absorbProbability) break;
    if (!scatter(W.g, longPath, rng, d, scatters, w)) break;
  }
  k.exited[ci].add(exitedSum);
  k.escaped[ci].add(escapedWeight);
  k.addExitedByOrder(ci, exitedByOrder);
  k.events += scatters;
  tally.endPhoton();
}

// One photon of channel `c` in a body filled with a heterogeneous medium (majorant_grid.h): the
// same emission, entry, boundary, exit and re-entry as tracePhoton; the free flight is delta
// tracking through the majorant grid, the boundary found by one ray query bounded by the
// collision it found, and a real collision uses the local medium: analog absorption with
// probability σa/σt there, then Henyey-Greenstein scattering with the local g. After a
// reflection or a re-entry the tracking starts afresh (the tentative collisions are a Poisson
// process: memoryless at any stopping point). Like the homogeneous walk, a photon that slipped
// out through an edge (mesh_tracer.h) flies on in "medium" (the field there, with the grid's
// largest bound beyond its box) until it crosses the mesh; one whose ray meets neither a
// collision nor the mesh is dropped (it would fly forever).
// A photon may still take very long (a region of a thin medium inside a mesh that reflects it
// totally, again and again): the walk looks at `stop` every kStopCheckSteps steps and returns
// false, the photon abandoned, once it is set (a time limit, Ctrl-C); true otherwise.
inline constexpr uint64_t kStopCheckSteps = 4096;
template <class BodyT>
bool traceVolumePhoton(const BodyT& body, const BoundingSphere& bounds,
                       std::span<const Light> lights, const ChannelWalk& W,
                       const VolumeMedium& V, int c, uint64_t longPath, Rng& rng,
                       BlockCounters& k, ExitTally::Block& tally, const std::atomic<bool>& stop) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const size_t ci = static_cast<size_t>(c);
  const double eps = body.epsilon();
  const double scale = V.coefficient_scale;
  const MajorantGrid& grid = *V.grid;
  double w = 0.0;
  glm::dvec3 x, d;
  if (!launch(body, bounds, lights, W, c, rng, k, tally, w, x, d)) return true;
  SurfaceHit hit;
  bool onSurface = true;
  uint64_t scatters = 0;
  double exitedSum = 0.0, escapedWeight = 0.0;
  std::array<double, kScatteringOrders> exitedByOrder{};  // as tracePhoton
  material::LocalMedium local;  // the medium at the last tentative collision
  double localSigmaT = 0.0;     // its σt in channel c [1/scene unit]
  uint64_t specular = 0;        // as tracePhoton
  bool reflected = false;       // as tracePhoton

  for (uint64_t step = 1;; ++step) {
    if (step % kStopCheckSteps == 0 && stop.load(std::memory_order_relaxed)) return false;
    // The first real collision along the ray, ignoring the boundary, then the boundary up to
    // there: the collisions the tracking finds before the boundary have exactly the density they
    // would have if it stopped there (what lies beyond does not change them), and the ray query
    // is bounded by the collision distance, as in the homogeneous walk (an unbounded query per
    // flight costs about 3x more in Embree).
    double t = 0.0;
    const glm::dvec3 o = x;
    auto accept = [&](double tc, double bound) {
      local = V.at(o + tc * d);
      localSigmaT = (local.sigma_a[ci] + local.sigma_s[ci]) * scale;
      if (localSigmaT >= bound) {
        if (localSigmaT > bound * (1.0 + 1e-9))
          V.majorant_violations->fetch_add(1, std::memory_order_relaxed);
        return true;
      }
      return uniform01(rng) * bound < localSigmaT;
    };
    const bool collided = grid.track(o, d, kInf, c, rng, accept, t);
    if (!body.intersect(o, d, onSurface ? eps : 0.0, collided ? t : kInf, hit)) {
      if (!collided) break;  // lost (see above)
      x = o + t * d;
      onSurface = false;
      if (W.afterSpecularOnly && scatters == 0 && specular == 0) break;
      // Absorption with the local albedo, scattering with the local g.
      if (uniform01(rng) * localSigmaT < local.sigma_a[ci] * scale) break;
      if (!scatter(static_cast<float>(local.g), longPath, rng, d, scatters, w)) break;
      continue;
    }
    x = o + hit.t * d;
    onSurface = true;
    const AtBoundary b = crossCounted(body, W, eps, c, w, hit.normal, x, d, rng, tally, scatters,
                                      exitedSum, exitedByOrder, specular, reflected);
    if (b != AtBoundary::Escaped) continue;
    escapedWeight = w;
    break;
  }
  k.exited[ci].add(exitedSum);
  k.escaped[ci].add(escapedWeight);
  k.addExitedByOrder(ci, exitedByOrder);
  k.events += scatters;
  tally.endPhoton();
  return true;
}

std::vector<Light> validatedLights(std::span<const Light> lights);
std::vector<ChannelWalk> channelWalks(const BoundingSphere& bounds,
                                      std::span<const ScalarMedium> channels,
                                      std::span<const Light> lights);

template <class BodyT>
TransportStats traceBlocks(const BodyT& body, std::span<const ScalarMedium> channels,
                           std::span<const Light> givenLights, const TransportOptions& O,
                           ExitTally& tally, const ProgressCallback& progress,
                           const VolumeMedium* volume = nullptr) {
  O.validate();
  const std::vector<Light> lightList = validatedLights(givenLights);
  const std::span<const Light> lights(lightList);
  const BoundingSphere bounds = body.bounds();
  std::vector<ChannelWalk> walks = channelWalks(bounds, channels, lights);
  for (ChannelWalk& w : walks) w.afterSpecularOnly = O.after_specular_only;
  const size_t nc = channels.size();
  const uint64_t blocks = (O.photons + kBlockPhotons - 1) / kBlockPhotons;

  struct Result {
    std::unique_ptr<ExitTally::Block> tally;
    BlockCounters counters;
  };
  // Zero sums on the grids of what a photon of each channel carries (exact_sum.h).
  TransportStats stats = emptyStats(bounds, nc, lights);

  auto make = [&] { return Result{tally.newBlock(), BlockCounters(nc)}; };
  auto work = [&](uint64_t b, Result& r, const std::atomic<bool>& stop) {
    for (size_t c = 0; c < nc; ++c) {
      Rng rng(O.seed, b * nc + c);
      for (uint64_t p = 0; p < kBlockPhotons; ++p) {
        if ((p & 63u) == 0 && stop.load(std::memory_order_relaxed)) return false;
        if (volume) {
          if (!traceVolumePhoton(body, bounds, lights, walks[c], *volume, static_cast<int>(c),
                                 O.long_path_roulette, rng, r.counters, *r.tally, stop))
            return false;  // stopped within a photon: the block is dropped whole
        } else
          tracePhoton(body, bounds, lights, walks[c], static_cast<int>(c), O.long_path_roulette,
                      rng, r.counters, *r.tally);
      }
    }
    return true;
  };
  auto merge = [&](uint64_t, Result& r) {
    tally.merge(*r.tally);
    addBlock(stats, r.counters);
  };
  const uint64_t perBlock = kBlockPhotons * nc, total = blocks * perBlock;
  std::function<bool(uint64_t, double)> tick;
  if (progress)
    tick = [&](uint64_t done, double seconds) {
      return progress(TraceProgress{done * perBlock, total, seconds});
    };
  const BlockRun run = runBlocks<Result>(O.first_block, blocks, O.threads, make, work, merge, tick);
  stats.next_block = O.first_block + blocks;
  stats.seconds = run.seconds;
  stats.threads = run.threads;
  stats.partial = run.stopped;
  if (progress) progress(TraceProgress{run.blocks_done * perBlock, total, run.seconds});
  return stats;
}

}  // namespace translucent::reference::detail
