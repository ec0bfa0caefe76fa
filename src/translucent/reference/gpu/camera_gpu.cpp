// SPDX-License-Identifier: GPL-3.0-or-later
// The GPU walker of the camera method (camera_gpu.h).
#include "translucent/reference/gpu/camera_gpu.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <variant>

#include "translucent/geometry/flat_bvh.h"
#include "translucent/gpu/bvh_buffers.h"
#include "translucent/gpu/compute.h"
#include "translucent/gpu/program.h"
#include "translucent/reference/gpu/field_gpu.h"
#include "translucent/reference/gpu/walk_program.h"

namespace translucent::reference {
namespace {

// camera_walk.comp's records (std430).
struct PathState {
  double x, y, z, beta, o0, o1, o2, scale;
  float dx, dy, dz;
  uint32_t flags, counter, used, scatters, shadowRays;
  uint32_t light, item;
  float g;
  uint32_t pad;
};
static_assert(sizeof(PathState) == 112);
struct GpuLight {
  float p[3];
  uint32_t type;
  float dir[3];
  float radius;
  float e;
  float color;  // the light's colour in this channel
  float pad[2];
};
static_assert(sizeof(GpuLight) == 48);

void put(float (&out)[3], const glm::dvec3& v) {
  for (int a = 0; a < 3; ++a) out[a] = static_cast<float>(v[a]);
}

// The delta lights in channel c (camera_paths.cpp: deltaIncident times the light's colour).
std::vector<GpuLight> gpuLights(std::span<const Light> lights, int c) {
  std::vector<GpuLight> out;
  for (const Light& l : lights) {
    GpuLight g{};
    const double color = l.color[static_cast<size_t>(c)];
    g.color = static_cast<float>(color);
    if (const auto* dl = std::get_if<DirectionalLight>(&l.emitter)) {
      g.type = 0;
      put(g.dir, dl->direction);
      g.e = static_cast<float>(dl->irradiance * color);
    } else if (const auto* pl = std::get_if<PointLight>(&l.emitter)) {
      g.type = 1;
      put(g.p, pl->position);
      g.e = static_cast<float>(pl->intensity * color);
    } else if (const auto* bl = std::get_if<BeamLight>(&l.emitter)) {
      g.type = 2;
      put(g.p, bl->origin);
      put(g.dir, bl->direction);
      g.radius = static_cast<float>(bl->radius);
      g.e = static_cast<float>(bl->power / (std::numbers::pi * bl->radius * bl->radius) * color);
    } else {
      g.type = 3;  // environment: its map and samplers in RefDoubles (packLights)
    }
    out.push_back(g);
  }
  return out;
}

// camera_walk.comp's RefDoubles and RefUints (the shader's header gives the layout): every
// environment light's map and per-channel samplers, and at η ≠ 1 every delta light's refracted
// connections.
void packLights(std::span<const Light> lights,
                std::span<const std::unique_ptr<RefractedLight>> refracted, double eta,
                std::vector<double>& d, std::vector<uint32_t>& u) {
  const size_t n = lights.size();
  d.assign(16 * n, 0.0);
  u.assign(8 * n, 0);
  auto put3 = [&](size_t at, const glm::dvec3& v) {
    for (int a = 0; a < 3; ++a) d[at + static_cast<size_t>(a)] = v[a];
  };
  auto checked = [](size_t v) {
    if (v > 0xFFFFFFFFu)
      throw gpu::GlError("GPU camera walk: the lights' tables exceed 2^32 entries");
    return static_cast<uint32_t>(v);
  };
  for (size_t l = 0; l < n; ++l) {
    if (const auto* env = std::get_if<EnvironmentLight>(&lights[l].emitter)) {
      const lights::EnvironmentMap& map = *env->map;
      const auto w = static_cast<size_t>(map.width), h = static_cast<size_t>(map.height);
      u[8 * l] = checked(d.size());
      u[8 * l + 1] = static_cast<uint32_t>(w);
      u[8 * l + 2] = static_cast<uint32_t>(h);
      u[8 * l + 6] = 3;
      d[16 * l] = env->rotate * std::numbers::pi / 180.0;
      for (size_t c = 0; c < 3; ++c) {
        d[16 * l + 1 + c] = env->intensity * lights[l].color[c];
        const auto& sampler = env->samplers[c];
        d[16 * l + 4 + c] = sampler ? sampler->integral() : 0.0;
        for (size_t i = 0; i < w * h; ++i) d.push_back(map.rgb[3 * i + c]);
        if (sampler) {
          d.insert(d.end(), sampler->rowSums().begin(), sampler->rowSums().end());
          for (size_t y = 0; y < h; ++y) {
            const auto& cols = sampler->columnSums(static_cast<int>(y));
            d.insert(d.end(), cols.begin(), cols.end());
          }
        } else {
          d.resize(d.size() + (h + 1) + h * (w + 1), 0.0);  // never read: the integral is 0
        }
      }
      continue;
    }
    const RefractedLight* r = l < refracted.size() ? refracted[l].get() : nullptr;
    if (eta == 1.0 || r == nullptr) continue;  // a delta light at η = 1: straight connections
    put3(16 * l, r->gridLower());
    put3(16 * l + 3, r->gridCell());
    put3(16 * l + 6, r->origin());
    put3(16 * l + 9, r->toLight());
    d[16 * l + 12] = r->power();
    d[16 * l + 13] = r->radius();
    u[8 * l] = checked(d.size());
    for (const RefractedLight::Facet& f : r->facets()) {
      const size_t at = d.size();
      d.resize(at + 16, 0.0);
      put3(at, f.v0);
      put3(at + 3, f.n);
      put3(at + 6, f.a);
      put3(at + 9, f.b);
      put3(at + 12, f.din);
      d[at + 15] = f.irradiance;
    }
    u[8 * l + 1] = checked(u.size());
    u.insert(u.end(), r->start().begin(), r->start().end());
    u[8 * l + 2] = checked(u.size());
    u.insert(u.end(), r->items().begin(), r->items().end());
    const glm::ivec3 dims = r->gridCells();
    u[8 * l + 3] = static_cast<uint32_t>(dims.x);
    u[8 * l + 4] = static_cast<uint32_t>(dims.y);
    u[8 * l + 5] = static_cast<uint32_t>(dims.z);
    u[8 * l + 6] = static_cast<uint32_t>(r->kind());  // Directional 0, Point 1, Beam 2
  }
}

using namespace gpu_walk;

class GpuCameraWalker final : public CameraWalker {
 public:
  GpuCameraWalker(gpu::Context& context, const geometry::TriangleMesh& mesh, const std::string& what)
      : context_(context), program_(build(context, false)) {
    bvh_ = gpu::BvhBuffers::upload(geometry::FlatBvh::build(mesh, what));
    control_ = gpu::makeStorageBuffer(2 * sizeof(uint32_t));
    name_ = deviceName();
    limit_ = loopLimit();
  }
  ~GpuCameraWalker() override { context_.makeCurrent(); }

