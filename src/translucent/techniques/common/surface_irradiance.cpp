// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/techniques/common/surface_irradiance.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <variant>

#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "translucent/io/image_io.h"
#include "translucent/gpu/compute.h"
#include "translucent/lights/environment_map.h"
#include "translucent/techniques/common/light_shadows.h"
#include "translucent/techniques/technique.h"

namespace translucent::techniques {
namespace {

// Modes of shaders/pointcloud/irradiance.comp.
enum Mode : int {
  kClear = 0,
  kDirectional = 1,
  kPoint = 2,
  kBeam = 3,
  kFiltered = 4,
  kEnvironmentSh = 5,
  kEnvironmentSample = 6,
  kEnvironmentResolve = 7,
  kClearEnvironment = 8,
};

// SSBO bindings of irradiance.comp.
enum Binding : GLuint { kPoints = 2, kIrradiance = 3, kEnvAccum = 4, kLightDirections = 14 };

glm::vec3 toVec3(const glm::dvec3& v) { return glm::vec3(v); }
glm::vec3 toVec3(const Rgb& c) {
  return {static_cast<float>(c[0]), static_cast<float>(c[1]), static_cast<float>(c[2])};
}

// A texture for the filtered directional light: a file, or a built-in 8x8 checker.
gpu::Texture filterTexture(const std::filesystem::path& file) {
  gpu::Texture tex = gpu::Texture::create(GL_TEXTURE_2D);
  std::vector<float> rgba;
  int w = 0, h = 0;
  if (file == "checker") {
    w = h = 8;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const float v = ((x + y) % 2 == 0) ? 1.0f : 0.05f;
        rgba.insert(rgba.end(), {v, v, v, 1.0f});
      }
  } else {
    analysis::RgbImage img;
    try {
      img = analysis::readRgb(file.string());
    } catch (const std::exception& e) {
      throw ParameterError(fmt::format("filter texture '{}' cannot be read: {}", file.string(), e.what()));
    }
    w = img.width;
    h = img.height;
    if (w < 1 || h < 1) throw ParameterError(fmt::format("filter texture '{}' is empty", file.string()));
    // Image rows start at the top; texture rows at v = 0 (the bottom).
    for (int y = h - 1; y >= 0; --y)
      for (int x = 0; x < w; ++x) {
        const size_t i = (size_t(y) * size_t(w) + size_t(x)) * 3;
        for (int c = 0; c < 3; ++c) {
          const float v = img.rgb[i + size_t(c)];
          if (!std::isfinite(v) || v < 0.0f)
            throw ParameterError(fmt::format("filter texture '{}': pixel ({}, {}) holds {}: "
                                             "expected finite values >= 0", file.string(), x, y, v));
          rgba.push_back(v);
        }
        rgba.push_back(1.0f);
      }
  }
  gpu::allocateTexture2D(tex, 1, GL_RGBA32F, w, h, fmt::format("filter texture '{}'", file.string()));
  glTextureSubImage2D(tex.id(), 0, 0, 0, w, h, GL_RGBA, GL_FLOAT, rgba.data());
  const GLint filter = file == "checker" ? GL_NEAREST : GL_LINEAR;
  glTextureParameteri(tex.id(), GL_TEXTURE_MIN_FILTER, filter);
  glTextureParameteri(tex.id(), GL_TEXTURE_MAG_FILTER, filter);
  glTextureParameteri(tex.id(), GL_TEXTURE_WRAP_S, GL_REPEAT);
  glTextureParameteri(tex.id(), GL_TEXTURE_WRAP_T, GL_REPEAT);
  gpu::checkGlError("uploading a filter texture");
  return tex;
}

}  // namespace

void filterAxes(const glm::dvec3& l, glm::dvec3& u, glm::dvec3& v) {
  const glm::dvec3 ref = std::abs(l.x) < 0.9 ? glm::dvec3(1.0, 0.0, 0.0) : glm::dvec3(0.0, 0.0, 1.0);
  u = glm::normalize(ref - glm::dot(ref, l) * l);
  v = glm::cross(l, u);
}

