// SPDX-License-Identifier: GPL-3.0-or-later
// The GPU walker of the mesh tracer (mesh_gpu.h).
#include "translucent/gpu/bvh_buffers.h"
#include "translucent/reference/gpu/mesh_gpu.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <variant>

#include "translucent/geometry/deform.h"
#include "translucent/geometry/flat_bvh.h"
#include "translucent/gpu/compute.h"
#include "translucent/reference/gpu/field_gpu.h"
#include "translucent/reference/majorant_grid.h"
#include "translucent/gpu/program.h"
#include "translucent/reference/gpu/walk_program.h"
#include "translucent/reference/philox.h"
#include "translucent/reference/sampling.h"

namespace translucent::reference {
namespace {

// mesh_walk.comp's records (std430).
struct PhotonOut {
  double entered, exited, escaped;
  uint32_t scatters, exits;
};
static_assert(sizeof(PhotonOut) == 32);
struct ExitOut {
  double px, py, pz, weight;
  float nx, ny, nz, dx, dy, dz;
  uint32_t photon, rank;
};
static_assert(sizeof(ExitOut) == 64);
// A suspended walk (mesh_walk.comp: WalkState), kept on the GPU only.
struct WalkState {
  double x, y, z, w, entered, exited, escaped, pad;
  float dx, dy, dz;
  uint32_t flags, counter, used, scatters, exits;
};
static_assert(sizeof(WalkState) == 96);
struct GpuLight {
  float p[3];
  uint32_t type;
  float dir[3];
  float radius;
  float t1[3];
  float cosMax;
  float t2[3];
  float cdf;
};
static_assert(sizeof(GpuLight) == 64);

void put(float (&out)[3], const glm::dvec3& v) {
  out[0] = static_cast<float>(v.x);
  out[1] = static_cast<float>(v.y);
  out[2] = static_cast<float>(v.z);
}

// The lights as mesh_walk.comp emits them (transport_impl.h: emit), with channel c's cdf.
// Light i's cumulative share of the channel's flux, as the shader compares it (float; the last 1).
float lightCdf(const WalkChannel& ch, size_t i) {
  return i + 1 < ch.light_cdf.size() ? static_cast<float>(ch.light_cdf[i]) : 1.0f;
}

std::vector<GpuLight> gpuLights(const MeshWalkSetup& setup, const WalkChannel& ch) {
  std::vector<GpuLight> out;
  const BoundingSphere& b = setup.bounds;
  for (size_t i = 0; i < setup.lights.size(); ++i) {
    GpuLight g{};
    glm::dvec3 axis{0.0, 0.0, 1.0};
    if (const auto* dl = std::get_if<DirectionalLight>(&setup.lights[i].emitter)) {
      g.type = 0;
      put(g.p, b.center + 2.0 * b.radius * dl->direction);
      axis = dl->direction;
      put(g.dir, -dl->direction);
      g.radius = static_cast<float>(b.radius);
    } else if (const auto* pl = std::get_if<PointLight>(&setup.lights[i].emitter)) {
      g.type = 1;
      put(g.p, pl->position);
      const glm::dvec3 toCenter = b.center - pl->position;
      const double dist = glm::length(toCenter);
      g.cosMax = -1.0f;
      if (dist > b.radius) {
        axis = toCenter / dist;
        g.cosMax = static_cast<float>(
            std::sqrt(std::max(0.0, 1.0 - (b.radius / dist) * (b.radius / dist))));
      }
      put(g.dir, axis);
    } else if (const auto* bl = std::get_if<BeamLight>(&setup.lights[i].emitter)) {
      g.type = 2;
      put(g.p, bl->origin);
      axis = bl->direction;
      put(g.dir, bl->direction);
      g.radius = static_cast<float>(bl->radius);
    } else {
      g.type = 3;  // environment: the direction per photon from EnvDirs
      put(g.p, b.center);
      g.radius = static_cast<float>(b.radius);
    }
    glm::dvec3 t1, t2;
    detail::tangentFrame(axis, t1, t2);
    put(g.t1, t1);
    put(g.t2, t2);
    g.cdf = lightCdf(ch, i);
    out.push_back(g);
  }
  return out;
}

using namespace gpu_walk;

class GpuMeshWalker final : public MeshWalker {
 public:
  GpuMeshWalker(gpu::Context& context, const geometry::TriangleMesh& mesh, const std::string& what)
      : context_(context), program_(build(context, false)) {
    bvh_ = gpu::BvhBuffers::upload(geometry::FlatBvh::build(mesh, what));
    counter_ = gpu::makeStorageBuffer(sizeof(uint32_t));
    control_ = gpu::makeStorageBuffer(2 * sizeof(uint32_t));
    name_ = deviceName();
    limit_ = loopLimit();
  }
  // The buffers and the program are released in their context.
  ~GpuMeshWalker() override { context_.makeCurrent(); }

