// SPDX-License-Identifier: GPL-3.0-or-later
// `translucent compare`: the parts that need no GPU. The CLI (apps/cli/cmd_compare.cpp) renders
// the real-time techniques and hands their frames to this library, which computes the two
// references, caches them, builds the masks and assembles the metrics that the report
// (analysis/report.h) shows.
//
// Three images are compared per pair, per pixel average (camera.h):
//   exitance        radiant exitance B
//   radiance        the diffusion radiance L = Ft(η, ω_o) B / π (Eq. 2.16, Jensen convention),
//                   divided by 4C_φ(1/η) under the normalized convention (exit_radiance.h)
//   cone_radiance   the true radiance towards the camera (the path tracer's cone average): what a
//                   technique's L should be; physical reference only
// and three pairs give the errors:
//   technique vs model      the technique's own error (its approximation of the BSSRDF model)
//   model vs physical       the model's error (the BSSRDF against volumetric transport)
//   technique vs physical   the total error
//
// References (each with a per-pixel standard error):
//   physical   reference::MeshPathTracer (volumetric photon tracing, seed 3.2), `count` photons
//              per channel; or (method "camera") reference::CameraPathTracer, `count` camera
//              paths per pixel and channel, whose cone_radiance is the true radiance (cone 0)
//              and whose radiance is Ft·B/π, the diffusion convention
//   model      reference::renderModelReference (the scene's BSSRDF integrated over the whole
//              surface), `count` samples, of the scene's material (scene::sceneMaterial): for a
//              heterogeneous one brute-force Eq. 8 with per-point profiles (model_reference.h)
// Heterogeneous materials (materialReferences below): a 3D field has a volume, so the physical
// reference is the path tracer through the field; a 2D surface map has none, so there is no
// physical reference and the model reference (brute-force Eq. 8) is the reference.
// Both are stored with the Jensen radiance; the normalized one is the same image divided by the
// constant 4C_φ(1/η) = diffuseTransmittanceFromOutside(η) (exit_radiance.h), exactly what
// exitRadianceFactor computes per sample, so one cached reference serves both conventions.
//
// Masks: the metrics are taken over interior pixels only, where every one of a stratified grid
// of camera rays through the pixel hits the mesh (and, when the model reference is there, where
// its coverage is 1): silhouette pixels average surface and background, and a technique that
// rasterises them differently is not wrong. The cone radiance is biased low within θc of the
// silhouette (camera.h: part of the cone lies below the horizon), so its mask also requires
// n·v >= sin θc for every ray of the grid.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "translucent/analysis/metrics.h"
#include "translucent/bssrdf/exit_radiance.h"
#include "translucent/geometry/mesh.h"
#include "translucent/reference/slab.h"  // ProgressCallback
#include "translucent/scene/scene.h"

namespace translucent::reference {
class McImage;
}

namespace translucent::analysis {

// Bumped whenever a reference computed from the same inputs would change (tracer, model
// reference or cache layout): old cache entries then miss.
inline constexpr int kReferenceCodeVersion = 1;

// An RGB image, rows from the top, with its per-pixel standard error (empty: exact).
struct CompareImage {
  int width = 0, height = 0;
  std::vector<float> rgb, se;
  bool empty() const { return rgb.empty(); }
  ImageRef ref() const { return {width, height, rgb, se}; }
  // The image (and its error) times `factor`.
  CompareImage scaled(double factor) const;
};

// A Monte Carlo image with its standard error (what the physical reference stores, also for a
// path tracer refined pass by pass, as the explorer's Compare dock does).
CompareImage toCompareImage(const reference::McImage& image);

enum class ReferenceKind { Physical, Model };
const char* toString(ReferenceKind kind);  // "physical", "model"
// "physical" or "model"; ParameterError naming `option` otherwise.
ReferenceKind parseReferenceKind(const std::string& name, const std::string& option);

struct ReferenceRequest {
  ReferenceKind kind = ReferenceKind::Physical;
  uint64_t count = 0;  // photons per channel (physical, light), camera paths per pixel and
                       // channel (physical, camera) or samples (model)
  uint64_t seed = 1;
  int threads = 0;     // 0: all cores (results do not depend on it)
  int subpixels = 1;   // model: rays per pixel per axis (1: the pixel centre, as techniques shade)
  // Physical: "cpu" or "gpu" (reference/gpu/mesh_gpu.h: other random streams, so other images
  // of the same quantity; in the key only when "gpu", so CPU keys stay as they were). "gpu"
  // opens a GL context of its own for the trace (`compare --reference-device gpu`).
  std::string device = "cpu";
  // Physical: "light" (photons from the lights, reference::MeshPathTracer: its cone_radiance the
  // cone average over the scene's cone_angle) or "camera" (paths from the camera,
  // reference::CameraPathTracer: its cone_radiance the true radiance, cone half-angle 0). In the
  // key only when "camera", so light keys stay as they were.
  std::string method = "light";
};

struct Reference {
  ReferenceKind kind = ReferenceKind::Physical;
  CompareImage exitance, radiance;  // radiance: Jensen convention
  CompareImage cone_radiance;       // physical only: the true radiance towards the camera
  // Physical: the half-angle its cone_radiance averages over (degrees; 0 from the camera
  // method: the true radiance); none: the scene's cone_angle (the light method).
  std::optional<double> cone_angle;
  std::vector<float> coverage;      // model only: fraction of camera rays hitting the mesh
  ReferenceRequest request;
  uint64_t count_done = 0;  // photons per channel / samples actually computed
  double seconds = 0.0;     // compute time (of the original run when read from the cache)
  bool partial = false;     // stopped early (Ctrl-C): never cached
  bool from_cache = false;
  std::string key;          // referenceKey()
  std::filesystem::path cache_file;  // where it was read or stored ("" when not)
  std::string cache_note;   // why it was not cached, if so

