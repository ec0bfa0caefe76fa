// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/techniques/tsm/tsm_technique.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>

#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "translucent/bssrdf/bssrdf_file.h"
#include "translucent/bssrdf/exit_radiance.h"
#include "translucent/gpu/bssrdf_kernels.h"
#include "translucent/gpu/compute.h"
#include "translucent/gpu/pass_timer.h"
#include "translucent/techniques/common/gl_resources.h"
#include "translucent/techniques/common/specular.h"
#include "translucent/techniques/common/light_view_map.h"
#include "translucent/techniques/common/profile_kernel.h"

namespace translucent::tsm {
namespace {

using techniques::GBuffer;
using techniques::GpuMesh;
using techniques::LightViewMap;
using techniques::ParameterInfo;

// SSBO bindings of shaders/tsm/filter.comp: 5 the profile (pointcloud/kernel_table.glsl), 6 the
// region weights, 7 and 8 the outputs (as the point cloud's radiance pass).
enum Binding : GLuint { kProfile = 5, kRegions = 6, kRadianceOut = 7, kExitanceOut = 8 };

constexpr size_t kTableSize = 4096;    // profile entries, uniform in r up to r_max
constexpr size_t kRegionH = 64;   // region weights: entries in h, uniform over [0, r_max]
constexpr size_t kRegionC = 20;   // and in cos θ_g, uniform over [kMinCosG, 1]
constexpr int kPatternSize = 21;        // TSM_SAMPLES in filter.comp

std::vector<ParameterInfo> parameterInfos() {
  std::vector<ParameterInfo> infos{
      ParameterInfo::enumeration("pattern", "tsm21", {"tsm21"},
                                 "filter pattern on the light's projection plane: tsm21, a centre "
                                 "sample and 4 rings of 5 at radii doubling out to R (21 samples)"),
      ParameterInfo::enumeration("weights", "region", {"region", "point"},
                                 "sample weights: region, Rd integrated over the sample's region "
                                 "at its offset along the light; point, Rd(|x_i − x_o|) times its area"),
      ParameterInfo::floating("filter_radius", 1.0, 0.05, 4.0,
                              "pattern radius R in units of r_max, the radius holding 99.9% of Rd "
                              "(widest channel)",
                              "r_max"),
      ParameterInfo::integer("map_size", 512, 64, 8192,
                             "resolution of each light's irradiance map", "texels")
          // The map's texels are the surface samples the pattern reads.
          .withSweep({128, 256, 512, 1024, 2048}),
      techniques::radianceConventionParameter(),
  };
  for (ParameterInfo& p : techniques::specularParameters()) infos.push_back(std::move(p));
  return infos;
}

glm::vec3 toVec3(const Rgb& c) {
  return {static_cast<float>(c[0]), static_cast<float>(c[1]), static_cast<float>(c[2])};
}

}  // namespace

std::vector<PatternSample> tsm21Pattern() {
  std::vector<PatternSample> out;
  const double b0 = kTsm21Bounds[0];
  out.push_back({glm::vec2(0.0f), static_cast<float>(std::numbers::pi * b0 * b0), 0});
  constexpr int perRing = 5;
  for (int k = 1; k < int(kTsm21Bounds.size()); ++k) {
    const double a = kTsm21Bounds[size_t(k - 1)], b = kTsm21Bounds[size_t(k)];
    const double area = std::numbers::pi * (b * b - a * a) / perRing;
    // The radius halving the sector's area.
    const double rho = std::sqrt(0.5 * (a * a + b * b));
    for (int j = 0; j < perRing; ++j) {
      const double phi = 2.0 * std::numbers::pi * (j + 0.5 * (k % 2)) / perRing;
      out.push_back({glm::vec2(float(rho * std::cos(phi)), float(rho * std::sin(phi))),
                     static_cast<float>(area), k});
    }
  }
  return out;
}

double regionWeight(const bssrdf::ProfileTable& table, double radius, int region, double h,
                    double cosG, int steps) {
  const double a = region == 0 ? 0.0 : kTsm21Bounds[size_t(region - 1)] * radius;
  const double b = kTsm21Bounds[size_t(region)] * radius;
  const int samples = region == 0 ? 1 : 5;
  const double c = std::clamp(cosG, kMinCosG, 1.0);
  // Over the projection plane, p = (ρ cos φ, ρ sin φ) with the tilt along φ = 0, the surface
  // point lies at in-plane offset (ρ cos φ / c, ρ sin φ) and dA_S = dA_P / c:
  //   W = (1/n) ∫∫ R(√(ρ² (cos²φ / c² + sin²φ) + h²)) ρ dρ dφ / c,
  // by the midpoint rule in u = ρ² (ρ dρ = du / 2) and in φ over a quarter (symmetry).
  const int phiSteps = c < 1.0 ? 16 : 1;
  const double u0 = a * a, du = (b * b - u0) / steps, dphi = 0.5 * std::numbers::pi / phiSteps;
  double sum = 0.0;
  for (int j = 0; j < phiSteps; ++j) {
    const double phi = (j + 0.5) * dphi, cp = std::cos(phi), sp = std::sin(phi);
    const double stretch = cp * cp / (c * c) + sp * sp;
    for (int i = 0; i < steps; ++i) sum += table.lookup(std::sqrt((u0 + (i + 0.5) * du) * stretch + h * h));
  }
  // (1/2) du · 4 dφ · sum over the quarter = 2π · mean over φ · (1/2) du Σ.
  return std::numbers::pi * (sum / phiSteps) * du / (c * samples);
}

// ---------------------------------------------------------------------------------------------

// The mesh, its bounding sphere and GPU copy: techniques::ClosedMeshState.
struct TsmTechnique::Impl : techniques::ClosedMeshState {
  techniques::ParameterSet params{parameterInfos()};

