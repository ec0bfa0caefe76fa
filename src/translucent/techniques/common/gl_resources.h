// SPDX-License-Identifier: GPL-3.0-or-later
// GL pieces that the real-time techniques share (techniques/common): the mesh on the GPU, the
// scene camera's matrices, depth maps rendered from a light (shadow maps), and the camera's
// G-buffer.
// All need a current OpenGL 4.5 core context (gpu/context.h).
#pragma once

#include <memory>
#include <optional>
#include <string>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "translucent/geometry/deform.h"
#include "translucent/geometry/mesh.h"
#include "translucent/gpu/objects.h"
#include "translucent/gpu/pass_timer.h"
#include "translucent/gpu/program.h"
#include "translucent/reference/camera.h"
#include "translucent/scene/scene.h"
#include "translucent/techniques/technique.h"

namespace translucent::techniques {

// Smooth vertex normals of a mesh (area-weighted face normals summed at each vertex, normalised);
// the mesh's own normals when it has them.
std::vector<glm::dvec3> vertexNormals(const geometry::TriangleMesh& mesh);

// The mesh as interleaved float positions and normals with an index buffer, and optionally one
// more float per vertex (the empirical technique's ambient occlusion).
class GpuMesh {
 public:
  GpuMesh() = default;
  // Normals: vertexNormals(mesh).
  explicit GpuMesh(const geometry::TriangleMesh& mesh);
  // Given normals (one per vertex) and, when not empty, one scalar per vertex as attribute 2.
  GpuMesh(const geometry::TriangleMesh& mesh, const std::vector<glm::dvec3>& normals,
          const std::vector<float>& scalar = {});
  // Draws every triangle with the currently used program (attribute 0: position, 1: normal,
  // 2: the scalar).
  void draw() const;
  size_t triangleCount() const { return triangles_; }
  size_t vertexCount() const { return vertexCount_; }

  // The mesh as uploaded is the rest pose; this writes it deformed by `chain` at `time` into the
  // vertex buffer, on the GPU (shaders/common/deform.comp: positions, and the normals by the
  // Jacobian's inverse transpose, as geometry::deformMesh does on the CPU). The first call keeps
  // a copy of the rest pose on the GPU; a call with the same chain and time does nothing, and
  // an identity at `time` restores the rest pose. Every technique that draws through GpuMesh
  // (shadow and light-view maps, G-buffers, layers) then sees the deformed surface.
  void deform(const std::vector<geometry::Deformation>& chain, double time);
  // The interleaved vertex buffer (floats: position, normal[, scalar]; floatsPerVertex() each).
  const gpu::Buffer& vertexBuffer() const { return vertices_; }
  unsigned floatsPerVertex() const { return stride_; }

 private:
  gpu::VertexArray vao_;
  gpu::Buffer vertices_, indices_;
  gpu::Buffer rest_;  // the rest pose's vertex buffer (after the first deform())
  std::shared_ptr<gpu::ShaderProgram> deformProgram_;
  std::string deformState_;  // deformKey and time of the vertex buffer's contents ("": rest)
  size_t triangles_ = 0, vertexCount_ = 0;
  unsigned stride_ = 6;
};

// The view of a light that covers the sphere (center, radius), shared by the depth maps
// (ShadowMap) and the light-view irradiance maps (light_view_map.h): orthographic along a
// directional light, or perspective from a point light outside the sphere.
struct LightProjection {
  glm::mat4 viewProj{1.0f};  // world -> light clip space
  glm::mat4 toTexture{1.0f};  // world -> [0,1]³ texture coordinates and depth (after the divide)
  bool perspective = false;
  // World size of the map's side (orthographic), or its side on the plane at unit distance from
  // the light (perspective: 2 tan(half angle)).
  float extent = 0.0f;
  float range = 1.0f;          // depth range in world units (far - near)
  glm::vec3 axis{0.0f};        // unit, from the light towards the sphere's centre
  glm::vec3 origin{0.0f};      // the light's position (perspective)
};
// Orthographic view along -towardsLight covering the sphere (1.02 radii).
LightProjection directionalLightProjection(const glm::dvec3& towardsLight, const glm::dvec3& center,
                                           double radius);
// Perspective view from `position` enclosing the sphere; throws gpu::GlError when the light
// lies inside it.
LightProjection pointLightProjection(const glm::dvec3& position, const glm::dvec3& center,
                                     double radius);

// A square depth map rendered from a light, sampled with hardware PCF (sampler2DShadow:
// GL_COMPARE_REF_TO_TEXTURE, GL_LEQUAL, bilinear). Back faces only are drawn (the mesh is
// closed and outward-oriented), plus a slope-scaled polygon offset, so lit surfaces never
// compare against themselves.
class ShadowMap {
 public:
  explicit ShadowMap(int size);
  int size() const { return size_; }

