// SPDX-License-Identifier: GPL-3.0-or-later
// Shadow maps of a technique's lights, shared by the techniques that light a point set through
// shaders/pointcloud/irradiance.comp (pointcloud, tsis): which map each light type renders, and
// the lookup settings from the techniques' shadow_* parameters.
#pragma once

#include <glm/vec3.hpp>

#include "translucent/gpu/program.h"
#include "translucent/scene/scene.h"
#include "translucent/techniques/common/gl_resources.h"
#include "translucent/techniques/technique.h"

namespace translucent::techniques {

// The lookup from the parameters shadow_samples, shadow_offset, shadow_bias and shadow_radius.
ShadowLookup shadowLookup(const ParameterSet& params);

// Renders `map` for `light`: orthographic along a directional, filtered directional or beam
// light, perspective from a point light, covering the sphere (center, radius). Environment
// lights have no single map (nothing is rendered).
void renderLightShadow(ShadowMap& map, const scene::Light& light, const GpuMesh& mesh,
                       const gpu::ShaderProgram& depthProgram, const glm::dvec3& center,
                       double radius);

}  // namespace translucent::techniques
