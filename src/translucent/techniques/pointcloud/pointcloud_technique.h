// SPDX-License-Identifier: GPL-3.0-or-later
// The hierarchical point-cloud technique on the GPU (seed 2.6.4, 3.3; Jensen & Buhler 2002):
// Translucent's main real-time renderer of a BSSRDF on an arbitrary closed mesh.
//
// Per frame (each pass timed on the GPU):
//   shadow maps  depth maps of the mesh from each light (and from the environment samples of
//                occluded IBL; gl_resources.h)
//   irradiance   E_i of every surface sample, transmitted into the medium (Ft(η, ω_i) included),
//                one compute dispatch per light (shaders/pointcloud/irradiance.comp): directional,
//                point, beam, filtered directional (texture along the light), environment (SH9,
//                unoccluded) and occluded environment (a few shadow-mapped directions per frame,
//                accumulated over frames until `ibl_samples`)
//   refit        the octree's node power, area and centroid, bottom-up, one dispatch per level
//                (refit.comp)
//   g-buffer     world position and normal of the visible surface (gbuffer.vert/.frag)
//   radiance     per pixel, Algorithm 2 over the octree with the solid-angle criterion and the
//                BSSRDF kernel (tabulated profile, or the .bssrdf file's shader):
//                L = s Ft(η, ω_o) B / π [+ specular] (radiance.comp), s = 1 (radiance_convention
//                jensen) or 1/(4Cφ(1/η)) (normalized; seed Eq. 2.16, bssrdf/exit_radiance.h);
//                the "exitance" layer is B in either convention
// Preparation (prepare(), or render() after a parameter change): load and place the mesh
// (scene/scene.h), require it closed, orient it outwards, sample `points` area-uniform points
// (geometry/point_cloud.h, cached on disk), build the octree (geometry/octree.h), tabulate the
// model's profile and upload everything.
//
// Parameters (name, default, range, unit; see parameters() for the help text):
//   points 100000 [1000, 5000000]; sampling elimination|random; seed 1;
//   epsilon kDefaultEpsilon (0.1, cpu_traversal.h) [1e-4, 100] sr; criterion bbox|centroid;
//   kernel table|shader;
//   table_size 4096 [64, 65536]; shadow_map_size 2048 [64, 8192] texels;
//   shadow_offset 1.0 [0, 16] texels; shadow_bias 1.0 [0, 16] texels; shadow_samples 8 [1, 64];
//   shadow_radius 1.5 [0, 16] texels; ibl_samples 256 [1, 65536]; ibl_samples_per_frame 16 [1, 1024];
//   radiance_convention normalized (kDefaultRadianceConvention) | jensen;
//   specular false; roughness 0.3 [0.01, 1].
//
// Heterogeneous materials (material/material.h; prepare() calls scene::sceneMaterial(scene, mesh),
// or takes the Material given to setMaterial()): for a Kind::Volume material every point carries
// its local profile (material/point_profiles.h: n = kDefaultProfileSegments segments of ln P on
// [0, r_s], r_s the largest 95% radius; an SSBO of n + 1 vec4 per point in octree slot order),
// the radiance pass evaluates Eq. 8, sqrt(P_c(r) P_o(r)), with P_o the shading point's profile
// (interpolated from per-vertex profiles on the triangle the G-buffer names) and, for a cluster,
// the power-weighted mean of sqrt P of its points (refit every frame with the power;
// cpu_traversal.h says why). Kind::Volume and Kind::Surface both: a surface map is read at the
// atlas UV of each point (from its triangle, PointCloud::faces, and the default atlas,
// geometry::AtlasOptions{}, built or read from the cache) and of each vertex. The `shader` kernel is not available for heterogeneous materials (ParameterError).
// A homogeneous material takes exactly the path it took before (same programs, same buffers).
//
// Units: scene units for lengths; light fluxes as in the scene (scene/scene.h); the image is
// radiance per unit of the lights' flux units.
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "translucent/geometry/mesh.h"
#include "translucent/geometry/octree.h"
#include "translucent/geometry/point_cloud.h"
#include "translucent/material/material.h"
#include "translucent/material/point_profiles.h"
#include "translucent/techniques/common/profile_kernel.h"
#include "translucent/techniques/pointcloud/cpu_traversal.h"
#include "translucent/techniques/technique.h"

