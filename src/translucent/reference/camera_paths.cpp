// SPDX-License-Identifier: GPL-3.0-or-later
// The camera-side mesh reference: backward volumetric path tracing with next-event estimation
// (camera_paths.h).
#include "translucent/reference/camera_paths.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <type_traits>

#include <glm/geometric.hpp>

#include "translucent/lights/environment_map.h"
#include "translucent/optics/fresnel.h"
#include "translucent/reference/block_driver.h"
#include "translucent/reference/phase.h"
#include "translucent/reference/refracted_light.h"
#include "translucent/reference/rng.h"
#include "translucent/reference/sampling.h"
#include "translucent/reference/transport_impl.h"
#include "translucent/reference/walk.h"

namespace translucent::reference {

using detail::tangentFrame;
using detail::uniform01;

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kInf = std::numeric_limits<double>::infinity();
// Throughput roulette: below this, survive with probability β / kRoulette at weight kRoulette.
constexpr double kRoulette = 0.25;
// Shadow rays: an optical depth beyond this is transmittance 0 (e^-50 ~ 2e-22: far below any
// Monte Carlo error; it saves the further ray queries of a ray that crosses the body again).
constexpr double kOpaqueDepth = 50.0;

// 2D (0,2)-sequence in base 2: the first two Sobol dimensions (van der Corput and its Pascal-
// matrix companion; Sobol 1967, Joe & Kuo 2008), as 32-bit fractions.
uint32_t vanDerCorput(uint32_t i) {
  i = (i << 16) | (i >> 16);
  i = ((i & 0x00ff00ffu) << 8) | ((i & 0xff00ff00u) >> 8);
  i = ((i & 0x0f0f0f0fu) << 4) | ((i & 0xf0f0f0f0u) >> 4);
  i = ((i & 0x33333333u) << 2) | ((i & 0xccccccccu) >> 2);
  i = ((i & 0x55555555u) << 1) | ((i & 0xaaaaaaaau) >> 1);
  return i;
}
uint32_t sobolSecond(uint32_t i) {
  uint32_t r = 0;
  for (uint32_t v = 1u << 31; i != 0; i >>= 1, v ^= v >> 1)
    if (i & 1u) r ^= v;
  return r;
}
// (a + shift) mod 1 for a 32-bit fraction a.
double shifted(uint32_t a, uint32_t shift) {
  return static_cast<double>(static_cast<uint32_t>(a + shift)) * 0x1.0p-32;
}

// The medium at a collision: albedo and g (homogeneous: the channel's; a field: the local ones).
struct Collision {
  double albedo = 0.0, g = 0.0;
};

struct Counters {
  uint64_t paths = 0, events = 0, shadowRays = 0;
};

// The next direction of a path travelling along d after a collision, from the Henyey-Greenstein
// phase function about d (the light arriving along -d' scatters into -d with cos θ = d·d', the
// same density as forwards), and its density per steradian (for the environment lights' MIS).
glm::dvec3 samplePhase(const glm::dvec3& d, double g, Rng& rng, double& pdf) {
  const double mu = static_cast<double>(sampleHgCosine(static_cast<float>(g), rng.uniform()));
  const double phi = 2.0 * kPi * uniform01(rng);
  const double sinT = std::sqrt(std::max(0.0, 1.0 - mu * mu));
  glm::dvec3 t1, t2;
  tangentFrame(d, t1, t2);
  pdf = hgCosineDensity(mu, g) / (2.0 * kPi);
  return glm::normalize(sinT * std::cos(phi) * t1 + sinT * std::sin(phi) * t2 + mu * d);
}

// A delta light's direction ω_l from x (unit, towards it), its irradiance at x on a plane
// perpendicular to ω_l before the light's colour (directional: E; point: I / r²; beam of radius
// > 0: P / (π r²) inside its cylinder, downstream of its origin) and the distance to it (kInf for
// a directional light); false where it does not light x, and for an environment light (sampled
// apart).
bool deltaIncident(const Light& light, const glm::dvec3& x, glm::dvec3& w, double& e,
                   double& dist) {
  dist = kInf;
  if (const auto* dl = std::get_if<DirectionalLight>(&light.emitter)) {
    w = dl->direction;
    e = dl->irradiance;
  } else if (const auto* pl = std::get_if<PointLight>(&light.emitter)) {
    w = pl->position - x;
    dist = glm::length(w);
    if (!(dist > 0.0)) return false;
    w /= dist;
    e = pl->intensity / (dist * dist);
  } else if (const auto* bl = std::get_if<BeamLight>(&light.emitter)) {
    const glm::dvec3 r = x - bl->origin;
    const double along = glm::dot(r, bl->direction);
    if (!(along > 0.0) || glm::length(r - along * bl->direction) > bl->radius) return false;
    w = -bl->direction;
    dist = along;
    e = bl->power / (kPi * bl->radius * bl->radius);
  } else {
    return false;
  }
  return true;
}

// Russian roulette on the transmittance T a refracted connection will carry, asked before its
// ray queries (RefractedLight::forEachWeighted): below kConnectRoulette it survives with
// probability T / kConnectRoulette and then carries kConnectRoulette: unbiased, and a deep
// collision spends no rays on connections through tens of mean free paths.
constexpr double kConnectRoulette = 1e-3;
double connectionWeight(double T, Rng& rng) {
  if (T >= kConnectRoulette) return 1.0;
  return uniform01(rng) * kConnectRoulette < T ? kConnectRoulette / T : 0.0;
}

// The boundary as the walks see it: the index ratio (as the light method's walk takes it, for its
// flight in air: transport_impl.h reenter) and, per light, its refracted connections (η ≠ 1;
// null for environment lights and at η = 1).
struct Boundary {
  Boundary(double eta_, std::span<const std::unique_ptr<RefractedLight>> refracted_)
      : eta(eta_), refracted(refracted_) {
    walk.eta = eta_;
    walk.matched = eta_ == 1.0;
  }
  double eta = 1.0;
  std::span<const std::unique_ptr<RefractedLight>> refracted;
  detail::ChannelWalk walk;
  bool matched() const { return walk.matched; }
};

// What became of a path that met the boundary from inside (crossFromInside).
enum class Crossing { Reflected, Reentered, Escaped };

// A path at the boundary point x, reached from inside along d (geometric normal `normal`): the
// adjoint of the light method's crossBoundary (transport_impl.h). η = 1: straight on in air.
// η ≠ 1: Fresnel reflection back in with probability F (1 under total internal reflection:
// Reflected), else refraction out with the radiance factor η² (L / n² is invariant along a
// refracted ray, so L_inside = F L_reflected + (1 - F) η² L_air). In air the light method's own
// flight (reenter: at every hit of the body's outside a mirror reflection with probability F,
// else refraction in, here with the factor 1 / η²) to the re-entry (Reentered) or away
// (Escaped). A path that escapes after its flight in air was mirrored (`mirrored`) carries light
// whose first meeting with the body was that reflection: the light method drops it (the
// specular reflection of the lights, which renderers add as a surface term, transport.h), so the
// caller scores nothing for it.
Crossing crossFromInside(const MeshBody& body, const Boundary& boundary, glm::dvec3& x,
                         glm::dvec3& d, const glm::dvec3& normal, double& factor, bool& mirrored,
                         Rng& rng) {
  mirrored = false;
  const double eta = boundary.eta;
  if (!boundary.matched()) {
    const glm::dvec3 outward = glm::dot(normal, d) > 0.0 ? normal : -normal;
    const double cosIn = glm::dot(d, outward);
    if (uniform01(rng) < fresnelReflectance(cosIn, 1.0 / eta)) {
      d = glm::normalize(d - 2.0 * cosIn * outward);
      return Crossing::Reflected;
    }
    d = detail::refract(d, outward, eta, refractedCosine(cosIn, 1.0 / eta));
  }
  // Out and in again: η² / η² = 1.
  if (detail::reenter(body, boundary.walk, body.epsilon(), x, d, rng, &mirrored))
    return Crossing::Reentered;
  if (!boundary.matched()) factor *= eta * eta;
  return Crossing::Escaped;
}

// The light of a refracted path (RefractedLight::Path) that leaves the body at the surface point
// x (outward unit normal n) unscattered: its exitance E μ (1 - F) (μ the cosine inside, F the
// Fresnel reflectance seen from inside; 0 under total internal reflection) before the
// transmittance, and its direction in air.
double refractedExit(const RefractedLight::Path& p, const glm::dvec3& n, double eta,
                     glm::dvec3& out) {
  const glm::dvec3 travel = -p.w;
  const double mu = glm::dot(travel, n);
  if (!(mu > 0.0)) return 0.0;
  const double ft = fresnelTransmittance(mu, 1.0 / eta);
  if (!(ft > 0.0)) return 0.0;
  out = detail::refract(travel, n, eta, refractedCosine(mu, 1.0 / eta));
  return p.irradiance * mu * ft;
}

// One channel's paths through the body (camera_paths.h).
class ChannelPaths {
 public:
  ChannelPaths(const MeshBody& body, Boundary boundary, std::span<const Light> lights,
               const ScalarMedium* medium, const VolumeMedium* volume, int channel, uint64_t longPath)
      : body_(body), boundary_(boundary), lights_(lights), volume_(volume), c_(channel),
        longPath_(longPath), eps_(body.epsilon()) {
    if (medium) {
      sigmaT_ = medium->sigmaT();
      albedo_ = medium->sigma_s / sigmaT_;
      g_ = medium->g;
    }
  }

