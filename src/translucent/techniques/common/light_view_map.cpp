// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/techniques/common/light_view_map.h"

#include <fmt/format.h>

#include "translucent/gpu/context.h"
#include "translucent/gpu/objects.h"

namespace translucent::techniques {

LightViewMap::LightViewMap(int size) : size_(size) {
  if (size < 1 || size > 16384)
    throw gpu::GlError(fmt::format("light-view map of {}x{} texels: expected a size in [1, 16384]", size, size));
  auto target = [&](GLenum format) {
    gpu::Texture t = gpu::Texture::create(GL_TEXTURE_2D);
    gpu::allocateTexture2D(t, 1, format, size, size, "light-view map");
    // texelFetch only: each texel is one surface sample of the filter, not a value to blend.
    glTextureParameteri(t.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(t.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    return t;
  };
  position_ = target(GL_RGBA32F);  // positions set the kernel's distances: 32 bits
  normal_ = target(GL_RGBA32F);
  irradiance_ = target(GL_RGBA32F);
  depth_ = target(GL_DEPTH_COMPONENT24);
  fbo_ = gpu::Framebuffer::create();
  glNamedFramebufferTexture(fbo_.id(), GL_COLOR_ATTACHMENT0, position_.id(), 0);
  glNamedFramebufferTexture(fbo_.id(), GL_COLOR_ATTACHMENT1, normal_.id(), 0);
  glNamedFramebufferTexture(fbo_.id(), GL_COLOR_ATTACHMENT2, irradiance_.id(), 0);
  glNamedFramebufferTexture(fbo_.id(), GL_DEPTH_ATTACHMENT, depth_.id(), 0);
  const GLenum buffers[3] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
  glNamedFramebufferDrawBuffers(fbo_.id(), 3, buffers);
  if (glCheckNamedFramebufferStatus(fbo_.id(), GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw gpu::GlError(fmt::format("light-view map of {}x{} texels: the framebuffer is incomplete", size, size));
  gpu::checkGlError("creating a light-view map");
}

gpu::ShaderProgram LightViewMap::program() {
  return gpu::ShaderProgram::graphics("common/light_view_map.vert", "common/light_view_map.frag");
}

void LightViewMap::renderDirectional(const GpuMesh& mesh, const gpu::ShaderProgram& program,
                                     const glm::dvec3& towardsLight, const glm::vec3& irradiance,
                                     double eta, const glm::dvec3& center, double radius) {
  projection_ = directionalLightProjection(towardsLight, center, radius);
  render(mesh, program, irradiance, eta);
}

void LightViewMap::renderPoint(const GpuMesh& mesh, const gpu::ShaderProgram& program,
                               const glm::dvec3& position, const glm::vec3& intensity, double eta,
                               const glm::dvec3& center, double radius) {
  projection_ = pointLightProjection(position, center, radius);
  render(mesh, program, intensity, eta);
}

double LightViewMap::texelSize(double depth) const {
  const double t = double(projection_.extent) / double(size_);
  return projection_.perspective ? t * depth : t;
}

void LightViewMap::render(const GpuMesh& mesh, const gpu::ShaderProgram& program,
                          const glm::vec3& value, double eta) {
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_.id());
  glViewport(0, 0, size_, size_);
  const float zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
  const float one = 1.0f;
  for (int i = 0; i < 3; ++i) glClearNamedFramebufferfv(fbo_.id(), GL_COLOR, i, zero);
  glClearNamedFramebufferfv(fbo_.id(), GL_DEPTH, 0, &one);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  // Front faces only (the mesh is closed and oriented outwards): the surface the light reaches.
  glEnable(GL_CULL_FACE);
  glCullFace(GL_BACK);
  program.use();
  program.set("ViewProjection", projection_.viewProj);
  program.set("Perspective", projection_.perspective);
  program.set("LightAxis", projection_.axis);
  program.set("LightPosition", projection_.origin);
  program.set("LightValue", value);
  program.set("Eta", static_cast<float>(eta));
  mesh.draw();
  glDisable(GL_CULL_FACE);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  gpu::checkGlError("rendering a light-view map");
}

void LightViewMap::bind(const gpu::ShaderProgram& p, unsigned firstUnit, int index) const {
  glBindTextureUnit(firstUnit, position_.id());
  glBindTextureUnit(firstUnit + 1, normal_.id());
  glBindTextureUnit(firstUnit + 2, irradiance_.id());
  // Element `index` of the include's uniform arrays (LVM_MAPS of them; 1 by default).
  const auto name = [index](const char* n) { return fmt::format("{}[{}]", n, index); };
  p.set(name("LvmPosition"), int(firstUnit));
  p.set(name("LvmNormal"), int(firstUnit + 1));
  p.set(name("LvmIrradiance"), int(firstUnit + 2));
  p.set(name("LvmMatrix"), projection_.toTexture);
  p.set(name("LvmPerspective"), projection_.perspective);
  p.set(name("LvmExtent"), projection_.extent);
  p.set(name("LvmAxis"), projection_.axis);
  p.set(name("LvmOrigin"), projection_.origin);
}

}  // namespace translucent::techniques