  void trace(const CameraWalkSetup& setup, std::span<const CameraWalkSample> samples,
             std::vector<CameraWalkScore>& out) override {
    context_.makeCurrent();
    if (setup.volume && !volumeProgram_) volumeProgram_.emplace(build(context_, true));
    const gpu::ShaderProgram& p = setup.volume ? *volumeProgram_ : program_;
    const std::vector<GpuLight> lights = gpuLights(setup.lights, setup.channel);
    gpu::Buffer lightBuffer = gpu::makeStorageBuffer(std::span<const GpuLight>(lights));
    const ScalarMedium& m = setup.medium;
    setLowHigh(p, "Seed", setup.seed);
    p.set("Channel", static_cast<unsigned>(setup.channel));
    p.set("LightCount", static_cast<unsigned>(lights.size()));
    p.set("Paths", static_cast<unsigned>(setup.paths));
    p.set("SigmaT", static_cast<float>(m.sigmaT()));
    p.set("Albedo", static_cast<float>(m.sigmaT() > 0.0 ? m.sigma_s / m.sigmaT() : 0.0));
    volume_.set(p, setup.volume, setup.channel);
    p.set("G", static_cast<float>(m.g));
    p.set("Epsilon", static_cast<float>(setup.epsilon));
    p.set("Matched", setup.eta == 1.0);
    p.set("Eta", static_cast<float>(setup.eta));
    tables(setup);
    setLongPath(p, setup.long_path_roulette);
    const double theta = setup.cone_half_angle * std::numbers::pi / 180.0;
    const double sin2 = std::sin(theta) * std::sin(theta);
    p.set("Cone", setup.cone_half_angle > 0.0);
    p.set("CosCone", static_cast<float>(std::cos(theta)));
    p.set("ConeFactor", static_cast<float>(sin2 > 0.0 ? 2.0 * (1.0 - std::cos(theta)) / sin2 : 0.0));
    p.set("ConeMeasure", static_cast<float>(std::numbers::pi * sin2));

    const uint64_t n = samples.size() * static_cast<uint64_t>(setup.paths);
    if (n > (uint64_t{1} << 31)) throw gpu::GlError("GPU camera walk: too many paths in one batch");
    out.assign(n, CameraWalkScore{});
    if (n == 0) return;
    if (samples.size() > sampleCapacity_) {
      samples_ = gpu::makeStorageBuffer(samples.size() * sizeof(CameraWalkSample));
      sampleCapacity_ = samples.size();
    }
    gpu::uploadBytes(samples_, 0, samples.size() * sizeof(CameraWalkSample), samples.data());
    if (n > pathCapacity_) {
      outs_ = gpu::makeStorageBuffer(n * sizeof(CameraWalkScore));
      states_ = gpu::makeStorageBuffer(n * sizeof(PathState));
      for (gpu::Buffer& l : lists_) l = gpu::makeStorageBuffer(n * sizeof(uint32_t));
      pathCapacity_ = n;
    }
    // Paths suspend after `budget` loop iterations and are resumed by further dispatches (the
    // shader's "Suspension"); a batch whose largest count could have met the driver's limit is
    // traced again with half the budget (the same paths: the streams are counters).
    // A quarter of the light walk's budget: the loops the shader does not count (the constant
    // ones of Philox's rounds and the ray set-up, run per facet candidate and per shadow ray, many
    // more per collision than in the light walk) let llvmpipe cut paths silently at the full
    // budget. Measured on the Marble bunny at eta 1.3 under two suns (32x24, 4 paths per pixel):
    // at the full budget two runs traced 240,835 and 242,334 collisions against 258,126 (6.5%
    // of them lost) and differed in 57 of 2304 pixel values, the image 1.5% dark; at a quarter
    // every run agrees bit for bit (CameraGpu.RefractiveBunnyIsTheSameOnEveryRun).
    uint32_t budget = limit_.budget() / 4;
    for (;;) {
      p.set("WorkBudget", budget);
      volume_.resetViolations();
      volume_.bind(setup.channel);
      gpu::bindStorage(0, samples_);
      gpu::bindStorage(1, bvh_.nodes);
      gpu::bindStorage(2, bvh_.triangles);
      gpu::bindStorage(3, outs_);
      gpu::bindStorage(4, refDoubles_);
      gpu::bindStorage(6, refUints_);
      gpu::bindStorage(5, lightBuffer);
      gpu::bindStorage(10, states_);
      const uint32_t maxWork = dispatchSuspendable(p, n, control_, lists_);
      if (limit_.clear(maxWork)) break;
      if (budget <= 64) throwLoopLimit("GPU camera walk", maxWork, limit_, name_);
      budget /= 2;
    }
    gpu::downloadBytes(outs_, 0, n * sizeof(CameraWalkScore), out.data());
    if (setup.volume) {
      // Of the dispatch that fit (the counter is zeroed before each).
      if (const uint32_t v = volume_.violations())
        setup.volume->majorant_violations->fetch_add(v, std::memory_order_relaxed);
    }
  }