  std::optional<scene::Scene> scene;

  std::string kernelKey;
  std::array<bssrdf::ProfileTable, 3> tables;
  gpu::Buffer profile;
  std::string regionKey;
  gpu::Buffer regions;

  std::optional<gpu::ShaderProgram> mapProgram, gbufferProgram, filterProgram;

  struct LightState {
    scene::Light light;
    std::unique_ptr<LightViewMap> map;
  };
  std::vector<LightState> lights;
  // The light maps hold position, normal and E as each light sees the mesh: nothing of the
  // camera's, so they are rendered after prepare() (mesh, lights, η) or a new map_size only.
  bool mapsDirty = true;

  GBuffer gbuffer;
  gpu::Buffer radianceOut, exitanceOut;
  size_t outPixels = 0;
  std::optional<gpu::PassTimer> timer;
  techniques::SpecularPass specular;

  void buildPrograms() {
    if (mapProgram) return;
    mapProgram.emplace(LightViewMap::program());
    gbufferProgram.emplace(
        gpu::ShaderProgram::graphics("pointcloud/gbuffer.vert", "pointcloud/gbuffer.frag"));
    filterProgram.emplace(gpu::ShaderProgram::compute("tsm/filter.comp"));
    gpu::checkGlError("building the tsm programs");
  }

  // A deformed mesh: the rest pose uploaded once, deformed on the GPU at each new time.
  void loadMesh(const scene::Scene& s) { (void)loadClosedMesh(s, /*gpuDeform=*/true); }

  void prepareLights(const scene::Scene& s) {
    lights.clear();
    const int size = params.getInt("map_size");
    for (size_t i = 0; i < s.lights.size(); ++i) {
      LightState st;
      st.light = s.lights[i];
      const auto& e = st.light.emitter;
      const char* kind = nullptr;
      if (std::holds_alternative<scene::FilteredDirectionalLight>(e)) kind = "a filtered directional light";
      else if (std::holds_alternative<reference::BeamLight>(e)) kind = "a beam light";
      else if (std::holds_alternative<scene::EnvironmentLight>(e)) kind = "an environment light";
      else if (!std::holds_alternative<reference::DirectionalLight>(e) &&
               !std::holds_alternative<reference::PointLight>(e))
        kind = "this light type";
      if (kind)
        throw ParameterError(fmt::format("lights[{}]: {}: the tsm technique supports directional and "
                                         "point lights only (one light-view map each)", i, kind));
      if (const auto* p = std::get_if<reference::PointLight>(&e);
          p && !(glm::length(p->position - center) > 1.02 * radius))
        throw ParameterError(fmt::format("lights[{}]: the point light lies inside the mesh's bounding "
                                         "sphere: the tsm technique's light-view map needs it outside", i));
      st.map = std::make_unique<LightViewMap>(size);
      lights.push_back(std::move(st));
    }
    mapsDirty = true;
  }

