// SPDX-License-Identifier: GPL-3.0-or-later
// Photon transport through a closed homogeneous body of arbitrary shape: the random walk of seed
// section 3.2 (Algorithm 1) with the boundary given by ray queries instead of the slab's planes.
// The lit sphere (sphere.h) and the triangle mesh tracer (mesh_tracer.h) are this walk with an
// analytic sphere and an Embree scene as the body.
//
// What is traced, per photon and per colour channel:
//   - emission from one light (directional, point, beam or environment), chosen with probability
//     proportional to the flux it sends towards the body (every photon then carries the same
//     flux, the total);
//   - the light enters at the first surface hit of its ray (so the body shadows itself), with the
//     exact unpolarised Fresnel transmittance Ft(η, cos θi) as a weight (the specularly reflected
//     part is not subsurface light and is not traced) and Snell refraction;
//   - free flights with density σt e^{-σt s}, boundary found by the body's ray query;
//   - at the boundary, exact Fresnel reflectance F seen from inside: internal reflection with
//     probability F (the rest of the flight continues along the mirrored direction, Algorithm 1
//     line 8), else the photon leaves, refracted, and is handed to the tally (every exit is
//     scored: it is exitance at that point);
//   - after an exit the photon flies on in air along the refracted ray (from the exit point, hits
//     closer than epsilon() ignored). If that ray meets the body again (a non-convex body: ear to
//     head, a fin, the two arms of a U), the photon re-enters there and its walk goes on; it ends
//     when an exit ray escapes (nothing hit) or the photon is absorbed. At a re-entry the
//     transmitted part is treated as at the first entry: Snell refraction, Fresnel transmittance
//     Ft(η, cos θi). The reflected part is traced, not dropped: with probability F the photon is
//     mirrored off the outside of the surface, keeping its weight, and flies on in air (it may
//     re-enter elsewhere or escape); else it is refracted in, also keeping its weight. The first
//     entry drops its F because that is the specular reflection of the light source, which every
//     renderer adds as its own surface term; the F at a re-entry is subsurface light (the glow of
//     the ear seen in the head) that no other term accounts for, so dropping it would lose flux
//     (with it, every entered photon is absorbed or escapes: entered = absorbed + escaped for any
//     η). That mirrored light is not exitance and is scored nowhere (camera.h). The remaining
//     free path at an exit carries over to the re-entry (exponential flights are memoryless), so
//     η = 1 needs no random number there. Bodies that declare themselves convex (a static
//     `kConvex = true`, e.g. SphereBody) skip the re-entry query; for a convex mesh the exit ray
//     never hits, so nothing is drawn and results are those of a walk without re-entry (up to
//     the rare photons that slip through the mesh at an edge, mesh_tracer.h);
//   - analog absorption with probability 1 - α at each collision (Algorithm 1 line 15), then
//     Henyey-Greenstein scattering (phase.h);
//   - the seed's long-path roulette after `long_path_roulette` scattering events (keep with
//     probability 1/10, weight x10): unbiased, and it guarantees that every walk ends.
// Heterogeneous media (tracePhotons with a VolumeMedium, majorant_grid.h): the same walk with
// the free flight by delta tracking through a majorant grid and, at a real collision, the local
// albedo (analog absorption) and local g; η is the object's single η (the media of a field are
// index-matched, material/material.h). The homogeneous walk is untouched by it.
// Everything is unbiased. A photon may leave several times (and score several times, even into
// the same pixel): a standard error needs the per-photon second moment, so tallies must sum a
// photon's scores before squaring. ExitTally::Block::endPhoton() marks the end of each photon
// for that; TransportStats::exited adds one per-photon total (all its exits), escaped the weight
// of its final departure.
//
// Units: positions in scene units, coefficients per scene unit (Medium::channel applies the
// scale). Light fluxes in watts (or any unit; results are linear in it): a directional light's
// irradiance is measured on a plane perpendicular to its direction.
//
// Determinism: photons are traced in blocks of kBlockPhotons per channel; channel c of block b
// draws from the stream Rng(seed, b * channels + c), and block results are merged in block order.
// A run is a function of (scene, options, seed) only, whatever the thread count; a run of
// K blocks equals, bit for bit, runs of K1 and K - K1 blocks with first_block = 0 and K1.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <variant>
#include <vector>

#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

#include "translucent/lights/environment_map.h"
#include "translucent/reference/exact_sum.h"
#include "translucent/optics/medium.h"
#include "translucent/reference/majorant_grid.h"
#include "translucent/reference/run_state.h"
#include "translucent/reference/slab.h"

