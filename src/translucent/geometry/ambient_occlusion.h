// SPDX-License-Identifier: GPL-3.0-or-later
// Per-vertex ambient occlusion: the `a` of the empirical translucency shader's lighting equation
// (seed 3.1 "Ambient Occlusion Term", Eq. 3.5; `a` in Eq. 3.6).
//
// For a point P with normal N, Eq. 3.5 is
//     AO(P) = (1 / nRays) Σ_i V(P, ω_i),
// with ω_i spread over the hemisphere about N and V = 1 when the ray (P, ω_i) leaves the scene
// without hitting anything (no distance limit). The seed casts 320 rays per vertex, uniformly over
// the hemisphere: AO is then the fraction of the hemisphere's solid angle that sees the sky. The
// cosine-weighted option draws ω_i with density cos θ / π instead, which makes AO the fraction of
// the *projected* solid angle that is visible (the view factor to the sky; what a diffuse surface
// under a uniform sky actually receives).
//
// Visibility uses Embree 3 (one rtcOccluded1 per ray; the scene is built once per call, its build
// time reported). Ray origins are offset along N by ε = 1e-5 · (|centre| + radius) of the mesh's
// bounding sphere, and rays start at t = ε, so a vertex does not occlude itself.
//
// Normals: the mesh's vertex normals when it has them, otherwise area-weighted face normals. A
// vertex no triangle uses has no normal; it gets AO = 1.
//
// Determinism: ray i of vertex v is drawn from a counter-based generator keyed by (seed, v), and
// each vertex's sum is accumulated in ray order on one thread, so the values are bit-identical for
// a given seed whatever the number of threads.
//
// Cache: loadOrComputeAmbientOcclusion stores the values in a small binary file whose name holds
// the mesh content hash (meshHash), the ray count, the seed and the weighting, in the folder of
// defaultCacheDirectory() (point_cloud.h) unless told otherwise.
//
// Units: AO is dimensionless, in [0, 1].
#pragma once

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "translucent/geometry/mesh.h"

namespace translucent::geometry {

// Thrown for bad options or normals; the message names the parameter and what was expected.
class AmbientOcclusionError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct AmbientOcclusionOptions {
  int rays = 320;               // rays per vertex (seed default), 1 .. 1,000,000
  uint64_t seed = 1;
  bool cosineWeighted = false;  // false: uniform over the hemisphere (Eq. 3.5 as in the seed)
};

struct AmbientOcclusion {
  std::vector<float> values;   // per vertex, in [0, 1]
  // Embree scene build: copying the mesh and building the BVH (0 when read from the cache).
  // Creating the Embree device (which starts its thread pool) is counted apart, in
  // deviceSeconds: it does not depend on the mesh.
  double bvhSeconds = 0.0;
  double deviceSeconds = 0.0;
  double aoSeconds = 0.0;      // ray casting (0 when read from the cache)
  bool fromCache = false;
  std::filesystem::path file;  // the cache file (loadOrCompute only)
  std::string note;            // empty, or why the cache could not be read or written
};

// AO of every vertex of `mesh` (which must pass validate()). Throws AmbientOcclusionError for a
// ray count out of range or a mesh vertex normal that is not finite and non-zero.
AmbientOcclusion computeAmbientOcclusion(const TriangleMesh& mesh,
                                         const AmbientOcclusionOptions& options);

// AO at arbitrary points with unit normals `normals` (same size), occluded by `mesh`. Point k
// uses the random stream of vertex k, so for the mesh's own vertices and normals it gives the
// same values as computeAmbientOcclusion.
AmbientOcclusion computeAmbientOcclusion(const TriangleMesh& mesh,
                                         const std::vector<glm::dvec3>& points,
                                         const std::vector<glm::dvec3>& normals,
                                         const AmbientOcclusionOptions& options);

// The unit normal used for each vertex (see the top of the file); zero for unused vertices.
std::vector<glm::dvec3> ambientOcclusionNormals(const TriangleMesh& mesh);

// File name of the cached AO of (mesh, options).
std::string ambientOcclusionCacheFileName(const TriangleMesh& mesh,
                                          const AmbientOcclusionOptions& options);

// Reads the cached values from `cacheDir` when a valid file is there, otherwise computes and
// stores them (written to a temporary file and renamed). A missing, corrupt or mismatching file
// is recomputed and replaced; a folder that cannot be written is reported in `note`.
AmbientOcclusion loadOrComputeAmbientOcclusion(const TriangleMesh& mesh,
                                               const AmbientOcclusionOptions& options,
                                               const std::filesystem::path& cacheDir);
AmbientOcclusion loadOrComputeAmbientOcclusion(const TriangleMesh& mesh,
                                               const AmbientOcclusionOptions& options);

}  // namespace translucent::geometry