  // L under `convention`: the Jensen image scaled by 1 / (4C_φ(1/η)) for Normalized.
  CompareImage radianceFor(bssrdf::ExitConvention convention, double eta) const;
};

// The material's part of a reference's cache key: a text that changes whenever the material would
// change a reference, so that a heterogeneous scene never reuses a homogeneous reference (nor one
// of another field or map). For now the homogeneous fields: {"kind": "homogeneous", the model,
// σa, σs, g, η, scale}. A heterogeneous material's description (its kind, field or map with
// parameters, file contents by hash, surface_depth) is to be fed to referenceKey below in its
// place, here, once scenes describe one. The heterogeneous model reference's own settings
// (ModelReferenceOptions::profile_segments) are code defaults: changing them needs a
// kReferenceCodeVersion bump.
std::string referenceMaterialDescription(const scene::Scene& scene);

// The hash (SHA-256, hex) of everything a reference depends on: the scene's canonical JSON
// (scene::toJson) without the technique and display settings, the material description, the mesh
// file's bytes, the kind, count, seed and subpixels, the stored convention and
// kReferenceCodeVersion. Not the thread count (a run is a function of its seed only). Throws
// ParameterError naming the mesh file when it cannot be read. Without a description:
// referenceMaterialDescription(scene).
std::string referenceKey(const scene::Scene& scene, const ReferenceRequest& request);
std::string referenceKey(const scene::Scene& scene, const ReferenceRequest& request,
                         const std::string& material_description);
// The JSON text that referenceKey hashes (for the report and for tests).
std::string referenceKeyText(const scene::Scene& scene, const ReferenceRequest& request);
std::string referenceKeyText(const scene::Scene& scene, const ReferenceRequest& request,
                             const std::string& material_description);

// Which reference is physical for a material, in words for the report.
struct MaterialReferences {
  std::string kind;          // "homogeneous", "volume" (3D field), "surface" (2D map)
  bool physical = true;      // a physical reference can be computed for it now
  std::string text;          // one or two sentences: which reference is physical and why
};
MaterialReferences materialReferences(const material::Material& material);

// Complete references on disk: <dir>/<kind>-<key>.exr (every image and its error as layers,
// readable by any EXR viewer) and .json (what it is, how long it took).
class ReferenceCache {
 public:
  explicit ReferenceCache(std::filesystem::path dir) : dir_(std::move(dir)) {}
  const std::filesystem::path& dir() const { return dir_; }
  std::filesystem::path fileFor(ReferenceKind kind, const std::string& key) const;
  // The cached reference, or nothing when there is none (or it is unreadable or does not match:
  // then `note` says why).
  std::optional<Reference> load(ReferenceKind kind, const std::string& key, int width, int height,
                                std::string* note = nullptr) const;
  // Stores a complete reference (atomically: written to a temporary name, then renamed); sets
  // its cache_file, or cache_note when the folder cannot be written (never an error).
  void store(Reference& reference) const;

