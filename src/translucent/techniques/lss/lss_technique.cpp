// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/techniques/lss/lss_technique.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cmath>
#include <numbers>
#include <optional>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include "translucent/bssrdf/bssrdf_file.h"
#include "translucent/bssrdf/exit_radiance.h"
#include "translucent/gpu/bssrdf_kernels.h"
#include "translucent/gpu/compute.h"
#include "translucent/gpu/pass_timer.h"
#include "translucent/techniques/common/gl_resources.h"
#include "translucent/techniques/common/specular.h"
#include "translucent/techniques/common/light_shadows.h"  // shadowLookup
#include "translucent/techniques/common/profile_kernel.h"
#include "translucent/techniques/common/surface_irradiance.h"

namespace translucent::lss {
namespace {

using techniques::GBuffer;
using techniques::GpuMesh;
using techniques::ParameterInfo;

// SSBO bindings: 2, 3, 5, 7, 8 as the point cloud's shaders (the shared irradiance pass,
// kernel_table.glsl, the output images); 9.. the lss buffers.
enum Binding : GLuint {
  kPoints = 2,
  kIrradiance = 3,
  kProfile = 5,
  kRadianceOut = 7,
  kExitanceOut = 8,
  kCdf = 9,
  kAccum = 12,
};

std::vector<ParameterInfo> parameterInfos() {
  std::vector<ParameterInfo> infos{
      ParameterInfo::integer("samples", 64, 4, 4096,
                             "N: image-plane samples per pixel and frame, drawn with density "
                             "following 2πr Rd(r) around the pixel")
          // Error falls as 1/√N per frame: each step quadruples N.
          .withSweep({16, 64, 256, 1024, 4096}),
      ParameterInfo::enumeration("sequence", "stratified", {"stratified", "random"},
                                 "the (radius, angle) numbers: a stratified lattice rotated per pixel "
                                 "and frame, or independent uniform (plain Monte Carlo: error "
                                 "exactly as 1/√N)"),
      ParameterInfo::boolean("accumulate", true,
                             "average the frames (new samples every frame) into a converging image; "
                             "false: every frame is the real-time image of N samples"),
      ParameterInfo::integer("accumulate_samples", 4096, 4, 16777216,
                             "samples per pixel of a converged image: ⌈accumulate_samples / N⌉ "
                             "accumulated frames (a batch render renders them all at once)"),
      techniques::tableSizeParameter("entries of the tabulated profile and of its radial CDFs "
                                     "(uniform in r up to the radius holding 99.9% of Rd)"),
      techniques::radianceConventionParameter(),
  };
  for (ParameterInfo& p : techniques::specularParameters()) infos.push_back(std::move(p));
  // The shared irradiance pass's shadow and environment settings (surface_irradiance.h).
  for (ParameterInfo& p : techniques::lightingParameters()) infos.push_back(std::move(p));
  return infos;
}

glm::vec3 toVec3(const glm::dvec3& v) { return glm::vec3(v); }

}  // namespace

// ---------------------------------------------------------------------------------------------

// The mesh, its bounding sphere and GPU copy: techniques::ClosedMeshState.
struct LssTechnique::Impl : techniques::ClosedMeshState {
  techniques::ParameterSet params{parameterInfos()};

  std::optional<scene::Scene> scene;

  // Kernel: the profile table and the radial CDFs.
  std::string kernelKey;
  std::array<bssrdf::ProfileTable, 3> tables;
  RadialSampler sampler;
  gpu::Buffer profile, cdf;

  std::optional<gpu::ShaderProgram> gbufferProgram, packProgram, radianceProgram;

  // The camera-view irradiance: the shared pass (techniques/common/surface_irradiance.h) over
  // the pixels' points, every light type.
  techniques::SurfaceIrradiance lighting;
  bool lightingDirty = true;     // the lights, the mesh or the shadow settings changed
  bool pointsMoved = true;       // the pixels' points changed (a camera move, a new image size)
  bool irradianceFinal = true;   // false while an occluded environment still adds directions

  GBuffer gbuffer;
  gpu::Buffer points, radianceOut, exitanceOut, accum;
  size_t outPixels = 0;
  uint64_t frameIndex = 0;  // frames accumulated so far
  uint64_t frameSeed = 0;   // every frame rendered (seeds the sequences)
  bool accumulationDirty = true;
  std::optional<gpu::PassTimer> timer;
  techniques::SpecularPass specular;
  std::vector<std::string> notes;

