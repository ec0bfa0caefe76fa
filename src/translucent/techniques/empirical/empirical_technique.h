// SPDX-License-Identifier: GPL-3.0-or-later
// The empirical translucency shader (seed chapter 3, appendices B and C): a real-time look of
// translucency from screen-space thickness, per-vertex ambient occlusion and an ad-hoc lighting
// equation; no radiometric model behind it.
//
// Per frame (each pass timed on the GPU):
//   front      the nearest surface: window depth, normal, AO, world position
//              (shaders/empirical/layers.vert, front.frag)
//   back       the second layer by depth peeling: fragments no farther than the front layer plus
//              `peel_epsilon` are discarded, so the depth test keeps the far side of the first
//              solid span (back.frag)
//   shade      eye-space distances from the actual projection matrix, the back distance smoothed
//              by the depth-aware Gaussian of Eq. C.1, thickness t = (back - front) / D with D the
//              diameter of the mesh's bounding sphere, then Eq. 3.6 (shade.comp)
// Preparation: load and place the mesh (oriented outwards when closed) and its per-vertex AO
// (geometry/ambient_occlusion.h, cached on disk; `ao` false: a = 1), both in the rest pose. A
// deformed mesh (mesh.deform) is deformed on the GPU per time (techniques::GpuMesh::deform), the
// material and AO staying those of the rest pose: the material follows the surface, and the AO is
// the rest pose's, precomputed once as the seed's is (a frame note says so), not traced per time.
//
// Lights (up to 4): directional lights give L and I_d = I_s = colour × irradiance; point lights
// L towards the light and I_d = I_s = colour × intensity / distance²; other types are rejected.
// I_a is the `ambient_light` grey.
//
// Frame layers (debug outputs, RGB with the value in all three channels; 0 on the background):
//   front_depth, back_depth   eye distances of the two layers [scene units] (back unsmoothed)
//   thickness                 normalised smoothed thickness t (unclamped)
//   ao                        interpolated per-vertex AO
//
// Radiance: the image is the colour of Eq. 3.6 itself; no radiant exitance B is computed and no
// radiance is derived from one, so the exit-radiance conventions of seed Eq. 2.16 (the point-cloud
// technique's `radiance_convention`, bssrdf/exit_radiance.h) do not apply and there is no such
// parameter here.
//
// Heterogeneous materials (material/material.h; prepare() calls scene::restMaterial(scene, mesh),
// or takes the Material given to setMaterial()). An approximation, as the whole shader is: K_d is
// scaled per vertex (interpolated over the triangles) by Rd(local medium) / Rd(representative
// medium), per channel, with Rd the total diffuse reflectance of the material's model
// (Model::totalReflectance; the dipole for a .bssrdf model) and the local medium
// Material::surfaceMedium at the vertex. Where the material is the representative medium the
// image is the homogeneous one; elsewhere the colour follows how much more or less light that
// medium reflects per channel. Thickness and backlight do not change with the medium. A Kind::Surface
// map is read at each vertex's UV in the rest pose's default atlas (geometry::AtlasOptions{}). A homogeneous material takes the programs and buffers it took before.
//
// Parameters: see parameters() (every term of Eq. 3.6, the smoothing kernel, the AO rays, and
// `preset`, which sets thickness_exponent, backlight and diffuse_weight from Table 4.3).
#pragma once

#include <memory>
#include <optional>

#include "translucent/material/material.h"
#include "translucent/techniques/technique.h"

namespace translucent::empirical {

class EmpiricalTechnique final : public techniques::Technique {
 public:
  EmpiricalTechnique();
  ~EmpiricalTechnique() override;
  EmpiricalTechnique(const EmpiricalTechnique&) = delete;
  EmpiricalTechnique& operator=(const EmpiricalTechnique&) = delete;

  std::string_view name() const override { return "empirical"; }
  std::string_view description() const override;
  const std::vector<techniques::ParameterInfo>& parameters() const override;
  void setParameter(std::string_view name, const techniques::ParameterValue& value) override;
  techniques::ParameterValue parameter(std::string_view name) const override;
  void prepare(const scene::Scene& scene, gpu::Context& gl) override;
  techniques::Frame render(const techniques::FrameRequest& request) override;
  // Keeps the preparation: the lights as checked, the mesh, its AO, a heterogeneous material's
  // per-vertex colours and the frame targets (prepare() computes those colours again). Nothing
  // per frame is light-side: the lights are uniforms of the shade pass, and the front and back
  // layers are the camera's, so a frame after a move costs what any frame costs.
  bool setCamera(const reference::Camera& camera) override;

  // The material to render from the next prepare() on instead of scene::sceneMaterial(scene,
  // mesh) (a hand-built Material: tests, callers with their own fields); std::nullopt goes back
  // to the scene's.
  void setMaterial(std::optional<material::Material> material);
  // True when the last prepare() found a heterogeneous material it renders as such.
  bool heterogeneous() const;

  // Diameter D of the placed mesh's bounding sphere (valid after prepare()).
  double sceneDiameter() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

std::unique_ptr<techniques::Technique> makeEmpiricalTechnique();

}  // namespace translucent::empirical
