// SPDX-License-Identifier: GPL-3.0-or-later
// The GPU slab tracer (slab_gpu.h): batches of blocks dispatched to slab_walk.comp, their exit
// records scored on the CPU with the CPU walkers' functions (walk.h).
#include "translucent/reference/gpu/slab_gpu.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <span>

#include "translucent/gpu/compute.h"
#include "translucent/gpu/program.h"
#include "translucent/reference/gpu/walk_program.h"
#include "translucent/reference/layered_slab.h"
#include "translucent/reference/walk.h"

namespace translucent::reference {
namespace {

// One photon's record, as slab_walk.comp writes it (std430: 40 bytes, 8-aligned).
struct ExitRecord {
  float x, y, cos_out;
  uint32_t kind;  // 0: top, 1: bottom, 2: absorbed or ended by a roulette
  double weight, absorbed;
  uint32_t scatters;
  uint32_t pad;  // 1: the driver cut the walk's loop (slab_walk.comp: `ended`)
};
static_assert(sizeof(ExitRecord) == 40);

using namespace gpu_walk;

// What both slab walks take of a Walk: the seed, the beam's entry and the two surfaces, the
// long-path roulette.
void setSurfaces(const gpu::ShaderProgram& p, const TraceOptions& options, const detail::Walk& W) {
  setLowHigh(p, "Seed", options.seed);
  p.set("Entry", glm::vec3(W.entry.x, W.entry.y, W.entry.z));
  setDouble(p, "EntryWeight", W.entryWeight);
  p.set("MatchedTop", W.top.matched);
  p.set("MatchedBottom", W.bottom.matched);
  p.set("EtaTop", static_cast<float>(W.top.eta));
  p.set("EtaBottom", static_cast<float>(W.bottom.eta));
  setLongPath(p, W.longPath);
}

gpu::ShaderProgram walkProgram(const SlabSetup& setup, const TraceOptions& options,
                               const detail::Walk& W) {
  gpu::Defines defines;
  if (setup.finite()) defines.emplace_back("FINITE", "1");
  if (options.absorption == Absorption::Weighted) defines.emplace_back("WEIGHTED", "1");
  gpu::ShaderProgram p = gpu::ShaderProgram::compute("reference/slab_walk.comp", defines);
  setSurfaces(p, options, W);
  p.set("InvSigmaT", W.invSigmaT);
  p.set("G", W.g);
  p.set("Thickness", W.thickness);
  setDouble(p, "Albedo", W.albedo);
  setHighLow(p, "AbsorbThreshold", W.absorbThreshold);
  return p;
}

// Scores one block's records (walk.h, as walk_scalar.cpp scores its exits).
void scoreBlock(const detail::Walk& W, std::span<const ExitRecord> records, detail::Tally& T) {
  for (const ExitRecord& e : records) {
    if (e.pad != 0) throwCutWalk("GPU slab walk");  // slab_walk.comp, layered_walk.comp: `ended`
    if (e.kind == 0)
      detail::scoreTop(W, T, e.x, e.y, static_cast<double>(e.cos_out), e.scatters, e.weight);
    else if (e.kind == 1)
      detail::scoreBottom(T, e.scatters, e.weight);
    T.absorbed.add(e.absorbed);
    T.events += e.scatters;
    ++T.photons;
  }
}

// The batches of the run's share of blocks through `program` (its uniforms set but FirstPhoton
// and Count), each block's records scored into its own tally, merged in block order.
SlabResult traceBatches(const gpu::ShaderProgram& program, const detail::Walk& W,
                        const TraceOptions& options, double rsp, const ProgressCallback& progress,
                        RunState* state) {
  const detail::BlockShare share = detail::blockShare(options);
  detail::ExactTally total(options.radial_bins, options.angle_bins);

  // Batches grow from 16 blocks while one takes under ~0.1 s (progress and stops act between
  // batches), up to 1024 blocks: 1M photons, 40 MB of records.
  constexpr uint64_t kMaxBatch = 1024;
  const uint64_t maxBatch = std::max<uint64_t>(1, std::min(kMaxBatch, share.count));
  gpu::Buffer records = gpu::makeStorageBuffer(maxBatch * kBlockPhotons * sizeof(ExitRecord));
  gpu::bindStorage(0, records);
  std::vector<ExitRecord> host;
  const auto start = std::chrono::steady_clock::now();
  auto elapsed = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  uint64_t batch = std::min<uint64_t>(16, maxBatch);
  for (uint64_t done = 0; done < share.count;) {
    const uint64_t b0 = share.first + done, nb = std::min(batch, share.count - done);
    const uint64_t firstPhoton = b0 * kBlockPhotons;
    const uint64_t n = options.photonsInBlocks(b0, nb);
    setLowHigh(program, "FirstPhoton", firstPhoton);
    program.set("Count", static_cast<unsigned>(n));
    const double t0 = elapsed();
    gpu::dispatch1D(program, n);
    host.resize(n);
    gpu::downloadBytes(records, 0, n * sizeof(ExitRecord), host.data());
    for (uint64_t k = 0; k < nb; ++k) {
      const uint64_t begin = k * kBlockPhotons, end = std::min(n, begin + kBlockPhotons);
      detail::Tally T(options.radial_bins, options.angle_bins);
      scoreBlock(W, std::span(host).subspan(begin, end - begin), T);
      total.merge(T);
    }
    done += nb;
    if (elapsed() - t0 < 0.05) batch = std::min(batch * 2, maxBatch);
    if (progress && done < share.count && !progress({total.photons, share.photons, elapsed()}))
      break;
  }
  SlabResult result =
      detail::finishSlabRun(total, options, rsp, share.photons, elapsed(), 1, progress, state);
  result.device = deviceName();
  return result;
}

}  // namespace

SlabResult traceSlabGpu(const SlabSetup& setup, const TraceOptions& options,
                        const ProgressCallback& progress, RunState* state) {
  setup.validate();
  options.validate();
  double rsp = 0.0;
  const detail::Walk W = detail::makeWalk(setup, options, rsp);
  const gpu::ShaderProgram program = walkProgram(setup, options, W);
  return traceBatches(program, W, options, rsp, progress, state);
}

SlabResult traceLayeredSlabGpu(const LayeredSlabSetup& setup, const TraceOptions& options,
                               const ProgressCallback& progress, RunState* state) {
  SlabSetup slab;
  const detail::Layers L = detail::layeredWalk(setup, options, slab);
  double rsp = 0.0;
  const detail::Walk W = detail::makeWalk(slab, options, rsp);
  gpu::Defines defines;
  if (options.absorption == Absorption::Weighted) defines.emplace_back("WEIGHTED", "1");
  const gpu::ShaderProgram p = gpu::ShaderProgram::compute("reference/layered_walk.comp", defines);
  // layered_walk.comp's Layer (std430, 32 bytes).
  struct GpuLayer {
    float top, bottom, sigma_t, g;
    double albedo;
    uint32_t threshold_hi, threshold_lo;
  };
  static_assert(sizeof(GpuLayer) == 32);
  std::vector<GpuLayer> layers;
  for (size_t i = 0; i < L.sigmaT.size(); ++i) {
    const double bottom = L.boundary[i + 1];
    layers.push_back({static_cast<float>(L.boundary[i]),
                      std::isfinite(bottom) ? static_cast<float>(bottom) : 3e38f,
                      static_cast<float>(L.sigmaT[i]), L.g[i], L.albedo[i],
                      static_cast<uint32_t>(L.absorbThreshold[i] >> 32),
                      static_cast<uint32_t>(L.absorbThreshold[i])});
  }
  const gpu::Buffer layerBuffer = gpu::makeStorageBuffer(std::span<const GpuLayer>(layers));
  gpu::bindStorage(1, layerBuffer);
  setSurfaces(p, options, W);
  p.set("LayerCount", static_cast<unsigned>(layers.size()));
  return traceBatches(p, W, options, rsp, progress, state);
}

}  // namespace translucent::reference