  void trace(const MeshWalkSetup& setup, int channel, uint64_t first, uint64_t count,
             WalkedBatch& out) override {
    context_.makeCurrent();
    const WalkChannel& ch = setup.channels.at(static_cast<size_t>(channel));
    if (setup.volume && !volumeProgram_) volumeProgram_.emplace(build(context_, true));
    const gpu::ShaderProgram& p = setup.volume ? *volumeProgram_ : program_;
    const std::vector<GpuLight> lights = gpuLights(setup, ch);
    gpu::Buffer lightBuffer = gpu::makeStorageBuffer(std::span<const GpuLight>(lights));
    setChannel(p, ch, setup.seed, setup.long_path_roulette);
    p.set("Channel", static_cast<unsigned>(channel));
    p.set("LightCount", static_cast<unsigned>(lights.size()));
    setDouble(p, "Flux", ch.flux);
    p.set("Matched", ch.eta == 1.0);
    p.set("AfterSpecularOnly", setup.after_specular_only);
    p.set("Eta", static_cast<float>(ch.eta));
    p.set("Epsilon", static_cast<float>(setup.epsilon));
    volume_.set(p, setup.volume, channel);

    const uint64_t n = count * kBlockPhotons, firstPhoton = first * kBlockPhotons;
    if (n > photonCapacity_) {
      photons_ = gpu::makeStorageBuffer(n * sizeof(PhotonOut));
      states_ = gpu::makeStorageBuffer(n * sizeof(WalkState));
      for (gpu::Buffer& l : lists_) l = gpu::makeStorageBuffer(n * sizeof(uint32_t));
      photonCapacity_ = n;
    }
    // Most photons leave once or twice; a batch with more exits than the buffer holds is traced
    // again into a larger one (the same photons: the streams are counters).
    if (exitCapacity_ < 2 * n) growExits(2 * n);
    setLowHigh(p, "FirstPhoton", firstPhoton);
    environmentDirections(setup, channel, firstPhoton, n);
    p.set("Count", static_cast<unsigned>(n));
    // Walks suspend after `budget` loop iterations and are resumed by further dispatches
    // (mesh_walk.comp, "Suspension"), so that no invocation meets the driver's loop limit; a
    // batch whose largest count could have met it is traced again with half the budget (the
    // same walks: the streams are counters), and refused when a single free flight would.
    uint32_t exitCount = 0, budget = limit_.budget();
    for (;;) {
      const uint32_t zero = 0;
      gpu::uploadBytes(counter_, 0, sizeof(zero), &zero);
      volume_.resetViolations();
      p.set("ExitCapacity", static_cast<unsigned>(exitCapacity_));
      p.set("WorkBudget", budget);
      gpu::bindStorage(0, photons_);
      gpu::bindStorage(1, bvh_.nodes);
      gpu::bindStorage(2, bvh_.triangles);
      gpu::bindStorage(3, exits_);
      gpu::bindStorage(4, counter_);
      gpu::bindStorage(5, lightBuffer);
      gpu::bindStorage(6, envDirs_);
      volume_.bind(channel);
      gpu::bindStorage(10, states_);
      const uint32_t maxWork = dispatchSuspendable(p, n, control_, lists_);
      if (!limit_.clear(maxWork)) {
        if (budget <= 64) throwLoopLimit("GPU mesh walk", maxWork, limit_, name_);
        budget /= 2;
        continue;
      }
      gpu::downloadBytes(counter_, 0, sizeof(exitCount), &exitCount);
      if (exitCount <= exitCapacity_) break;
      growExits(exitCount + exitCount / 4);
    }
    hostPhotons_.resize(n);
    gpu::downloadBytes(photons_, 0, n * sizeof(PhotonOut), hostPhotons_.data());
    if (setup.volume) {
      // Of the dispatch that fit (the counter is zeroed before each).
      const uint32_t violations = volume_.violations();
      if (violations)
        setup.volume->majorant_violations->fetch_add(violations, std::memory_order_relaxed);
    }
    hostExits_.resize(exitCount);
    if (exitCount) gpu::downloadBytes(exits_, 0, exitCount * sizeof(ExitOut), hostExits_.data());

    // Back into photon order: photon k's exits at first_exit(k) + rank.
    out.photons.assign(n, WalkedPhoton{});
    uint32_t next = 0;
    for (uint64_t k = 0; k < n; ++k) {
      const PhotonOut& r = hostPhotons_[k];
      WalkedPhoton& ph = out.photons[k];
      ph.entered = r.entered;
      ph.exited = r.exited;
      ph.escaped = r.escaped;
      ph.scatters = r.scatters;
      ph.first_exit = next;
      ph.exits = r.exits;
      next += r.exits;
    }
    if (next != exitCount)
      throw std::runtime_error("GPU mesh walk: the photons' exit counts do not add up to the exits written");
    out.exits.assign(exitCount, WalkedExit{});
    for (const ExitOut& e : hostExits_) {
      const WalkedPhoton& ph = out.photons.at(e.photon);
      // mesh_walk.comp: the rank in the low 30 bits, the scattering order in the top two.
      WalkedExit& x = out.exits.at(ph.first_exit + (e.rank & 0x3fffffffu));
      x.order = static_cast<ScatteringOrder>(e.rank >> 30);
      x.position = glm::dvec3(e.px, e.py, e.pz);
      x.normal = glm::dvec3(e.nx, e.ny, e.nz);
      x.direction = glm::dvec3(e.dx, e.dy, e.dz);
      x.weight = e.weight;
    }
  }

