// SPDX-License-Identifier: GPL-3.0-or-later
// The precomputed subsurface transfer of a static closed mesh (the `transfer` technique's CPU
// half): a matrix from the irradiance transmitted into N surface nodes to the radiant exitance
// at the same nodes, computed once by the path tracer (reference/surface_transfer.h), and the
// weights that interpolate the nodes' exitance to the mesh's vertices.
//
//   nodes      N area-uniform surface samples (geometry/point_cloud.h, blue noise by sample
//              elimination), node j with position p_j, normal n_j and area A_j: the area of its
//              cell (the surface points binned into it by the rule below), by Monte Carlo;
//   entries    a beam of the mean cell area (radius sqrt(A / (N π))) at each node, `photons`
//              photons per channel, at normal incidence; with `first_order`, also four beams
//              whose refracted direction leans by τ0 = kTilt (the sine of its angle to -n_j)
//              towards ±u_j and ±v_j (u_j a tangent of the node, v_j = n_j × u_j), with the
//              same random numbers as the normal beam (common random numbers: the differences
//              below have far less noise than the beams);
//   exclusion  with exclude_single, exits after exactly one scattering event are left out unless
//              the photon was reflected inside on the way (ExitRecord::reflected): the per-pixel
//              term traces the light straight in and the view ray straight out, so single
//              scattering with an internal reflection stays in the matrices;
//   bins       every exit is scored into the exit node: the nearest node whose normal faces the
//              same side as the exit's (n_i · n_exit > 0; the nearest overall if none of the
//              kExitCandidates nearest does), so that the two faces of a thin part stay apart;
//   irradiance E_j is the mean over kCellSamples area-uniform points of node j's cell (probes of
//              the cell areas), not a point sample at the node: on the backlit bunny with 512
//              nodes the per-node error against the path tracer falls from 23% to 13% (12% to
//              10% at 2048 nodes and 4x the photons);
//   matrices   K_c[i][j] = X_c[i][j] / Φ_c[j] · A_j / A_i, with X the exiting flux binned into
//              node i from entry j and Φ the flux that entered there, for the normal beam (K⁰)
//              and, with first_order, the central differences K^u = (K(+u) - K(-u)) / 2τ0 and
//              K^v alike: for light transmitted into node j with irradiance E_j (Ft included, as
//              the techniques' irradiance pass computes it) along a refracted direction whose
//              tangential part is τ_j (|τ| = sin θ_t),
//                  B_i = Σ_j K⁰[i][j] E_j + K^u[i][j] (τ_j · u_j) E_j + K^v[i][j] (τ_j · v_j) E_j
//              [W / scene unit²]: the first-order expansion in the incident direction of the
//              exitance the path tracer scores over node i's cell (a light-side estimator whose
//              photons start at every node, not only the lit ones). Oblique light enters less
//              deep and displaced towards where it travels: on a lit sphere the normal beams
//              alone leave 5-17% too little light in the bands lit at grazing incidence
//              (test_transfer);
//   secant     with Incidence::Secant, the four tilted beams' matrices are kept as they are
//              (K(±u), K(±v): five matrices) and per frame each node's column is interpolated
//              towards the beam on its light's side, linearly in the tilt:
//                  B_i = Σ_j K⁰[i][j] (1 - |t_u| - |t_v|) E_j + K(s_u u)[i][j] |t_u| E_j
//                        + K(s_v v)[i][j] |t_v| E_j,   t = (τ_j · u_j, τ_j · v_j) / τ0,
//              s the signs of t, t scaled down to |t_u| + |t_v| = 1 where it exceeds it (light
//              steeper than the tilted beams: the weights stay convex; extending the line
//              overshot on the backlit bunny, +16% against +12% bias). Unlike the central
//              differences this keeps the part of the response that is even in the tilt: light
//              entering obliquely stays nearer the surface and travels along its own direction,
//              not along -n_j towards the body's inside. On a sphere of radius 10 mm in Skin1 lit
//              and seen along one axis, the exitance by image ring is 1.08-1.15x the path
//              tracer's in the centre with the normal beams, 0.93-0.98x with the central
//              differences, 0.98-1.05x with the secant; on the 10 mm skin head the total
//              exitance is 0.99-1.01x (normal beams 1.00-1.05x, their multiply scattered part
//              1.07-1.11x);
//   vertices   B at each vertex from its kVertexNodes nearest nodes, weighted by a Gaussian of
//              the node spacing h = sqrt(A / N) and by max(n_v · n_i, 0)² (the same thin-part
//              rule), normalised: a partition of unity, so a constant B is kept exactly.
//
// What it does not hold: the second order in the incident direction, detail of B finer than the
// node spacing, and deformation (the operator belongs to one shape). Its cost is N² · 3 floats
// per matrix (three with first_order) and N · photons · 3 photon walks per beam direction (five
// with first_order) of preprocessing.
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
// τ0 of the tilted beams: sin θ_t = 0.5 (30° inside; 40.5° outside at η = 1.3, and reachable
// from outside for every η <= 2).
inline constexpr double kTilt = 0.5;
// Irradiance samples per cell: E_j is the mean over them (a point sample at the node puts the
// whole cell in the light or in the shadow where a shadow edge or terminator crosses it).
inline constexpr uint32_t kCellSamples = 16;

