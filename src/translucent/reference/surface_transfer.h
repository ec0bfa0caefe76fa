// SPDX-License-Identifier: GPL-3.0-or-later
// Subsurface transport from chosen surface points: the photon walk of transport.h started at
// small entry discs on the body's surface instead of at the scene's lights. What leaves the body,
// per entry, is the column of a transfer operator from surface irradiance to surface exitance
// (precomputed radiance transfer for translucent objects: Wang, Tran, Snyder, Guo & Shum 2005,
// "All-frequency interactive relighting of translucent objects with single and multiple
// scattering"; Hašan, Pellacini & Bala 2006, "Direct-to-indirect transfer for cinematic
// relighting"), here computed by the path tracer itself, so that it carries the body's real shape
// (thin parts, curvature, re-entry through concavities) rather than a half-space model.
//
// Per entry j and colour channel: `photons` photons of a collimated beam of radius r_j that
// arrives at p_j along its direction (-n_j by default; its origin r_j back along it), with the
// exact walk of
// tracePhotons: Fresnel transmittance Ft(η, cos θi) and Snell refraction at the first hit,
// free flights (exponential, or delta tracking through the majorant grid of a heterogeneous
// medium), internal reflection, exits (each reported to `score`), flight in air and re-entry,
// analog absorption and the long-path roulette. Every photon carries 1 W before the entry; the
// flux actually transmitted in is summed per entry and channel (SurfaceTransferStats::entered),
// so that score's weights divided by it are the exiting flux per unit entering flux, whatever
// part of the disc missed or grazed the surface.
// Determinism: channel c of entry j draws from Rng(seed, stream_j · channels + c); the exits of entry j
// are reported, in photon order, from one thread. Results depend on (body, media, entries,
// options) only, not on the thread count.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "translucent/reference/majorant_grid.h"
#include "translucent/reference/transport.h"

namespace translucent::reference {

struct SurfaceEntry {
  glm::dvec3 position{};  // on the surface
  glm::dvec3 normal{};    // unit, outward
  double radius = 0.0;    // of the beam [scene units], > 0
  // The beam's direction of flight (unit, into the surface: direction · normal < 0); zero: along
  // -normal (normal incidence).
  glm::dvec3 direction{0.0};
  // Photons of channel c draw from Rng(seed, stream · channels + c): entries that share a stream
  // share their random numbers (common random numbers, for differences between entries that
  // differ only in direction).
  uint64_t stream = 0;
};

struct SurfaceTransferOptions {
  uint64_t photons = 1024;  // per entry and channel
  uint64_t seed = 1;
  int threads = 0;  // 0: all hardware threads
  uint64_t long_path_roulette = TransportOptions{}.long_path_roulette;
};

struct SurfaceTransferStats {
  // Per entry and channel: the flux transmitted into the body [W] (photons × 1 W × the mean Ft
  // over the disc; 0 for an entry whose disc missed the body or that was not traced).
  std::vector<std::array<double, 3>> entered;
  size_t entries_done = 0;  // entries [0, entries_done) are complete
  uint64_t photons = 0;     // traced, over all entries and channels
  uint64_t scattering_events = 0;
  double seconds = 0.0;
  int threads = 0;
  bool partial = false;  // stopped by the progress callback before every entry was traced
};

// Called for every exit of a photon that entered through entry `entry` (ExitRecord::weight in W,
// of the photon's 1 W before the entry). Each entry's calls come from one thread; different
// entries' may come from different threads at once.
using SurfaceExitScore = std::function<void(size_t entry, const ExitRecord& exit)>;

// Traces the entries in order of index on `threads` threads (progress counts photons over all
// channels; returning false stops after the entries being traced, which are dropped: their
// `entered` stays 0 and their scores must be discarded by the caller, entries_done says where
// the complete prefix ends). `channels`: 1 or 3 media; `volume`: a heterogeneous medium filling
// the body (then `channels` gives η per channel; three channels), or null. Throws ParameterError
// for bad media, entries or options.
SurfaceTransferStats traceSurfaceEntries(const Body& body, std::span<const ScalarMedium> channels,
                                         const VolumeMedium* volume,
                                         std::span<const SurfaceEntry> entries,
                                         const SurfaceTransferOptions& options,
                                         const SurfaceExitScore& score,
                                         const ProgressCallback& progress = {});

}  // namespace translucent::reference