namespace translucent::pointcloud {

// Default of the `radiance_convention` parameter (bssrdf::toString of an ExitConvention), chosen
// from the measurement against the path tracer in docs/radiance-convention.md (`translucent
// convention-study`): over the image interior of the lit sphere and the front-lit bunny (30
// material channels) the true radiance deviates from the normalized law by 3.3% on average and
// from Jensen's by 3.7%, normalized being closer by more than 2σ in 7 channels and Jensen in 4;
// for Marble (α' >= 0.997) truth / normalized is 0.976-1.000 and truth / Jensen 1.040-1.065.
// Normalized is also the law that carries out exactly the exitance B. README, "Radiance
// convention". (The constant lives with the shared descriptor, techniques/common/profile_kernel.h.)
inline constexpr const char* kDefaultRadianceConvention = techniques::kDefaultRadianceConvention;

class PointCloudTechnique final : public techniques::Technique {
 public:
  PointCloudTechnique();
  ~PointCloudTechnique() override;
  PointCloudTechnique(const PointCloudTechnique&) = delete;
  PointCloudTechnique& operator=(const PointCloudTechnique&) = delete;

  std::string_view name() const override { return "pointcloud"; }
  std::string_view description() const override;
  const std::vector<techniques::ParameterInfo>& parameters() const override;
  void setParameter(std::string_view name, const techniques::ParameterValue& value) override;
  techniques::ParameterValue parameter(std::string_view name) const override;
  void prepare(const scene::Scene& scene, gpu::Context& gl) override;
  techniques::Frame render(const techniques::FrameRequest& request) override;
  // The camera only moves the G-buffer and the radiance pass: points, octree, shadow maps and
  // irradiance (and an occluded environment's accumulation) are kept.
  bool setCamera(const reference::Camera& camera) override;

  // The material to render from the next prepare() on instead of scene::sceneMaterial(scene,
  // mesh) (a hand-built Material: tests, callers with their own fields); std::nullopt goes back
  // to the scene's. `options` sets n and r_s of the per-point profiles.
  void setMaterial(std::optional<material::Material> material,
                   const material::ProfileOptions& options = {});

  // ---- Inspection (tests and benchmarks; valid after a render) --------------------------------
  // True when the last prepare() found a heterogeneous material (Kind::Volume or Kind::Surface).
  bool heterogeneous() const;
  // Heterogeneous: the per-point profiles (indexed like pointCloud()) and the per-vertex ones
  // (indexed like mesh().positions) the GPU uses; empty otherwise.
  const material::PointProfiles& cloudProfiles() const;
  const material::PointProfiles& vertexProfiles() const;
  // The placed, outward-oriented mesh, its point cloud and the octree built over it.
  const geometry::TriangleMesh& mesh() const;
  const geometry::PointCloud& pointCloud() const;
  // The octree with the irradiance the GPU computed in the last frame (refit on the CPU).
  geometry::Octree octreeWithGpuIrradiance() const;
  // The irradiance of the last frame per point, indexed like pointCloud().
  std::vector<glm::vec3> gpuIrradiance() const;
  // The kernel the radiance pass uses, for the CPU traversal (table kernel only).
  RgbKernel cpuKernel() const;
  // G-buffer positions of the last frame (xyz; w = 1 where covered, 1 + the triangle index for a
  // heterogeneous material; 0 elsewhere), rows from the top.
  std::vector<glm::vec4> gbufferPositions() const;
  TraversalOptions traversalOptions() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

std::unique_ptr<techniques::Technique> makePointCloudTechnique();

}  // namespace translucent::pointcloud