  // Orthographic view along -towardsLight covering the sphere (center, radius).
  void renderDirectional(const GpuMesh& mesh, const gpu::ShaderProgram& depthProgram,
                         const glm::dvec3& towardsLight, const glm::dvec3& center, double radius);
  // Perspective view from `position` (outside the sphere) enclosing the sphere.
  void renderPoint(const GpuMesh& mesh, const gpu::ShaderProgram& depthProgram,
                   const glm::dvec3& position, const glm::dvec3& center, double radius);

  const gpu::Texture& texture() const { return depth_; }
  // World -> [0,1]³ texture coordinates and depth (after the perspective divide).
  const glm::mat4& matrix() const { return matrix_; }
  bool perspective() const { return perspective_; }
  // World size of a texel (orthographic), or per unit distance from the light (perspective).
  float texelSize() const { return texel_; }
  // Depth range in world units (orthographic; converts a world offset to depth units).
  float depthRange() const { return range_; }

 private:
  void render(const GpuMesh& mesh, const gpu::ShaderProgram& program, const glm::mat4& viewProj);
  int size_ = 0;
  gpu::Texture depth_;
  gpu::Framebuffer fbo_;
  glm::mat4 matrix_{1.0f};
  bool perspective_ = false;
  float texel_ = 0.0f, range_ = 1.0f;
};

// How shaders/pointcloud/irradiance.comp's visibility() looks a shadow map up (the point-cloud
// technique's shadow_* parameters, in texels): jittered hardware-PCF lookups on a Vogel spiral.
struct ShadowLookup {
  int samples = 8;        // 1..64
  float offset = 1.0f;    // along the normal [texels]
  float bias = 1.0f;      // depth offset of orthographic maps [texels]
  float radius = 1.5f;    // of the jitter [texels]
  // The map's own bilinear comparison (hardware PCF: each lookup averages the 2x2 texels'
  // tests); off, one texel's test per lookup. With `samples` 1 or more, the four shadow variants
  // of seed Fig. 3.3 (none, hardware, jittered, both).
  bool hardware_pcf = true;
};
// Sets the shadow uniforms of irradiance.comp (Shadowed, ShadowMap on unit 0, FilterTexture on
// unit 1, ShadowMatrix, ...) for `map`, or Shadowed = false (and `dummy`, a 1x1 depth texture
// with comparison, on unit 0) when map is null.
void setShadowUniforms(const gpu::ShaderProgram& program, const ShadowMap* map,
                       const ShadowLookup& lookup, const gpu::Texture& dummy);

// The smallest sphere about the bounding box's centre that holds every vertex (what the shadow
// maps and the camera's automatic clip distances cover).
struct BoundingSphereOf {
  glm::dvec3 center{0.0};
  double radius = 0.0;
};
BoundingSphereOf boundingSphere(const geometry::TriangleMesh& mesh);

// 1x1 textures bound where a sampler has nothing to read (no shadow map, no filter texture), so
// that every sampler refers to a complete texture of its type: a depth texture with comparison
// (sampler2DShadow) and a white RGBA32F texture.
struct PlaceholderTextures {
  gpu::Texture shadow, filter;
  static PlaceholderTextures create();
};

// Camera matrices of a reference::Camera (pinhole: vertical fov; orthographic: view_height),
// with near/far clip distances (0: from the bounding sphere (center, radius): 1.1 radii in
// front of and behind its centre).
struct CameraMatrices {
  glm::dmat4 view{1.0}, projection{1.0};
  glm::mat4 viewProjection() const { return glm::mat4(projection * view); }
};
CameraMatrices cameraMatrices(const reference::Camera& camera, double near, double far,
                              const glm::dvec3& center, double radius, int width, int height);
inline glm::mat4 cameraViewProjection(const reference::Camera& camera, double near, double far,
                                      const glm::dvec3& center, double radius, int width,
                                      int height) {
  return cameraMatrices(camera, near, far, center, radius, width, height).viewProjection();
}

// World position (w = 1 where covered) and shading normal per pixel, RGBA32F, with a depth buffer.
class GBuffer {
 public:
  void resize(int width, int height);
  void render(const GpuMesh& mesh, const gpu::ShaderProgram& program, const glm::mat4& viewProj);
  int width() const { return width_; }
  int height() const { return height_; }
  const gpu::Texture& position() const { return position_; }
  const gpu::Texture& normal() const { return normal_; }