struct SurfaceIrradiance::LightState {
  scene::Light light;
  std::unique_ptr<ShadowMap> shadow;
  gpu::Texture filter;
  std::shared_ptr<lights::EnvironmentMap> env;
  std::unique_ptr<lights::EnvironmentSampler> sampler;  // occluded environment
  std::array<glm::vec3, 9> sh{};                        // unoccluded environment
};

SurfaceIrradiance::SurfaceIrradiance() = default;
SurfaceIrradiance::~SurfaceIrradiance() = default;

void SurfaceIrradiance::ensurePrograms() {
  if (irradianceProgram_) return;
  depthProgram_ = std::make_unique<gpu::ShaderProgram>(
      gpu::ShaderProgram::graphics("pointcloud/depth.vert", "pointcloud/depth.frag"));
  irradianceProgram_ =
      std::make_unique<gpu::ShaderProgram>(gpu::ShaderProgram::compute("pointcloud/irradiance.comp"));
  PlaceholderTextures t = PlaceholderTextures::create();
  dummyShadow_ = std::move(t.shadow);
  dummyFilter_ = std::move(t.filter);
  gpu::checkGlError("building the irradiance pass");
}

void SurfaceIrradiance::prepareLights(const scene::Scene& s, const glm::dvec3& center, double radius,
                                      int shadowMapSize, std::string_view technique) {
  ensurePrograms();
  std::vector<LightState> states;
  int environments = 0;
  for (size_t i = 0; i < s.lights.size(); ++i) {
    LightState st;
    st.light = s.lights[i];
    const auto& e = st.light.emitter;
    if (const auto* b = std::get_if<reference::BeamLight>(&e); b && !(b->radius > 0.0))
      throw ParameterError(fmt::format("lights[{}]: a beam of radius 0 (a pencil beam) carries no "
                                       "irradiance the {} technique's surface points can sample: "
                                       "expected radius > 0", i, technique));
    if (const auto* p = std::get_if<reference::PointLight>(&e);
        p && !(glm::length(p->position - center) > 1.02 * radius))
      throw ParameterError(fmt::format("lights[{}]: the point light lies inside the mesh's bounding "
                                       "sphere: the {} technique's shadow map needs it outside", i,
                                       technique));
    if (const auto* f = std::get_if<scene::FilteredDirectionalLight>(&e)) st.filter = filterTexture(f->texture);
    if (const auto* env = std::get_if<scene::EnvironmentLight>(&e)) {
      if (++environments > 1)
        throw ParameterError(fmt::format("lights[{}]: a second environment light: the {} technique "
                                         "takes at most one", i, technique));
      st.env = std::make_shared<lights::EnvironmentMap>(lights::EnvironmentMap::load(env->file));
      const glm::dvec3 scale =
          env->intensity * glm::dvec3(st.light.color[0], st.light.color[1], st.light.color[2]);
      if (env->occlusion)
        st.sampler = std::make_unique<lights::EnvironmentSampler>(*st.env, env->rotate);
      else
        st.sh = lights::irradianceSh9(*st.env, env->rotate, s.medium.eta, scale);
    } else {
      st.shadow = std::make_unique<ShadowMap>(shadowMapSize);
    }
    states.push_back(std::move(st));
  }
  lights_ = std::move(states);
  lightList_ = s.lights;
  center_ = center;
  radius_ = radius;
  shadowSize_ = shadowMapSize;
  envShadow_.reset();
  envDirections_ = 0;
  fresh_ = false;
}

bool SurfaceIrradiance::hasOccludedEnvironment() const {
  for (const auto& st : lights_)
    if (st.sampler) return true;
  return false;
}

void SurfaceIrradiance::dispatch(int mode) const {
  irradianceProgram_->set("Mode", mode);
  gpu::dispatch1D(*irradianceProgram_, count_);
}

