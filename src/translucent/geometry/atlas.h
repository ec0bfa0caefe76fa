// SPDX-License-Identifier: GPL-3.0-or-later
// The surface atlas: a parameterisation of a triangle mesh into the unit square in which every
// triangle owns texels, no two triangles overlap, and texel area is as close as possible to
// proportional to surface area. It is the texture space of texture-space importance sampling
// (seed 3.1.1, 3.2.1): the irradiance is rendered into it as E'(x) = E(x) A_S / A_T (Eq. 3.3)
// and texels are importance-sampled, so a triangle whose texel area A_T is shrunk relative to its
// surface area A_S is undersampled (the artefacts of seed Fig. 4.7a); hence the seed's preference
// for an area-preserving map (3.2.1, Yoshizawa et al. 2004).
//
// Methods:
//   Authalic   charts grown over the surface (each a topological disk), each mapped by CGAL's
//              discrete authalic parameterizer (Desbrun, Meyer & Alliez 2002) onto a circle with
//              arc-length boundary spacing, scaled so that every chart's texel area is
//              proportional to its surface area, rotated to its smallest bounding box and packed
//              (shelves) with gutters. A chart whose map folds (the authalic weights can be
//              negative) falls back to Floater's mean value coordinates, which cannot fold.
//   Lscm       the same charts mapped by least squares conformal maps (Lévy et al. 2002, free
//              boundary): angle preserving, so area is distorted wherever a chart is curved: the
//              non-area-preserving map of seed Fig. 4.7. A chart whose map folds or whose
//              boundary crosses itself is split and mapped again.
//   Triangles  every triangle its own chart, laid out isometrically with one global scale (zero
//              area distortion) and packed by bounding box with a 1-texel gutter: the fallback,
//              and a second parameterisation to compare. Seams everywhere, low utilisation.
//   Mesh UVs   the mesh's own texture coordinates, when AtlasOptions::useMeshUVs asks for them
//              and they are valid (meshUVProblem); otherwise the method above is built and
//              Atlas::meshUVRejection says why they were not used.
//
// Texel conventions: the atlas has size × size texels; texel (x, y) covers
// [x, x + 1) × [y, y + 1) / size in UV, its centre at (x + ½, y + ½) / size; rows are stored with
// y = 0 first (v = 0 is the first row, as OpenGL's texture origin).
//
// Determinism: charts are grown sequentially in face order and mapped in parallel into
// per-chart slots, so the atlas is bit-identical for any number of threads.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "translucent/geometry/mesh.h"

namespace translucent::geometry {

// Thrown for bad atlas options (the message names the parameter) and for meshes that cannot be
// parameterised; unreadable cache files are never errors (CachedAtlas::note).
class AtlasError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

enum class AtlasMethod { Authalic, Lscm, Triangles, MeshUVs };
// "authalic", "lscm", "triangles", "mesh-uvs"; parseAtlasMethod accepts the first three and throws
// AtlasError listing them (the mesh's UVs are asked for with AtlasOptions::useMeshUVs).
const char* toString(AtlasMethod method);
AtlasMethod parseAtlasMethod(const std::string& name);

struct AtlasOptions {
  uint32_t size = 1024;                    // texels per side, 16 .. 16384
  // Lscm by default, not the seed's (and the issue's) area-preserving authalic map: CGAL's discrete
  // authalic map needs a fixed convex (circular) border, which squeezes the boundary triangles,
  // so on the bunny, armadillo and cow it distorts area more than LSCM does (RMS ln(A_T/A_S)
  // 0.153 / 0.156 / 0.145 against 0.110 / 0.114 / 0.085 at 1024², BENCHMARKS.md of commit 91fe617) and, split
  // into tens of thousands of charts to stay fold-free, uses a third of the texels.
  AtlasMethod method = AtlasMethod::Lscm;  // Authalic, Lscm or Triangles
  bool useMeshUVs = false;                 // keep the mesh's UVs when they are valid
  // Texels between charts (and half of it to the atlas border); 0: the method's default, 2 for
  // charts (bilinear lookups and conservative coverage stay inside a chart's own texels), 1 for
  // Triangles (every texel of gutter costs a whole triangle's worth of atlas there).
  uint32_t gutter = 0;
  // Chart growing: a face joins a chart while its normal is within this angle of the chart's
  // mean normal [degrees, 10 .. 90], and while the chart's area is at most maxChartArea of the
  // mesh's (0 .. 1]. Smaller charts distort less and cost more gutter.
  double maxChartAngle = 60.0;
  double maxChartArea = 0.05;
};

struct Atlas {
  uint32_t size = 0;                    // texels per side
  AtlasMethod method = AtlasMethod::Authalic;  // what was built (MeshUVs when kept)
  uint32_t gutter = 0;                  // texels between charts (0 for MeshUVs)
  std::string meshUVRejection;          // why the mesh's UVs were not kept (empty: kept or not
                                        // asked for)
  std::vector<glm::vec2> uvs;           // per corner: 3 per triangle, in [0, 1]²,
                                        // counter-clockwise when the triangle is
  std::vector<double> surfaceArea;      // A_S per triangle [scene units²]
  std::vector<double> texelArea;        // A_T per triangle [texels]: the UV area × size²
  std::vector<uint32_t> chart;          // chart id per triangle, 0 .. chartCount - 1
  uint32_t chartCount = 0;
  uint32_t foldedCharts = 0;            // charts whose first map folded (re-mapped or split)
  uint32_t distortedCharts = 0;         // charts split because their map distorted area too much