  // The radiance arriving at the surface point x from inside along -d (d points into the body),
  // split into its unscattered (out[0]: an environment seen through the body), single-scattered
  // (out[1]) and multiply scattered (out[2]) parts.
  void radiance(glm::dvec3 x, glm::dvec3 d, Rng& rng, Counters& k, double out[3]) const {
    ++k.paths;
    double beta = 1.0;
    uint64_t scatters = 0;
    bool onSurface = true;
    double phasePdf = 0.0;  // of the last scattering's direction [1/sr] (none yet: 0)
    Collision col;
    for (;;) {
      bool mirrored = false;
      if (!flight(x, d, onSurface, rng, col, beta, mirrored)) {
        // Escaped: the environment's radiance along -d, MIS-weighted against its sampling by
        // next-event estimation at the last collision (η = 1; at η ≠ 1 only escaping paths find
        // the environment: weight 1).
        if (!mirrored)
          out[std::min<uint64_t>(scatters, 2)] +=
              beta * escaped(d, boundary_.matched() ? phasePdf : 0.0);
        return;
      }
      onSurface = false;
      ++k.events;
      beta *= col.albedo;
      if (!(beta > 0.0)) return;
      out[scatters == 0 ? 1 : 2] += beta * direct(x, d, col.g, rng, k);
      ++scatters;
      if (longPath_ != 0 && scatters > longPath_) {
        if (rng.next() >= detail::kSurviveThreshold) return;
        beta *= detail::kSurviveBoost;
      }
      if (beta < kRoulette) {
        if (!(uniform01(rng) * kRoulette < beta)) return;
        beta = kRoulette;
      }
      d = samplePhase(d, col.g, rng, phasePdf);
    }
  }

 private:
  // Σ over the environment lights of L_c(ω) towards the escape direction ω, weighted by the
  // balance heuristic against next-event estimation's density for it (phasePdf 0: a camera or
  // exitance ray that met no collision, which next-event estimation cannot produce: weight 1).
  double escaped(const glm::dvec3& w, double phasePdf) const {
    double sum = 0.0;
    for (const Light& light : lights_) {
      const auto* env = std::get_if<EnvironmentLight>(&light.emitter);
      if (!env) continue;
      const double L = double(env->map->lookup(w, env->rotate)[c_]) * env->intensity * light.color[size_t(c_)];
      if (!(L > 0.0)) continue;
      const auto& sampler = env->samplers[size_t(c_)];
      const double pdfLight = phasePdf > 0.0 && sampler ? sampler->pdf(w) : 0.0;
      sum += L * (phasePdf > 0.0 ? phasePdf / (phasePdf + pdfLight) : 1.0);
    }
    return sum;
  }

  // From x along d to the next real collision (x moved there, `col` its medium); false when the
  // path leaves the body for good (d its direction in air). At the boundary crossFromInside:
  // straight on at η = 1, Fresnel reflection or refraction otherwise (its radiance factors on
  // beta; `mirrored` as there).
  bool flight(glm::dvec3& x, glm::dvec3& d, bool onSurface, Rng& rng, Collision& col,
              double& beta, bool& mirrored) const {
    SurfaceHit hit;
    if (!volume_) {
      double s = -std::log(1.0 - uniform01(rng)) / sigmaT_;
      for (;;) {
        if (!body_.intersect(x, d, onSurface ? eps_ : 0.0, s, hit)) {
          x += s * d;
          col = {albedo_, g_};
          return true;
        }
        x += hit.t * d;
        s = std::max(0.0, s - hit.t);  // the rest of the free path goes on (memoryless flights)
        if (crossFromInside(body_, boundary_, x, d, hit.normal, beta, mirrored, rng) ==
            Crossing::Escaped)
          return false;
        onSurface = true;
      }
    }
    const VolumeMedium& V = *volume_;
    const size_t ci = static_cast<size_t>(c_);
    const double scale = V.coefficient_scale;
    for (;;) {
      const glm::dvec3 o = x;
      material::LocalMedium local;
      double localSigmaT = 0.0;
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
      double t = 0.0;
      const bool collided = V.grid->track(o, d, kInf, c_, rng, accept, t);
      if (!body_.intersect(o, d, onSurface ? eps_ : 0.0, collided ? t : kInf, hit)) {
        if (!collided) return false;  // neither a collision nor the boundary: lost
        x = o + t * d;
        col = {localSigmaT > 0.0 ? local.sigma_s[ci] * scale / localSigmaT : 0.0, local.g};
        return true;
      }
      // At the boundary: reflected, or on in air to the re-entry; the tracking starts afresh.
      x = o + hit.t * d;
      if (crossFromInside(body_, boundary_, x, d, hit.normal, beta, mirrored, rng) ==
          Crossing::Escaped)
        return false;
      onSurface = true;
    }
  }

  // Σ over the lights of p(d·ω_l) L_l T(x, light): next-event estimation at the collision x of a
  // path travelling along d (camera_paths.h).
  double direct(const glm::dvec3& x, const glm::dvec3& d, double g, Rng& rng, Counters& k) const {
    double sum = 0.0;
    for (size_t i = 0; i < lights_.size(); ++i) {
      const Light& light = lights_[i];
      if (!boundary_.matched()) {
        // η ≠ 1: the delta lights through every facet that refracts them to x (RefractedLight);
        // the environment only by the paths that escape.
        if (!boundary_.refracted[i]) continue;
        const double color = light.color[static_cast<size_t>(c_)];
        boundary_.refracted[i]->forEachWeighted(
            x, false,
            [&](const RefractedLight::Path& p) {
              return volume_ ? 1.0 : connectionWeight(std::exp(-sigmaT_ * p.dist), rng);
            },
            [&](const RefractedLight::Path& p, double keep) {
              ++k.shadowRays;
              const double T =
                  volume_ ? ratioTracking(x, p.w, p.dist, rng) : std::exp(-sigmaT_ * p.dist) * keep;
              sum += hgCosineDensity(glm::dot(d, p.w), g) / (2.0 * kPi) * p.irradiance * color * T;
            });
        continue;
      }
      if (const auto* env = std::get_if<EnvironmentLight>(&light.emitter)) {
        // A direction from the channel's sampler (density ∝ its radiance), weighted by the
        // balance heuristic against phase sampling (escaped()).
        const auto& sampler = env->samplers[size_t(c_)];
        if (!sampler) continue;
        const double u1 = uniform01(rng), u2 = uniform01(rng);
        const lights::EnvironmentSampler::Sample smp = sampler->sample({u1, u2});
        if (!(smp.pdf > 0.0)) continue;
        const double phase = hgCosineDensity(glm::dot(d, smp.direction), g) / (2.0 * kPi);
        const double L = smp.radiance[size_t(c_)] * env->intensity * light.color[size_t(c_)];
        if (!(L * phase > 0.0)) continue;
        ++k.shadowRays;
        sum += phase * L / (smp.pdf + phase) * transmittance(x, smp.direction, kInf, false, rng);
        continue;
      }
      glm::dvec3 w;
      double li = 0.0, dist = kInf;
      if (!incident(light, x, w, li, dist)) continue;
      const double phase = hgCosineDensity(glm::dot(d, w), g) / (2.0 * kPi);
      if (!(li * phase > 0.0)) continue;
      ++k.shadowRays;
      sum += phase * li * transmittance(x, w, dist, false, rng);
    }
    return sum;
  }