void SurfaceIrradiance::lightDispatch(const LightState& st, const ShadowLookup& lookup) const {
  const gpu::ShaderProgram& p = *irradianceProgram_;
  const glm::vec3 color = toVec3(st.light.color);
  const auto& e = st.light.emitter;
  setShadowUniforms(p, st.shadow.get(), lookup, dummyShadow_);
  glBindTextureUnit(1, dummyFilter_.id());
  if (const auto* d = std::get_if<reference::DirectionalLight>(&e)) {
    p.set("LightDirection", toVec3(d->direction));
    p.set("LightValue", color * float(d->irradiance));
    dispatch(kDirectional);
  } else if (const auto* pl = std::get_if<reference::PointLight>(&e)) {
    p.set("LightPosition", toVec3(pl->position));
    p.set("LightValue", color * float(pl->intensity));
    dispatch(kPoint);
  } else if (const auto* b = std::get_if<reference::BeamLight>(&e)) {
    p.set("LightDirection", toVec3(-b->direction));
    p.set("BeamOrigin", toVec3(b->origin));
    p.set("BeamRadius", float(b->radius));
    p.set("LightValue", color * float(b->power / (std::numbers::pi * b->radius * b->radius)));
    dispatch(kBeam);
  } else if (const auto* f = std::get_if<scene::FilteredDirectionalLight>(&e)) {
    glm::dvec3 u, v;
    filterAxes(f->direction, u, v);
    glBindTextureUnit(1, st.filter.id());
    p.set("LightDirection", toVec3(f->direction));
    p.set("LightValue", color * float(f->irradiance));
    p.set("FilterU", toVec3(u));
    p.set("FilterV", toVec3(v));
    p.set("FilterSize", float(f->texture_size));
    dispatch(kFiltered);
  } else if (!st.sampler) {
    glProgramUniform3fv(p.id(), p.uniformLocation("Sh"), 9, glm::value_ptr(st.sh[0]));
    dispatch(kEnvironmentSh);
  }
}

// Occluded environment light: `count` more shadow-mapped directions into the accumulator. The
// directions are the sampler's fixed sequence, so a converged E is the same whatever the frames.
void SurfaceIrradiance::environmentSamples(const LightState& st, const GpuMesh& mesh,
                                           const ShadowLookup& lookup, uint64_t count) {
  const auto& env = std::get<scene::EnvironmentLight>(st.light.emitter);
  const gpu::ShaderProgram& p = *irradianceProgram_;
  if (!envShadow_) envShadow_ = std::make_unique<ShadowMap>(shadowSize_);
  const glm::dvec3 scale = env.intensity * glm::dvec3(st.light.color[0], st.light.color[1], st.light.color[2]);
  for (uint64_t k = 0; k < count; ++k) {
    const lights::EnvironmentSampler::Sample s = st.sampler->sequence(envDirections_ + k, 1);
    envShadow_->renderDirectional(mesh, *depthProgram_, s.direction, center_, radius_);
    setShadowUniforms(p, envShadow_.get(), lookup, dummyShadow_);
    glBindTextureUnit(1, dummyFilter_.id());
    p.set("LightDirection", toVec3(s.direction));
    p.set("LightValue", toVec3(s.radiance * scale / s.pdf));
    dispatch(kEnvironmentSample);
  }
  envDirections_ += count;
}

std::vector<ParameterInfo> lightingParameters() {
  return {
      ParameterInfo::integer("shadow_map_size", 2048, 64, 8192, "shadow map resolution", "texels"),
      ParameterInfo::floating("shadow_offset", 1.0, 0.0, 16.0,
                              "shadow lookup offset along the surface point's normal", "texels"),
      ParameterInfo::floating("shadow_bias", 1.0, 0.0, 16.0,
                              "depth offset of the shadow comparison (orthographic maps)", "texels"),
      ParameterInfo::integer("shadow_samples", 8, 1, 64,
                             "jittered hardware-PCF lookups per surface point (Bitterli 2013, Fig. 3.3 d)"),
      ParameterInfo::floating("shadow_radius", 1.5, 0.0, 16.0, "radius of the jittered lookups",
                              "texels"),
      ParameterInfo::boolean("shadow_hardware_pcf", true,
                             "bilinear depth comparison of the shadow map (hardware PCF); with "
                             "shadow_samples 1 or more the four variants of Bitterli 2013, Fig. 3.3"),
      ParameterInfo::integer("ibl_samples", 256, 1, 65536,
                             "occluded environment lighting: shadow-mapped directions in total"),
      ParameterInfo::integer("ibl_samples_per_frame", 16, 1, 1024,
                             "occluded environment lighting: directions added per frame"),
  };
}

