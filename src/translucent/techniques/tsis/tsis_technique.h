// SPDX-License-Identifier: GPL-3.0-or-later
// Texture-space importance sampling on the GPU (seed chapter 3; issue #11 §2): the integral
// B(x_o) = ∫_S E(x_i) R(|x_i − x_o|) dA over the surface, rewritten over the surface atlas as
// ∫_T E'(x_i) R dx_i with E' = E A_S/A_T (Eq. 3.3) and estimated by N samples drawn in texture
// space with probability proportional to E' (Eq. 3.4, 3.5), shared by every pixel.
//
// Per frame (each pass timed on the GPU):
//   shadow maps  depth maps of the mesh from each light (techniques/common/gl_resources.h)
//   irradiance   Stage 1: E of every covered atlas texel's surface point, by the point-cloud
//                technique's irradiance pass (shaders/pointcloud/irradiance.comp: Ft(η, ω_i),
//                shadows), then the importance s_t = ΣE'_c a_t of each texel (tsis/importance.comp)
//   sum mipmap   Stage 2a: level k = sums of 2×2 blocks of level k − 1 (tsis/reduce.comp)
//   sampling     Stage 2b: N samples by the hierarchical inverse CDF of Algorithm 3.1 with
//                stratified u rotated every frame, or independent u (tsis/sample.comp)
//   g-buffer     world position and normal of the visible surface (pointcloud/gbuffer.*)
//   radiance     Stage 3: B = 1/N Σ w_i R(|x_i − x_o|) per pixel, L = s Ft(η, ω_o) B/π (Eq. 3.6,
//                with the point cloud's radiance_convention s); accumulated over frames
//                (tsis/radiance.comp)
// Preparation: load and place the mesh (closed, oriented outwards, as the point cloud), build or
// load the surface atlas (geometry/atlas.h, cached on disk), take every texel the atlas's
// coverage gives a triangle (conservative: every triangle owns at least one texel) with its
// surface point and normal, tabulate the model's profile (techniques/common/profile_kernel.h).
//
// The texel geometry (positions, normals, areas) is computed once on the CPU from the atlas's
// coverage rather than rasterised by GL every frame: it does not change with the lights, and the
// coverage is conservative (a triangle smaller than a texel still owns one), which GL's
// rasteriser is not. The texel area is a_t = A_S^j / n_j for the n_j texels that triangle j owns:
// Eq. 3.3's A_S/A_T with A_T counted in owned texels, so that Σ_t a_t = A_S exactly.
//
// Parameters (name, default, range; see parameters() for the help text):
//   samples 1024 [49, 14400]; sequence stratified|random; atlas_size 1024 [16, 4096] texels;
//   atlas_method lscm|authalic|triangles; mode global|hybrid (seed 3.3: R W_g by TSIS plus the
//   Local Translucent Shadow Map of R W_l, techniques/tsis/hybrid_split.h; 1 to 4 directional or
//   point lights, a light-view map each); term full|local|global; split_k 1.5 /mm; split_bound 0.1 /mm; circles 20 [1, 64];
//   circle_samples 20 [1, 64]; ltsm_map_size 1024 [64, 4096]; accumulate true;
//   accumulate_samples 65536 [49, 2^24] (samples per pixel of a converged image: frames of N
//   samples, Stage 1 once per batch); table_size 4096 [64, 65536]; radiance_convention
//   normalized | jensen; and the shared lighting's shadow_* and ibl_* (surface_irradiance.h).
//
// Lights: every type the shared irradiance pass takes (directional, filtered directional, point
// outside the bounding sphere, beam of radius > 0, environment with SH9 or, with occlusion,
// shadow-mapped directions that accumulate over frames: the frames' mean stays unbiased since
// each frame's E is).
#pragma once

#include <array>
#include <memory>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "translucent/bssrdf/profile_table.h"
#include "translucent/geometry/mesh.h"
#include "translucent/techniques/technique.h"

namespace translucent::tsis {

// A covered atlas texel as the GPU sees it.
struct TexelPoint {
  glm::vec3 position{0.0f};
  glm::vec3 normal{0.0f};
  float area = 0.0f;   // a_t: the surface area the texel stands for [scene units²]
  uint32_t texel = 0;  // y · atlas size + x
};

class TsisTechnique final : public techniques::Technique {
 public:
  TsisTechnique();
  ~TsisTechnique() override;
  TsisTechnique(const TsisTechnique&) = delete;
  TsisTechnique& operator=(const TsisTechnique&) = delete;

  std::string_view name() const override { return "tsis"; }
  std::string_view description() const override;
  const std::vector<techniques::ParameterInfo>& parameters() const override;
  void setParameter(std::string_view name, const techniques::ParameterValue& value) override;
  techniques::ParameterValue parameter(std::string_view name) const override;
  void prepare(const scene::Scene& scene, gpu::Context& gl) override;
  techniques::Frame render(const techniques::FrameRequest& request) override;
  // The texels' lighting (atlas, shadow maps, irradiance, an occluded environment's
  // accumulation) does not depend on the camera: kept; the accumulated image starts again.
  bool setCamera(const reference::Camera& camera) override;

  // ---- Inspection (tests; valid after a render) -----------------------------------------------
  const geometry::TriangleMesh& mesh() const;
  uint32_t atlasSize() const;
  const std::vector<TexelPoint>& texelPoints() const;
  // E (transmitted irradiance) of each texel point in the last frame, indexed like texelPoints().
  std::vector<glm::vec3> texelIrradiance() const;
  // Level 0 of the sum mipmap: s_t per texel (atlas size², row y = 0 first), and the total S.
  std::vector<float> importance() const;
  float totalImportance() const;
  // The texel of each of the last frame's N samples.
  std::vector<uint32_t> sampleTexels() const;
  // G-buffer positions of the last frame (xyz; w = 1 where covered), rows from the top.
  std::vector<glm::vec4> gbufferPositions() const;
  const std::array<bssrdf::ProfileTable, 3>& profileTables() const;
  // Frames in the accumulated image of the last render.
  int accumulatedFrames() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

std::unique_ptr<techniques::Technique> makeTsisTechnique();

}  // namespace translucent::tsis