 public:
  // The unscattered light leaving the body at the surface point x (outward unit normal n): the
  // light of a delta light that crossed the body without a collision and leaves at x, travelling
  // along -ω_l with n·(-ω_l) > 0. Per light, its irradiance there E_l (on a plane perpendicular
  // to ω_l), the cosine μ = n·(-ω_l) and the transmittance T along the straight segment from x
  // to the light through every part of the body (η = 1), so that
  //     B0(x) = Σ_l E_l μ T                                     (radiant exitance, camera.h)
  //     C0(x) = Σ_{l: -ω_l in the cone} E_l μ T / (π sin²θc (n·v))   (cone average, camera.h)
  // (the radiance of a delta light is a delta in direction: ∫ L (n·ω) dω over any set of
  // directions holding -ω_l is E_l T μ). No path of `radiance` can hit a delta light, so this
  // term is added deterministically; the light method scores it as the exits of its photons of
  // scattering order 0 (camera.h), wherever x sees the camera, not only towards it.
  // `cosCone` <= 1: the cone's cosine (C0 is returned for cosCone < 1, else 0).
  void unscattered(const glm::dvec3& x, const glm::dvec3& n, const glm::dvec3& v, double cosCone,
                   double coneMeasure, Rng& rng, Counters& k, double& b0, double& c0) const {
    b0 = c0 = 0.0;
    for (size_t i = 0; i < lights_.size(); ++i) {
      const Light& light = lights_[i];
      if (!boundary_.matched()) {
        // η ≠ 1: the light refracted in at a facet that reaches x unscattered and is refracted
        // out there (refractedExit).
        if (!boundary_.refracted[i]) continue;
        const double color = light.color[static_cast<size_t>(c_)];
        boundary_.refracted[i]->forEach(x, true, [&](const RefractedLight::Path& p) {
          glm::dvec3 out;
          const double e0 = refractedExit(p, n, boundary_.eta, out) * color;
          if (!(e0 > 0.0)) return;
          ++k.shadowRays;
          const double e =
              e0 * (volume_ ? ratioTracking(x, p.w, p.dist, rng) : std::exp(-sigmaT_ * p.dist));
          b0 += e;
          if (cosCone < 1.0 && glm::dot(out, v) >= cosCone) c0 += e / (coneMeasure * glm::dot(n, v));
        });
        continue;
      }
      glm::dvec3 w;
      double li = 0.0, dist = kInf;
      if (!incident(light, x, w, li, dist)) continue;
      const double mu = -glm::dot(n, w);
      if (!(mu > 0.0 && li > 0.0)) continue;
      ++k.shadowRays;
      const double e = li * mu * transmittance(x, w, dist, true, rng);
      b0 += e;
      if (cosCone < 1.0 && glm::dot(-w, v) >= cosCone) c0 += e / (coneMeasure * glm::dot(n, v));
    }
  }

 private:
  // deltaIncident in this channel (times the light's colour).
  bool incident(const Light& light, const glm::dvec3& x, glm::dvec3& w, double& li,
                double& dist) const {
    if (!deltaIncident(light, x, w, li, dist)) return false;
    li *= light.color[static_cast<size_t>(c_)];
    return true;
  }

  // T along x + t w, t in (0, dist], x inside the body, or on its surface with w pointing in
  // (`onSurface`: hits closer than epsilon are its own surface): the product over the parts of
  // the ray inside the body (η = 1: straight through every boundary).
  double transmittance(glm::dvec3 x, const glm::dvec3& w, double dist, bool onSurface,
                       Rng& rng) const {
    double depth = 0.0, ratio = 1.0;
    bool inside = true;
    SurfaceHit hit;
    for (;;) {
      const bool h = body_.intersect(x, w, onSurface ? eps_ : 0.0, dist, hit);
      const double len = h ? hit.t : dist;
      if (inside && len > 0.0) {
        if (!volume_) {
          depth += sigmaT_ * len;
        } else {
          ratio *= ratioTracking(x, w, len, rng);
          if (!(ratio > 0.0)) return 0.0;
        }
        if (depth > kOpaqueDepth) return 0.0;
      }
      if (!h) break;
      x += hit.t * w;
      if (std::isfinite(dist)) dist = std::max(0.0, dist - hit.t);
      inside = !inside;
      onSurface = true;
    }
    return ratio * std::exp(-depth);
  }

  // Ratio tracking over x + t w, t in (0, len] (Novák et al. 2018, Eq. 29): ∏ (1 - σt/σ̄) over
  // the tentative collisions of the majorant grid, with a roulette (survive 1/2, weight x2) once
  // the product is below 0.01.
  double ratioTracking(const glm::dvec3& x, const glm::dvec3& w, double len, Rng& rng) const {
    const VolumeMedium& V = *volume_;
    const size_t ci = static_cast<size_t>(c_);
    const double scale = V.coefficient_scale;
    double T = 1.0;
    auto accept = [&](double tc, double bound) {
      const material::LocalMedium local = V.at(x + tc * w);
      const double sigmaT = (local.sigma_a[ci] + local.sigma_s[ci]) * scale;
      if (sigmaT > bound * (1.0 + 1e-9))
        V.majorant_violations->fetch_add(1, std::memory_order_relaxed);
      T *= 1.0 - std::min(1.0, sigmaT / bound);
      if (!(T > 0.0)) return true;  // stop: T = 0
      if (T < 0.01) {
        if (uniform01(rng) < 0.5) {
          T = 0.0;
          return true;
        }
        T *= 2.0;
      }
      return false;
    };
    double t = 0.0;
    (void)V.grid->track(x, w, len, c_, rng, accept, t);
    return T;
  }

  const MeshBody& body_;
  Boundary boundary_;
  std::span<const Light> lights_;
  const VolumeMedium* volume_;
  int c_;
  uint64_t longPath_;
  double eps_;
  double sigmaT_ = 1.0, albedo_ = 0.0, g_ = 0.0;
};

// The three channels of a homogeneous medium along one path (CameraPathOptions::joint_channels):
// the paths of ChannelPaths, with the free flights of the three channels combined by one-sample
// multiple importance sampling (the balance heuristic over the channels, Veach 1997 §9.2.4; the
// "chromatic media" estimator of Pharr, Jakob & Humphreys, pbrt-v4 §14.2): a flight's length is
// drawn from one channel chosen uniformly, so its density is the mean over the channels,
//     p(t) = (1/3) Σ_c σt_c e^{-σt_c t}       (a collision at t),
//     P(d) = (1/3) Σ_c e^{-σt_c d}            (no collision before the boundary at d),
// and channel c's throughput is multiplied by σs_c e^{-σt_c t} / p(t), or by e^{-σt_c d} / P(d):
// unbiased for every channel whatever the others, and with weights near 1 where the channels'
// σt are close. One camera ray, one walk, one shadow ray per light and collision then serve
// three channels. The phase function must be the same in every channel (one g).
class RgbPaths {
 public:
  RgbPaths(const MeshBody& body, Boundary boundary, std::span<const Light> lights,
           std::span<const ScalarMedium> channels, uint64_t longPath)
      : body_(body), boundary_(boundary), lights_(lights), longPath_(longPath),
        eps_(body.epsilon()), g_(channels[0].g) {
    for (size_t c = 0; c < 3; ++c) {
      sigmaT_[c] = channels[c].sigmaT();
      sigmaS_[c] = channels[c].sigma_s;
    }
    for (const Light& light : lights_) {
      const auto* env = std::get_if<EnvironmentLight>(&light.emitter);
      envSamplers_.push_back(env ? std::make_shared<const lights::EnvironmentSampler>(
                                       *env->map, env->rotate, lights::SampleWeight::Luminance)
                                 : nullptr);
    }
  }

