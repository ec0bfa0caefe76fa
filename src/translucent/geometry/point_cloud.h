// SPDX-License-Identifier: GPL-3.0-or-later
// Area-uniform surface samples: the point cloud of the hierarchical (two-pass) subsurface
// scattering technique (seed 2.6.4 "Generating Sample Locations", 3.3.1; Jensen & Buhler 2002).
//
// Each sample p carries a position, a normal, an area p_a with Σ p_a = A (the mesh area) and,
// optionally, an irradiance E (RGB). With a uniform sample density every point gets
// p_a = A / |P|, which the seed recommends because errors in p_a show up as low-frequency noise.
//
// Sampling methods:
//   Random       independent area-weighted samples (a Poisson process on the surface); the
//                baseline, clumpy: nearest-neighbour distances have CV ≈ sqrt(4/π - 1) ≈ 0.52.
//   Elimination  Yuksel 2015, "Sample Elimination for Generating Poisson Disk Sample Sets":
//                `oversampling`·N random candidates; each candidate i gets the weight
//                w_i = Σ_j (1 - d̂_ij / (2 r_max))^8 over the candidates j closer than 2 r_max,
//                with r_max = sqrt(A / (2√3 N)) (the densest packing radius of N discs on A) and
//                d̂_ij = max(d_ij, r_min) (his "weight limiting",
//                r_min = 2 r_max · 0.65 (1 - (N/M)^1.5)); then the heaviest candidate is removed
//                and its neighbours' weights reduced, until exactly N remain. Blue noise as good
//                as Turk's relaxation (the seed's choice) at a fraction of the cost, with no
//                projection of points across faces. Distances are Euclidean in 3D.
//
// Determinism: candidate k is drawn from a counter-based generator keyed by (seed, k) and every
// parallel loop writes only its own outputs in a fixed order, so the result is bit-identical for
// a given seed whatever the number of threads.
//
// Storage: floats throughout (what the GPU uploads, and what a PLY round trip keeps exactly).
// Units: positions in scene units, areas in scene units², irradiance in W / scene unit².
#pragma once

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "translucent/geometry/mesh.h"

namespace translucent::geometry {

// Thrown for bad sampling options, malformed point clouds and unreadable PLY files; the
// message names the parameter or file and what was expected.
class PointCloudError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct PointCloud {
  std::vector<glm::vec3> positions;   // on the surface [scene units]
  std::vector<glm::vec3> normals;     // unit; interpolated vertex normal, else the face normal
  std::vector<float> areas;           // p_a [scene units²]; Σ p_a = mesh area
  std::vector<uint32_t> faces;        // triangle each point lies on (empty: unknown)
  std::vector<glm::vec3> irradiance;  // E per point, RGB [W / scene unit²] (empty: none)

  size_t size() const { return positions.size(); }
  double totalArea() const;  // Σ p_a, accumulated in double
  bool hasIrradiance() const { return !irradiance.empty(); }