  void buildPrograms() {
    if (gbufferProgram) return;
    gbufferProgram.emplace(
        gpu::ShaderProgram::graphics("pointcloud/gbuffer.vert", "pointcloud/gbuffer.frag"));
    packProgram.emplace(gpu::ShaderProgram::compute("lss/pack.comp"));
    radianceProgram.emplace(gpu::ShaderProgram::compute("lss/radiance.comp"));
    gpu::checkGlError("building the lss programs");
  }

  // A deformed mesh: the rest pose uploaded once, deformed on the GPU at each new time.
  void loadMesh(const scene::Scene& s) { (void)loadClosedMesh(s, /*gpuDeform=*/true); }

  void prepareLights(const scene::Scene& s) {
    lighting.prepareLights(s, center, radius, params.getInt("shadow_map_size"), "lss");
    lightingDirty = true;
  }

  void buildKernel() {
    const scene::Scene& s = *scene;
    const std::string key = fmt::format("{}|{}|{}|{}|{}|{}|{}", s.model, s.medium.sigma_a, s.medium.sigma_s,
                                        s.medium.g, s.medium.eta, s.medium.scale,
                                        params.getInt("table_size"));
    if (key == kernelKey) return;
    kernelKey.clear();
    s.medium.validate();
    std::optional<gpu::BssrdfEvaluator> evaluator;
    if (bssrdf::hasBssrdfExtension(s.model)) {
      evaluator.emplace(s.model);
      evaluator->setMedium(s.medium);
    }
    techniques::RgbProfileTable t = techniques::tabulateRgbProfile(
        s, static_cast<size_t>(params.getInt("table_size")), evaluator ? &*evaluator : nullptr);
    RadialSampler rs(t.tables);
    for (size_t c = 0; c < 3; ++c)
      if (!(rs.mass(c) > 0.0))
        throw ParameterError(fmt::format("model '{}': the {} channel's profile integrates to {}: the "
                                         "lss technique samples radii from it and needs Rd > 0",
                                         s.model, kChannelNames[c], 2.0 * std::numbers::pi * rs.mass(c)));
    std::vector<glm::vec4> nodes(rs.size());
    for (size_t i = 0; i < nodes.size(); ++i)
      nodes[i] = glm::vec4(float(rs.cdf(0)[i]), float(rs.cdf(1)[i]), float(rs.cdf(2)[i]), 0.0f);
    tables = std::move(t.tables);
    sampler = std::move(rs);
    profile = gpu::makeStorageBuffer(std::span<const glm::vec4>(t.gpu));
    cdf = gpu::makeStorageBuffer(std::span<const glm::vec4>(nodes));
    kernelKey = key;
    accumulationDirty = true;
  }

  // The camera uniforms of lss/camera.glsl.
  void setCamera(const gpu::ShaderProgram& p, const glm::mat4& viewProj, int width, int height) const {
    const reference::Camera& cam = scene->camera;
    const bool ortho = cam.projection == reference::Camera::Projection::Orthographic;
    p.set("InverseViewProjection", glm::inverse(viewProj));
    glProgramUniform2ui(p.id(), p.uniformLocation("Size"), unsigned(width), unsigned(height));
    p.set("CameraPosition", toVec3(cam.position));
    p.set("CameraForward", toVec3(glm::normalize(cam.look_at - cam.position)));
    p.set("Orthographic", ortho);
    const double scale = ortho ? cam.view_height / double(height)
                               : 2.0 * std::tan(0.5 * cam.fov * std::numbers::pi / 180.0) / double(height);
    p.set("PixelScale", static_cast<float>(scale));
  }