  size_t triangleCount() const { return surfaceArea.size(); }
  // The corner UVs of triangle t.
  glm::vec2 uv(size_t t, int corner) const { return uvs[3 * t + static_cast<size_t>(corner)]; }
};

// Why the mesh's own UVs cannot serve as an atlas, or empty when they can: every triangle has
// positive (counter-clockwise) UV area, every UV is inside [0, 1]², no two triangles overlap.
std::string meshUVProblem(const TriangleMesh& mesh);

using AtlasProgress = std::function<void(uint64_t done, uint64_t total)>;
// Builds the atlas of a mesh that passes validate(). Throws AtlasError naming the option for
// options out of range, or when the charts do not fit into the atlas.
Atlas buildAtlas(const TriangleMesh& mesh, const AtlasOptions& options,
                 const AtlasProgress& progress = {});

// ---- Coverage: which triangle owns each texel -------------------------------------------------
// A texel belongs to the triangle that contains its centre (a centre exactly on an edge or
// vertex goes to one of the triangles by a fixed symbolic perturbation of the centre, so that
// neighbours in a chart never both take it). A triangle that contains no texel centre (smaller
// than a texel, or a sliver) then takes, conservatively, the nearest texel whose square it
// touches: an empty one if there is one, else one from a neighbour that keeps at least one.
struct AtlasCoverage {
  uint32_t size = 0;
  std::vector<int32_t> owner;          // size × size, row y = 0 first; -1: no triangle
  std::vector<uint32_t> texels;        // texels each triangle owns
  size_t conflicts = 0;                // texel centres strictly inside two triangles (overlaps)
  size_t conservative = 0;             // texels given to triangles without a texel centre
  size_t uncovered = 0;                // triangles still without a texel (should be 0)
  size_t ownedTexels = 0;

  int32_t at(uint32_t x, uint32_t y) const { return owner[size_t{y} * size + x]; }
};
AtlasCoverage rasterizeCoverage(const Atlas& atlas);

// A texel's point on the surface: the barycentric coordinates of its centre in its triangle's
// UVs (the closest point of the triangle for a conservatively given texel), the position, and the
// normal (interpolated vertex normals, normalised; the face normal when the mesh has none).
struct TexelSurfacePoint {
  uint32_t triangle = 0;
  glm::dvec3 barycentric{0.0};
  glm::dvec3 position{0.0};
  glm::dvec3 normal{0.0};
};
std::optional<TexelSurfacePoint> texelSurfacePoint(const TriangleMesh& mesh, const Atlas& atlas,
                                                   const AtlasCoverage& coverage, uint32_t x,
                                                   uint32_t y);

// ---- Statistics ---------------------------------------------------------------------------
// Area distortion d_T = ln((A_T / ΣA_T) / (A_S / ΣA_S)): 0 for a map whose texel area is
// proportional to surface area; its distribution is weighted by A_S (the fraction of the surface
// that is under- or oversampled, seed 3.2.1).
struct AtlasStatistics {
  double distortionRms = 0.0;   // sqrt(Σ A_S d² / Σ A_S)
  double distortionMean = 0.0;  // Σ A_S d / Σ A_S
  double distortionP05 = 0.0, distortionP50 = 0.0, distortionP95 = 0.0;  // area-weighted
  double distortionMin = 0.0, distortionMax = 0.0;
  double utilisation = 0.0;     // ΣA_T / size²: the fraction of the atlas inside triangles
  double coveredFraction = 0.0; // owned texels / size²
  uint32_t charts = 0;
  size_t triangles = 0;
  size_t trianglesBelowOneTexel = 0;  // A_T < 1 texel (owned conservatively)
  // Σ_texels A_S/A_T of the owner over Σ A_S: how well the texels recover the surface area
  // (1 exactly when every triangle owns texels in proportion to A_T).
  double recoveredAreaRatio = 0.0;
};
// d_T per triangle.
std::vector<double> areaDistortion(const Atlas& atlas);
AtlasStatistics atlasStatistics(const Atlas& atlas, const AtlasCoverage& coverage);

// Number of pairs of triangles whose UV interiors overlap (0 for a valid atlas): exact
// separating-axis tests between the triangles sharing a cell of a uniform grid.
size_t countUVOverlaps(const std::vector<glm::dvec2>& cornerUVs);

// ---- On-disk cache ------------------------------------------------------------------------
// In defaultCacheDirectory() (point_cloud.h) unless told otherwise; the file name holds the mesh
// hash (and the UVs' hash when they are asked for), the method, size, gutter, chart options and
// the format/algorithm version.
std::string atlasCacheFileName(const TriangleMesh& mesh, const AtlasOptions& options);

struct CachedAtlas {
  Atlas atlas;
  bool fromCache = false;
  std::filesystem::path file;
  std::string note;  // empty, or why the cache could not be read or written
};
// Reads one atlas cache file for `mesh`: its content hash must match (a tampered or truncated
// file is refused) and its counts the mesh. Throws AtlasError naming the file.
Atlas readAtlasCache(const std::filesystem::path& file, const TriangleMesh& mesh);
CachedAtlas loadOrBuildAtlas(const TriangleMesh& mesh, const AtlasOptions& options,
                             const std::filesystem::path& cacheDir,
                             const AtlasProgress& progress = {});
CachedAtlas loadOrBuildAtlas(const TriangleMesh& mesh, const AtlasOptions& options,
                             const AtlasProgress& progress = {});

}  // namespace translucent::geometry