  // ChannelPaths::radiance for the three channels: out[c][0] unscattered, [1] single, [2] the rest.
  void radiance(glm::dvec3 x, glm::dvec3 d, Rng& rng, Counters& k, double out[3][3]) const {
    ++k.paths;
    glm::dvec3 beta(1.0);
    uint64_t scatters = 0;
    bool onSurface = true;
    double phasePdf = 0.0;
    SurfaceHit hit;
    for (;;) {
      const size_t hero = std::min<size_t>(2, static_cast<size_t>(3.0 * uniform01(rng)));
      const double s = -std::log(1.0 - uniform01(rng)) / sigmaT_[hero];
      if (body_.intersect(x, d, onSurface ? eps_ : 0.0, s, hit)) {
        // The boundary first: every channel's chance of getting there over P(d).
        double P = 0.0;
        glm::dvec3 T;
        for (int c = 0; c < 3; ++c) {
          T[c] = std::exp(-sigmaT_[size_t(c)] * hit.t);
          P += T[c] / 3.0;
        }
        if (!(P > 0.0)) return;
        beta *= T / P;
        x += hit.t * d;
        // Reflected, or on in air to where the path meets the body again, or to the environment
        // (ChannelPaths::flight and escaped).
        double factor = 1.0;
        bool mirrored = false;
        const Crossing cross =
            crossFromInside(body_, boundary_, x, d, hit.normal, factor, mirrored, rng);
        beta *= factor;
        if (cross == Crossing::Escaped) {
          if (mirrored) return;
          const glm::dvec3 L = beta * escaped(d, boundary_.matched() ? phasePdf : 0.0);
          for (int c = 0; c < 3; ++c) out[c][std::min<uint64_t>(scatters, 2)] += L[c];
          return;
        }
        onSurface = true;
        continue;
      }
      x += s * d;
      onSurface = false;
      ++k.events;
      double p = 0.0;
      glm::dvec3 f;
      for (int c = 0; c < 3; ++c) {
        const double e = std::exp(-sigmaT_[size_t(c)] * s);
        p += sigmaT_[size_t(c)] * e / 3.0;
        f[c] = sigmaS_[size_t(c)] * e;
      }
      if (!(p > 0.0)) return;
      beta *= f / p;
      if (!(std::max({beta.x, beta.y, beta.z}) > 0.0)) return;
      glm::dvec3 direct3(0.0);
      direct(x, d, rng, k, direct3);
      for (int c = 0; c < 3; ++c) out[c][scatters == 0 ? 1 : 2] += beta[c] * direct3[c];
      ++scatters;
      if (longPath_ != 0 && scatters > longPath_) {
        if (rng.next() >= detail::kSurviveThreshold) return;
        beta *= detail::kSurviveBoost;
      }
      if (const double largest = std::max({beta.x, beta.y, beta.z}); largest < kRoulette) {
        // Russian roulette on the largest channel (after the long-path step, as the per-channel
        // walk): survive with probability largest / kRoulette.
        if (!(uniform01(rng) * kRoulette < largest)) return;
        beta *= kRoulette / largest;
      }
      d = samplePhase(d, g_, rng, phasePdf);
    }
  }

  // ChannelPaths::unscattered for the three channels.
  void unscattered(const glm::dvec3& x, const glm::dvec3& n, const glm::dvec3& v, double cosCone,
                   double coneMeasure, Counters& k, double b0[3], double c0[3]) const {
    for (int c = 0; c < 3; ++c) b0[c] = c0[c] = 0.0;
    for (size_t i = 0; i < lights_.size(); ++i) {
      const Light& light = lights_[i];
      if (!boundary_.matched()) {
        if (!boundary_.refracted[i]) continue;
        const glm::dvec3 color(light.color[0], light.color[1], light.color[2]);
        boundary_.refracted[i]->forEach(x, true, [&](const RefractedLight::Path& p) {
          glm::dvec3 out;
          const double e0 = refractedExit(p, n, boundary_.eta, out);
          if (!(e0 > 0.0)) return;
          ++k.shadowRays;
          const glm::dvec3 e = e0 * color * attenuation(p.dist);
          const bool inCone = cosCone < 1.0 && glm::dot(out, v) >= cosCone;
          for (int c = 0; c < 3; ++c) {
            b0[c] += e[c];
            if (inCone) c0[c] += e[c] / (coneMeasure * glm::dot(n, v));
          }
        });
        continue;
      }
      glm::dvec3 w, li;
      double dist = kInf;
      if (!incident(light, x, w, li, dist)) continue;
      const double mu = -glm::dot(n, w);
      if (!(mu > 0.0)) continue;
      ++k.shadowRays;
      const glm::dvec3 e = li * mu * transmittance(x, w, dist, true);
      const bool inCone = cosCone < 1.0 && glm::dot(-w, v) >= cosCone;
      for (int c = 0; c < 3; ++c) {
        b0[c] += e[c];
        if (inCone) c0[c] += e[c] / (coneMeasure * glm::dot(n, v));
      }
    }
  }

 private:
  // ChannelPaths::escaped for the three channels; the environment's directions are sampled by
  // luminance here (one density for the three channels).
  glm::dvec3 escaped(const glm::dvec3& w, double phasePdf) const {
    glm::dvec3 sum(0.0);
    for (size_t i = 0; i < lights_.size(); ++i) {
      const auto* env = std::get_if<EnvironmentLight>(&lights_[i].emitter);
      if (!env) continue;
      const glm::dvec3 L = glm::dvec3(env->map->lookup(w, env->rotate)) * env->intensity *
                           glm::dvec3(lights_[i].color[0], lights_[i].color[1], lights_[i].color[2]);
      const double pdfLight = phasePdf > 0.0 && envSamplers_[i] ? envSamplers_[i]->pdf(w) : 0.0;
      sum += L * (phasePdf > 0.0 ? phasePdf / (phasePdf + pdfLight) : 1.0);
    }
    return sum;
  }

  // Σ over the lights of p(d·ω_l) L_l T(x, light), per channel (ChannelPaths::direct).
  void direct(const glm::dvec3& x, const glm::dvec3& d, Rng& rng, Counters& k, glm::dvec3& sum) const {
    for (size_t i = 0; i < lights_.size(); ++i) {
      const Light& light = lights_[i];
      if (!boundary_.matched()) {
        // η ≠ 1 (ChannelPaths::direct).
        if (!boundary_.refracted[i]) continue;
        const glm::dvec3 color(light.color[0], light.color[1], light.color[2]);
        const double least = std::min({sigmaT_[0], sigmaT_[1], sigmaT_[2]});
        boundary_.refracted[i]->forEachWeighted(
            x, false,
            [&](const RefractedLight::Path& p) {
              return connectionWeight(std::exp(-least * p.dist), rng);
            },
            [&](const RefractedLight::Path& p, double keep) {
              ++k.shadowRays;
              sum += hgCosineDensity(glm::dot(d, p.w), g_) / (2.0 * kPi) * p.irradiance * color *
                     attenuation(p.dist) * keep;
            });
        continue;
      }
      if (const auto* env = std::get_if<EnvironmentLight>(&light.emitter)) {
        if (!envSamplers_[i]) continue;
        const double u1 = uniform01(rng), u2 = uniform01(rng);
        const lights::EnvironmentSampler::Sample smp = envSamplers_[i]->sample({u1, u2});
        if (!(smp.pdf > 0.0)) continue;
        const double phase = hgCosineDensity(glm::dot(d, smp.direction), g_) / (2.0 * kPi);
        if (!(phase > 0.0)) continue;
        ++k.shadowRays;
        const glm::dvec3 L = smp.radiance * env->intensity *
                             glm::dvec3(light.color[0], light.color[1], light.color[2]);
        sum += phase / (smp.pdf + phase) * L * transmittance(x, smp.direction, kInf, false);
        continue;
      }
      glm::dvec3 w, li;
      double dist = kInf;
      if (!incident(light, x, w, li, dist)) continue;
      const double phase = hgCosineDensity(glm::dot(d, w), g_) / (2.0 * kPi);
      if (!(phase > 0.0) || !(std::max({li.x, li.y, li.z}) > 0.0)) continue;
      ++k.shadowRays;
      sum += phase * li * transmittance(x, w, dist, false);
    }
  }

