// SPDX-License-Identifier: GPL-3.0-or-later
// The precomputed subsurface transfer of a static closed mesh (the `transfer` technique's CPU
// half): a matrix from the irradiance transmitted into N surface nodes to the radiant exitance
// at the same nodes, computed once by the path tracer (reference/surface_transfer.h), and the
// weights that interpolate the nodes' exitance to the mesh's vertices.
//
//   nodes      N area-uniform surface samples (geometry/point_cloud.h, blue noise by sample
//              elimination), node j with position p_j, normal n_j and area A_j: the area of its
//              cell (the surface points binned into it by the rule below), by Monte Carlo;
//   entries    a disc of the mean cell area at each node (radius sqrt(A / (N π))), lit at normal incidence
//              by `photons` photons per channel;
//   bins       every exit is scored into the exit node: the nearest node whose normal faces the
//              same side as the exit's (n_i · n_exit > 0; the nearest overall if none of the
//              kExitCandidates nearest does), so that the two faces of a thin part stay apart;
//   matrix     K_c[i][j] = X_c[i][j] / Φ_c[j] · A_j / A_i, with X the exiting flux binned into
//              node i from entry j and Φ the flux that entered there: then, for the irradiance
//              E_j transmitted into the medium at node j (Ft included, as the techniques'
//              irradiance pass computes it), the exitance is B_i = Σ_j K_c[i][j] E_j
//              [W / scene unit²], a Monte Carlo estimate of the exitance the path tracer scores
//              over node i's cell for that irradiance (a light-side estimator whose photons
//              start at every node, not only the lit ones);
//   vertices   B at each vertex from its kVertexNodes nearest nodes, weighted by a Gaussian of
//              the node spacing h = sqrt(A / N) and by max(n_v · n_i, 0)² (the same thin-part
//              rule), normalised: a partition of unity, so a constant B is kept exactly.
//
// What it does not hold: light that arrives at other angles than the normal enters the same way
// (the first collision moves by less than a mean free path; the irradiance's Ft uses the true
// angle), detail of B finer than the node spacing, and deformation (the operator belongs to one
// shape). Its cost is N² · 3 floats of memory and N · photons · 3 photon walks of preprocessing.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "translucent/geometry/mesh.h"
#include "translucent/geometry/point_cloud.h"
#include "translucent/material/material.h"
#include "translucent/reference/slab.h"

namespace translucent::transfer {

inline constexpr int kVertexNodes = 8;     // nodes interpolated per vertex
inline constexpr int kExitCandidates = 8;  // nearest nodes an exit may be binned into

struct TransferOptions {
  int nodes = 2048;        // N
  uint64_t photons = 512;  // per node and channel
  uint64_t seed = 1;       // of the node sampling and of the photons
  int threads = 0;         // 0: all hardware threads
};

struct TransferOperator {
  size_t nodes = 0;
  std::vector<glm::vec3> positions, normals;  // per node
  std::vector<float> areas;                   // per node [scene units²]
  // K_c[i][j] at matrix[(c · N + i) · N + j] [dimensionless: (W/unit² out) per (W/unit² in)].
  std::vector<float> matrix;
  // Per vertex kVertexNodes (node, weight) pairs; weights sum to 1 (unused slots weight 0).
  std::vector<uint32_t> vertexNodes;
  std::vector<float> vertexWeights;
  // How it was made (kept in the cache file, shown by the technique).
  double seconds = 0.0;        // preprocessing, wall clock
  uint64_t photons = 0;        // traced, over all nodes and channels
  uint64_t missedEntries = 0;  // node discs whose beam did not enter the body (columns of 0)

  size_t bytes() const;
  // B_i = Σ_j K_c[i][j] E_j per channel (E: transmitted irradiance per node, RGB), on the CPU:
  // the oracle of the GPU pass.
  std::vector<glm::vec3> exitance(const std::vector<glm::vec3>& irradiance) const;
  // The vertices' B from the nodes' (the vertex weights).
  std::vector<glm::vec3> vertexExitance(const std::vector<glm::vec3>& nodeExitance) const;
};

// Builds the operator of `mesh` (placed, closed, outward) filled with `material` (homogeneous
// or a 3D field; a surface map has no volume: ParameterError). `progress` as the path tracers'
// (returning false abandons the build: ParameterError "stopped").
// `vertexNormals`: unit, per vertex of `mesh` (techniques::vertexNormals).
TransferOperator buildTransferOperator(const geometry::TriangleMesh& mesh,
                                       const std::vector<glm::dvec3>& vertexNormals,
                                       const material::Material& material,
                                       const TransferOptions& options,
                                       const reference::ProgressCallback& progress = {});

// A cached build: `key` names what the operator depends on (mesh, material, options); the file
// in `cacheDir` holds the key and is used only when it matches exactly. A missing, corrupt or
// mismatching file is rebuilt and replaced (atomically); a folder that cannot be written is
// reported in `note`, never an error.
struct CachedTransfer {
  TransferOperator op;
  bool fromCache = false;
  std::filesystem::path file;
  std::string note;
};
CachedTransfer loadOrBuildTransferOperator(const geometry::TriangleMesh& mesh,
                                           const std::vector<glm::dvec3>& vertexNormals,
                                           const material::Material& material,
                                           const TransferOptions& options, const std::string& key,
                                           const std::filesystem::path& cacheDir,
                                           const reference::ProgressCallback& progress = {});

void writeTransferOperator(const TransferOperator& op, const std::string& key,
                           const std::filesystem::path& path);
// Throws std::runtime_error naming the file when it is not a transfer operator of `key`.
TransferOperator readTransferOperator(const std::filesystem::path& path, const std::string& key);

}  // namespace translucent::transfer