  std::string name() const override { return name_; }

 private:
  static gpu::ShaderProgram build(const gpu::Context& context, bool volume) {
    context.makeCurrent();
    return gpu::ShaderProgram::compute("reference/mesh_walk.comp",
                                       volume ? gpu::Defines{{"VOLUME", "1"}} : gpu::Defines{});
  }
  // The directions towards the scene's environment lights of photons firstPhoton .. firstPhoton +
  // n - 1 of `channel`. The light a photon comes from is chosen in the shader from the first word
  // of its stream, philox((p_lo, p_hi, 0, channel), Seed)[0], against the lights' float CDF; the
  // same choice is made here, bit for bit (24-bit uniform, float comparisons), so that a photon
  // of an environment light gets a direction of that light's map. The direction is drawn by that
  // map's sampler (exact, texel by texel in solid angle, as the CPU's emit) from two 53-bit
  // uniforms of the photon's words philox((p_lo, p_hi, 0, 8 + channel), Seed): a function of the
  // seed, photon and channel only.
  void environmentDirections(const MeshWalkSetup& setup, int channel, uint64_t firstPhoton,
                             uint64_t n) {
    bool any = false;
    for (const Light& l : setup.lights) any = any || std::holds_alternative<EnvironmentLight>(l.emitter);
    if (!any) {
      if (!envDirs_) envDirs_ = gpu::makeStorageBuffer(16);  // bound, never read
      return;
    }
    const WalkChannel& ch = setup.channels.at(static_cast<size_t>(channel));
    std::vector<float> cdf(setup.lights.size());
    for (size_t i = 0; i < cdf.size(); ++i) cdf[i] = lightCdf(ch, i);
    hostDirs_.assign(4 * n, 0.0f);
    const PhiloxKey key{static_cast<uint32_t>(setup.seed), static_cast<uint32_t>(setup.seed >> 32)};
    auto unit53 = [](uint32_t hi, uint32_t lo) {
      return static_cast<double>((uint64_t{hi >> 5} << 26) | (lo >> 6)) * 0x1.0p-53;
    };
    for (uint64_t k = 0; k < n; ++k) {
      const uint64_t photon = firstPhoton + k;
      const auto lo = static_cast<uint32_t>(photon), hi = static_cast<uint32_t>(photon >> 32);
      // mesh_walk.comp: li from uniformFloat(), its first word (unitFromBits, walk_math.glsl).
      size_t li = 0;
      if (setup.lights.size() > 1) {
        const uint32_t w0 = philox4x32_10({lo, hi, 0u, static_cast<uint32_t>(channel)}, key)[0];
        const float u = static_cast<float>(w0 >> 8) * (1.0f / 16777216.0f);
        while (li + 1 < cdf.size() && cdf[li] <= u) ++li;
      }
      const auto* env = std::get_if<EnvironmentLight>(&setup.lights[li].emitter);
      // A channel without radiance is never chosen (its flux is 0) unless every light is black
      // in it, and then its photons carry 0 whatever they do: any direction will do; so will it
      // for a photon of another kind of light, which does not read it.
      glm::dvec3 dir{0.0, 1.0, 0.0};
      if (env != nullptr) {
        if (const auto& sampler = env->samplers[static_cast<size_t>(channel)]) {
          const PhiloxCounter w = philox4x32_10({lo, hi, 0u, 8u + static_cast<uint32_t>(channel)}, key);
          dir = sampler->sample({unit53(w[0], w[1]), unit53(w[2], w[3])}).direction;
        }
      }
      hostDirs_[4 * k] = static_cast<float>(dir.x);
      hostDirs_[4 * k + 1] = static_cast<float>(dir.y);
      hostDirs_[4 * k + 2] = static_cast<float>(dir.z);
    }
    if (n > dirCapacity_) {
      envDirs_ = gpu::makeStorageBuffer(n * 4 * sizeof(float));
      dirCapacity_ = n;
    }
    gpu::uploadBytes(envDirs_, 0, n * 4 * sizeof(float), hostDirs_.data());
  }

  void growExits(uint64_t capacity) {
    exits_ = gpu::makeStorageBuffer(capacity * sizeof(ExitOut));
    exitCapacity_ = capacity;
  }
  gpu::Context& context_;
  gpu::ShaderProgram program_;                      // homogeneous media
  std::optional<gpu::ShaderProgram> volumeProgram_;  // VOLUME: made on first use
  gpu::BvhBuffers bvh_;
  gpu::Buffer counter_, photons_, exits_, envDirs_, states_, control_;
  gpu::Buffer lists_[2];  // resume and suspend lists, swapped between dispatches
  LoopLimit limit_;
  gpu_field::VolumeBuffers volume_;
  uint64_t photonCapacity_ = 0, exitCapacity_ = 0, dirCapacity_ = 0;
  std::vector<float> hostDirs_;
  std::vector<PhotonOut> hostPhotons_;
  std::vector<ExitOut> hostExits_;
  std::string name_;
};

}  // namespace

std::shared_ptr<MeshWalker> makeGpuMeshWalker(gpu::Context& context,
                                              const geometry::TriangleMesh& mesh,
                                              const std::string& what) {
  return std::make_shared<GpuMeshWalker>(context, mesh, what);
}

}  // namespace translucent::reference
