// SPDX-License-Identifier: GPL-3.0-or-later
// Single scattering S⁽¹⁾ of a closed, homogeneous mesh per pixel of a G-buffer (techniques/common):
// the light that scattered exactly once inside the body, towards the camera and, optionally,
// over the exit hemisphere. The explorer paper's "single scattering" term (the path tracer's
// ScatteringOrder::Single, reference/slab.h), evaluated as Jensen, Marschner, Levoy & Hanrahan
// 2001 (Eq. 4) do, along the refracted view ray, but with the mesh's own geometry: the view ray
// and the lights' rays are traced through the mesh (a BVH on the GPU, shaders/reference/bvh.glsl),
// so thin parts, concavities and the body's own shadow are those of the mesh, not of a
// half-space. At η = 1 the integrand is exact (straight lines through every part of the body);
// at η ≠ 1 the light's refraction at its entry point uses Jensen et al.'s refracted-length
// approximation. shaders/common/single_scattering.comp states the estimator.
//
// Lights: directional, point, beam (radius > 0). Refused, with a ParameterError naming lights[i]:
// environment lights and textured (filtered) directional lights. Materials: homogeneous only.
// Needs a current OpenGL 4.5 context.
#pragma once

#include <optional>
#include <string_view>
#include <vector>

#include "translucent/geometry/mesh.h"
#include "translucent/gpu/bvh_buffers.h"
#include "translucent/gpu/objects.h"
#include "translucent/gpu/program.h"
#include "translucent/scene/scene.h"
#include "translucent/techniques/common/gl_resources.h"
#include "translucent/techniques/technique.h"

namespace translucent::techniques {

struct SingleScatteringOptions {
  int samples = 4;     // distances per channel along each line (3 × samples in all)
  int directions = 0;  // exit directions for the exitance (0: radiance only)
};

// The parameters a technique offering the term takes: single_samples, single_directions.
std::vector<ParameterInfo> singleScatteringParameters();
SingleScatteringOptions singleScatteringOptions(const ParameterSet& params);

// Why single scattering cannot render the scene's lights ("" when it can).
std::string singleScatteringRefusal(const scene::Scene& scene);

class SingleScattering {
 public:
  // Builds the mesh's BVH (when the mesh changed) and uploads the scene's lights. Throws
  // ParameterError (lights, material) naming `technique`.
  void prepare(const geometry::TriangleMesh& mesh, const std::string& meshKey,
               const scene::Scene& scene, std::string_view technique);

  // Adds L⁽¹⁾ to `radiance` and, with options.directions > 0, B⁽¹⁾ to `exitance` (one vec4 per
  // pixel, rows from the top; the caller zeroes them or fills them with the other orders) for
  // every pixel of the G-buffer (position w = 1 + triangle). meshVertices/meshTriangles: the
  // mesh as uploadMeshStorage() writes it. Timed as "single scattering" in `timer` when given.
  // Throws gpu::GlError when a pixel's work exceeded the driver's loop limit (llvmpipe).
  void render(const GBuffer& gbuffer, const gpu::Buffer& meshVertices,
              const gpu::Buffer& meshTriangles, const scene::Scene& scene,
              const SingleScatteringOptions& options, const gpu::Buffer& radiance,
              const gpu::Buffer& exitance, gpu::PassTimer* timer);

 private:
  std::optional<gpu::ShaderProgram> segments_, sample_, finish_;
  std::string meshKey_;
  gpu::BvhBuffers bvh_;
  gpu::Buffer lights_, status_, segmentBuffer_, sums_;
  size_t lightCount_ = 0, pixels_ = 0;
  float epsilon_ = 1e-4f;
};

}  // namespace translucent::techniques