namespace translucent::reference {

struct SurfaceHit {
  double t = 0.0;       // distance along the ray
  glm::dvec3 normal{};  // unit geometric normal, either orientation
};

struct BoundingSphere {
  glm::dvec3 center{0.0};
  double radius = 0.0;
};

// A closed body whose inside is the medium. The transport never relies on the orientation of
// the normals: a ray from outside enters at its first hit, a ray from inside leaves at its first
// hit. Implementations must be safe to query from several threads at once. A final class that is
// convex may declare `static constexpr bool kConvex = true;` so that the templated walk
// (transport_impl.h) skips the re-entry query after an exit.
class Body {
 public:
  virtual ~Body() = default;
  // First boundary point o + t d with t in (t_min, t_max] (d unit length); false if none.
  virtual bool intersect(const glm::dvec3& o, const glm::dvec3& d, double t_min, double t_max,
                         SurfaceHit& hit) const = 0;
  // Whether any boundary point lies on o + t d, t in (t_min, t_max).
  virtual bool occluded(const glm::dvec3& o, const glm::dvec3& d, double t_min,
                        double t_max) const = 0;
  virtual BoundingSphere bounds() const = 0;
  // Distance below which a ray leaving a surface point ignores hits (its own surface) [scene
  // units]; set by the precision of the ray queries.
  virtual double epsilon() const = 0;
};

// Lights. Directions are unit vectors (normalised on validation).
struct DirectionalLight {
  glm::dvec3 direction{0.0, 0.0, 1.0};  // towards the light (the seed's l in n·l)
  double irradiance = 1.0;              // on a plane perpendicular to `direction` [W/unit²]
};
struct PointLight {
  glm::dvec3 position{0.0, 0.0, 10.0};
  double intensity = 1.0;  // [W/sr], isotropic
};
// A collimated beam of circular cross-section (radius 0: a pencil beam, the searchlight problem);
// its origin must lie outside the body.
struct BeamLight {
  glm::dvec3 origin{0.0, 0.0, 10.0};
  glm::dvec3 direction{0.0, 0.0, -1.0};  // of propagation
  double radius = 0.0;                    // [scene units]
  double power = 1.0;                     // total flux [W]
};
// Distant illumination from a latitude-longitude radiance map (lights/environment_map.h), scaled
// by `intensity` (and the light's colour). Photons of channel c come from direction ω with
// density ∝ that channel's radiance (samplers[c], exact for the piecewise-constant map), through
// a uniform point of the disc that covers the body's bounding sphere, perpendicular to ω: every
// photon then carries the same flux πR² ∫ L_c dω (the radiance crossing that disc towards the
// body). Make it with make(); copies share the map and samplers.
struct EnvironmentLight {
  std::shared_ptr<const lights::EnvironmentMap> map;
  double rotate = 0.0;     // degrees about +y
  double intensity = 1.0;  // multiplier of the map's radiance
  // Per channel: density ∝ the channel's radiance; null where that channel is 0 everywhere.
  std::array<std::shared_ptr<const lights::EnvironmentSampler>, 3> samplers;

  // Throws ParameterError when the map is empty or black in every channel.
  static EnvironmentLight make(std::shared_ptr<const lights::EnvironmentMap> map, double rotate,
                               double intensity);
};
struct Light {
  std::variant<DirectionalLight, PointLight, BeamLight, EnvironmentLight> emitter;
  Rgb color{1.0, 1.0, 1.0};  // per-channel multiplier of the emitted flux