EnvironmentBudget environmentBudget(const ParameterSet& params, bool converge) {
  EnvironmentBudget b;
  b.total = static_cast<uint64_t>(params.getInt("ibl_samples"));
  b.perFrame = static_cast<uint64_t>(params.getInt("ibl_samples_per_frame"));
  b.converge = converge;
  return b;
}

bool SurfaceIrradiance::update(const GpuMesh& mesh, const gpu::Buffer& points, size_t count, float eta,
                               const ShadowLookup& lookup, const EnvironmentBudget& budget,
                               gpu::PassTimer* timer, bool reuse, bool pointsMoved) {
  ensurePrograms();
  auto scope = [&](const char* name) {
    return timer ? std::optional<gpu::PassTimer::Scope>(timer->scope(name)) : std::nullopt;
  };
  const bool occluded = hasOccludedEnvironment();
  if (count != count_ || !irradiance_) {
    // New points: only a caller that vouches for the lights (pointsMoved) keeps the shadow maps.
    if (!pointsMoved) reuse = false;
    count_ = count;
    irradiance_ = gpu::makeStorageBuffer(std::max<size_t>(count, 1) * sizeof(glm::vec4));
    lightDirections_ = gpu::makeStorageBuffer(std::max<size_t>(count, 1) * sizeof(glm::vec4));
    envAccum_ = gpu::makeStorageBuffer(std::max<size_t>(occluded ? count : 1, 1) * sizeof(glm::vec4));
    envDirections_ = 0;
  }
  gpu::bindStorage(kPoints, points);
  gpu::bindStorage(kIrradiance, irradiance_);
  gpu::bindStorage(kLightDirections, lightDirections_);
  gpu::bindStorage(kEnvAccum, envAccum_);
  const gpu::ShaderProgram& ip = *irradianceProgram_;
  ip.set("PointCount", static_cast<unsigned>(count_));
  ip.set("Eta", eta);
  if (pointsMoved) envDirections_ = 0;
  if (occluded && envDirections_ == 0) {
    // A fresh accumulation (new points, lights or shadow settings); the buffer may be the size
    // of a previous light set without an occluded environment.
    envAccum_ = gpu::makeStorageBuffer(std::max<size_t>(count_, 1) * sizeof(glm::vec4));
    gpu::bindStorage(kEnvAccum, envAccum_);
    dispatch(kClearEnvironment);
  }
  reuse = reuse && fresh_;
  if (!reuse) {
    auto t = scope("shadow maps");
    for (auto& st : lights_)
      if (st.shadow) renderLightShadow(*st.shadow, st.light, mesh, *depthProgram_, center_, radius_);
  }
  // The environment's resolve adds to the direct irradiance: with an occluded environment the
  // direct part is dispatched again each update (cheap: the shadow maps are kept).
  if (!reuse || occluded || pointsMoved) {
    auto t = scope("irradiance");
    dispatch(kClear);
    for (const auto& st : lights_) lightDispatch(st, lookup);
  }
  fresh_ = true;
  bool final = true;
  if (occluded) {
    auto t = scope("environment samples");
    const uint64_t remaining = budget.total - std::min(budget.total, envDirections_);
    const uint64_t add = budget.converge ? remaining : std::min(remaining, budget.perFrame);
    for (const auto& st : lights_)
      if (st.sampler) environmentSamples(st, mesh, lookup, add);
    ip.set("EnvWeight", envDirections_ > 0 ? 1.0f / float(envDirections_) : 0.0f);
    dispatch(kEnvironmentResolve);
    final = envDirections_ >= budget.total;
  }
  gpu::checkGlError("irradiance pass");
  return final;
}

}  // namespace translucent::techniques