// How the operator follows the light's incident direction (the `incidence` parameter): normal
// beams only (one matrix), or the four tilted beams too, as central differences (first-order,
// three matrices) or as they are (secant, five).
enum class Incidence { Normal, FirstOrder, Secant };
inline constexpr size_t incidenceBeams(Incidence m) { return m == Incidence::Normal ? 1 : 5; }
inline constexpr size_t incidenceMatrices(Incidence m) {
  return m == Incidence::Normal ? 1 : m == Incidence::FirstOrder ? 3 : 5;
}

struct TransferOptions {
  int nodes = 2048;        // N
  uint64_t photons = 512;  // per node and channel
  uint64_t seed = 1;       // of the node sampling and of the photons
  Incidence incidence = Incidence::Normal;
  // Leave single scattering out (exits after exactly one scattering event, ScatteringOrder::
  // Single): the technique renders it per pixel (techniques/common/single_scattering.h).
  bool exclude_single = false;
  int threads = 0;         // 0: all hardware threads
};

struct TransferOperator {
  size_t nodes = 0;
  size_t matrices = 1;  // 1: K⁰; 3: K⁰, K^u, K^v; 5 (secant): K⁰, K(+u), K(-u), K(+v), K(-v)
  std::vector<glm::vec3> positions, normals, tangents;  // per node (tangents: u_j)
  std::vector<float> areas;                              // per node [scene units²]
  // Per node kCellSamples points of its cell (area-uniform), where the irradiance is sampled:
  // E_j is their mean.
  std::vector<glm::vec3> samplePositions, sampleNormals;
  // K^m_c[i][j] at matrix[((c · matrices + m) · N + i) · N + j] [dimensionless: (W/unit² out)
  // per (W/unit² in)]: per channel one block of all matrices.
  std::vector<float> matrix;
  // Per vertex kVertexNodes (node, weight) pairs; weights sum to 1 (unused slots weight 0).
  std::vector<uint32_t> vertexNodes;
  std::vector<float> vertexWeights;
  // How it was made (kept in the cache file, shown by the technique).
  double seconds = 0.0;        // preprocessing, wall clock
  uint64_t photons = 0;        // traced, over all nodes and channels
  uint64_t missedEntries = 0;  // node discs whose beam did not enter the body (columns of 0)

  size_t bytes() const;
  // B_i per channel from E (transmitted irradiance per node, RGB) and, with matrices == 3, Eu and
  // Ev (E times τ·u_j and τ·v_j; empty: normal incidence), on the CPU: the oracle of the GPU pass.
  std::vector<glm::vec3> exitance(const std::vector<glm::vec3>& irradiance,
                                  const std::vector<glm::vec3>& tiltU = {},
                                  const std::vector<glm::vec3>& tiltV = {}) const;
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