  void buildKernel() {
    const scene::Scene& s = *scene;
    const std::string key = fmt::format("{}|{}|{}|{}|{}|{}", s.model, s.medium.sigma_a, s.medium.sigma_s,
                                        s.medium.g, s.medium.eta, s.medium.scale);
    if (key != kernelKey) {
      kernelKey.clear();
      s.medium.validate();
      std::optional<gpu::BssrdfEvaluator> evaluator;
      if (bssrdf::hasBssrdfExtension(s.model)) {
        evaluator.emplace(s.model);
        evaluator->setMedium(s.medium);
      }
      techniques::RgbProfileTable t =
          techniques::tabulateRgbProfile(s, kTableSize, evaluator ? &*evaluator : nullptr);
      tables = std::move(t.tables);
      profile = gpu::makeStorageBuffer(std::span<const glm::vec4>(t.gpu));
      kernelKey = key;
      regionKey.clear();
    }
    // Region weights W_k(h, cos θ_g) per channel, h_j = r_max j / (n_h − 1),
    // c_m = kMinCosG + (1 − kMinCosG) m / (n_c − 1): they depend on R.
    const std::string rkey = fmt::format("{}", params.getFloat("filter_radius"));
    if (rkey == regionKey) return;
    const double R = filterRadius();
    const double rMax = tables[0].r_max;
    std::vector<glm::vec4> w(kTsm21Bounds.size() * kRegionC * kRegionH, glm::vec4(0.0f));
    for (size_t k = 0; k < kTsm21Bounds.size(); ++k)
      for (size_t m = 0; m < kRegionC; ++m) {
        const double c = kMinCosG + (1.0 - kMinCosG) * double(m) / double(kRegionC - 1);
        for (size_t j = 0; j < kRegionH; ++j) {
          const double h = rMax * double(j) / double(kRegionH - 1);
          for (int ch = 0; ch < 3; ++ch)
            w[(k * kRegionC + m) * kRegionH + j][ch] =
                static_cast<float>(regionWeight(tables[size_t(ch)], R, int(k), h, c, 96));
        }
      }
    regions = gpu::makeStorageBuffer(std::span<const glm::vec4>(w));
    regionKey = rkey;
  }

  double filterRadius() const { return params.getFloat("filter_radius") * tables[0].r_max; }

  void renderMap(LightState& st) {
    const scene::Scene& s = *scene;
    const glm::vec3 color = toVec3(st.light.color);
    const auto& e = st.light.emitter;
    if (const auto* d = std::get_if<reference::DirectionalLight>(&e))
      st.map->renderDirectional(*gpuMesh, *mapProgram, d->direction, color * float(d->irradiance),
                                s.medium.eta, center, radius);
    else if (const auto* p = std::get_if<reference::PointLight>(&e))
      st.map->renderPoint(*gpuMesh, *mapProgram, p->position, color * float(p->intensity),
                          s.medium.eta, center, radius);
  }

