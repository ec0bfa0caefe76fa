// SPDX-License-Identifier: GPL-3.0-or-later
// The "model" reference of `translucent compare`: the exact value that the real-time techniques
// approximate with the scene's BSSRDF model, by brute-force integration of the model's radial
// profile over the whole mesh for every visible pixel (seed 2.6.4 / 3.3, without the hierarchy):
//
//   B_c(x_o) = ∫_A R_c(|x_o - x_i|) E_c(x_i) dA(x_i)                        [W/unit²]
//   E_c(x)   = Σ_lights Ft(η, n·l) max(0, n·l) E_l(x) colour_c V(x, l)      (transmitted irradiance)
//   L_c      = exitRadianceFactor(convention, η, n_s·v) B_c                 (bssrdf/exit_radiance.h)
//
// with R_c the profile of channel c (chord distance, as the techniques and sphere_integration.h),
// E_l the light's irradiance at x on a plane facing it (directional: E; point: I/d²; beam:
// P/(π r²) inside its disc, downstream of its origin), V an Embree shadow ray. An environment
// light contributes ∫ L_c(ω) Ft(η, n·ω) max(0, n·ω) V(x, ω) dω, estimated per point by
// environment_rays shadow rays: half from the map's luminance sampler, half cosine-distributed,
// combined by the balance heuristic (Veach 1997); its noise is independent from point to point,
// so it is part of the per-sample terms' spread and of the standard error below (at the camera
// hits, 4x the rays, and their variance is added to the near field's). Technique minus
// model is then the technique's own error, model minus path tracer the model's.
//
// Normals, as the point-cloud technique (techniques/pointcloud) uses them:
//   irradiance   the point cloud's normal (geometry/point_cloud.h): the interpolated vertex normal
//                when the mesh has normals, else the face normal (irradiance.comp uses it);
//   exit         the G-buffer's normal: the interpolated smooth vertex normal (the mesh's normals,
//                else area-weighted face normals: geometry::ambientOcclusionNormals, the same as
//                techniques::vertexNormals), turned towards the viewer when the hit face is a back
//                face (gbuffer.frag); Ft(η, n_s·v) = 0 where n_s·v <= 0 (as pcFresnelTransmittance).
// The mesh must be closed; a copy is wound outwards (TriangleMesh::orientOutwards), as the
// technique does, so that face normals point out.
//
// Integration. N points x_k are drawn area-uniformly and independently on the mesh
// (geometry::samplePointCloud, method Random: deterministic for a seed on any thread count) and
// E(x_k) is computed once for each. For a camera hit x_o,
//   B(x_o) ≈ E(x_o) F(ρ) + (A/N) Σ_k R(|x_o - x_k|) E(x_k) [ρ <= |x_o - x_k| <= r_max],
// F(ρ) = 2π∫0^ρ R r dr (the profile's exact cumulative). The disc |x - x_o| < ρ is done
// analytically because every profile peaks at r = 0 (normalized diffusion's R ~ 1/r gives the
// plain estimator infinite variance). It assumes E ≈ E(x_o) and that the surface area within chord
// distance r of x_o is π r², which holds exactly on a plane and on a sphere (Archimedes: a cap of
// chord radius r has area π r²); the bias left is second order in ρ (ΔE and the difference of the
// principal curvatures; the tests vary ρ and find no change above the noise).
// ρ = near_field · sqrt(A/N) (a few sample spacings).
// Truncation: samples beyond r_max = max_c (radius holding 1 - tail of Rd_c) are skipped (a
// uniform grid prunes them); on a flat surface that drops at most tail_fraction[c] · max E of B_c
// (reported per channel).
// Profiles: R is read from a table uniform in s = sqrt(r) on [sqrt(ρ), sqrt(r_max)] (dense where
// the profile is steep), linearly interpolated; the table is refined until the interpolation
// error at the midpoints is below 1e-4 relative (or 2^16 entries); table_error reports
// ∫|R_table - R| 2πr dr / Rd over [ρ, r_max], the bound on the relative error this adds to B.
//
// Pixels: subpixels² camera rays per pixel, stratified: at the centres of their strata (default;
// subpixels 1: the pixel centre, where a rasteriser shades) or jittered in them. A ray that misses
// scores 0, so pixel values are image-plane averages like the path tracer's (camera.h), and
// coverage is the fraction of rays that hit. Without jitter the pixel value is the midpoint rule
// of the pixel average: its quadrature error is not part of the standard error (second order in
// the pixel size inside smooth regions, first order at silhouettes and shadow edges); with jitter
// the pixel average is unbiased and the standard error includes the rays' part (below).
//
// Standard error. The per-sample terms t_k = A · (1/S) Σ_s R(|x_s - x_k|) E(x_k) (S rays of a
// pixel, misses 0) are iid, so the sample variance of t_k over N gives the standard error of the
// surface integration for the pixel value (the sub-rays share the samples, hence one term per
// sample, not per ray); over 8 seeds the measured variance of the pixels is 1.1-1.2x the
// reported one (tests; the per-sample terms are heavy-tailed, so the sample variance tends to
// fall a little short of the true one at these sample counts). With jitter, the variance from the ray positions is estimated as if the rays were
// independent and uniform in the pixel: the spread of the per-ray values over S(S - 1), the
// spread taken as the product of the deviations computed from the even- and the odd-indexed
// samples (independent halves, so the samples' noise adds nothing to it in expectation). That
// ignores the stratification and so over-estimates: on the test scene the reported variance is
// ~2.7x the measured one.
//
// Determinism: the samples and E depend only on the seed; each pixel is one sum in a fixed order
// on one thread, and the sub-ray jitter of pixel p is the stream Rng(seed, p). The images are
// bit-identical for a seed whatever the thread count.
//
// Units: scene units; the medium's coefficients per medium unit, Medium::channel applies its scale
// (as for MeshPathTracer).
//
// Heterogeneous materials (material/material.h; the overload taking a material::Material). The
// kernel is Eq. 8 of SubEdit (material/point_profiles.h) brute-forced over the surface:
//   B(x_o) ≈ E(x_o) F_o(ρ) + (A/N) Σ_k sqrt(P_k(r) P_o(r)) E(x_k) [ρ <= r = |x_o - x_k| <= r_cut],
// P_k the profile of sample k's local medium (Material::surfaceMedium at its position, its
// irradiance normal and, for a surface map, its atlas UV), P_o that of the camera hit x_o (the
// same), both in the per-point representation of material::PointProfiles: profile_segments
// segments of ln P on [0, r_s], r_s the largest 95% radius over the samples' media (the hits' use
// the same r_s, so Eq. 8 combines nodes of one grid), the extrapolated tail cut at r_cut = 3 r_s,
// which is the pruning radius. F_o(ρ) = 2π∫0^ρ P_o r dr of x_o's own representation (Gauss-
// Legendre per segment): the near disc is the local homogeneous approximation, E ≈ E(x_o) and
// the medium ≈ x_o's within ρ; what is left is second order in ρ as above, plus the change of
// the medium across the disc where a boundary between media crosses it (the disc is a few sample
// spacings wide). With one medium everywhere the sum is the homogeneous one with the
// representation's profile instead of the model's: it differs from the homogeneous reference by
// the representation's error (at most 2.2e-3 of B at n = 64 on the test sphere,
// tests/reference/test_model_reference_hetero.cpp). Cost: ~2x the homogeneous AVX2 loop per
// (sample, hit) pair (BENCHMARKS.md of commit 91fe617); r_cut is usually a little below r_max.
// The inner loop is scalar double arithmetic (no table, no AVX2): the same standard errors (one
// term per sample, the two halves for the jitter), determinism and progress/stop as above. The
// atlas of a surface map is the default one (geometry::AtlasOptions{}, cached), read at the
// triangles' UVs by material/surface_uv.h as the point-cloud technique reads it. Media are
// deduplicated: a field of a few media costs a few profile evaluations; a continuous field one
// per sample and per camera hit.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "translucent/bssrdf/exit_radiance.h"
#include "translucent/bssrdf/profile.h"
#include "translucent/geometry/mesh.h"
#include "translucent/optics/medium.h"
#include "translucent/reference/camera.h"
#include "translucent/reference/transport.h"

