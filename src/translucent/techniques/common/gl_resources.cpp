// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/techniques/common/gl_resources.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "translucent/bssrdf/exit_radiance.h"
#include "translucent/gpu/compute.h"

namespace translucent::techniques {

// The same normals as geometry::deformMesh transforms, so that a mesh deformed on the CPU and
// one deformed on the GPU shade alike.
std::vector<glm::dvec3> vertexNormals(const geometry::TriangleMesh& mesh) {
  return geometry::smoothVertexNormals(mesh);
}

GpuMesh::GpuMesh(const geometry::TriangleMesh& mesh) : GpuMesh(mesh, vertexNormals(mesh)) {}

GpuMesh::GpuMesh(const geometry::TriangleMesh& mesh, const std::vector<glm::dvec3>& normals,
                 const std::vector<float>& scalar)
    : triangles_(mesh.triangleCount()), vertexCount_(mesh.vertexCount()) {
  if (normals.size() != mesh.vertexCount() || (!scalar.empty() && scalar.size() != mesh.vertexCount()))
    throw gpu::GlError(fmt::format("uploading the mesh: {} normals and {} scalars for {} vertices",
                                   normals.size(), scalar.size(), mesh.vertexCount()));
  const GLuint stride = scalar.empty() ? 6 : 7;
  stride_ = stride;
  std::vector<float> v;
  v.reserve(mesh.vertexCount() * stride);
  for (size_t i = 0; i < mesh.vertexCount(); ++i) {
    const glm::vec3 p(mesh.positions[i]), n(normals[i]);
    v.insert(v.end(), {p.x, p.y, p.z, n.x, n.y, n.z});
    if (!scalar.empty()) v.push_back(scalar[i]);
  }
  std::vector<uint32_t> idx;
  idx.reserve(triangles_ * 3);
  for (const glm::uvec3& t : mesh.triangles) idx.insert(idx.end(), {t.x, t.y, t.z});
  vertices_ = gpu::Buffer::create();
  gpu::allocateBuffer(vertices_, v.size() * sizeof(float), v.data(), 0, "mesh vertices");
  indices_ = gpu::Buffer::create();
  gpu::allocateBuffer(indices_, idx.size() * sizeof(uint32_t), idx.data(), 0, "mesh indices");
  vao_ = gpu::VertexArray::create();
  glVertexArrayVertexBuffer(vao_.id(), 0, vertices_.id(), 0, GLsizei(stride * sizeof(float)));
  glVertexArrayElementBuffer(vao_.id(), indices_.id());
  for (GLuint a = 0; a < stride / 3 + (stride % 3 ? 1 : 0); ++a) {
    glEnableVertexArrayAttrib(vao_.id(), a);
    glVertexArrayAttribFormat(vao_.id(), a, a == 2 ? 1 : 3, GL_FLOAT, GL_FALSE, a * 3 * sizeof(float));
    glVertexArrayAttribBinding(vao_.id(), a, 0);
  }
  gpu::checkGlError("uploading the mesh");
}

void GpuMesh::deform(const std::vector<geometry::Deformation>& chain, double time) {
  if (chain.size() > geometry::kMaxDeformations)
    throw gpu::GlError(fmt::format("deforming the mesh: {} deformations, at most {}", chain.size(),
                                   geometry::kMaxDeformations));
  const std::string state = geometry::deformStateKey(chain, time);
  if (state == deformState_) return;
  const bool identity = state.empty();
  const GLsizeiptr bytes = GLsizeiptr(vertexCount_ * stride_ * sizeof(float));
  if (!rest_.id()) {
    // The vertex buffer still holds the rest pose (nothing else writes it): keep a copy.
    rest_ = gpu::makeStorageBuffer(size_t(bytes));
    glCopyNamedBufferSubData(vertices_.id(), rest_.id(), 0, 0, bytes);
  }
  if (identity) {
    glCopyNamedBufferSubData(rest_.id(), vertices_.id(), 0, 0, bytes);
  } else {
    if (!deformProgram_)
      deformProgram_ = std::make_shared<gpu::ShaderProgram>(gpu::ShaderProgram::compute("common/deform.comp"));
    const gpu::ShaderProgram& p = *deformProgram_;
    const geometry::DeformUniforms u = geometry::deformUniforms(chain, time);
    p.set("VertexCount", unsigned(vertexCount_));
    p.set("Stride", stride_);
    p.set("DeformCount", int(chain.size()));
    const GLsizei n = GLsizei(chain.size());
    glProgramUniform4fv(p.id(), p.uniformLocation("DeformA"), n, glm::value_ptr(u.a[0]));
    glProgramUniform4fv(p.id(), p.uniformLocation("DeformB"), n, glm::value_ptr(u.b[0]));
    glProgramUniform4fv(p.id(), p.uniformLocation("DeformC"), n, glm::value_ptr(u.c[0]));
    gpu::bindStorage(0, rest_);
    gpu::bindStorage(1, vertices_);
    // The vertex fetch of later draws reads what the shader wrote.
    gpu::dispatch1D(p, vertexCount_,
                    GL_VERTEX_ATTRIB_ARRAY_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT |
                        GL_BUFFER_UPDATE_BARRIER_BIT);
  }
  gpu::checkGlError("deforming the mesh");
  deformState_ = state;
}

void GpuMesh::draw() const {
  glBindVertexArray(vao_.id());
  glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(triangles_ * 3), GL_UNSIGNED_INT, nullptr);
  glBindVertexArray(0);
}