  // ChannelPaths::incident for the three channels at once.
  bool incident(const Light& light, const glm::dvec3& x, glm::dvec3& w, glm::dvec3& li,
                double& dist) const {
    double e = 0.0;
    if (!deltaIncident(light, x, w, e, dist)) return false;
    li = e * glm::dvec3(light.color[0], light.color[1], light.color[2]);
    return true;
  }

  // Per channel e^{-σt_c ℓ} along a segment of length ℓ inside the body.
  glm::dvec3 attenuation(double length) const {
    return {std::exp(-sigmaT_[0] * length), std::exp(-sigmaT_[1] * length),
            std::exp(-sigmaT_[2] * length)};
  }

  // Per channel e^{-σt_c ℓ}, ℓ the length of x + t w, t in (0, dist], inside the body
  // (ChannelPaths::transmittance; one walk of the ray for the three channels).
  glm::dvec3 transmittance(glm::dvec3 x, const glm::dvec3& w, double dist, bool onSurface) const {
    const double least = std::min({sigmaT_[0], sigmaT_[1], sigmaT_[2]});
    double length = 0.0;
    bool inside = true;
    SurfaceHit hit;
    for (;;) {
      const bool h = body_.intersect(x, w, onSurface ? eps_ : 0.0, dist, hit);
      const double len = h ? hit.t : dist;
      if (inside && len > 0.0) length += len;
      if (least * length > kOpaqueDepth) return glm::dvec3(0.0);
      if (!h) break;
      x += hit.t * w;
      if (std::isfinite(dist)) dist = std::max(0.0, dist - hit.t);
      inside = !inside;
      onSurface = true;
    }
    return attenuation(length);
  }

  const MeshBody& body_;
  Boundary boundary_;
  std::span<const Light> lights_;
  uint64_t longPath_;
  double eps_;
  double g_;
  std::array<double, 3> sigmaT_{}, sigmaS_{};
  // Per light: the luminance sampler of an environment light (null for the others).
  std::vector<std::shared_ptr<const lights::EnvironmentSampler>> envSamplers_;
};

std::vector<ScalarMedium> materialChannels(const material::Material& m) {
  if (m.kind == material::Material::Kind::Surface)
    throw ParameterError(
        "camera paths: a surface-map material (2D maps over the atlas) has no volume to trace; "
        "its reference is the compare report's model reference (brute-force Eq. 8)");
  m.medium.validate();
  std::vector<ScalarMedium> ch;
  for (int c = 0; c < 3; ++c) ch.push_back(m.medium.channel(c));
  return ch;
}

// The images' per-sample scores of one pixel and channel: [image][order], image 0 the radiance
// towards the camera, 1 the exitance, 2 the diffusion radiance; order 0 unscattered (the light
// that crossed the body without a collision: ChannelPaths::unscattered), 1 single, 2 multiple.
using Scores = std::array<std::array<double, kScatteringOrders>, 3>;

// The cone the light-traced complement averages over: the camera method's own cone, or
// complement_cone for the true radiance (camera_paths.h).
double complementConeFor(const CameraPathOptions& o) {
  return o.cone_half_angle > 0.0 ? o.cone_half_angle : o.complement_cone;
}

}  // namespace

void CameraPathOptions::validate() const {
  if (!(complement_cone > 0.0 && complement_cone < 90.0))
    throw ParameterError(fmt::format(
        "camera paths: complement cone is {}: expected degrees in (0, 90)", complement_cone));
  if (threads < 0)
    throw ParameterError(fmt::format("camera paths: threads is {}: expected >= 0 (0: all)", threads));
  if (!(cone_half_angle >= 0.0 && cone_half_angle < 90.0))
    throw ParameterError(fmt::format(
        "camera paths: cone half-angle is {}: expected degrees in [0, 90) (0: the true radiance)",
        cone_half_angle));
}

std::string CameraPathTracer::refusal(double eta, std::span<const Light> lights) {
  if (!(eta >= 1.0))
    return fmt::format(
        "the camera method needs eta >= 1 (a body at least as dense as the air around it), the "
        "material has eta {}: its refracted next-event estimation bounds the refracted light by "
        "the contraction of angles on the way in; the light method (`pathtrace mesh --method "
        "light`) traces it",
        eta);
  for (size_t i = 0; i < lights.size(); ++i) {
    if (const auto* b = std::get_if<BeamLight>(&lights[i].emitter); b && !(b->radius > 0.0))
      return fmt::format(
          "light {} is a pencil beam (radius 0): no shadow ray can hit it; the light method "
          "(`pathtrace mesh --method light`) traces it",
          i + 1);
  }
  return {};
}

CameraPathTracer::CameraPathTracer(const geometry::TriangleMesh& mesh, const Medium& medium,
                                   std::vector<Light> lights, const Camera& camera,
                                   const CameraPathOptions& options)
    : lights_(std::move(lights)), options_(options), body_(mesh), camera_(camera) {
  medium.validate();
  for (int c = 0; c < 3; ++c) channels_.push_back(medium.channel(c));
  init(mesh);
  initComplement(mesh, medium);
}

CameraPathTracer::CameraPathTracer(const geometry::TriangleMesh& mesh, const ScalarMedium& medium,
                                   std::vector<Light> lights, const Camera& camera,
                                   const CameraPathOptions& options)
    : channels_{medium}, lights_(std::move(lights)), options_(options), body_(mesh),
      camera_(camera) {
  medium.validate();
  init(mesh);
  initComplement(mesh, medium);
}

CameraPathTracer::CameraPathTracer(const geometry::TriangleMesh& mesh,
                                   const material::Material& material, std::vector<Light> lights,
                                   const Camera& camera, const CameraPathOptions& options,
                                   glm::ivec3 majorant_cells)
    : channels_(materialChannels(material)), lights_(std::move(lights)), options_(options),
      body_(mesh), camera_(camera) {
  if (material.kind == material::Material::Kind::Volume) {
    const geometry::Bounds b = mesh.bounds();
    const glm::dvec3 pad(1e-6 * (glm::length(b.center()) + b.radius()));
    volume_ = VolumeMedium::make(material, b.lower - pad, b.upper + pad, majorant_cells);
  }
  init(mesh);
  initComplement(mesh, material, majorant_cells);
}

CameraPathTracer::~CameraPathTracer() = default;

template <class M>
void CameraPathTracer::initComplement(const geometry::TriangleMesh& mesh, const M& medium,
                                      glm::ivec3 cells) {
  if (eta_ == 1.0) return;
  std::vector<Light> delta;
  for (const Light& l : lights_)
    if (!std::holds_alternative<EnvironmentLight>(l.emitter)) delta.push_back(l);
  if (delta.empty()) return;
  TracerOptions o;
  o.seed = mix64(options_.seed ^ 0x636F6D706C656D65ull);  // "compleme"
  o.threads = options_.threads;
  o.long_path_roulette = options_.long_path_roulette;
  o.split_orders = options_.split_orders;
  o.after_specular_only = true;
  if constexpr (std::is_same_v<M, material::Material>)
    complement_ = std::make_unique<MeshPathTracer>(mesh, medium, std::move(delta),
                                                   camera_.camera(), complementConeFor(options_), o,
                                                   cells);
  else
    complement_ = std::make_unique<MeshPathTracer>(mesh, medium, std::move(delta),
                                                   camera_.camera(), complementConeFor(options_), o);
  combine();
}

double CameraPathTracer::complementCone() const {
  return complement_ ? complementConeFor(options_) : 0.0;
}