namespace translucent::material {
struct Material;
}

namespace translucent::reference {

struct ModelReferenceOptions {
  uint64_t samples = 200000;  // surface samples (area-uniform), 1 .. 2^24 - 1; more = less noise
  int subpixels = 2;          // camera rays per pixel per axis (stratified), 1 .. 16
  uint64_t seed = 1;
  int threads = 0;            // 0: all
  bssrdf::ExitConvention convention = bssrdf::ExitConvention::Jensen;  // L = exitRadianceFactor(...) * B
  bool jitter = false;        // true: rays jittered in their strata (false: at the strata's centres)
  double near_field = 3.0;    // ρ in sample spacings sqrt(A/N), > 0
  double tail = 1e-4;         // fraction of Rd beyond the pruning radius r_max, in (0, 0.01]
  bool portable = false;      // the baseline-ISA inner loop even where AVX2 + FMA is available
  int environment_rays = 64;  // shadow rays per sample for E from an environment light (even,
                              // 2 .. 4096; 4x at the camera hits)
  int profile_segments = 64;  // heterogeneous materials: segments n of each point's ln P
                              // (material::PointProfiles), 1 .. 1024; more = closer to the model

  // Throws ParameterError naming the bad field.
  void validate() const;
};

struct ModelReferenceImages {
  int width = 0, height = 0;
  std::vector<float> exitance, exitance_se;  // RGB interleaved, rows from the top: pixel average of B [W/unit²], and its standard error
  std::vector<float> radiance, radiance_se;  // L from B by the convention, Ft(η, ω_o) at the camera direction
  std::vector<float> coverage;               // per pixel: fraction of the camera rays that hit the mesh (1 = interior pixel)
  double seconds = 0.0;
  uint64_t samples = 0;
  bool partial = false;  // stopped by the progress callback