  techniques::Frame render(const techniques::FrameRequest& request) {
    if (!scene) throw ParameterError("tsm: render() before prepare(): expected a scene");
    const scene::Scene& s = *scene;
    const auto [width, height] = techniques::frameSize(request, s.camera);
    buildPrograms();
    buildKernel();
    if (!timer) timer.emplace();
    techniques::Frame frame;

    const size_t pixels = size_t(width) * size_t(height);
    if (pixels != outPixels) {
      radianceOut = gpu::makeStorageBuffer(pixels * sizeof(glm::vec4));
      exitanceOut = gpu::makeStorageBuffer(pixels * sizeof(glm::vec4));
      outPixels = pixels;
    }
    {
      auto t = timer->scope("g-buffer");
      gbuffer.resize(width, height);
      const glm::mat4 vp = techniques::cameraViewProjection(s.camera, s.clip_near, s.clip_far, center,
                                                            radius, width, height);
      gbuffer.render(*gpuMesh, *gbufferProgram, vp);
    }
    if (mapsDirty) {
      auto t = timer->scope("light maps");
      for (auto& st : lights) renderMap(st);
      mapsDirty = false;
    }
    {
      auto t = timer->scope("filter");
      const gpu::ShaderProgram& p = *filterProgram;
      gpu::bindStorage(kProfile, profile);
      gpu::bindStorage(kRegions, regions);
      gpu::bindStorage(kRadianceOut, radianceOut);
      gpu::bindStorage(kExitanceOut, exitanceOut);
      techniques::setExitRadianceUniforms(p, gbuffer, s, params, width, height);
      p.set("ProfileRMax", static_cast<float>(tables[0].r_max));
      p.set("ProfileCount", static_cast<unsigned>(tables[0].size()));
      p.set("RegionH", static_cast<unsigned>(kRegionH));
      p.set("RegionC", static_cast<unsigned>(kRegionC));
      p.set("MinCosG", static_cast<float>(kMinCosG));
      p.set("FilterRadius", static_cast<float>(filterRadius()));
      p.set("RegionWeights", params.getEnum("weights") == "region");
      const std::vector<PatternSample> pattern = tsm21Pattern();
      std::vector<glm::vec4> packed;
      for (const auto& q : pattern) packed.emplace_back(q.offset, q.area, float(q.region));
      glProgramUniform4fv(p.id(), p.uniformLocation("Pattern"), kPatternSize, glm::value_ptr(packed[0]));
      const std::array<unsigned, 3> groups{(unsigned(width) + 7u) / 8u, (unsigned(height) + 7u) / 8u, 1u};
      if (lights.empty()) {
        // No light: nothing to filter, B = 0.
        p.set("Clear", true);
        gpu::dispatch(p, groups);
      }
      p.set("Clear", false);
      for (size_t i = 0; i < lights.size(); ++i) {
        lights[i].map->bind(p, 2);
        p.set("First", i == 0);
        gpu::dispatch(p, groups);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
      }
    }
    specular.add(gbuffer, *scene, params, radianceOut, &*timer);
    gpu::checkGlError("tsm frame");

    frame.width = width;
    frame.height = height;
    if (request.readback) techniques::readRadianceAndExitance(frame, radianceOut, exitanceOut, pixels);
    techniques::addPasses(frame, *timer);
    return frame;
  }
};

// ---------------------------------------------------------------------------------------------

TsmTechnique::TsmTechnique() : impl_(std::make_unique<Impl>()) {}
TsmTechnique::~TsmTechnique() = default;

std::string_view TsmTechnique::description() const {
  return "translucent shadow maps: a 21-sample filter of light-view irradiance maps (Dachsbacher & "
         "Stamminger 2003)";
}

const std::vector<techniques::ParameterInfo>& TsmTechnique::parameters() const {
  return impl_->params.infos();
}

void TsmTechnique::setParameter(std::string_view name, const techniques::ParameterValue& value) {
  const techniques::ParameterValue checked = techniques::checkedValue(impl_->params.info(name), value);
  if (!impl_->params.set(name, checked)) return;
  if (name == "map_size" && impl_->scene) impl_->prepareLights(*impl_->scene);
}

techniques::ParameterValue TsmTechnique::parameter(std::string_view name) const {
  return impl_->params.get(name);
}

void TsmTechnique::prepare(const scene::Scene& scene, gpu::Context& gl) {
  gl.makeCurrent();
  scene.camera.validate();
  scene.medium.validate();
  techniques::requireHomogeneousMaterial(scene, "tsm");
  impl_->buildPrograms();
  impl_->scene.reset();  // until this preparation succeeds
  impl_->loadMesh(scene);
  impl_->prepareLights(scene);
  impl_->scene = scene;
  impl_->buildKernel();
}

techniques::Frame TsmTechnique::render(const techniques::FrameRequest& request) {
  return impl_->render(request);
}

bool TsmTechnique::setCamera(const reference::Camera& camera) {
  if (!impl_->scene) return false;
  camera.validate();
  impl_->scene->camera = camera;
  return true;
}

const std::array<bssrdf::ProfileTable, 3>& TsmTechnique::profileTables() const { return impl_->tables; }
double TsmTechnique::filterRadius() const { return impl_->filterRadius(); }

std::unique_ptr<techniques::Technique> makeTsmTechnique() { return std::make_unique<TsmTechnique>(); }

}  // namespace translucent::tsm