void CameraPathTracer::combine() {
  // Per pixel and channel the sum of two independent estimates: values add, variances add. The
  // sums are stored as those of the camera's samples (count n) with that mean and standard
  // error: s = n v, s2 = n v² + (n - 1) n se² (exact_sum.h: meanAndError).
  const Camera& cam = camera_.camera();
  const int nc = static_cast<int>(channels_.size());
  auto one = [&](const McImage& a, const McImage& b, double typical) {
    McImage out(cam.width, cam.height, nc, McImage::Statistics::PerPixel, FixedScale::around(typical));
    for (int y = 0; y < cam.height; ++y)
      for (int x = 0; x < cam.width; ++x) {
        const size_t pix = static_cast<size_t>(y) * static_cast<size_t>(cam.width) + static_cast<size_t>(x);
        const uint64_t n = a.pixelCount(pix);
        out.addPixelCount(pix, n);
        if (n == 0) continue;
        const double N = static_cast<double>(n);
        for (int c = 0; c < nc; ++c) {
          const Estimate ea = a.pixel(x, y, c), eb = b.pixel(x, y, c);
          const double v = ea.value + eb.value;
          const double se2 = ea.std_error * ea.std_error + eb.std_error * eb.std_error;
          out.addSums(out.index(x, y, c), N * v, N * v * v + (N - 1.0) * N * se2);
        }
      }
    return out;
  };
  auto set = [&](const CameraImages& a, const CameraImages& b) {
    CameraImages r;
    r.cone_radiance = one(a.cone_radiance, b.cone_radiance, typical_);
    r.exitance = one(a.exitance, b.exitance, kPi * typical_);
    r.radiance = one(a.radiance, b.radiance, typical_);
    return r;
  };
  combined_ = set(images_, complement_->images());
  if (orders_)
    for (size_t k = 0; k < kScatteringOrders; ++k)
      combinedOrders_[k] = set((*orders_)[k], complement_->orderImages(static_cast<ScatteringOrder>(k)));
}

void CameraPathTracer::init(const geometry::TriangleMesh& mesh) {
  static std::atomic<uint64_t> tracers{0};
  id_ = ++tracers;
  forward_ = glm::normalize(camera_.camera().look_at - camera_.camera().position);
  options_.validate();
  if (lights_.empty()) throw ParameterError("camera paths: no lights: expected at least one");
  for (size_t i = 0; i < lights_.size(); ++i)
    lights_[i] = lights_[i].validated(fmt::format("light {}", i + 1));
  for (size_t c = 0; c < channels_.size(); ++c) {
    const ScalarMedium& m = channels_[c];
    m.validate(channels_.size() == 3 ? kChannelNames[c] : "");
    if (!volume_ && !(m.sigmaT() > 0.0))
      throw ParameterError("camera paths: sigma_a + sigma_s is 0: expected a scattering or "
                           "absorbing medium");
  }
  const double eta = volume_ ? volume_->eta : channels_.front().eta;
  for (const ScalarMedium& m : channels_)
    if (!volume_ && m.eta != eta)
      throw ParameterError("camera paths: the channels have different eta: expected one");
  if (const std::string why = refusal(eta, lights_); !why.empty()) throw ParameterError(why);
  eta_ = eta;
  refracted_.clear();
  refracted_.resize(lights_.size());
  if (eta != 1.0) {
    // The refracted connections of every delta light (refracted_light.h).
    const std::vector<glm::dvec3> outward = RefractedLight::outwardNormals(mesh, body_);
    for (size_t i = 0; i < lights_.size(); ++i)
      if (!std::holds_alternative<EnvironmentLight>(lights_[i].emitter))
        refracted_[i] = std::make_unique<RefractedLight>(mesh, outward, body_, lights_[i], eta);
  }

  // The grid of the images' exact sums: about the radiance a light gives by single scattering.
  const BoundingSphere bounds = body_.bounds();
  double typical = 0.0;
  for (const Light& l : lights_) {
    double e = 0.0;
    if (const auto* dl = std::get_if<DirectionalLight>(&l.emitter)) e = dl->irradiance;
    if (const auto* pl = std::get_if<PointLight>(&l.emitter)) {
      const double r = std::max(glm::length(pl->position - bounds.center), bounds.radius);
      e = pl->intensity / (r * r);
    }
    if (const auto* bl = std::get_if<BeamLight>(&l.emitter))
      e = bl->power / (kPi * bl->radius * bl->radius);
    typical = std::max(typical, e * std::max({l.color[0], l.color[1], l.color[2]}) / (4.0 * kPi));
  }
  const Camera& cam = camera_.camera();
  const int nc = static_cast<int>(channels_.size());
  typical_ = typical;
  auto make = [&] {
    CameraImages im;
    const FixedScale scale = FixedScale::around(typical);
    im.cone_radiance = McImage(cam.width, cam.height, nc, McImage::Statistics::PerPixel, scale);
    im.radiance = im.cone_radiance;
    im.exitance = McImage(cam.width, cam.height, nc, McImage::Statistics::PerPixel,
                          FixedScale::around(kPi * typical));
    return im;
  };
  images_ = make();
  if (options_.split_orders) orders_ = std::array<CameraImages, kScatteringOrders>{make(), make(), make()};
  rowSamples_.assign(static_cast<size_t>(cam.height), 0);
}

CameraPathTracer::PixelSequence CameraPathTracer::pixelSequence(int i, int j,
                                                               uint64_t seedKey) const {
  const Camera& cam = camera_.camera();
  PixelSequence p;
  p.i = i;
  p.j = j;
  const uint64_t pixel = static_cast<uint64_t>(j) * static_cast<uint64_t>(cam.width) + static_cast<uint64_t>(i);
  Rng shiftRng(seedKey, (uint64_t{1} << 63) | pixel);
  p.shiftX = shiftRng.next();
  p.shiftY = shiftRng.next();
  if (cam.projection == Camera::Projection::Pinhole)
    p.filter = camera_.pixelSize() * camera_.pixelSize() / camera_.pixelMeasure(i, j);
  return p;
}

void CameraPathTracer::sampleRay(const PixelSequence& p, uint64_t s, glm::dvec3& origin,
                                 glm::dvec3& dir, double& weight) const {
  const Camera& cam = camera_.camera();
  const auto si = static_cast<uint32_t>(s);
  camera_.ray(p.i + shifted(vanDerCorput(si), p.shiftX),
              static_cast<double>(p.j) + shifted(sobolSecond(si), p.shiftY), origin, dir);
  // The box filter over the pixel's solid angle (pinhole: dΩ = cos³θ dA on the plane at
  // distance 1) or area (orthographic).
  weight = 1.0;
  if (cam.projection == Camera::Projection::Pinhole) {
    const double cosT = glm::dot(dir, forward_);
    weight = cosT * cosT * cosT * p.filter;
  }
}

void CameraPathTracer::setWalker(std::shared_ptr<CameraWalker> walker,
                                 std::shared_ptr<MeshWalker> complement) {
  walker_ = std::move(walker);
  if (complement_) complement_->setWalker(std::move(complement));
}

const CameraImages& CameraPathTracer::orderImages(ScatteringOrder order) const {
  if (!orders_) throw std::logic_error("camera paths: the images are not split by order");
  return complement_ ? combinedOrders_[static_cast<size_t>(order)] : (*orders_)[static_cast<size_t>(order)];
}