  // Throws PointCloudError naming `what` unless the cloud is non-empty, every per-point array is
  // either empty (faces, irradiance only) or of size(), positions are finite, normals are unit
  // length (within 1e-3), areas are positive and finite, and irradiance is finite and >= 0.
  void validate(const std::string& what) const;
};

enum class SamplingMethod { Random, Elimination };
// "random" / "elimination"; parseSamplingMethod throws PointCloudError listing the valid names.
const char* toString(SamplingMethod method);
SamplingMethod parseSamplingMethod(const std::string& name);

struct SamplingOptions {
  size_t count = 0;  // exact number of points, 1 .. 2^24 - 1 (the octree's 24-bit indices)
  uint64_t seed = 1;
  SamplingMethod method = SamplingMethod::Elimination;
  double oversampling = 5.0;  // candidates per output point for Elimination, in [2, 32]
                              // (Yuksel: 5 is where more candidates stop paying off)
};

// Samples `options.count` points on the mesh (which must pass validate()). Normals are the
// normalised interpolated vertex normals when the mesh has them, otherwise face normals; every
// point gets the area A / count. Throws PointCloudError for a count or oversampling out of range.
PointCloud samplePointCloud(const TriangleMesh& mesh, const SamplingOptions& options);

// Nearest-neighbour distances of a point cloud (Euclidean, 3D): the uniformity measure. A
// Poisson process on a surface has CV ≈ 0.52; blue noise has a much smaller one.
struct NearestNeighbourStats {
  double mean = 0.0;
  double stddev = 0.0;
  double cv = 0.0;  // coefficient of variation: stddev / mean
  double min = 0.0;
  double max = 0.0;
};
NearestNeighbourStats nearestNeighbourStats(const PointCloud& cloud);

// 64-bit hash of the mesh content (positions, triangles, normals): the cache key.
uint64_t meshHash(const TriangleMesh& mesh);

// ---- PLY files ---------------------------------------------------------------------------
// assimp's PLY exporter writes only its fixed vertex layout (x y z, nx ny nz, s t, uchar colours,
// tangents): no custom float property such as the area, and colours quantised to 8 bits. Point
// clouds therefore go through this small reader/writer of their own.
//
// writePointCloudPly writes binary_little_endian 1.0 with one `vertex` element of float
// x y z nx ny nz area, then uint face (when known), then float irradiance_r _g _b (when present).
// The file is written to a temporary name in the same folder and renamed, so readers never see a
// partial file. Throws PointCloudError naming the file on I/O failure.
void writePointCloudPly(const PointCloud& cloud, const std::filesystem::path& path);

// Reads ascii or binary (either endianness) PLY: the `vertex` element must have x, y, z, nx, ny,
// nz and area, or radius for a surfel disc of area π r² (any scalar type, in any order); face and
// irradiance_r/g/b are optional; other properties and elements are skipped. The result is validate()d. Throws PointCloudError naming
// the file and what was expected.
PointCloud readPointCloudPly(const std::filesystem::path& path);
// Whether `path` is a PLY point cloud rather than a mesh: a PLY header (read up to end_header,
// at most 64 KiB) with a `vertex` element that has an `area` or `radius` property and no `face`
// element of triangles (no element named "face", or one with 0 instances). False for anything
// else, unreadable files included (the mesh reader then says what is wrong).
bool isPointCloudPly(const std::filesystem::path& path);
// The same for a cache file: the header must hold the content hash that writePointCloudPly
// writes ("comment content_hash <hex>") and the data must match it; a tampered or truncated file
// throws PointCloudError (readPointCloudPly checks the hash too, when there is one).
PointCloud readPointCloudCache(const std::filesystem::path& path);

// ---- On-disk cache -----------------------------------------------------------------------
// The folder: $TRANSLUCENT_CACHE_DIR if set, else $XDG_CACHE_HOME/translucent, else
// $HOME/.cache/translucent (else a folder under the system temporary directory).
std::filesystem::path defaultCacheDirectory();

// File name identifying a sampling: mesh hash, count, seed, method, oversampling and the
// algorithm version (bumped whenever the samples a seed produces change).
std::string cacheFileName(const TriangleMesh& mesh, const SamplingOptions& options);

struct CachedPointCloud {
  PointCloud cloud;
  bool fromCache = false;      // true: read from `file`; false: sampled now
  std::filesystem::path file;  // the cache file (written when sampled, unless `note` says why not)
  std::string note;            // empty, or why the cache could not be read or written
};

// Returns the cached point cloud for (mesh, options) from `cacheDir` when a valid file is there,
// otherwise samples it and stores it (atomically). A missing, corrupt or mismatching cache file
// is resampled and replaced; a cache folder that cannot be written is reported in `note`, never
// an error.
CachedPointCloud loadOrSamplePointCloud(const TriangleMesh& mesh, const SamplingOptions& options,
                                        const std::filesystem::path& cacheDir);
CachedPointCloud loadOrSamplePointCloud(const TriangleMesh& mesh, const SamplingOptions& options);

}  // namespace translucent::geometry