  std::string name() const override { return name_; }

 private:
  // VOLUME: the 3D fields' walk (a second program, so that the homogeneous one does not carry
  // the tracking's code).
  static gpu::ShaderProgram build(const gpu::Context& context, bool volume) {
    context.makeCurrent();
    return gpu::ShaderProgram::compute("reference/camera_walk.comp",
                                       volume ? gpu::Defines{{"VOLUME", "1"}} : gpu::Defines{});
  }
  // The lights' tables on the device (packLights), uploaded once per tracer.
  void tables(const CameraWalkSetup& setup) {
    if (refDoubles_ && setup.tracer == tablesOf_) return;
    std::vector<double> d;
    std::vector<uint32_t> u;
    packLights(setup.lights, setup.refracted, setup.eta, d, u);
    if (d.empty()) d.assign(2, 0.0);
    if (u.empty()) u.assign(4, 0);
    refDoubles_ = gpu::makeStorageBuffer(std::span<const double>(d));
    refUints_ = gpu::makeStorageBuffer(std::span<const uint32_t>(u));
    tablesOf_ = setup.tracer;
  }
  gpu::Context& context_;
  gpu::Buffer refDoubles_, refUints_;
  uint64_t tablesOf_ = 0;  // the tracer whose tables refDoubles_ and refUints_ hold
  gpu::ShaderProgram program_;                      // homogeneous media
  std::optional<gpu::ShaderProgram> volumeProgram_;  // VOLUME: made on first use
  gpu_field::VolumeBuffers volume_;
  gpu::BvhBuffers bvh_;
  gpu::Buffer control_, samples_, outs_, states_;
  gpu::Buffer lists_[2];
  LoopLimit limit_;
  uint64_t sampleCapacity_ = 0, pathCapacity_ = 0;
  std::string name_;
};

}  // namespace

std::shared_ptr<CameraWalker> makeGpuCameraWalker(gpu::Context& context,
                                                  const geometry::TriangleMesh& mesh,
                                                  const std::string& what) {
  return std::make_shared<GpuCameraWalker>(context, mesh, what);
}

}  // namespace translucent::reference