CameraPathStats CameraPathTracer::addPass(uint64_t samples, const ProgressCallback& progress) {
  if (samples == 0) throw ParameterError("camera paths: samples is 0: expected at least 1");
  const Camera& cam = camera_.camera();
  const int w = cam.width, h = cam.height;
  const size_t nc = channels_.size();
  for (const uint64_t done : rowSamples_)
    if (done + samples > (uint64_t{1} << 32))
      throw ParameterError("camera paths: more than 2^32 samples per pixel");
  const bool cone = options_.cone_half_angle > 0.0;
  const double theta = options_.cone_half_angle * kPi / 180.0;
  const double cosCone = std::cos(theta), sin2Cone = std::sin(theta) * std::sin(theta);
  const double coneSolidAngle = 2.0 * kPi * (1.0 - cosCone);
  const uint64_t seedKey = mix64(options_.seed ^ 0x63616D6572617061ull);  // "camerapa"
  const Boundary boundary{eta_, refracted_};
  std::vector<ChannelPaths> paths;
  for (size_t c = 0; c < nc; ++c)
    paths.emplace_back(body_, boundary, lights_, volume_ ? nullptr : &channels_[c],
                       volume_ ? &*volume_ : nullptr, static_cast<int>(c),
                       options_.long_path_roulette);
  const int images = options_.exitance ? 3 : 1;
  // One walk for the three channels of a homogeneous medium with one phase function (RgbPaths).
  const bool joint = options_.joint_channels && !volume_ && nc == 3 &&
                     channels_[0].g == channels_[1].g && channels_[1].g == channels_[2].g;
  std::optional<RgbPaths> rgb;
  if (joint) rgb.emplace(body_, boundary, lights_, channels_, options_.long_path_roulette);

  // One block per row: per pixel, channel, image and order the sums of the samples and squares.
  struct Row {
    std::vector<double> s, s2;  // [(x * nc + c) * 12 + image * 4 + k], k = order or 3 = total
    Counters k;
  };
  auto slot = [&](int x, size_t c, int image, size_t k) {
    return ((static_cast<size_t>(x) * nc + c) * 3 + static_cast<size_t>(image)) * 4 + k;
  };
  auto make = [] { return Row{}; };
  auto work = [&](uint64_t j, Row& row, const std::atomic<bool>& stop) {
    const size_t n = static_cast<size_t>(w) * nc * 12;
    row.s.assign(n, 0.0);
    row.s2.assign(n, 0.0);
    const uint64_t first = rowSamples_[j];
    for (int i = 0; i < w; ++i) {
      if (stop.load(std::memory_order_relaxed)) return false;
      const uint64_t pixel = j * static_cast<uint64_t>(w) + static_cast<uint64_t>(i);
      const PixelSequence seq = pixelSequence(i, static_cast<int>(j), seedKey);
      // Separate: one walk per channel (its own random stream); joint: one walk for all three
      // (RgbPaths), on the stream of channel 0.
      const size_t groups = joint ? 1 : nc;
      for (size_t gi = 0; gi < groups; ++gi) {
        const size_t c0 = joint ? 0 : gi, c1 = joint ? nc : gi + 1;
        for (uint64_t s = first; s < first + samples; ++s) {
          Rng rng(seedKey, ((pixel * nc + gi) << 32) + s);
          glm::dvec3 o, d;
          double wPix = 1.0;
          sampleRay(seq, s, o, d, wPix);
          std::array<Scores, 3> sc{};  // per channel
          SurfaceHit hit;
          if (body_.intersect(o, d, 0.0, kInf, hit)) {
            const glm::dvec3 x = o + hit.t * d;
            const glm::dvec3 nrm = glm::dot(hit.normal, d) < 0.0 ? hit.normal : -hit.normal;
            // Ft(η, v) of the diffusion radiance Ft B / π (camera.h).
            const double ftView = eta_ == 1.0 ? 1.0 : fresnelTransmittance(glm::dot(nrm, -d), eta_);
            // The radiance arriving at x from inside the body along -dir (dir pointing in), per
            // channel of the group and order part.
            auto traceInside = [&](const glm::dvec3& dir, double out[3][3]) {
              if (joint) {
                rgb->radiance(x, dir, rng, row.k, out);
              } else {
                paths[gi].radiance(x, dir, rng, row.k, out[gi]);
              }
            };
            // The radiance leaving x along -dir (dir pointing in, from air): at η ≠ 1 the part
            // refracted out of the body, Ft L_inside / η² along the refracted direction (the
            // specular reflection of the surroundings is not subsurface light: the light
            // method scores none, transport.h).
            auto trace = [&](const glm::dvec3& dir, double out[3][3]) {
              if (eta_ == 1.0) return traceInside(dir, out);
              const glm::dvec3 inward = -nrm;
              const double cosI = glm::dot(dir, inward);
              const double f = fresnelTransmittance(cosI, eta_) / (eta_ * eta_);
              traceInside(detail::refract(dir, inward, 1.0 / eta_, refractedCosine(cosI, eta_)), out);
              for (size_t c = c0; c < c1; ++c)
                for (size_t k = 0; k < 3; ++k) out[c][k] *= f;
            };
            if (!cone) {
              double L[3][3] = {};
              trace(d, L);
              for (size_t c = c0; c < c1; ++c)
                for (size_t k = 0; k < 3; ++k) sc[c][0][k] = wPix * L[c][k];
            } else {
              // ω uniform in the cone about v = -d; weight (n·ω) Ω_c / (π sin²θc (n·v)).
              const glm::dvec3 v = -d;
              const double cosA = 1.0 - uniform01(rng) * (1.0 - cosCone);
              const double sinA = std::sqrt(std::max(0.0, 1.0 - cosA * cosA));
              const double phi = 2.0 * kPi * uniform01(rng);
              glm::dvec3 t1, t2;
              tangentFrame(v, t1, t2);
              const glm::dvec3 om =
                  glm::normalize(sinA * std::cos(phi) * t1 + sinA * std::sin(phi) * t2 + cosA * v);
              const double nOm = glm::dot(nrm, om), nV = glm::dot(nrm, v);
              if (nOm > 0.0 && nV > 0.0) {
                double L[3][3] = {};
                trace(-om, L);
                const double f = wPix * nOm * coneSolidAngle / (kPi * sin2Cone * nV);
                for (size_t c = c0; c < c1; ++c)
                  for (size_t k = 0; k < 3; ++k) sc[c][0][k] = f * L[c][k];
              }
            }
            if (options_.exitance) {
              // A cosine-distributed direction about n (Malley): B = π E[L(x, ω')].
              double px, py;
              detail::sampleDisc(rng, 1.0, px, py);
              const double pz = std::sqrt(std::max(0.0, 1.0 - px * px - py * py));
              glm::dvec3 t1, t2;
              tangentFrame(nrm, t1, t2);
              const glm::dvec3 om = glm::normalize(px * t1 + py * t2 + pz * nrm);
              double Lb[3][3] = {};
              if (pz > 0.0) trace(-om, Lb);
              for (size_t c = c0; c < c1; ++c)
                for (size_t k = 0; k < 3; ++k) {
                  sc[c][1][k] = wPix * kPi * Lb[c][k];
                  sc[c][2][k] = wPix * ftView * Lb[c][k];  // Ft(η, v) B / π (camera.h)
                }
            }
            if (options_.exitance || cone) {
              // The light that crossed the body unscattered and leaves at x (ChannelPaths::
              // unscattered), after the paths so that their random streams do not depend on it.
              double b0[3] = {}, cc0[3] = {};
              if (joint)
                rgb->unscattered(x, nrm, -d, cone ? cosCone : 1.0, kPi * sin2Cone, row.k, b0, cc0);
              else
                paths[gi].unscattered(x, nrm, -d, cone ? cosCone : 1.0, kPi * sin2Cone, rng, row.k,
                                      b0[gi], cc0[gi]);
              for (size_t c = c0; c < c1; ++c) {
                // (+=: an environment seen through the body is unscattered light from the walks.)
                sc[c][0][0] += wPix * cc0[c];
                if (options_.exitance) {
                  sc[c][1][0] += wPix * b0[c];
                  sc[c][2][0] += wPix * ftView * b0[c] / kPi;
                }
              }
            }
          }
          for (size_t c = c0; c < c1; ++c)
            for (int im = 0; im < images; ++im) {
              const auto& v = sc[c][static_cast<size_t>(im)];
              const double total = v[0] + v[1] + v[2];
              for (size_t k = 0; k < 4; ++k) {
                const double val = k < 3 ? v[k] : total;
                row.s[slot(i, c, im, k)] += val;
                row.s2[slot(i, c, im, k)] += val * val;
              }
            }
        }
      }
    }
    return true;
  };
  CameraPathStats pass;
  auto merge = [&](uint64_t j, Row& row) {
    for (int i = 0; i < w; ++i) {
      const size_t pix = static_cast<size_t>(j) * static_cast<size_t>(w) + static_cast<size_t>(i);
      for (int im = 0; im < images; ++im) {
        auto image = [&](CameraImages& set) -> McImage& {
          return im == 0 ? set.cone_radiance : (im == 1 ? set.exitance : set.radiance);
        };
        for (size_t c = 0; c < nc; ++c) {
          const size_t idx = images_.exitance.index(i, static_cast<int>(j), static_cast<int>(c));
          image(images_).addSums(idx, row.s[slot(i, c, im, 3)], row.s2[slot(i, c, im, 3)]);
          if (orders_)
            for (size_t k = 0; k < kScatteringOrders; ++k)
              image((*orders_)[k]).addSums(idx, row.s[slot(i, c, im, k)], row.s2[slot(i, c, im, k)]);
        }
        image(images_).addPixelCount(pix, samples);
        if (orders_)
          for (size_t k = 0; k < kScatteringOrders; ++k) image((*orders_)[k]).addPixelCount(pix, samples);
      }
    }
    rowSamples_[j] += samples;
    pass.paths += row.k.paths;
    pass.scattering_events += row.k.events;
    pass.shadow_rays += row.k.shadowRays;
  };
  const uint64_t perRow = static_cast<uint64_t>(w) * samples * nc;
  const uint64_t total = perRow * static_cast<uint64_t>(h);
  std::function<bool(uint64_t, double)> tick;
  if (progress)
    tick = [&](uint64_t rows, double seconds) {
      return progress(TraceProgress{rows * perRow, total, seconds});
    };
  // On a device (walker_): rows in batches of samples, each row's sums as the CPU's rows give
  // them (the per-sample scores in the same order), merged when all its samples of every channel
  // are in; a stop between batches keeps the rows merged so far. A batch starts at 2^12 samples
  // and doubles to 2^16 while one takes under 0.1 s, so that a slow device (llvmpipe) still
  // answers a stop within a fraction of a second.
  auto onDevice = [&]() {
    uint64_t budget = uint64_t{1} << 12;
    detail::BlockRun r;
    r.threads = 1;
    const auto start = std::chrono::steady_clock::now();
    auto seconds = [&] {
      return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    };
    const uint64_t perRowSamples = static_cast<uint64_t>(w) * samples;
    std::vector<CameraWalkSample> batch;
    std::vector<CameraWalkScore> scores;
    for (uint64_t j0 = 0, j1 = 0; j0 < static_cast<uint64_t>(h) && !r.stopped; j0 = j1) {
      j1 = std::min<uint64_t>(static_cast<uint64_t>(h), j0 + std::max<uint64_t>(1, budget / perRowSamples));
      std::vector<Row> rows(j1 - j0);
      for (Row& row : rows) {
        row.s.assign(static_cast<size_t>(w) * nc * 12, 0.0);
        row.s2.assign(row.s.size(), 0.0);
      }
      for (uint64_t s0 = 0, s1 = 0; s0 < samples && !r.stopped; s0 = s1) {
        s1 = std::min(samples, s0 + std::max<uint64_t>(1, budget / (static_cast<uint64_t>(w) * (j1 - j0))));
        const double began = seconds();
        batch.clear();
        for (uint64_t j = j0; j < j1; ++j)
          for (int i = 0; i < w; ++i) {
            const uint64_t pixel = j * static_cast<uint64_t>(w) + static_cast<uint64_t>(i);
            const PixelSequence seq = pixelSequence(i, static_cast<int>(j), seedKey);
            for (uint64_t s = rowSamples_[j] + s0; s < rowSamples_[j] + s1; ++s) {
              glm::dvec3 o, d;
              double wPix = 1.0;
              sampleRay(seq, s, o, d, wPix);
              CameraWalkSample smp{};
              for (int a = 0; a < 3; ++a) {
                smp.origin[a] = static_cast<float>(o[a]);
                smp.direction[a] = static_cast<float>(d[a]);
              }
              smp.weight = static_cast<float>(wPix);
              smp.pixel = static_cast<uint32_t>(pixel);
              smp.sample = static_cast<uint32_t>(s);
              batch.push_back(smp);
            }
          }
        for (size_t c = 0; c < nc; ++c) {
          CameraWalkSetup setup;
          setup.medium = channels_[c];
          setup.volume = volume_ ? &*volume_ : nullptr;
          setup.eta = eta_;
          setup.refracted = refracted_;
          setup.tracer = id_;
          setup.lights = lights_;
          setup.channel = static_cast<int>(c);
          setup.epsilon = body_.epsilon();
          setup.seed = seedKey;
          setup.long_path_roulette = options_.long_path_roulette;
          setup.cone_half_angle = options_.cone_half_angle;
          setup.paths = images > 1 ? 2 : 1;
          walker_->trace(setup, batch, scores);
          const size_t np = static_cast<size_t>(setup.paths);
          for (size_t k = 0; k < batch.size(); ++k) {
            const uint64_t pixel = batch[k].pixel;
            Row& row = rows[pixel / static_cast<uint64_t>(w) - j0];
            const int x = static_cast<int>(pixel % static_cast<uint64_t>(w));
            for (int im = 0; im < images; ++im) {
              // Image 2, Ft(η, v) B / π, from the exitance's path.
              const CameraWalkScore& sc = scores[k * np + static_cast<size_t>(std::min(im, 1))];
              const double f = im == 2 ? static_cast<double>(sc.ft_view) / kPi : 1.0;
              double sum = 0.0;
              for (size_t o = 0; o < 3; ++o) {
                const double v = f * sc.order[o];
                sum += v;
                row.s[slot(x, c, im, o)] += v;
                row.s2[slot(x, c, im, o)] += v * v;
              }
              row.s[slot(x, c, im, 3)] += sum;
              row.s2[slot(x, c, im, 3)] += sum * sum;
              if (im < 2 && sc.collisions != CameraWalkScore::kMissed) {
                ++row.k.paths;
                row.k.events += sc.collisions;
                row.k.shadowRays += sc.shadow_rays;
              }
            }
          }
          if (progress &&
              !progress(TraceProgress{j0 * perRowSamples * nc +
                                          (j1 - j0) * static_cast<uint64_t>(w) * (s0 * nc + (s1 - s0) * (c + 1)),
                                      total, seconds()}))
            r.stopped = true;
        }
        if (seconds() - began < 0.1 && budget < (uint64_t{1} << 16)) budget *= 2;
      }
      if (r.stopped) break;
      for (uint64_t j = j0; j < j1; ++j) merge(j, rows[j - j0]);
      r.blocks_done = j1;
    }
    r.seconds = seconds();
    return r;
  };
  const detail::BlockRun run =
      walker_ ? onDevice()
              : detail::runBlocks<Row>(0, static_cast<uint64_t>(h), options_.threads, make, work,
                                       merge, tick);
  if (progress) progress(TraceProgress{run.blocks_done * perRow, total, run.seconds});
  pass.samples = samples;
  pass.seconds = run.seconds;
  pass.threads = run.threads;
  pass.partial = run.stopped;
  stats_.samples = *std::min_element(rowSamples_.begin(), rowSamples_.end());
  stats_.paths += pass.paths;
  stats_.scattering_events += pass.scattering_events;
  stats_.shadow_rays += pass.shadow_rays;
  stats_.seconds += run.seconds;
  stats_.threads = run.threads;
  stats_.partial = stats_.partial || run.stopped;
  if (complement_ && !run.stopped) {
    // The complement's photons: complement_photons per sample of every pixel so far, in whole
    // blocks (a function of the samples per pixel only, not of how they came in passes).
    const uint64_t want = stats_.samples * static_cast<uint64_t>(w) * static_cast<uint64_t>(h) *
                          options_.complement_photons;
    const uint64_t blocks = (want + kBlockPhotons - 1) / kBlockPhotons;
    const uint64_t done = complement_->stats().photons.empty() ? 0 : complement_->stats().next_block;
    if (blocks > done) {
      // Shown as the pass's end while it runs; a stop ends it after whole blocks (the next pass
      // continues from there).
      ProgressCallback tickComplement;
      if (progress)
        tickComplement = [&](const TraceProgress& p) {
          return progress(TraceProgress{total, total, run.seconds + p.seconds});
        };
      const TransportStats t = complement_->addBlocks(done, blocks - done, tickComplement);
      if (t.partial) {
        pass.partial = true;
        stats_.partial = true;
      }
      pass.seconds += t.seconds;
      stats_.seconds += t.seconds;
    }
    stats_.complement_photons = complement_->stats().photons.empty() ? 0 : complement_->stats().photons[0];
    pass.complement_photons = stats_.complement_photons;
  }
  if (complement_) combine();  // a stopped pass: its rows, and no more complement photons
  return pass;
}

}  // namespace translucent::reference
