// SPDX-License-Identifier: GPL-3.0-or-later
// The GPU walker of the lit sphere (sphere_gpu.h).
#include "translucent/reference/gpu/sphere_gpu.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "translucent/gpu/compute.h"
#include "translucent/gpu/program.h"
#include "translucent/reference/gpu/walk_program.h"
#include "translucent/reference/sampling.h"

namespace translucent::reference {
namespace {

// One photon's record, as sphere_walk.comp writes it (std430: 64 bytes, 8-aligned).
struct PhotonRecord {
  double px, py, pz, exited, entered;
  float dx, dy, dz;
  uint32_t scatters, left;
  uint32_t pad;  // 1: the driver cut the walk's loop (sphere_walk.comp: `ended`)
};
static_assert(sizeof(PhotonRecord) == 64);

using namespace gpu_walk;

class GpuSphereWalker final : public SphereWalker {
 public:
  explicit GpuSphereWalker(gpu::Context& context) : context_(context), program_(build(context)) {
    name_ = deviceName();
  }

  void trace(const SphereWalkSetup& setup, int channel, uint64_t first, uint64_t count,
             WalkedBatch& out) override {
    context_.makeCurrent();
    const WalkChannel& ch = setup.channels.at(static_cast<size_t>(channel));
    const gpu::ShaderProgram& p = program_;
    setChannel(p, ch, setup.seed, setup.long_path_roulette);
    p.set("Channel", static_cast<unsigned>(channel));
    setDouble(p, "Radius", setup.radius);
    const glm::dvec3 L = glm::normalize(setup.light_direction);
    glm::dvec3 t1, t2;
    detail::tangentFrame(L, t1, t2);
    setDvec3(p, "LightDir", L);
    setDvec3(p, "T1", t1);
    setDvec3(p, "T2", t2);
    setDouble(p, "Flux", ch.flux);
    p.set("Matched", ch.eta == 1.0);
    setDouble(p, "Eta", ch.eta);

    const uint64_t n = count * kBlockPhotons, firstPhoton = first * kBlockPhotons;
    if (n > capacity_) {
      records_ = gpu::makeStorageBuffer(n * sizeof(PhotonRecord));
      capacity_ = n;
    }
    gpu::bindStorage(0, records_);
    setLowHigh(p, "FirstPhoton", firstPhoton);
    p.set("Count", static_cast<unsigned>(n));
    gpu::dispatch1D(p, n);
    host_.resize(n);
    gpu::downloadBytes(records_, 0, n * sizeof(PhotonRecord), host_.data());
    out.photons.assign(n, WalkedPhoton{});
    out.exits.clear();
    for (uint64_t k = 0; k < n; ++k) {
      const PhotonRecord& r = host_[k];
      if (r.pad != 0) throwCutWalk("GPU sphere walk");  // sphere_walk.comp: `ended`
      WalkedPhoton& ph = out.photons[k];
      ph.entered = r.entered;
      ph.scatters = r.scatters;
      if (r.left == 0) continue;  // absorbed, ended by the roulette, or missed
      ph.exited = ph.escaped = r.exited;
      ph.first_exit = static_cast<uint32_t>(out.exits.size());
      ph.exits = 1;
      WalkedExit e;
      e.position = glm::dvec3(r.px, r.py, r.pz);
      e.normal = glm::normalize(e.position);
      e.direction = glm::dvec3(r.dx, r.dy, r.dz);
      e.weight = r.exited;
      e.order = scatteringOrder(r.scatters);  // the sphere is convex: its only exit is its last event
      out.exits.push_back(e);
    }
  }

  // The buffers and the program are released in their context.
  ~GpuSphereWalker() override { context_.makeCurrent(); }

  std::string name() const override { return name_; }

 private:
  static gpu::ShaderProgram build(const gpu::Context& context) {
    context.makeCurrent();
    return gpu::ShaderProgram::compute("reference/sphere_walk.comp");
  }
  gpu::Context& context_;
  gpu::ShaderProgram program_;
  gpu::Buffer records_;
  uint64_t capacity_ = 0;
  std::vector<PhotonRecord> host_;
  std::string name_;
};

}  // namespace

std::shared_ptr<SphereWalker> makeGpuSphereWalker(gpu::Context& context) {
  return std::make_shared<GpuSphereWalker>(context);
}

}  // namespace translucent::reference
