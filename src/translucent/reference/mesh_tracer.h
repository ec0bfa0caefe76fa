// SPDX-License-Identifier: GPL-3.0-or-later
// Reference transport in a closed triangle mesh: the walk of transport.h with Embree 3 ray
// queries as the boundary, lit by directional, point and beam lights, seen by a pinhole (or
// orthographic) camera (camera.h).
//
// The mesh must be closed (watertight); its winding and normals are not used: a ray from outside
// enters at its first hit, so the mesh shadows itself, and a ray from inside leaves at its first
// hit; refraction and Fresnel use the geometric normal of the hit triangle. The mesh need not be
// convex: light that leaves one part and meets another (ear to head) re-enters there
// (transport.h). Self-intersecting or nested surfaces are not supported (their "inside" is not
// well defined).
//
// Output per pixel (camera.h): the pixel average of the radiant exitance B, of the diffusion
// radiance Ft(η, ω_o) B / π, and of the true radiance towards the camera averaged over a cone of
// half-angle θc; unbiased for these pixel averages. Passes accumulate as in the sphere tracer.
//
// Precision: Embree intersects in single precision. A ray leaving a surface point ignores hits
// closer than epsilon() = 1e-5 (|centre| + radius of the bounds) (its own triangle); rays from
// interior points use no such offset, so the walk sees every boundary it reaches. Near an edge
// the offset can also skip a neighbouring triangle, and the photon then slips through the mesh
// unseen; the walk, still "inside", later scores an exit where it really crosses inwards (and,
// with re-entry, may go on scoring a few such exits). Measured with an outward-oriented copy of
// the mesh: about 1.8e-4 of the exits (bunny: 59 of 324640 exits, in 27 of 1.2M photons; a
// rotated cube: 28 of 158667), a negligible bias, but enough that one such photon changes the
// random stream of its block (so a convex mesh's results are not always bit-identical to the
// walk without re-entry).
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "translucent/geometry/mesh.h"
#include "translucent/geometry/ray_scene.h"
#include "translucent/material/material.h"
#include "translucent/reference/camera.h"
#include "translucent/reference/sphere.h"
#include "translucent/reference/transport.h"

namespace translucent::reference {

class MeshBody final : public Body {
 public:
  // Builds the Embree scene (robust, high-quality BVH). Throws geometry::MeshError (naming
  // `what`) for invalid or open meshes, std::runtime_error for Embree failures.
  explicit MeshBody(const geometry::TriangleMesh& mesh, const std::string& what = "mesh");
  ~MeshBody() override;
  MeshBody(const MeshBody&) = delete;
  MeshBody& operator=(const MeshBody&) = delete;

  bool intersect(const glm::dvec3& o, const glm::dvec3& d, double t_min, double t_max,
                 SurfaceHit& hit) const override;
  bool occluded(const glm::dvec3& o, const glm::dvec3& d, double t_min,
                double t_max) const override;
  BoundingSphere bounds() const override { return bounds_; }
  double epsilon() const override { return epsilon_; }
  size_t triangleCount() const { return triangles_; }
  // Whether p lies inside the closed mesh (geometry::insideClosedMesh: ray parity by majority).
  bool inside(const glm::dvec3& p) const;

