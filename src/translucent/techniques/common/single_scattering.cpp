// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/techniques/common/single_scattering.h"

#include <fmt/format.h>

#include <array>
#include <numbers>
#include <type_traits>
#include <variant>

#include <glm/geometric.hpp>
#include <glm/vec4.hpp>

#include "translucent/geometry/flat_bvh.h"
#include "translucent/gpu/bvh_buffers.h"
#include "translucent/gpu/compute.h"
#include "translucent/gpu/gl.h"

namespace translucent::techniques {
namespace {

// SSBO bindings of shaders/common/single_scattering.comp (7, 8: the caller's outputs; 12, 13:
// the mesh as uploadMeshStorage writes it).
enum Binding : GLuint {
  kNodes = 5,
  kTriangles = 6,
  kRadiance = 7,
  kExitance = 8,
  kLights = 9,
  kStatus = 10,
  kSegments = 11,
  kMeshVertices = 12,
  kMeshTriangles = 13,
  kSums = 15,
};

// SsLight of the shader.
struct LightRecord {
  glm::vec4 a{0.0f}, b{0.0f}, c{0.0f};
};

glm::vec3 rgb(const Rgb& color, double value) {
  return {float(color[0] * value), float(color[1] * value), float(color[2] * value)};
}

}  // namespace

std::vector<ParameterInfo> singleScatteringParameters() {
  return {
      // Default 2, measured on the compare suite (96x72, llvmpipe): against the physical
      // reference 7.50% mean / 6.15% median error as with 4 strata (7.50% / 6.19%), at 53-62% of
      // their frame time (1 stratum: 7.76% / 6.81%). With 4 the backlit bunny took 2.45x the
      // point cloud's frame, with 2 1.53x.
      ParameterInfo::integer("single_samples", 2, 1, 64,
                             "single scattering: distances per colour channel along each view ray "
                             "(midpoints of equal-probability strata; the error falls as 1/samples²)"),
      ParameterInfo::integer("single_directions", 0, 0, 256,
                             "single scattering: exit directions per pixel for its exitance "
                             "(the exitance layer; 0: radiance only, no exitance layer)"),
  };
}

SingleScatteringOptions singleScatteringOptions(const ParameterSet& params) {
  SingleScatteringOptions o;
  o.samples = params.getInt("single_samples");
  o.directions = params.getInt("single_directions");
  return o;
}

std::string singleScatteringRefusal(const scene::Scene& scene) {
  if (!scene.material.homogeneous())
    return fmt::format("material.type '{}': single scattering is rendered for homogeneous "
                       "materials only", scene.material.type());
  for (size_t i = 0; i < scene.lights.size(); ++i) {
    const auto& e = scene.lights[i].emitter;
    if (std::holds_alternative<scene::EnvironmentLight>(e))
      return fmt::format("lights[{}]: single scattering is rendered for directional, point and "
                         "beam lights: expected no environment light", i);
    if (std::holds_alternative<scene::FilteredDirectionalLight>(e))
      return fmt::format("lights[{}]: single scattering is rendered for directional, point and "
                         "beam lights: expected no textured directional light", i);
    if (const auto* b = std::get_if<reference::BeamLight>(&e); b && !(b->radius > 0.0))
      return fmt::format("lights[{}]: a pencil beam (radius 0) has no area to light a pixel's "
                         "view ray: expected a radius > 0", i);
  }
  return {};
}

void SingleScattering::prepare(const geometry::TriangleMesh& mesh, const std::string& meshKey,
                               const scene::Scene& s, std::string_view technique) {
  if (const std::string why = singleScatteringRefusal(s); !why.empty())
    throw ParameterError(fmt::format("{} (the {} technique)", why, technique));
  if (!segments_) {
    segments_.emplace(gpu::ShaderProgram::compute("common/single_scattering.comp", {{"SS_MODE", "0"}}));
    sample_.emplace(gpu::ShaderProgram::compute("common/single_scattering.comp", {{"SS_MODE", "1"}}));
    finish_.emplace(gpu::ShaderProgram::compute("common/single_scattering.comp", {{"SS_MODE", "2"}}));
    status_ = gpu::makeStorageBuffer(sizeof(uint32_t));
  }
  if (meshKey != meshKey_ || meshKey.empty()) {
    bvh_ = gpu::BvhBuffers::upload(
        geometry::FlatBvh::build(mesh, fmt::format("the {} technique's mesh", technique)));
    // Rays leave surface points with this offset: well above float error on the mesh's scale,
    // well below any feature (1e-5 of the bounding box's diagonal).
    epsilon_ = float(2e-5 * mesh.bounds().radius());
    meshKey_ = meshKey;
  }
  std::vector<LightRecord> records;
  for (const scene::Light& l : s.lights) {
    LightRecord r;
    std::visit(
        [&](const auto& e) {
          using T = std::decay_t<decltype(e)>;
          if constexpr (std::is_same_v<T, reference::DirectionalLight>) {
            r.a = glm::vec4(glm::vec3(glm::normalize(e.direction)), 0.0f);
            r.b = glm::vec4(rgb(l.color, e.irradiance), 0.0f);
          } else if constexpr (std::is_same_v<T, reference::PointLight>) {
            r.a = glm::vec4(glm::vec3(e.position), 1.0f);
            r.b = glm::vec4(rgb(l.color, e.intensity), 0.0f);
          } else if constexpr (std::is_same_v<T, reference::BeamLight>) {
            r.a = glm::vec4(-glm::vec3(glm::normalize(e.direction)), 2.0f);
            r.b = glm::vec4(rgb(l.color, e.power / (std::numbers::pi * e.radius * e.radius)),
                            float(e.radius));
            r.c = glm::vec4(glm::vec3(e.origin), 0.0f);
          }
        },
        l.emitter);
    records.push_back(r);
  }
  lightCount_ = records.size();
  if (records.empty()) records.emplace_back();  // a buffer is never empty
  lights_ = gpu::makeStorageBuffer(std::span<const LightRecord>(records));
  gpu::checkGlError("preparing single scattering");
}

void SingleScattering::render(const GBuffer& gbuffer, const gpu::Buffer& meshVertices,
                              const gpu::Buffer& meshTriangles, const scene::Scene& s,
                              const SingleScatteringOptions& o, const gpu::Buffer& radiance,
                              const gpu::Buffer& exitance, gpu::PassTimer* timer) {
  if (!segments_) throw ParameterError("single scattering: render() before prepare()");
  const int width = gbuffer.width(), height = gbuffer.height();
  const size_t pixels = size_t(width) * size_t(height);
  if (pixels != pixels_) {
    segmentBuffer_ = gpu::makeStorageBuffer(2 * pixels * sizeof(glm::vec4));
    sums_ = gpu::makeStorageBuffer(pixels * sizeof(glm::vec4));
    pixels_ = pixels;
  }
  std::optional<gpu::PassTimer::Scope> scope;
  if (timer) scope.emplace(timer->scope("single scattering"));
  // Only a driver with a loop limit (llvmpipe) needs the work count back: elsewhere no read-back
  // stalls the frame.
  const gpu::LoopLimit limit = gpu::loopLimit();
  if (limit.limited) {
    const uint32_t zero = 0;
    gpu::upload(status_, std::span<const uint32_t>(&zero, 1));
  }
  glm::vec3 sigmaT, sigmaS;
  for (int c = 0; c < 3; ++c) {
    const ScalarMedium m = s.medium.channel(c);
    sigmaT[c] = float(m.sigmaT());
    sigmaS[c] = float(m.sigma_s);
  }
  const bool ortho = s.camera.projection == reference::Camera::Projection::Orthographic;
  for (const gpu::ShaderProgram* p : {&*segments_, &*sample_, &*finish_}) {
    glProgramUniform2ui(p->id(), p->uniformLocation("Size"), unsigned(width), unsigned(height));
    p->set("Eta", float(s.medium.eta));
    p->set("SigmaT", sigmaT);
    p->set("SigmaS", sigmaS);
    p->set("G", float(s.medium.g));
    p->set("Lights", unsigned(lightCount_));
    p->set("Samples", unsigned(o.samples));
    p->set("Directions", unsigned(o.directions));
    p->set("Epsilon", epsilon_);
    p->set("CameraPosition", glm::vec3(s.camera.position));
    p->set("CameraForward", glm::vec3(glm::normalize(s.camera.look_at - s.camera.position)));
    p->set("Orthographic", ortho);
  }
  glBindTextureUnit(0, gbuffer.position().id());
  gpu::bindStorage(kNodes, bvh_.nodes);
  gpu::bindStorage(kTriangles, bvh_.triangles);
  gpu::bindStorage(kRadiance, radiance);
  gpu::bindStorage(kExitance, exitance);
  gpu::bindStorage(kLights, lights_);
  gpu::bindStorage(kStatus, status_);
  gpu::bindStorage(kSegments, segmentBuffer_);
  gpu::bindStorage(kMeshVertices, meshVertices);
  gpu::bindStorage(kMeshTriangles, meshTriangles);
  gpu::bindStorage(kSums, sums_);
  const std::array<GLuint, 3> groups{(unsigned(width) + 7u) / 8u, (unsigned(height) + 7u) / 8u, 1u};
  const unsigned lines = 1u + unsigned(o.directions);
  for (unsigned line = 0; line < lines; ++line) {
    segments_->set("Line", line);
    gpu::dispatch(*segments_, groups);
    sample_->set("Line", line);
    for (unsigned c = 0; c < 3; ++c)
      for (unsigned j = 0; j < unsigned(o.samples); ++j) {
        sample_->set("Channel", c);
        sample_->set("Index", j);
        gpu::dispatch(*sample_, groups);
      }
    finish_->set("Line", line);
    gpu::dispatch(*finish_, groups);
  }
  gpu::checkGlError("single scattering");
  if (!limit.limited) return;
  const uint32_t maxWork = gpu::download<uint32_t>(status_, 1)[0];
  if (!limit.clear(maxWork))
    throw gpu::GlError(fmt::format(
        "single scattering: a pixel's ray queries took {} loop iterations in one pass, more than "
        "the driver's limit of {} per group of {} invocations (Mesa llvmpipe) allows; the image "
        "would be wrong: use a coarser mesh or a GPU driver without the limit",
        maxWork, limit.iterations, limit.lanes));
}

}  // namespace translucent::techniques
