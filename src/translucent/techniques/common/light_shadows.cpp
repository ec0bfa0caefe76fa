// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/techniques/common/light_shadows.h"

#include <variant>

namespace translucent::techniques {

ShadowLookup shadowLookup(const ParameterSet& params) {
  ShadowLookup lookup;
  lookup.samples = params.getInt("shadow_samples");
  lookup.offset = static_cast<float>(params.getFloat("shadow_offset"));
  lookup.bias = static_cast<float>(params.getFloat("shadow_bias"));
  lookup.radius = static_cast<float>(params.getFloat("shadow_radius"));
  lookup.hardware_pcf = params.getBool("shadow_hardware_pcf");
  return lookup;
}

void renderLightShadow(ShadowMap& map, const scene::Light& light, const GpuMesh& mesh,
                       const gpu::ShaderProgram& depthProgram, const glm::dvec3& center,
                       double radius) {
  const auto& e = light.emitter;
  if (const auto* d = std::get_if<reference::DirectionalLight>(&e))
    map.renderDirectional(mesh, depthProgram, d->direction, center, radius);
  else if (const auto* f = std::get_if<scene::FilteredDirectionalLight>(&e))
    map.renderDirectional(mesh, depthProgram, f->direction, center, radius);
  else if (const auto* b = std::get_if<reference::BeamLight>(&e))
    map.renderDirectional(mesh, depthProgram, -b->direction, center, radius);
  else if (const auto* pl = std::get_if<reference::PointLight>(&e))
    map.renderPoint(mesh, depthProgram, pl->position, center, radius);
}

}  // namespace translucent::techniques