 private:
  geometry::RayScene scene_;
  BoundingSphere bounds_;
  double epsilon_ = 0.0;
  size_t triangles_ = 0;
};

// A walker of the mesh other than the CPU's (the GPU: reference/gpu/mesh_gpu.h), made for one
// mesh. It traces whole blocks of one channel and hands back, per photon, its exits and flux
// sums (transport.h: WalkedBatch); MeshPathTracer scores them as its own photons
// (scoreWalkedBlocks), so only the random streams differ.
struct MeshWalkSetup {
  std::vector<Light> lights;  // validated (unit directions)
  BoundingSphere bounds;      // the mesh's (emission discs and cones)
  double epsilon = 0.0;       // MeshBody::epsilon(): rays leaving the surface ignore closer hits
  std::vector<WalkChannel> channels;
  uint64_t seed = 1;
  uint64_t long_path_roulette = 0;  // 0: off
  // A heterogeneous medium filling the body (the tracer's; it outlives the setup), else null.
  const VolumeMedium* volume = nullptr;
  bool after_specular_only = false;  // TransportOptions::after_specular_only
};

using MeshWalker = PhotonWalker<MeshWalkSetup>;

class MeshPathTracer {
 public:
  // Three channels of a medium (coefficients per scene unit) or one (grey images).
  MeshPathTracer(const geometry::TriangleMesh& mesh, const Medium& medium,
                 std::vector<Light> lights, const Camera& camera, double cone_half_angle,
                 const TracerOptions& options);
  MeshPathTracer(const geometry::TriangleMesh& mesh, const ScalarMedium& medium,
                 std::vector<Light> lights, const Camera& camera, double cone_half_angle,
                 const TracerOptions& options);
  // A built material (material/material.h; the scene's: scene::sceneMaterial(scene, mesh)).
  // Homogeneous: the constructor above with material.medium (bit-identical results). Volume:
  // the field inside the mesh, delta-tracked through a majorant grid over the mesh's bounds
  // (`majorant_cells` per axis, 0: MajorantGrid::defaultCells), η = material.medium.eta.
  // Surface (2D atlas maps) has no volume to trace: ParameterError (its reference is the compare
  // report's model reference, brute-force Eq. 8 over the surface).
  MeshPathTracer(const geometry::TriangleMesh& mesh, const material::Material& material,
                 std::vector<Light> lights, const Camera& camera, double cone_half_angle,
                 const TracerOptions& options, glm::ivec3 majorant_cells = {0, 0, 0});

  // Traces `photons` more photons per channel (rounded up to whole blocks of kBlockPhotons).
  TransportStats addPass(uint64_t photons, const ProgressCallback& progress = {});
  // Blocks [first, first + blocks) of a run (SpherePathTracer::addBlocks: a shard, issue 17).
  TransportStats addBlocks(uint64_t first, uint64_t blocks, const ProgressCallback& progress = {});
  // The images and statistics as named arrays (run_state.h), and back (SpherePathTracer::read).
  void write(RunState& state) const;
  // `seconds`, `threads`: the timing to report (e.g. the shards' total).
  void read(const RunState& state, double seconds = 0.0, int threads = 0);

  const CameraImages& images() const { return tally_->images(); }
  // With TracerOptions::split_orders, the images by scattering order (ImageTally::orderImages).
  bool splitsOrders() const { return tally_->splitsOrders(); }
  const CameraImages& orderImages(ScatteringOrder order) const { return tally_->orderImages(order); }
  const TransportStats& stats() const { return stats_; }
  const MeshBody& body() const { return body_; }
  // The heterogeneous medium (null for a homogeneous one) and its majorant grid.
  const VolumeMedium* volume() const { return volume_ ? &*volume_ : nullptr; }
  // VolumeMedium::majorant_violations so far (0 for a homogeneous medium).
  uint64_t majorantViolations() const {
    return mergedMajorantViolations_ + (volume_ ? volume_->majorantViolations() : 0);
  }
  const CameraModel& camera() const { return tally_->camera(); }
  // From now on, trace with `walker` (made for this tracer's mesh; null: the CPU again). Every run
  // the tracer holds can be walked on the GPU; which 3D fields the GPU evaluates,
  // reference/gpu/device.h says (meshGpuRefusal).
  void setWalker(std::shared_ptr<MeshWalker> walker) { walker_ = std::move(walker); }
  std::string device() const { return walker_ ? walker_->name() : "cpu"; }
  MeshWalkSetup walkSetup() const;

  // Photons that scored into more than one pixel (ImageTally::severalPixelPhotons).
  uint64_t severalPixelPhotons() const { return tally_->severalPixelPhotons(); }

 private:
  void init(const Camera& camera, double cone_half_angle);
  std::vector<ScalarMedium> channels_;
  std::optional<VolumeMedium> volume_;
  std::vector<Light> lights_;
  TracerOptions options_;
  MeshBody body_;
  std::unique_ptr<ImageTally> tally_;
  TransportStats stats_;
  uint64_t mergedMajorantViolations_ = 0;  // from a state read in
  std::shared_ptr<MeshWalker> walker_;
};

}  // namespace translucent::reference