 private:
  std::filesystem::path dir_;
};

// Writes a reference as EXR: base RGB the exitance, layers exitance_stderr, radiance,
// radiance_stderr, cone_radiance and cone_radiance_stderr (physical), coverage (model).
void writeReferenceExr(const std::filesystem::path& path, const Reference& reference,
                       const std::string& source);

// $TRANSLUCENT_CACHE_DIR, $XDG_CACHE_HOME/translucent or ~/.cache/translucent, then "references".
std::filesystem::path defaultReferenceCacheDirectory();

// Computes a reference of the scene (mesh: scene::loadSceneMesh(scene)) with its material
// (scene::sceneMaterial(scene, mesh)). Progress counts photons (physical, all channels) or
// samples (model); returning false stops it: the result is partial. Throws ParameterError naming
// what the reference cannot handle (a light type, a .bssrdf model, a physical reference of a
// material that has none: materialReferences(...).physical false).
Reference computeReference(const scene::Scene& scene, const geometry::TriangleMesh& mesh,
                           const ReferenceRequest& request,
                           const reference::ProgressCallback& progress = {});

// The cached reference when there is one, otherwise computed and (when complete) stored.
Reference cachedReference(const scene::Scene& scene, const geometry::TriangleMesh& mesh,
                          const ReferenceRequest& request, const ReferenceCache* cache,
                          const reference::ProgressCallback& progress = {});

// A physical reference from the outputs of `translucent pathtrace mesh` (or of `translucent merge`
// of its shards, issue 17): its JSON file and the EXR that JSON names (a relative name is looked
// up beside the JSON first, then from the working directory). It must be a complete run of this
// scene, material and mesh (with any photon count and seed: each gives a reference of the scene):
// its "reference_key" must be referenceKey(scene, {physical, its photons per channel, its
// seed}); otherwise ParameterError naming the file and the parts of the key that differ (scene,
// medium, material, mesh file, ...).
Reference loadPathtracedReference(const std::filesystem::path& json_file, const scene::Scene& scene);

// Of several such runs (`--reference-from` given once per file, e.g. the merged references of a
// suite's scenes traced on a cluster), the first traced for this scene and its file; std::nullopt when none
// is, and then *why says for each file what differs (the message loadPathtracedReference throws,
// joined by "; "). A file that is not such a run, is partial or unreadable is a ParameterError.
struct ReferenceFromFile {
  Reference reference;
  std::filesystem::path file;
};
std::optional<ReferenceFromFile> findPathtracedReference(const std::vector<std::filesystem::path>& json_files,
                                                 const scene::Scene& scene, std::string* why = nullptr);

// Per pixel 1 where all grid × grid camera rays (stratified, pixel centres of the cells) hit the
// mesh and, when min_cos > 0, see it with |n·v| >= min_cos; 0 elsewhere.
std::vector<uint8_t> interiorMask(const geometry::TriangleMesh& mesh,
                                  const reference::Camera& camera, int grid, double min_cos);

struct Masks {
  std::vector<uint8_t> interior;  // for exitance and radiance
  std::vector<uint8_t> cone;      // for cone_radiance: also n·v >= sin θc
  uint64_t interiorPixels() const;
  uint64_t conePixels() const;
};
// interiorMask with a grid of 4, and-ed with coverage == 1 when `model_coverage` is not empty.
// The cone half-angle of the physical reference among `references` (Reference::cone_angle: 0
// from the camera method); nullopt (the scene's cone_angle) for the light method's or none.
std::optional<double> physicalConeAngle(std::span<const Reference> references);

// `cone_angle`: the physical reference's (physicalConeAngle; default the scene's).
Masks compareMasks(const scene::Scene& scene, const geometry::TriangleMesh& mesh,
                   std::span<const float> model_coverage,
                   std::optional<double> cone_angle = std::nullopt);

// The metrics of `test` against `reference` over `mask` (`display`: the tone mapping for SSIM
// and FLIP; its mask is replaced); ParameterError when the sizes differ.
Metrics compareImages(const CompareImage& test, const CompareImage& reference,
                      std::span<const uint8_t> mask, const MetricOptions& display = {});

// One row of the report's tables.
struct PairMetrics {
  std::string test;       // technique name, or "model"
  std::string reference;  // "model" or "physical"
  std::string quantity;   // "exitance", "radiance", "cone_radiance"
  std::string convention; // of L ("jensen"/"normalized"; "" for exitance)
  std::string mask;       // "interior" or "interior_cone"
  Metrics metrics;
};

// What one technique's frame gives compare (apps render it; analysis does not see the GPU).
struct TechniqueImages {
  std::string name;
  bssrdf::ExitConvention convention = bssrdf::ExitConvention::Jensen;
  CompareImage radiance;  // L
  CompareImage exitance;  // B; empty when the technique has none
};

// Every pair of the header comment for one technique (against the references present).
std::vector<PairMetrics> techniqueMetrics(const TechniqueImages& technique,
                                          std::span<const Reference> references, double eta,
                                          const Masks& masks, const MetricOptions& display = {});
// The model against the physical reference (B, and L under `convention` against the diffusion
// and the true radiance); empty unless both references are present.
std::vector<PairMetrics> modelMetrics(std::span<const Reference> references,
                                      bssrdf::ExitConvention convention, double eta,
                                      const Masks& masks, const MetricOptions& display = {});

}  // namespace translucent::analysis