  // A copy with unit directions; throws ParameterError naming `what` (e.g. "light 2") and the
  // bad field.
  Light validated(const std::string& what) const;
};

// A photon leaving the body.
struct ExitRecord {
  glm::dvec3 position{};   // on the surface
  glm::dvec3 normal{};     // outward unit normal there
  glm::dvec3 direction{};  // direction of flight outside (refracted)
  double weight = 0.0;     // flux it carries [W]
  int channel = 0;
  // How often the photon scattered before this exit (the seed's S(0), S(1), S_d; slab.h).
  ScatteringOrder order = ScatteringOrder::Unscattered;
  // Whether the photon was reflected back inside at the boundary (Fresnel or total internal
  // reflection) between its entry and this exit; a flight in air and re-entry does not count.
  bool reflected = false;
};

// Where exiting photons go. Each block of photons is recorded into its own Block by one worker
// thread, then merged into the tally in block order (so sums do not depend on thread timing).
// A photon's exits are recorded in order, then endPhoton() is called once for it (also for a
// photon that never exited). A block that keeps second moments must add the photon's summed
// score per bin there, not w² per record: a photon that left twice through one bin would
// otherwise count as two independent samples (an underestimated standard error). A block that
// scores into bins every photon can reach at most once (a face of a convex body) may ignore it.
class ExitTally {
 public:
  class Block {
   public:
    virtual ~Block() = default;
    virtual void record(const ExitRecord& e) = 0;
    virtual void endPhoton() {}
  };
  virtual ~ExitTally() = default;
  virtual std::unique_ptr<Block> newBlock() const = 0;
  virtual void merge(Block& block) = 0;
};

// Sums of a per-photon quantity and of its square.
struct Moments {
  double s = 0.0, s2 = 0.0;
  void add(double w) {
    s += w;
    s2 += w * w;
  }
  void merge(const Moments& o) {
    s += o.s;
    s2 += o.s2;
  }
  // Mean over n photons (zeros included) and its standard error, divided by `measure`.
  Estimate estimate(uint64_t n, double measure = 1.0) const;
};

struct TransportOptions {
  uint64_t photons = 1'000'000;  // per channel; rounded up to whole blocks of kBlockPhotons
  uint64_t seed = 1;
  uint64_t first_block = 0;  // index of the first block (progressive passes continue from here)
  int threads = 0;           // 0: all hardware threads
  // Long-path roulette after this many scattering events (0: off). On by default so that every
  // walk ends even in a body without absorption; at 10^6 events it changes nothing else.
  uint64_t long_path_roulette = 1'000'000;
  // Score only the light that met the boundary again (an internal reflection, or an exit and a
  // re-entry) between its entry and its first scattering: the part of the delta lights' light
  // that the camera method's refracted next-event estimation cannot find (camera_paths.h). A
  // photon that scatters first, or leaves at its first boundary event, is scored nowhere.
  bool after_specular_only = false;

  void validate() const;
};

// The options a progressive tracer (sphere.h, mesh_tracer.h) keeps for all its passes.
struct TracerOptions {
  uint64_t seed = 1;
  int threads = 0;  // 0: all hardware threads
  uint64_t long_path_roulette = TransportOptions{}.long_path_roulette;
  // Also keep the images per scattering order (ImageTally's split_orders; camera.h).
  bool split_orders = false;
  bool after_specular_only = false;  // TransportOptions::after_specular_only
};

// Per-channel sums of one run (or of several, merged). The flux sums are order-independent
// (exact_sum.h) on the grid of the flux a photon of the channel carries, so that shards of a run
// merge into its totals bit for bit.
struct TransportStats {
  std::vector<uint64_t> photons;    // photons traced, per channel
  std::vector<MomentSum> emitted;   // flux sent towards the body
  std::vector<MomentSum> entered;   // flux transmitted into the body
  std::vector<MomentSum> exited;    // flux leaving it, summed over every exit of a photon (a
                                    // photon that re-enters and leaves again counts twice)
  std::vector<MomentSum> escaped;   // flux of the final departures (entered = absorbed +
                                    // escaped; equals exited for a convex body)
  // `exited` by the scattering order of each exit (slab.h: ScatteringOrder), per channel; the
  // three add up to `exited`.
  std::array<std::vector<MomentSum>, kScatteringOrders> exited_by_order;
  uint64_t scattering_events = 0;
  uint64_t next_block = 0;  // first block a following pass should use
  double seconds = 0.0;
  int threads = 0;
  bool partial = false;  // stopped before all blocks were traced