 private:
  int width_ = 0, height_ = 0;
  gpu::Texture position_, normal_, depth_;
  gpu::Framebuffer fbo_;
};

// What the techniques that draw shadow or light-view maps keep of the scene's mesh (their Impl
// derives from it): closed (the maps draw one side of the surface only, gl_resources.h and
// light_view_map.h), oriented outwards, its bounding sphere (the maps and the camera's automatic
// clip distances cover it) and its copy on the GPU.
//
// Deformed meshes (scene mesh.deform at scene.time): with gpuDeform, the rest mesh is loaded and
// uploaded once (scene::restMeshKey) and every change of the time deforms it on the GPU
// (GpuMesh::deform); `mesh` is then the CPU-deformed copy, for the bounding sphere. Without it
// (techniques that keep CPU-side geometry derived from the mesh: point clouds, atlases), a new
// time is a new mesh (scene::meshKey) and the technique prepares again from the CPU-deformed
// mesh.
struct ClosedMeshState {
  std::string meshKey;  // scene::meshKey (restMeshKey with gpuDeform) of the loaded mesh
  std::string deformState;  // gpuDeform: the deformation and time of gpuMesh
  geometry::TriangleMesh mesh;
  geometry::TriangleMesh rest;  // gpuDeform: the rest pose (oriented outwards)
  std::optional<GpuMesh> gpuMesh;
  glm::dvec3 center{0.0};
  double radius = 1.0;
  // Techniques that need no interior (the point cloud: seed 3.6, a surface integral) accept open
  // meshes; openEdges is then their count (0: closed).
  bool allowOpen = false;
  size_t openEdges = 0;
  // When the scene's mesh file is a point cloud: its points, placed (scene::ScenePoints; the
  // mesh is then the surface reconstructed through them).
  std::optional<scene::ScenePoints> filePoints;
  // Loads the scene's mesh unless it is the one loaded (same key); true when it did (a GPU
  // deformation to a new time alone returns false). Throws geometry::MeshError naming the file
  // for an open mesh unless allowOpen.
  bool loadClosedMesh(const scene::Scene& s, bool gpuDeform = false);
};

// The image size a request asks for (the scene camera's where the request says 0); ParameterError
// outside [1, 16384] in either direction.
struct FrameSize {
  int width = 0, height = 0;
};
FrameSize frameSize(const FrameRequest& request, const reference::Camera& camera);

// For techniques that render homogeneous media only (tsis, tsm, lss): a spatially varying
// material would otherwise render as its representative medium without a word (a silently
// wrong image). Throws ParameterError naming the technique and the material's type, and the
// techniques that do render it.
void requireHomogeneousMaterial(const scene::Scene& scene, const char* technique);

// The mesh as shaders read it from storage buffers (pointcloud/hetero.glsl, bindings 12 and 13:
// vec4 positions with w = 1, uvec4 triangles with w = 0): the G-buffer's triangle index becomes a
// point's triangle and its vertices there.
void uploadMeshStorage(const geometry::TriangleMesh& mesh, gpu::Buffer& vertices,
                       gpu::Buffer& triangles);

// The uniforms every radiance pass over the G-buffer shares (pointcloud, tsis, tsm, splatting,
// transfer: L = s Ft(η, n·ω_o) B / π per pixel): the G-buffer's position and normal on texture
// units 0 and 1, Size (width, height), Eta, ExitScale (s of the technique's radiance_convention
// parameter, bssrdf/exit_radiance.h; one η per medium, so the same factor in every channel),
// CameraPosition, CameraForward and Orthographic of the scene's camera.
void setExitRadianceUniforms(const gpu::ShaderProgram& program, const GBuffer& gbuffer,
                             const scene::Scene& scene, const ParameterSet& params, int width,
                             int height);

// Every pass the timer ended since its last collect() into frame.passes (waits for the GPU).
void addPasses(Frame& frame, gpu::PassTimer& timer);

// The radiance and exitance outputs of a technique's last pass (one vec4 per pixel, rows from
// the top) into frame.rgb and frame.layers["exitance"].
void readRadianceAndExitance(Frame& frame, const gpu::Buffer& radiance, const gpu::Buffer& exitance,
                             size_t pixels);

}  // namespace translucent::techniques
