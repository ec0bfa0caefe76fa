// SPDX-License-Identifier: GPL-3.0-or-later
// The irradiance pass that the techniques lighting a set of surface points share (pointcloud:
// the point cloud's samples; tsis: the atlas texels; lss: the camera's visible pixels): the
// irradiance transmitted into the medium at each point,
//     E_i = ∫ L(ω) Ft(η, n_i·ω) max(n_i·ω, 0) V(p_i, ω) dω,
// for every light type a scene can hold (shaders/pointcloud/irradiance.comp, one dispatch per
// light), with the same conventions in every technique:
//   directional, filtered directional, beam   shadow map along the light (orthographic)
//   point (outside the bounding sphere)       perspective shadow map
//   environment, occlusion false              SH9 irradiance (lights/environment_map.h), unshadowed
//   environment, occlusion true               shadow-mapped directions drawn from the map's
//                                             importance sampler, accumulated over frames
// The points are PcPoint records (shaders/pointcloud/common.glsl: position + area, normal + w)
// in a buffer the technique owns; the irradiance (one vec4 per point, RGB) is this class's.
// Needs a current OpenGL 4.5 context.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

#include "translucent/gpu/objects.h"
#include "translucent/gpu/pass_timer.h"
#include "translucent/gpu/program.h"
#include "translucent/scene/scene.h"
#include "translucent/techniques/common/gl_resources.h"
#include "translucent/techniques/technique.h"

namespace translucent::techniques {

// u, v axes perpendicular to a light direction l (scene::FilteredDirectionalLight's texture).
void filterAxes(const glm::dvec3& l, glm::dvec3& u, glm::dvec3& v);

// The parameters of the lighting every technique using this pass takes, with the same names,
// defaults and ranges: shadow_map_size, shadow_offset, shadow_bias, shadow_samples,
// shadow_radius (shadowLookup()), ibl_samples, ibl_samples_per_frame (environmentBudget()).
std::vector<ParameterInfo> lightingParameters();

// How many shadow-mapped directions an occluded environment light gets: `total` in all, at most
// `perFrame` more per update unless `converge` (then all that remain).
struct EnvironmentBudget {
  uint64_t total = 256;
  uint64_t perFrame = 16;
  bool converge = false;
};
// The budget from a technique's ibl_samples and ibl_samples_per_frame parameters.
EnvironmentBudget environmentBudget(const ParameterSet& params, bool converge);

class SurfaceIrradiance {
 public:
  SurfaceIrradiance();
  ~SurfaceIrradiance();
  SurfaceIrradiance(const SurfaceIrradiance&) = delete;
  SurfaceIrradiance& operator=(const SurfaceIrradiance&) = delete;

  // Checks and loads the scene's lights: environment maps (SH9 or the sampler), filter textures,
  // one shadow map of shadowMapSize² per light. Refuses, with a ParameterError naming lights[i]
  // and `technique`: a beam of radius 0, a point light inside the sphere (center, radius) the
  // shadow maps cover, a second environment light. Restarts the environment accumulation.
  void prepareLights(const scene::Scene& scene, const glm::dvec3& center, double radius,
                     int shadowMapSize, std::string_view technique);

  // True if a light is an occluded environment (its irradiance converges over frames).
  bool hasOccludedEnvironment() const;
  // Shadow-mapped directions of the occluded environment accumulated so far.
  uint64_t environmentDirections() const { return envDirections_; }
  // Forget the accumulated environment directions (the shadow settings changed).
  void restartEnvironment() { envDirections_ = 0; }

  // E of the `count` points of `points` into irradiance(): shadow maps ("shadow maps"), every
  // light ("irradiance"), and the budget's next directions of an occluded environment light
  // ("environment samples"), each timed in `timer` when not null. A change of `count` (a new
  // point set) restarts the environment accumulation. Binds SSBOs 2, 3, 4, 14 (irradiance.comp's).
  // Returns true when E is final (no occluded environment, or all its directions are in).
  // With `reuse`, the caller vouches that the mesh, the points and the shadow settings are those
  // of the previous update (a camera move): the shadow maps are not rendered again, and without
  // an occluded environment the irradiance is kept as it is (nothing is dispatched); lights
  // prepared since, or another point count, still recompute everything. With `reuse` and
  // `pointsMoved` (lss: its points are the camera's pixels, which a camera move or a new image
  // size moves; the mesh, lights and shadow settings are the previous update's) only the shadow
  // maps are kept, whatever the count: E is computed at the new points, and an occluded
  // environment starts again (its accumulation is per point).
  bool update(const GpuMesh& mesh, const gpu::Buffer& points, size_t count, float eta,
              const ShadowLookup& lookup, const EnvironmentBudget& budget, gpu::PassTimer* timer,
              bool reuse = false, bool pointsMoved = false);

  const gpu::Buffer& irradiance() const { return irradiance_; }
  // Per point (vec4): xyz = Σ_l w_l ω_l, w = Σ_l w_l over the directional, filtered, beam and point
  // lights, ω_l the unit direction towards light l and w_l the mean of its RGB transmitted
  // irradiance at the point (after shadowing): the direction of the light that lit the point,
  // for directional BSSRDFs (pointcloud). Environment light adds nothing (w = 0 where only it
  // lit the point). SSBO 14 of irradiance.comp.
  const gpu::Buffer& lightDirections() const { return lightDirections_; }
  const std::vector<scene::Light>& lights() const { return lightList_; }

 private:
  struct LightState;
  void ensurePrograms();
  void dispatch(int mode) const;
  void lightDispatch(const LightState& st, const ShadowLookup& lookup) const;
  void environmentSamples(const LightState& st, const GpuMesh& mesh, const ShadowLookup& lookup,
                          uint64_t count);

  std::vector<LightState> lights_;
  std::vector<scene::Light> lightList_;
  glm::dvec3 center_{0.0};
  double radius_ = 1.0;
  int shadowSize_ = 2048;
  std::unique_ptr<ShadowMap> envShadow_;
  uint64_t envDirections_ = 0;

  std::unique_ptr<gpu::ShaderProgram> depthProgram_, irradianceProgram_;
  gpu::Texture dummyShadow_, dummyFilter_;
  gpu::Buffer irradiance_, envAccum_, lightDirections_;
  bool fresh_ = false;  // shadow maps and direct irradiance of the current lights are computed
  size_t count_ = 0;
};

}  // namespace translucent::techniques
