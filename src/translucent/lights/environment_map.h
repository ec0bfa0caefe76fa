// SPDX-License-Identifier: GPL-3.0-or-later
// Environment lighting, shared by the real-time techniques and the references: a
// latitude-longitude radiance map, its irradiance as nine spherical-harmonic coefficients (the
// point-cloud technique's unoccluded IBL, seed 3.3.2 "Image Based Lighting"), and importance
// sampling of directions (the technique's occluded IBL, where each sampled direction becomes a
// shadow-mapped directional light; the path tracer's photon emission; the model reference's
// irradiance integral).
//
// Directions (scene::EnvironmentLight): +y up; pixel column u ∈ [0, 1) has azimuth
// φ = 2π u − π and row v ∈ [0, 1) polar angle θ = π v from +y, direction
//     d = (sin θ sin φ, cos θ, −sin θ cos φ)
// (the centre column looks along −z), then rotated by `rotate` degrees about +y.
//
// Transmitted irradiance (what the subsurface transport receives), for a unit normal n:
//     E(n) = ∫ L(ω) Ft(η, n·ω) max(n·ω, 0) dω.
// The kernel k(t) = Ft(η, t) max(t, 0) is zonal, so by the Funk-Hecke theorem
//     E(n) = Σ_lm λ_l L_lm Y_lm(n),   λ_l = 2π ∫0^1 Ft(η, t) t P_l(t) dt
// (Ramamoorthi & Hanrahan 2001 for Ft = 1: λ_0 = π, λ_1 = 2π/3, λ_2 = π/4). Nine terms (l ≤ 2)
// capture a cosine-like kernel to within a few percent.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/ext/vector_int2.hpp>
#include <glm/vec3.hpp>

namespace translucent::lights {

struct EnvironmentMap {
  int width = 0, height = 0;
  std::vector<float> rgb;  // linear radiance, rows from the top (θ = 0 first)
  size_t clamped_negative = 0;  // values < 0 in the file, read as 0 (load())

  // Reads an EXR/HDR/... file through OpenImageIO (analysis::readRgb); negative values read as
  // 0 (counted in clamped_negative). Throws ParameterError naming the file when it cannot be
  // read, is empty or holds non-finite values.
  static EnvironmentMap load(const std::filesystem::path& file);
  // A map of constant radiance (tests, furnace checks).
  static EnvironmentMap constant(const glm::vec3& radiance, int width = 64, int height = 32);

  glm::vec3 texel(int x, int y) const;
  // Direction of a point (u, v) ∈ [0,1)² of the map, rotated by `rotate` degrees about +y.
  static glm::dvec3 direction(double u, double v, double rotate);
  // The texel (x, y) that direction d falls in, for the same rotation.
  glm::ivec2 texelOf(const glm::dvec3& d, double rotate) const;
  // Radiance towards direction d (nearest texel: the map is piecewise constant), same rotation.
  glm::vec3 lookup(const glm::dvec3& d, double rotate) const;
};

// λ_l of the transmitted-irradiance kernel for l = 0, 1, 2 (see above).
std::array<double, 3> transmittedIrradianceLambdas(double eta);

// Irradiance SH coefficients λ_l L_lm, l ≤ 2 (index l² + l + m), RGB, scaled by `scale`
// (intensity × colour). The real SH basis and ordering of shaders/pointcloud/irradiance.comp.
std::array<glm::vec3, 9> irradianceSh9(const EnvironmentMap& map, double rotate, double eta,
                                       const glm::dvec3& scale);
// E(n) from those coefficients (clamped to >= 0), as the shader does.
glm::dvec3 evalSh9(const std::array<glm::vec3, 9>& sh, const glm::dvec3& n);

// What a sampler's density follows: the luminance (Rec. 709 weights) or one colour channel.
enum class SampleWeight { Luminance, Red, Green, Blue };

// Importance sampling of directions with density proportional to the chosen weight of the map's
// radiance, exactly for the piecewise-constant map that lookup() evaluates: a texel is chosen
// with probability w(texel) ΔΩ(texel) / Σ w ΔΩ, where ΔΩ = Δφ (cos θ0 - cos θ1) is its exact
// solid angle, then a direction uniformly in solid angle within it (φ uniform, cos θ uniform).
// The pdf is then w(texel) / integral() per steradian, constant over a texel, so the estimator
// L/pdf of the sampled channel is the constant integral(): the path tracer's photons all carry
// the same flux. Throws ParameterError when the weight is zero everywhere. Keeps a pointer to the
// map: the map must outlive the sampler.
class EnvironmentSampler {
 public:
  EnvironmentSampler(const EnvironmentMap& map, double rotate,
                     SampleWeight weight = SampleWeight::Luminance);

  struct Sample {
    glm::dvec3 direction{0.0};  // unit, towards the environment
    glm::dvec3 radiance{0.0};   // L(ω) (RGB)
    double pdf = 0.0;           // per steradian
  };
  // The sample for u ∈ [0,1)²: u.y picks the row, then u.x the column (both by inverting the
  // cumulative sums), and the remainders place the direction within the texel.
  Sample sample(const glm::dvec2& u) const;
  // Density of sample() towards unit direction d [1/sr] (0 where the weight is 0).
  double pdf(const glm::dvec3& d) const;
  // ∫ w(L(ω)) dω over the sphere [radiance × sr].
  double integral() const { return total_; }
  // The cumulative sums sample() inverts (for a device copy): over the rows (height + 1), and
  // over the columns of row y (width + 1), of w × the texel's solid angle.
  const std::vector<double>& rowSums() const { return rowCdf_; }
  const std::vector<double>& columnSums(int y) const { return colCdf_[size_t(y)]; }
  // Sample k of the technique's fixed sequence (R2 quasi-random sequence, Roberts 2018,
  // Cranley-Patterson rotated by `seed`): stratified over any prefix, deterministic.
  Sample sequence(uint64_t k, uint64_t seed) const;

 private:
  double weightOf(const glm::vec3& c) const;
  const EnvironmentMap* map_;
  double rotate_;
  SampleWeight weight_;
  std::vector<double> rowCdf_;               // height + 1, Σ w ΔΩ
  std::vector<std::vector<double>> colCdf_;  // per row, width + 1, Σ w ΔΩ
  std::vector<double> rowWeight_;
  double total_ = 0.0;  // Σ w ΔΩ over texels
};

}  // namespace translucent::lights
