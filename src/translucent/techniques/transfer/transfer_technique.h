// SPDX-License-Identifier: GPL-3.0-or-later
// Precomputed subsurface transfer from the path tracer (the `transfer` technique): real-time
// relighting of a static translucent mesh whose subsurface transport was computed once by the
// reference path tracer on that very mesh, in the spirit of Wang et al. 2005 and Hašan et al.
// 2006 (transfer_operator.h). Where the other techniques evaluate a BSSRDF model made for a
// half-space (and so are as wrong as that model on thin parts, ears and backlit regions), this
// one carries the mesh's own transport; its errors are the discretisation (node spacing) and the
// preprocessing's Monte Carlo noise, both set by its parameters.
//
// Per frame (each pass timed on the GPU):
//   shadow maps, irradiance   the shared irradiance pass at kCellSamples points of each node's
//                             cell (surface_irradiance.h: every light type, Ft(η, ω_i) included)
//   cells                     E per node, the mean over its cell's points (shaders/transfer/
//                             cells.comp); with incidence first-order also E times the
//                             tangential part of the refracted light direction
//   transfer                  B_i = Σ_j K⁰[i][j] E_j (+ K^u E^u + K^v E^v; apply.comp)
//   vertices                  B at each vertex from its nodes (vertex.comp)
//   g-buffer                  position, triangle and normal of the visible surface
//   radiance                  B interpolated on the triangle, L = s Ft(η, n·ω_o) B / π
//                             (radiance.comp; s from radiance_convention, as pointcloud's)
// Preparation: load the mesh (closed, outwards), build the scene's material, then read the
// operator from the cache or build it (transfer_operator.h; its time, size and photon count are
// in the frame notes) and upload it. A camera move keeps everything but the last two passes.
//
// Refuses (ParameterError): deformed meshes (the operator belongs to one shape), surface-map
// materials (no volume to trace), more nodes than the GL driver's largest storage buffer holds.
//
// Parameters: nodes 2048 [64, 4096]; photons 512 [16, 65536] per node, beam and channel; seed 1;
// incidence normal | first-order; radiance_convention; the shared shadow and environment settings.
#pragma once

#include <array>
#include <memory>
#include <vector>

#include "translucent/techniques/technique.h"
#include "translucent/techniques/transfer/transfer_operator.h"

namespace translucent::transfer {

class TransferTechnique final : public techniques::Technique {
 public:
  TransferTechnique();
  ~TransferTechnique() override;
  TransferTechnique(const TransferTechnique&) = delete;
  TransferTechnique& operator=(const TransferTechnique&) = delete;

  std::string_view name() const override { return "transfer"; }
  std::string_view description() const override;
  const std::vector<techniques::ParameterInfo>& parameters() const override;
  void setParameter(std::string_view name, const techniques::ParameterValue& value) override;
  techniques::ParameterValue parameter(std::string_view name) const override;
  void prepare(const scene::Scene& scene, gpu::Context& gl) override;
  techniques::Frame render(const techniques::FrameRequest& request) override;
  bool setCamera(const reference::Camera& camera) override;

  // ---- Inspection (tests; valid after a render) -----------------------------------------------
  const TransferOperator& transferOperator() const;
  const geometry::TriangleMesh& mesh() const;
  // The nodes' transmitted irradiance (the mean over each cell's samples) and exitance of the
  // last frame (GPU results), RGB.
  std::vector<glm::vec3> gpuIrradiance() const;
  std::vector<glm::vec3> gpuNodeExitance() const;
  // With incidence first-order, the nodes' E^u and E^v of the last frame (cells.comp); else empty.
  std::array<std::vector<glm::vec3>, 2> gpuTiltedIrradiance() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

std::unique_ptr<techniques::Technique> makeTransferTechnique();

}  // namespace translucent::transfer
