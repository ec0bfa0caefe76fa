// SPDX-License-Identifier: GPL-3.0-or-later
// A light-view irradiance map (techniques/common): the mesh rasterised from a light into float
// textures holding, per texel, the world position of the surface the light sees first, its
// geometric normal, and the irradiance it transmits into the medium. It is the "translucent shadow map" of
// Dachsbacher & Stamminger 2003 ("Translucent Shadow Maps", EGSR 2003), which stores depth,
// irradiance and normal per texel; storing the world position instead of the depth gives the true
// 3D distance |x_i − x_o| of a texel to any surface point directly.
//
// What a texel stands for: on the map's projection plane a texel covers the area
//     a_p = (extent / size)²                        (orthographic: extent in world units),
//     a_p = (extent / size)² d² cos³α               (perspective: extent on the plane at unit
//                                                     distance; d = |x − light|, α off the axis),
// the area perpendicular to the light's rays at the texel's surface point (d² dω, seed Eq. 3.7),
// and the surface area dA = a_p / cos θ_g, θ_g between the light and the triangle's geometric
// normal. The irradiance stored already contains its cos θ (E = E_l Ft(η, cos θ) cos θ, the
// convention of shaders/pointcloud/irradiance.comp), so E dA = E_l Ft a_p cos θ / cos θ_g: the
// power the texel's surface takes in, however oblique.
//
// Users: the tsm technique (src/techniques/tsm/), which filters a neighbourhood of each pixel's
// projection; the hybrid method of the tsis technique (seed 3.3.2, "Local Translucent Shadow Map")
// is meant to reuse it. Shaders: shaders/common/light_view_map.{vert,frag} render it and
// shaders/common/light_view_map.glsl reads it (lvmProject, lvmTexel, lvmSurfaceArea); bind()
// sets that include's uniforms.
//
// Only the surface nearest to the light is stored: what it lights is exactly what the map holds
// (shadowing is implicit), and what it does not see receives no light from it.
#pragma once

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "translucent/gpu/objects.h"
#include "translucent/gpu/program.h"
#include "translucent/techniques/common/gl_resources.h"

namespace translucent::techniques {

class LightViewMap {
 public:
  // A size × size map (textures allocated now).
  explicit LightViewMap(int size);
  int size() const { return size_; }

  // The program that renders the map (shaders/common/light_view_map.{vert,frag}).
  static gpu::ShaderProgram program();

  // Orthographic along a directional light (towardsLight: unit vector to the light) of
  // irradiance `irradiance` (E_l × colour, on a plane facing the light), covering the sphere.
  void renderDirectional(const GpuMesh& mesh, const gpu::ShaderProgram& program,
                         const glm::dvec3& towardsLight, const glm::vec3& irradiance, double eta,
                         const glm::dvec3& center, double radius);
  // Perspective from a point light at `position` (outside the sphere; throws gpu::GlError when
  // inside) of intensity `intensity` (I_l × colour): E = I_l Ft cos θ / d².
  void renderPoint(const GpuMesh& mesh, const gpu::ShaderProgram& program,
                   const glm::dvec3& position, const glm::vec3& intensity, double eta,
                   const glm::dvec3& center, double radius);

  // RGBA32F: xyz world position, w = 1 where a surface covers the texel (0 elsewhere).
  const gpu::Texture& position() const { return position_; }
  // RGBA32F: xyz the triangle's unit geometric normal n_g (towards the light: the plane the
  // texel's surface lies in), w = cos θ_g = n_g · (direction to the light).
  const gpu::Texture& normal() const { return normal_; }
  // RGBA32F: rgb transmitted irradiance E [W / scene unit²], w unused.
  const gpu::Texture& irradiance() const { return irradiance_; }

  const LightProjection& projection() const { return projection_; }
  // World -> [0,1]³ map coordinates and depth (after the perspective divide).
  const glm::mat4& matrix() const { return projection_.toTexture; }
  bool perspective() const { return projection_.perspective; }
  // World size of one texel's side: orthographic, everywhere; perspective, on the plane
  // perpendicular to the axis at depth `depth` from the light.
  double texelSize(double depth = 1.0) const;

  // Sets the uniforms of shaders/common/light_view_map.glsl on `p` (element `index` of its
  // LVM_MAPS maps) and binds the three textures to units firstUnit, firstUnit + 1, firstUnit + 2.
  void bind(const gpu::ShaderProgram& p, unsigned firstUnit, int index = 0) const;

 private:
  void render(const GpuMesh& mesh, const gpu::ShaderProgram& program, const glm::vec3& value,
              double eta);
  int size_ = 0;
  gpu::Texture position_, normal_, irradiance_, depth_;
  gpu::Framebuffer fbo_;
  LightProjection projection_;
};

}  // namespace translucent::techniques