  // The radiance of one frame into the output (and accumulation) buffers.
  void radiancePass(const glm::mat4& viewProj, int width, int height, bool accumulate) {
    const scene::Scene& s = *scene;
    const gpu::ShaderProgram& p = *radianceProgram;
    gpu::bindStorage(kIrradiance, lighting.irradiance());
    gpu::bindStorage(kProfile, profile);
    gpu::bindStorage(kCdf, cdf);
    gpu::bindStorage(kRadianceOut, radianceOut);
    gpu::bindStorage(kExitanceOut, exitanceOut);
    gpu::bindStorage(kAccum, accum);
    glBindTextureUnit(0, gbuffer.position().id());
    glBindTextureUnit(1, gbuffer.normal().id());
    setCamera(p, viewProj, width, height);
    p.set("SampleCount", static_cast<unsigned>(params.getInt("samples")));
    p.set("Eta", static_cast<float>(s.medium.eta));
    p.set("ExitScale", glm::vec3(static_cast<float>(bssrdf::exitConventionScale(
                           bssrdf::parseExitConvention(params.getEnum("radiance_convention")),
                           s.medium.eta))));
    p.set("ProfileRMax", static_cast<float>(tables[0].r_max));
    p.set("ProfileCount", static_cast<unsigned>(tables[0].size()));
    p.set("ProfileMass", glm::vec3(float(sampler.mass(0)), float(sampler.mass(1)), float(sampler.mass(2))));
    p.set("Random", params.getEnum("sequence") == "random");
    p.set("Frame", static_cast<unsigned>(frameSeed));
    p.set("Accumulate", accumulate);
    p.set("FrameIndex", static_cast<unsigned>(accumulate ? frameIndex : 0));
    gpu::dispatch(p, {(unsigned(width) + 7u) / 8u, (unsigned(height) + 7u) / 8u, 1u});
    ++frameIndex;
    ++frameSeed;
  }