ShadowMap::ShadowMap(int size) : size_(size) {
  depth_ = gpu::Texture::create(GL_TEXTURE_2D);
  // 24-bit depth: steps of 3r / 2^24 ≈ 2e-7 r over a directional light's depth range (r: the
  // bounding radius), at most ~2e-5 r at the far side of a point light's perspective map with
  // the light 1% outside the bounding sphere: far below the normal and depth offsets (about a
  // texel, 1e-3 r). On the H100 two 2048² maps take 1.04 ms instead of 1.23 with 32-bit float
  // depth (BENCHMARKS.md of commit 91fe617).
  gpu::allocateTexture2D(depth_, 1, GL_DEPTH_COMPONENT24, size, size, "shadow map");
  glTextureParameteri(depth_.id(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTextureParameteri(depth_.id(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTextureParameteri(depth_.id(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(depth_.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glTextureParameteri(depth_.id(), GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
  glTextureParameteri(depth_.id(), GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
  fbo_ = gpu::Framebuffer::create();
  glNamedFramebufferTexture(fbo_.id(), GL_DEPTH_ATTACHMENT, depth_.id(), 0);
  glNamedFramebufferDrawBuffer(fbo_.id(), GL_NONE);
  glNamedFramebufferReadBuffer(fbo_.id(), GL_NONE);
  if (glCheckNamedFramebufferStatus(fbo_.id(), GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw gpu::GlError(fmt::format("shadow map of {}x{} texels: the framebuffer is incomplete", size, size));
  gpu::checkGlError("creating a shadow map");
}

namespace {
// [-1,1] clip coordinates to [0,1] texture coordinates and depth.
const glm::mat4 kBias = glm::translate(glm::mat4(1.0f), glm::vec3(0.5f)) *
                        glm::scale(glm::mat4(1.0f), glm::vec3(0.5f));

glm::dvec3 upFor(const glm::dvec3& forward) {
  return std::abs(forward.y) < 0.9 ? glm::dvec3(0.0, 1.0, 0.0) : glm::dvec3(1.0, 0.0, 0.0);
}
}  // namespace

LightProjection directionalLightProjection(const glm::dvec3& towardsLight, const glm::dvec3& center,
                                           double radius) {
  const double r = radius * 1.02;
  const glm::dvec3 l = glm::normalize(towardsLight);
  const glm::dmat4 view = glm::lookAt(center + 2.0 * r * l, center, upFor(l));
  const glm::dmat4 proj = glm::ortho(-r, r, -r, r, 0.5 * r, 3.5 * r);
  LightProjection p;
  p.viewProj = glm::mat4(proj * view);
  p.perspective = false;
  p.extent = static_cast<float>(2.0 * r);
  p.range = static_cast<float>(3.0 * r);
  p.toTexture = kBias * p.viewProj;
  p.axis = glm::vec3(-l);
  p.origin = glm::vec3(center + 2.0 * r * l);
  return p;
}

LightProjection pointLightProjection(const glm::dvec3& position, const glm::dvec3& center,
                                     double radius) {
  const double r = radius * 1.02;
  const double d = glm::length(center - position);
  if (!(d > r))
    throw gpu::GlError(fmt::format("point light at distance {:.4g} from the mesh's centre, inside "
                                   "its bounding sphere (radius {:.4g}): the point-cloud technique's "
                                   "shadow map needs the light outside", d, r));
  const double halfAngle = std::asin(r / d);
  const glm::dvec3 f = (center - position) / d;
  const glm::dmat4 view = glm::lookAt(position, center, upFor(f));
  const double near = std::max(d - r, 1e-4 * r), far = d + r;
  const glm::dmat4 proj = glm::perspective(2.0 * halfAngle, 1.0, near, far);
  LightProjection p;
  p.viewProj = glm::mat4(proj * view);
  p.perspective = true;
  p.extent = static_cast<float>(2.0 * std::tan(halfAngle));
  p.range = static_cast<float>(far - near);
  p.toTexture = kBias * p.viewProj;
  p.axis = glm::vec3(f);
  p.origin = glm::vec3(position);
  return p;
}

void ShadowMap::renderDirectional(const GpuMesh& mesh, const gpu::ShaderProgram& program,
                                  const glm::dvec3& towardsLight, const glm::dvec3& center,
                                  double radius) {
  const LightProjection p = directionalLightProjection(towardsLight, center, radius);
  perspective_ = false;
  texel_ = p.extent / static_cast<float>(size_);
  range_ = p.range;
  matrix_ = p.toTexture;
  render(mesh, program, p.viewProj);
}

void ShadowMap::renderPoint(const GpuMesh& mesh, const gpu::ShaderProgram& program,
                            const glm::dvec3& position, const glm::dvec3& center, double radius) {
  const LightProjection p = pointLightProjection(position, center, radius);
  perspective_ = true;
  texel_ = p.extent / static_cast<float>(size_);
  range_ = p.range;
  matrix_ = p.toTexture;
  render(mesh, program, p.viewProj);
}

void ShadowMap::render(const GpuMesh& mesh, const gpu::ShaderProgram& program,
                       const glm::mat4& viewProj) {
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_.id());
  glViewport(0, 0, size_, size_);
  const float one = 1.0f;
  glClearNamedFramebufferfv(fbo_.id(), GL_DEPTH, 0, &one);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glEnable(GL_CULL_FACE);
  glCullFace(GL_FRONT);
  glEnable(GL_POLYGON_OFFSET_FILL);
  glPolygonOffset(1.5f, 2.0f);
  program.use();
  program.set("ViewProjection", viewProj);
  mesh.draw();
  glDisable(GL_POLYGON_OFFSET_FILL);
  glDisable(GL_CULL_FACE);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  gpu::checkGlError("rendering a shadow map");
}

BoundingSphereOf boundingSphere(const geometry::TriangleMesh& mesh) {
  BoundingSphereOf b;
  b.center = mesh.bounds().center();
  for (const auto& p : mesh.positions) b.radius = std::max(b.radius, glm::length(p - b.center));
  return b;
}

PlaceholderTextures PlaceholderTextures::create() {
  PlaceholderTextures t;
  t.shadow = gpu::Texture::create(GL_TEXTURE_2D);
  glTextureStorage2D(t.shadow.id(), 1, GL_DEPTH_COMPONENT32F, 1, 1);
  glTextureParameteri(t.shadow.id(), GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
  t.filter = gpu::Texture::create(GL_TEXTURE_2D);
  glTextureStorage2D(t.filter.id(), 1, GL_RGBA32F, 1, 1);
  const float white[4] = {1.0f, 1.0f, 1.0f, 1.0f};
  glTextureSubImage2D(t.filter.id(), 0, 0, 0, 1, 1, GL_RGBA, GL_FLOAT, white);
  gpu::checkGlError("creating the placeholder textures");
  return t;
}

CameraMatrices cameraMatrices(const reference::Camera& camera, double near, double far,
                              const glm::dvec3& center, double radius, int width, int height) {
  CameraMatrices m;
  m.view = glm::lookAt(camera.position, camera.look_at, camera.up);
  const glm::dvec3 forward = glm::normalize(camera.look_at - camera.position);
  const double depth = glm::dot(center - camera.position, forward);
  const bool ortho = camera.projection == reference::Camera::Projection::Orthographic;
  if (near <= 0.0) near = ortho ? depth - 1.1 * radius : std::max(depth - 1.1 * radius, 1e-3 * radius);
  if (far <= 0.0) far = depth + 1.1 * radius;
  if (!(far > near)) far = near + 2.2 * radius;
  const double aspect = double(width) / double(height);
  if (ortho) {
    const double h = 0.5 * camera.view_height, w = h * aspect;
    m.projection = glm::ortho(-w, w, -h, h, near, far);
  } else {
    m.projection = glm::perspective(camera.fov * std::numbers::pi / 180.0, aspect, near, far);
  }
  return m;
}

void GBuffer::resize(int width, int height) {
  if (width == width_ && height == height_ && fbo_) return;
  width_ = width;
  height_ = height;
  auto target = [&](GLenum format) {
    gpu::Texture t = gpu::Texture::create(GL_TEXTURE_2D);
    gpu::allocateTexture2D(t, 1, format, width, height, "G-buffer");
    glTextureParameteri(t.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(t.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    return t;
  };
  position_ = target(GL_RGBA32F);
  // Half floats for the unit normal (relative error ~5e-4, used only in Ft(η, n·ω_o) and the
  // .bssrdf kernels): on the H100 the 1280×720 g-buffer pass takes 0.81 ms instead of 0.97 with
  // RGBA32F (BENCHMARKS.md of commit 91fe617). Positions stay 32-bit: they set the distances of the kernel.
  normal_ = target(GL_RGBA16F);
  depth_ = target(GL_DEPTH_COMPONENT24);  // visibility only; positions come from the colour target
  fbo_ = gpu::Framebuffer::create();
  glNamedFramebufferTexture(fbo_.id(), GL_COLOR_ATTACHMENT0, position_.id(), 0);
  glNamedFramebufferTexture(fbo_.id(), GL_COLOR_ATTACHMENT1, normal_.id(), 0);
  glNamedFramebufferTexture(fbo_.id(), GL_DEPTH_ATTACHMENT, depth_.id(), 0);
  const GLenum buffers[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
  glNamedFramebufferDrawBuffers(fbo_.id(), 2, buffers);
  if (glCheckNamedFramebufferStatus(fbo_.id(), GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw gpu::GlError(fmt::format("G-buffer of {}x{}: the framebuffer is incomplete", width, height));
  gpu::checkGlError("creating the G-buffer");
}

void GBuffer::render(const GpuMesh& mesh, const gpu::ShaderProgram& program,
                     const glm::mat4& viewProj) {
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_.id());
  glViewport(0, 0, width_, height_);
  const float zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
  const float one = 1.0f;
  glClearNamedFramebufferfv(fbo_.id(), GL_COLOR, 0, zero);
  glClearNamedFramebufferfv(fbo_.id(), GL_COLOR, 1, zero);
  glClearNamedFramebufferfv(fbo_.id(), GL_DEPTH, 0, &one);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDisable(GL_CULL_FACE);
  program.use();
  program.set("ViewProjection", viewProj);
  mesh.draw();
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  gpu::checkGlError("rendering the G-buffer");
}

void setShadowUniforms(const gpu::ShaderProgram& p, const ShadowMap* map,
                       const ShadowLookup& lookup, const gpu::Texture& dummy) {
  const int samples = lookup.samples;
  p.set("Shadowed", map != nullptr);
  p.set("ShadowMap", 0);
  p.set("FilterTexture", 1);
  glBindTextureUnit(0, map ? map->texture().id() : dummy.id());
  if (map == nullptr) return;
  const GLint filter = lookup.hardware_pcf ? GL_LINEAR : GL_NEAREST;
  glTextureParameteri(map->texture().id(), GL_TEXTURE_MIN_FILTER, filter);
  glTextureParameteri(map->texture().id(), GL_TEXTURE_MAG_FILTER, filter);
  const float texel = map->texelSize();
  p.set("ShadowMatrix", map->matrix());
  p.set("ShadowPerspective", map->perspective());
  p.set("ShadowTexel", texel);
  p.set("NormalOffset", lookup.offset);
  p.set("DepthBias", map->perspective() ? 0.0f : lookup.bias * texel / map->depthRange());
  p.set("ShadowSamples", samples);
  p.set("ShadowRadius", samples > 1 ? lookup.radius : 0.0f);
  // A Vogel (golden-angle) spiral of `samples` points filling the unit disc.
  std::vector<glm::vec2> jitter(static_cast<size_t>(samples));
  for (int i = 0; i < samples; ++i) {
    const double r = std::sqrt((i + 0.5) / samples), a = i * 2.39996322972865332;
    jitter[size_t(i)] = glm::vec2(float(r * std::cos(a)), float(r * std::sin(a)));
  }
  if (samples == 1) jitter[0] = glm::vec2(0.0f);
  glProgramUniform2fv(p.id(), p.uniformLocation("ShadowJitter"), samples, glm::value_ptr(jitter[0]));
}

bool ClosedMeshState::loadClosedMesh(const scene::Scene& s, bool gpuDeform) {
  const std::string key = gpuDeform ? scene::restMeshKey(s) : scene::meshKey(s);
  const std::string state = gpuDeform ? geometry::deformStateKey(s.mesh_deform, s.time) : "";
  if (key == meshKey && gpuMesh && state == deformState) return false;
  bool loaded = false;
  if (key != meshKey || !gpuMesh) {
    geometry::TriangleMesh m = gpuDeform ? scene::loadRestMesh(s, nullptr, nullptr, &filePoints)
                                         : scene::loadSceneMesh(s, nullptr, nullptr, &filePoints);
    openEdges = allowOpen ? m.openEdgeCount() : 0;
    if (!allowOpen)
      m.requireClosed(fmt::format("mesh file '{}' (the pointcloud technique renders open meshes)",
                                  s.mesh_file.string()));
    // An open surface has no inside whose signed volume could say which way is out: its winding
    // (and its normals) are used as the file gives them.
    if (openEdges == 0) m.orientOutwards();
    mesh = std::move(m);
    gpuMesh.emplace(mesh);
    meshKey = key;
    deformState.clear();
    loaded = true;
  }
  if (gpuDeform) {
    if (rest.positions.empty() || loaded) rest = mesh;
    gpuMesh->deform(s.mesh_deform, s.time);
    // The CPU copy for the bounding sphere (what the maps and clip distances cover) and for
    // anything else read from `mesh`.
    mesh = rest;
    geometry::deformMesh(s.mesh_deform, s.time, mesh);
    deformState = state;
  }
  const BoundingSphereOf bs = boundingSphere(mesh);
  center = bs.center;
  radius = bs.radius;
  return loaded;
}

void requireHomogeneousMaterial(const scene::Scene& scene, const char* technique) {
  if (scene.material.homogeneous()) return;
  throw ParameterError(fmt::format(
      "material.type '{}': the {} technique renders homogeneous materials only: expected "
      "\"type\": \"homogeneous\", or the pointcloud technique (per-point profiles, Eq. 8) or "
      "the empirical one (a per-vertex colour) for a spatially varying material",
      scene.material.type(), technique));
}

FrameSize frameSize(const FrameRequest& request, const reference::Camera& camera) {
  const FrameSize f{request.width > 0 ? request.width : camera.width,
                    request.height > 0 ? request.height : camera.height};
  if (f.width < 1 || f.height < 1 || f.width > 16384 || f.height > 16384)
    throw ParameterError(fmt::format("image size {}x{}: expected width and height in [1, 16384]",
                                     f.width, f.height));
  return f;
}

void addPasses(Frame& frame, gpu::PassTimer& timer) {
  for (const auto& pass : timer.collect()) frame.passes.push_back({pass.name, pass.ms, pass.depth});
}

void readRadianceAndExitance(Frame& frame, const gpu::Buffer& radiance, const gpu::Buffer& exitance,
                             size_t pixels) {
  const auto rad = gpu::download<glm::vec4>(radiance, pixels);
  const auto ex = gpu::download<glm::vec4>(exitance, pixels);
  frame.rgb.resize(pixels * 3);
  std::vector<float>& out = frame.layers["exitance"];
  out.resize(pixels * 3);
  for (size_t i = 0; i < pixels; ++i)
    for (int c = 0; c < 3; ++c) {
      frame.rgb[i * 3 + size_t(c)] = rad[i][c];
      out[i * 3 + size_t(c)] = ex[i][c];
    }
}

void uploadMeshStorage(const geometry::TriangleMesh& mesh, gpu::Buffer& vertices,
                       gpu::Buffer& triangles) {
  std::vector<glm::vec4> verts(mesh.vertexCount());
  for (size_t i = 0; i < verts.size(); ++i) verts[i] = glm::vec4(glm::vec3(mesh.positions[i]), 1.0f);
  std::vector<glm::uvec4> tris(mesh.triangleCount());
  for (size_t i = 0; i < tris.size(); ++i) tris[i] = glm::uvec4(mesh.triangles[i], 0u);
  vertices = gpu::makeStorageBuffer(std::span<const glm::vec4>(verts));
  triangles = gpu::makeStorageBuffer(std::span<const glm::uvec4>(tris));
}

void setExitRadianceUniforms(const gpu::ShaderProgram& p, const GBuffer& gbuffer,
                             const scene::Scene& s, const ParameterSet& params, int width,
                             int height) {
  glBindTextureUnit(0, gbuffer.position().id());
  glBindTextureUnit(1, gbuffer.normal().id());
  glProgramUniform2ui(p.id(), p.uniformLocation("Size"), unsigned(width), unsigned(height));
  p.set("Eta", static_cast<float>(s.medium.eta));
  p.set("ExitScale", glm::vec3(static_cast<float>(bssrdf::exitConventionScale(
                         bssrdf::parseExitConvention(params.getEnum("radiance_convention")),
                         s.medium.eta))));
  p.set("CameraPosition", glm::vec3(s.camera.position));
  p.set("CameraForward", glm::vec3(glm::normalize(s.camera.look_at - s.camera.position)));
  p.set("Orthographic", s.camera.projection == reference::Camera::Projection::Orthographic);
}

}  // namespace translucent::techniques