  // What the integration used (see the header comment).
  double area = 0.0;                // A, mesh area [unit²]
  double near_radius = 0.0;         // ρ [scene units]
  double prune_radius = 0.0;        // r_max [scene units]
  std::array<double, 3> near_fraction{};  // F_c(ρ) / Rd_c: share of Rd done analytically
  std::array<double, 3> tail_fraction{};  // 1 - F_c(r_max) / Rd_c: share of Rd pruned
  size_t table_size = 0;            // entries of the profile table
  double table_error = 0.0;         // max_c ∫|R_table - R| 2πr dr / Rd_c over [ρ, r_max]
  uint64_t lit_samples = 0;         // samples with E > 0 in some channel (the others add nothing)
  int threads = 0;
  // Heterogeneous materials (above; table_size 0, table_error 0, tail_fraction 0: the
  // representation holds no energy beyond r_cut = prune_radius; near_fraction: the largest
  // F(ρ) / F(r_cut) over the samples' media).
  bool heterogeneous = false;
  int profile_segments = 0;         // n
  double profile_radius = 0.0;      // r_s [scene units]
  size_t sample_media = 0;          // distinct local media of the samples
  size_t hit_media = 0;             // profiles evaluated for camera hits (distinct per image row)
};

// Lights: directional, point and beam (radius > 0; a pencil beam has no irradiance to sample) as
// the path tracer takes them; camera: camera.h. Throws ParameterError (bad options, medium,
// lights, camera), geometry::MeshError (invalid or open mesh), std::runtime_error (Embree).
// The progress callback counts pixels; returning false stops (rows not finished stay 0,
// partial = true).
ModelReferenceImages renderModelReference(const geometry::TriangleMesh& mesh, const Medium& medium,
                                          const bssrdf::Model& model, std::span<const Light> lights,
                                          const Camera& camera, const ModelReferenceOptions& options,
                                          const ProgressCallback& progress = {});

// The reference of a material (material/material.h; `mesh` in scene units, placed as the
// material's frame expects). A homogeneous material is exactly the overload above with
// material.medium and bssrdf::model(material.model) (bit-identical); a heterogeneous one is Eq. 8
// as in the header comment, with η and scale of material.medium. Throws ParameterError also for a
// .bssrdf file model (the local profiles need a registered one) and for a surface map whose
// mesh has no atlas (geometry::AtlasError).
ModelReferenceImages renderModelReference(const geometry::TriangleMesh& mesh,
                                          const material::Material& material,
                                          std::span<const Light> lights, const Camera& camera,
                                          const ModelReferenceOptions& options,
                                          const ProgressCallback& progress = {});

}  // namespace translucent::reference