  techniques::Frame render(const techniques::FrameRequest& request) {
    if (!scene) throw ParameterError("lss: render() before prepare(): expected a scene");
    const scene::Scene& s = *scene;
    const auto [width, height] = techniques::frameSize(request, s.camera);
    buildPrograms();
    buildKernel();
    if (!timer) timer.emplace();
    techniques::Frame frame;
    frame.notes = std::move(notes);
    notes.clear();

    const size_t pixels = size_t(width) * size_t(height);
    if (pixels != outPixels || gbuffer.width() != width || gbuffer.height() != height) {
      points = gpu::makeStorageBuffer(pixels * 2 * sizeof(glm::vec4));
      radianceOut = gpu::makeStorageBuffer(pixels * sizeof(glm::vec4));
      exitanceOut = gpu::makeStorageBuffer(pixels * sizeof(glm::vec4));
      accum = gpu::makeStorageBuffer(pixels * sizeof(glm::vec4));
      outPixels = pixels;
      accumulationDirty = true;
      pointsMoved = true;
    }
    const glm::mat4 vp = techniques::cameraViewProjection(s.camera, s.clip_near, s.clip_far, center,
                                                          radius, width, height);
    {
      auto t = timer->scope("g-buffer");
      gbuffer.resize(width, height);
      gbuffer.render(*gpuMesh, *gbufferProgram, vp);
    }
    {
      auto t = timer->scope("pack");
      const gpu::ShaderProgram& p = *packProgram;
      gpu::bindStorage(kPoints, points);
      glBindTextureUnit(0, gbuffer.position().id());
      glBindTextureUnit(1, gbuffer.normal().id());
      setCamera(p, vp, width, height);
      gpu::dispatch(p, {(unsigned(width) + 7u) / 8u, (unsigned(height) + 7u) / 8u, 1u});
    }
    // E of every pixel's point (every light type, shadowed); the update's shadow maps, lights and
    // environment directions are timed as passes of their own. The shadow maps depend on the
    // mesh and the lights only: kept until prepare() or a shadow setting changes them. E does
    // not survive a camera move (setCamera) or a new image size, unlike the point cloud's: lss
    // lights the camera's pixels, so those are new points, whose E is computed again (the
    // irradiance pass, not the shadow maps) and whose occluded environment starts again (its
    // directions are accumulated per point). A still frame keeps E as it is.
    const bool reuse = !lightingDirty;
    if (lightingDirty) lighting.restartEnvironment();
    lightingDirty = false;
    const bool wasFinal = irradianceFinal;
    irradianceFinal = lighting.update(*gpuMesh, points, pixels, static_cast<float>(s.medium.eta),
                                      techniques::shadowLookup(params),
                                      techniques::environmentBudget(params, request.converge), &*timer,
                                      reuse, pointsMoved);
    pointsMoved = false;
    // While an occluded environment adds directions E changes from frame to frame: frames of
    // different E must not be averaged, so accumulation starts over until E is final.
    if (!wasFinal || !irradianceFinal) accumulationDirty = true;

    const bool accumulate = params.getBool("accumulate");
    // A parameter, the scene or the image size changed: the accumulated frames are stale.
    if (accumulate && accumulationDirty) frameIndex = 0;
    accumulationDirty = false;
    const auto perFrame = static_cast<uint64_t>(params.getInt("samples"));
    const uint64_t target =
        (static_cast<uint64_t>(params.getInt("accumulate_samples")) + perFrame - 1) / perFrame;
    uint64_t count = 1;
    if (accumulate && request.converge && frameIndex < target) count = target - frameIndex;
    // The lights and the scene stay the same within one call: the irradiance once, then only
    // new samples.
    {
      // One pass however many frames a batch render accumulates in this call.
      auto t = timer->scope(count == 1 ? std::string("radiance") : fmt::format("radiance ({} frames)", count));
      for (uint64_t f = 0; f < count; ++f) radiancePass(vp, width, height, accumulate);
    }
    frame.converged = (!accumulate || frameIndex >= target) && irradianceFinal;
    specular.add(gbuffer, *scene, params, radianceOut, &*timer);
    gpu::checkGlError("lss frame");

    frame.width = width;
    frame.height = height;
    if (request.readback) techniques::readRadianceAndExitance(frame, radianceOut, exitanceOut, pixels);
    techniques::addPasses(frame, *timer);
    return frame;
  }
};

// ---------------------------------------------------------------------------------------------

LssTechnique::LssTechnique() : impl_(std::make_unique<Impl>()) {}
LssTechnique::~LssTechnique() = default;

std::string_view LssTechnique::description() const {
  return "local subsurface scattering: camera-view irradiance, per-pixel importance sampling of Rd "
         "on the image plane (Mertens et al. 2003)";
}

const std::vector<techniques::ParameterInfo>& LssTechnique::parameters() const {
  return impl_->params.infos();
}

void LssTechnique::setParameter(std::string_view name, const techniques::ParameterValue& value) {
  if (!impl_->params.set(name, value)) return;
  impl_->accumulationDirty = true;
  if (name == "shadow_map_size" && impl_->scene) impl_->prepareLights(*impl_->scene);
  if (name.starts_with("shadow_") || name.starts_with("ibl_")) impl_->lightingDirty = true;
}

techniques::ParameterValue LssTechnique::parameter(std::string_view name) const {
  return impl_->params.get(name);
}

void LssTechnique::prepare(const scene::Scene& scene, gpu::Context& gl) {
  gl.makeCurrent();
  scene.camera.validate();
  scene.medium.validate();
  techniques::requireHomogeneousMaterial(scene, "lss");
  impl_->buildPrograms();
  impl_->scene.reset();  // until this preparation succeeds
  impl_->loadMesh(scene);
  impl_->prepareLights(scene);
  impl_->scene = scene;
  impl_->buildKernel();
  impl_->accumulationDirty = true;
}

techniques::Frame LssTechnique::render(const techniques::FrameRequest& request) {
  return impl_->render(request);
}

bool LssTechnique::setCamera(const reference::Camera& camera) {
  if (!impl_->scene) return false;
  camera.validate();
  impl_->scene->camera = camera;
  impl_->pointsMoved = true;
  impl_->accumulationDirty = true;  // the accumulated image is the old view's
  return true;
}

const std::array<bssrdf::ProfileTable, 3>& LssTechnique::profileTables() const { return impl_->tables; }
const RadialSampler& LssTechnique::radialSampler() const { return impl_->sampler; }

std::vector<glm::vec3> LssTechnique::pixelIrradiance() const {
  const int w = impl_->gbuffer.width(), h = impl_->gbuffer.height();
  const auto e = gpu::download<glm::vec4>(impl_->lighting.irradiance(), size_t(w) * size_t(h));
  const auto p = gpu::download<glm::vec4>(impl_->points, 2 * size_t(w) * size_t(h));
  std::vector<glm::vec3> out(e.size());
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * size_t(w) + size_t(x);
      const bool covered = glm::dot(glm::vec3(p[2 * i + 1]), glm::vec3(p[2 * i + 1])) > 0.0f;
      out[size_t(h - 1 - y) * size_t(w) + size_t(x)] = covered ? glm::vec3(e[i]) : glm::vec3(0.0f);
    }
  return out;
}

int LssTechnique::accumulatedFrames() const { return static_cast<int>(impl_->frameIndex); }

std::unique_ptr<techniques::Technique> makeLssTechnique() { return std::make_unique<LssTechnique>(); }

}  // namespace translucent::lss
