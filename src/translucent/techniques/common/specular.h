// SPDX-License-Identifier: GPL-3.0-or-later
// An optional specular reflection that every technique rendering over a camera G-buffer adds to
// its radiance (techniques/common; shaders/common/specular.comp): the GGX microfacet BRDF (Walter
// et al. 2007) of the scene's directional and textured-directional lights, unshadowed, with the
// exact Fresnel reflectance at the object's η. The texture-space paper (Chang 2007) adds a Phong
// highlight after its tone mapping, the splatting paper has none; this is the same highlight for
// all, so that images of different techniques differ only in their subsurface term.
// Needs a current OpenGL 4.5 context.
#pragma once

#include <optional>
#include <vector>

#include <glm/vec3.hpp>

#include "translucent/gpu/objects.h"
#include "translucent/gpu/pass_timer.h"
#include "translucent/gpu/program.h"
#include "translucent/scene/scene.h"
#include "translucent/techniques/common/gl_resources.h"
#include "translucent/techniques/technique.h"

namespace translucent::techniques {

// The parameters: specular (off by default), roughness (GGX α).
std::vector<ParameterInfo> specularParameters();

// The lights the highlight reflects (directional and textured directional, at most 8; the
// texture is not applied): unit directions towards them and irradiance × colour.
struct SpecularLights {
  std::vector<glm::vec3> directions, values;
};
SpecularLights specularLights(const scene::Scene& scene);

// Closed form of the shader's L_s for one light (tests and the CPU side): unit normal n, view
// direction v (towards the camera) and light direction l, irradiance E.
double specularRadiance(const glm::dvec3& n, const glm::dvec3& v, const glm::dvec3& l, double E,
                        double roughness, double eta);

class SpecularPass {
 public:
  // With the technique's specular parameter on: adds L_s to `radiance` (one vec4 per pixel,
  // rows from the top) at every pixel the G-buffer covers, timed as "specular" in `timer`.
  // Nothing otherwise.
  void add(const GBuffer& gbuffer, const scene::Scene& scene, const ParameterSet& params,
           const gpu::Buffer& radiance, gpu::PassTimer* timer);

 private:
  std::optional<gpu::ShaderProgram> program_;
};

}  // namespace translucent::techniques