  void merge(const TransportStats& o);
  uint64_t totalPhotons() const;
  // The sums and counts as named arrays `<prefix>.…` (run_state.h), and back (read() replaces
  // the photons, flux sums and event count; the arrays must match this object's channels and
  // grids).
  void write(RunState& state, const std::string& prefix) const;
  void read(const RunState& state, const std::string& prefix);
  double photonsPerSecond() const { return seconds > 0.0 ? totalPhotons() / seconds : 0.0; }
};

// Traces options.photons photons per channel (channels: 1 or 3 media, same η expected but not
// required) from `lights` into `body` and records every exit in `tally` (a photon that leaves,
// re-enters and leaves again is recorded at both exits, then endPhoton()). The progress callback
// counts photons over all channels; returning false stops the run (blocks already traced are
// kept; partial = true). Throws ParameterError for bad media, lights or options.
TransportStats tracePhotons(const Body& body, std::span<const ScalarMedium> channels,
                            std::span<const Light> lights, const TransportOptions& options,
                            ExitTally& tally, const ProgressCallback& progress = {});

// The same through a body filled with a heterogeneous medium (three channels, majorant_grid.h;
// medium.grid must cover the body). Throws ParameterError for a medium without field or grid,
// bad lights or options.
TransportStats tracePhotons(const Body& body, const VolumeMedium& medium,
                            std::span<const Light> lights, const TransportOptions& options,
                            ExitTally& tally, const ProgressCallback& progress = {});

// Photons traced by another walker (the GPU's: reference/gpu), handed back for scoring. A batch
// holds whole blocks of one channel: photons[(b - first) kBlockPhotons + p] and their exits,
// in photon order (photon k's are exits[first_exit .. first_exit + exits - 1], in the order it
// left).
struct WalkedPhoton {
  double entered = 0.0;  // flux transmitted in at the first hit (0: missed the body)
  double exited = 0.0;   // the sum of its exits' weights
  double escaped = 0.0;  // the weight of its final departure (0: absorbed or ended by the roulette)
  uint64_t scatters = 0;
  uint32_t first_exit = 0, exits = 0;
};
struct WalkedExit {
  glm::dvec3 position{}, normal{}, direction{};  // as ExitRecord
  double weight = 0.0;
  ScatteringOrder order = ScatteringOrder::Unscattered;
};
struct WalkedBatch {
  std::vector<WalkedPhoton> photons;
  std::vector<WalkedExit> exits;
};
// What another walker needs of a channel (detail::channelWalks, made public): coefficients per
// scene unit, the light choice, and the flux every photon carries.
struct WalkChannel {
  double sigma_t = 1.0;
  double absorb_probability = 0.0;  // 1 - α
  double g = 0.0;
  double eta = 1.0;                 // n_inside / n_outside (1: index-matched)
  double flux = 0.0;                // what every photon of the channel carries
  std::vector<double> light_cdf;    // cumulative share of the flux per light (last: 1)
};
// Throws ParameterError for bad media or lights (as tracePhotons).
std::vector<WalkChannel> walkChannels(const BoundingSphere& bounds,
                                      std::span<const ScalarMedium> channels,
                                      std::span<const Light> lights);

// A walker other than the CPU's (the GPU's: reference/gpu) for the body whose tracer gives it
// `Setup` (SphereWalkSetup, MeshWalkSetup): whole blocks of one channel, handed back for the
// tracer to score as its own photons (scoreWalkedBlocks).
template <class Setup>
class PhotonWalker {
 public:
  virtual ~PhotonWalker() = default;
  // Photons of `channel` in blocks [first, first + count) into `out`.
  virtual void trace(const Setup& setup, int channel, uint64_t first, uint64_t count,
                     WalkedBatch& out) = 0;
  virtual std::string name() const = 0;  // what traces, for outputs: "gpu (<renderer>)"
};

// Traces blocks [first, first + count) of `channel` into `out`.
using WalkFunction = std::function<void(int channel, uint64_t first, uint64_t count, WalkedBatch& out)>;

// Blocks [first, first + blocks) traced by `walk` and scored as tracePhotons scores its own
// photons (per block and channel a tally block and flux counters, merged in block order; every
// photon of channel c carries channels[c].flux): the images and statistics a tracer keeps do
// not depend on which walker traced. Batches of blocks grow from 4 to 256 while one takes under
// ~0.05 s; progress is reported, and a stop honoured, between batches (partial = true).
// threads = 1.
TransportStats scoreWalkedBlocks(const BoundingSphere& bounds, std::span<const Light> lights,
                                 std::span<const WalkChannel> channels, uint64_t first,
                                 uint64_t blocks, const WalkFunction& walk, ExitTally& tally,
                                 const ProgressCallback& progress = {});

// Flux each light sends towards the body's bounding sphere in one channel [W] (what the photons
// of that light carry in total).
double emittedFlux(const Light& light, const BoundingSphere& bounds, int channel);

// Per channel the flux estimates of a run (emitted, entered, exited, escaped, with standard
// errors, and "exited_by_order": exited split into unscattered, single and multiple), as the
// "flux_per_channel" array of the path tracers' JSON (CLI and Python).
nlohmann::json fluxPerChannelJson(const TransportStats& stats);

// The statistics of a run that has traced nothing yet: `channels` channels of zero sums, each on
// the grid of the flux a photon of the channel carries (Σ of emittedFlux over the lights), as
// tracePhotons makes them. A run state (run_state.h) is read into these.
TransportStats emptyStats(const BoundingSphere& bounds, size_t channels,
                          std::span<const Light> lights);

}  // namespace translucent::reference
