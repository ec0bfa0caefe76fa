// SPDX-License-Identifier: GPL-3.0-or-later
// Multiresolution splatting on the GPU (Chen, Peers, Zhang & Tong 2012, "Real-time rendering of
// deformable heterogeneous translucent objects using multiresolution splatting"; seed
// multiresolution-splatting §3-4), and the Shah, Kontinen & Pattanaik 2009 baseline it
// accelerates (image-space splatting of every irradiance texel with full-size splats).
//
// The exitance at a visible surface point x_o (Eq. 5) is the sum over the irradiance samples x_i
// of the light's view,
//     B(x_o) = Σ_i sqrt(P_xo(d) P_xi(d)) E(x_i) ΔA(x_i),   d = |x_o − x_i|  (Eq. 8: Rd),
// and the radiance L = s Ft(η, n·ω_o) B / π (Eq. 7; s the radiance_convention scale, as tsm).
//   irradiance buffer  a LightViewMap per light (techniques/common/light_view_map.h): x_i, its
//                      normal, E (Ft and cos θ included) and ΔA (lvmSurfaceArea), plus the
//                      triangle index of x_i in the position's w (LVM_PRIMITIVE_ID); rendered
//                      (with its hierarchy, below) after prepare() or a new irradiance_size only,
//                      so camera moves and still frames keep it;
//   splatting buffer   the camera's G-buffer (world position, w = 1 + triangle; normal);
//   splat              one instanced draw of screen-space squares, one instance per irradiance
//                      texel, bounding the sphere of radius R_max about x_i; the fragment adds the
//                      term above for d in [R_min, R_max) into an RGBA32F target (GL_ONE, GL_ONE);
//   radiance           Eq. 7 per pixel (shaders/splatting/radiance.comp).
//
// Profiles (heterogeneous and homogeneous materials alike): per-vertex SubEdit profiles
// (material/point_profiles.h: n segments of ln P on [0, r_s], r_s the largest 95% radius, the tail
// up to r_cut = 3 r_s) computed once in prepare() on the CPU at the rest-pose vertices; the
// profile of any surface point (x_i or x_o) is the barycentric interpolation of its triangle's
// vertex nodes (pointcloud/hetero.glsl's arithmetic, shaders/splatting/profile.glsl), the
// barycentrics taken on the deformed mesh. A homogeneous material gives every vertex the same
// profile (the model's R(r) on the node grid).
//
// Multiresolution (multires = true, levels n > 1; Eqs. 12-17): the splatting buffer's mipmap by
// the 2×2 median-depth filter (shaders/splatting/downsample.comp, splatting::medianDepthIndex);
// each sample splats at level k only the distances [R^k_min, R^k_max) of Eq. 13
// (splatting::splatRanges, evaluated per sample in splat.vert: R_P the sample's 95% radius —
// per vertex, of its widest channel, interpolated —, T0 = projectedResolution at the sample's
// depth, R̄ from splatting::RbarTable built over the mean normalised profile of the vertex
// profiles with ε = epsilon), with one deviation: R^{n−1}_max = r_cut instead of R_P, so the
// profiles' tail beyond R_P (up to 5% of the energy) is kept at the coarsest level; each level's
// image is then bilaterally upsampled into the next finer one and added (Eq. 17,
// shaders/splatting/upsample.comp, splatting::bilateralUpsample; λz, λm; R_w the bounding-sphere
// diameter; z the view depth). multires = false (or levels = 1): one level, R_min = 0,
// R_max = r_cut. `shah` is that unaccelerated configuration (every irradiance texel, full-range
// splats).
//
// Adaptive sample selection (adaptive = true; Eqs. 10-11, Algorithm 1): the hierarchical
// irradiance buffer of `levels` levels per light (shaders/splatting/irradiance_mip.comp: level 0
// the light-view map's texels with power E ΔA, R_P and light-view depth; each coarser texel the
// sum of its children's power, their mean position, cos θ_g and R_P, the min/max of their depths,
// the profile of its most-covering child's triangle) and, per texel at every level, the rule of
// splatting::validSample with Eq. 10 = splatting::passesEq10 (z0 × the bounding radius, α, R_w
// the bounding-sphere diameter, the level's resolution; in splat.vert): a texel is splatted when
// it passes at its level (level 0: always, the fallback) and no coarser ancestor passes. Each
// selected sample then splats over the splatting levels as above. Approximations of this
// implementation (the paper leaves them open): the coarse sample's position is the mean of its
// covered texels (not necessarily on the surface; its profile is taken at its projection on the
// representative triangle).
//
// Lights: directional and point (outside the bounding sphere); environment, beam and filtered
// directional lights are refused with a ParameterError naming lights[i] and the supported types.
// Materials: homogeneous, volume (3D) and surface-map (2D) materials; a surface map is read at each
// vertex's UV in the default atlas of the rest pose (as the point cloud reads it for its vertices).
#pragma once

#include <memory>
#include <vector>

#include "translucent/geometry/mesh.h"
#include "translucent/material/point_profiles.h"
#include "translucent/techniques/common/gl_resources.h"
#include "translucent/techniques/common/light_view_map.h"
#include "translucent/techniques/technique.h"

namespace translucent::splatting {

class SplattingTechnique final : public techniques::Technique {
 public:
  // shah: the Shah et al. 2009 baseline (no acceleration parameters).
  explicit SplattingTechnique(bool shah = false);
  ~SplattingTechnique() override;
  SplattingTechnique(const SplattingTechnique&) = delete;
  SplattingTechnique& operator=(const SplattingTechnique&) = delete;

  std::string_view name() const override;
  std::string_view description() const override;
  const std::vector<techniques::ParameterInfo>& parameters() const override;
  void setParameter(std::string_view name, const techniques::ParameterValue& value) override;
  techniques::ParameterValue parameter(std::string_view name) const override;
  void prepare(const scene::Scene& scene, gpu::Context& gl) override;
  techniques::Frame render(const techniques::FrameRequest& request) override;
  // The vertex profiles, the irradiance buffers and their hierarchies are light-side: kept. The
  // splatting buffer is the camera's view, so the splats are redone, as every frame.
  bool setCamera(const reference::Camera& camera) override;

  // ---- Inspection (tests; valid after prepare / render) ---------------------------------------
  const material::PointProfiles& vertexProfiles() const;
  const geometry::TriangleMesh& mesh() const;  // the (CPU-deformed) mesh as drawn
  size_t lightCount() const;
  const techniques::LightViewMap& lightMap(size_t i) const;  // after render
  const techniques::GBuffer& gbuffer() const;                // after render

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

std::unique_ptr<techniques::Technique> makeSplattingTechnique();
std::unique_ptr<techniques::Technique> makeShahTechnique();

}  // namespace translucent::splatting
