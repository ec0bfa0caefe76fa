// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/techniques/common/specular.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <variant>

#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "translucent/gpu/compute.h"
#include "translucent/gpu/gl.h"
#include "translucent/optics/fresnel.h"

namespace translucent::techniques {

std::vector<ParameterInfo> specularParameters() {
  return {
      ParameterInfo::boolean("specular", false,
                             "add a GGX specular reflection of the directional lights (unshadowed)"),
      ParameterInfo::floating("roughness", 0.3, 0.01, 1.0, "GGX roughness α of the specular term"),
  };
}

SpecularLights specularLights(const scene::Scene& s) {
  SpecularLights out;
  for (const scene::Light& light : s.lights) {
    if (out.directions.size() == 8) break;
    const glm::vec3 color(float(light.color[0]), float(light.color[1]), float(light.color[2]));
    if (const auto* d = std::get_if<reference::DirectionalLight>(&light.emitter)) {
      out.directions.emplace_back(glm::normalize(d->direction));
      out.values.push_back(color * float(d->irradiance));
    } else if (const auto* f = std::get_if<scene::FilteredDirectionalLight>(&light.emitter)) {
      out.directions.emplace_back(glm::normalize(f->direction));
      out.values.push_back(color * float(f->irradiance));
    }
  }
  return out;
}

double specularRadiance(const glm::dvec3& n, const glm::dvec3& v, const glm::dvec3& l, double E,
                        double roughness, double eta) {
  const double nl = glm::dot(n, l);
  if (nl <= 0.0) return 0.0;
  const double a2 = roughness * roughness, nv = std::max(glm::dot(n, v), 1e-4);
  const glm::dvec3 h = glm::normalize(l + v);
  const double nh = std::max(glm::dot(n, h), 0.0);
  const double t = nh * nh * (a2 - 1.0) + 1.0;
  const double D = a2 / (std::numbers::pi * t * t);
  const double gl = 2.0 * nl / (nl + std::sqrt(a2 + (1.0 - a2) * nl * nl));
  const double gv = 2.0 * nv / (nv + std::sqrt(a2 + (1.0 - a2) * nv * nv));
  const double F = fresnelReflectance(std::clamp(glm::dot(v, h), 0.0, 1.0), eta);
  return E * D * gl * gv * F / (4.0 * nl * nv) * nl;
}

void SpecularPass::add(const GBuffer& gbuffer, const scene::Scene& s, const ParameterSet& params,
                       const gpu::Buffer& radiance, gpu::PassTimer* timer) {
  if (!params.getBool("specular")) return;
  const SpecularLights lights = specularLights(s);
  if (lights.directions.empty()) return;
  std::optional<gpu::PassTimer::Scope> scope;
  if (timer) scope.emplace(timer->scope("specular"));
  if (!program_) program_.emplace(gpu::ShaderProgram::compute("common/specular.comp"));
  const gpu::ShaderProgram& p = *program_;
  glBindTextureUnit(0, gbuffer.position().id());
  glBindTextureUnit(1, gbuffer.normal().id());
  glProgramUniform2ui(p.id(), p.uniformLocation("Size"), unsigned(gbuffer.width()),
                      unsigned(gbuffer.height()));
  p.set("Eta", float(s.medium.eta));
  p.set("CameraPosition", glm::vec3(s.camera.position));
  p.set("CameraForward", glm::vec3(glm::normalize(s.camera.look_at - s.camera.position)));
  p.set("Orthographic", s.camera.projection == reference::Camera::Projection::Orthographic);
  const int count = int(lights.directions.size());
  p.set("Lights", count);
  glProgramUniform3fv(p.id(), p.uniformLocation("LightDirection"), count,
                      glm::value_ptr(lights.directions[0]));
  glProgramUniform3fv(p.id(), p.uniformLocation("LightValue"), count, glm::value_ptr(lights.values[0]));
  p.set("Roughness", float(params.getFloat("roughness")));
  gpu::bindStorage(7, radiance);
  gpu::dispatch(p, {(unsigned(gbuffer.width()) + 7u) / 8u, (unsigned(gbuffer.height()) + 7u) / 8u, 1u});
  gpu::checkGlError("the specular pass");
}

}  // namespace translucent::techniques
