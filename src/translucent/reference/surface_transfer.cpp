// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/reference/surface_transfer.h"

#include <fmt/format.h>

#include <atomic>
#include <cmath>

#include <glm/geometric.hpp>

#include "translucent/reference/block_driver.h"
#include "translucent/reference/transport_impl.h"

namespace translucent::reference {
namespace {

// Forwards one entry's exits to the caller's score.
class EntryBlock final : public ExitTally::Block {
 public:
  EntryBlock(const SurfaceExitScore& score, size_t entry) : score_(score), entry_(entry) {}
  void record(const ExitRecord& e) override { score_(entry_, e); }

 private:
  const SurfaceExitScore& score_;
  size_t entry_;
};

Light entryLight(const SurfaceEntry& e) {
  BeamLight beam;
  beam.direction = e.direction == glm::dvec3(0.0) ? -e.normal : e.direction;
  // Back from the surface by the disc's radius: a disc that straddled a bump would start some
  // rays inside the body (they would "enter" where they leave it).
  beam.origin = e.position - e.radius * beam.direction;
  beam.radius = e.radius;
  beam.power = 1.0;
  return Light{beam, Rgb{1.0, 1.0, 1.0}};
}

}  // namespace

SurfaceTransferStats traceSurfaceEntries(const Body& body, std::span<const ScalarMedium> channels,
                                         const VolumeMedium* volume,
                                         std::span<const SurfaceEntry> entries,
                                         const SurfaceTransferOptions& O,
                                         const SurfaceExitScore& score,
                                         const ProgressCallback& progress) {
  const size_t nc = channels.size();
  if (nc != 1 && nc != 3)
    throw ParameterError(fmt::format("surface transfer: {} channels: expected 1 or 3", nc));
  if (volume && nc != 3)
    throw ParameterError("surface transfer: a heterogeneous medium needs three channels");
  for (const ScalarMedium& m : channels) m.validate();
  if (O.photons == 0) throw ParameterError("surface transfer: photons is 0: expected at least 1");
  if (!score) throw ParameterError("surface transfer: no score function");
  for (size_t j = 0; j < entries.size(); ++j) {
    const SurfaceEntry& e = entries[j];
    const double len = glm::length(e.normal);
    const bool along = e.direction == glm::dvec3(0.0) ||
                       (std::abs(glm::length(e.direction) - 1.0) < 1e-3 && glm::dot(e.direction, e.normal) < 0.0);
    if (!std::isfinite(e.position.x + e.position.y + e.position.z) || !(std::abs(len - 1.0) < 1e-3) ||
        !(e.radius > 0.0) || !std::isfinite(e.radius) || !along)
      throw ParameterError(fmt::format(
          "surface transfer: entry {}: expected a finite position, a unit normal, a radius > 0 and "
          "a unit direction into the surface or none (normal length {}, radius {})", j, len,
          e.radius));
  }
  const BoundingSphere bounds = body.bounds();
  struct Result {
    std::array<double, 3> entered{};
    uint64_t events = 0;
  };
  SurfaceTransferStats stats;
  stats.entered.assign(entries.size(), {0.0, 0.0, 0.0});
  auto make = [] { return Result{}; };
  auto work = [&](uint64_t j, Result& r, const std::atomic<bool>& stop) {
    const Light light = entryLight(entries[j]).validated(fmt::format("entry {}", j));
    const std::span<const Light> lights(&light, 1);
    const std::vector<detail::ChannelWalk> walks = detail::channelWalks(bounds, channels, lights);
    detail::BlockCounters k(nc);
    EntryBlock tally(score, static_cast<size_t>(j));
    for (size_t c = 0; c < nc; ++c) {
      Rng rng(O.seed, entries[j].stream * nc + c);
      for (uint64_t p = 0; p < O.photons; ++p) {
        if ((p & 63u) == 0 && stop.load(std::memory_order_relaxed)) return false;
        if (volume) {
          if (!detail::traceVolumePhoton(body, bounds, lights, walks[c], *volume, static_cast<int>(c),
                                         O.long_path_roulette, rng, k, tally, stop))
            return false;
        } else {
          detail::tracePhoton(body, bounds, lights, walks[c], static_cast<int>(c),
                              O.long_path_roulette, rng, k, tally);
        }
      }
      r.entered[c] = k.entered[c].s;
    }
    r.events = k.events;
    return true;
  };
  auto merge = [&](uint64_t j, Result& r) {
    stats.entered[j] = r.entered;
    stats.scattering_events += r.events;
    ++stats.entries_done;
  };
  const uint64_t perEntry = O.photons * nc, total = perEntry * entries.size();
  std::function<bool(uint64_t, double)> tick;
  if (progress)
    tick = [&](uint64_t done, double seconds) {
      return progress(TraceProgress{done * perEntry, total, seconds});
    };
  const detail::BlockRun run = detail::runBlocks<Result>(0, entries.size(), O.threads, make, work, merge, tick);
  stats.photons = stats.entries_done * perEntry;
  stats.seconds = run.seconds;
  stats.threads = run.threads;
  stats.partial = run.stopped;
  if (progress) progress(TraceProgress{stats.photons, total, run.seconds});
  return stats;
}

}  // namespace translucent::reference
