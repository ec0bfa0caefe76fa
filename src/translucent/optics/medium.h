// SPDX-License-Identifier: GPL-3.0-or-later
// Optical parameters of a homogeneous participating medium and the quantities derived from
// them, with the seeds' names (bssrdf-explorer sections 2.4-2.5, Jensen et al. 2001).
//
// Units: coefficients are per unit length of the medium's unit (the presets use 1/mm). `scale`
// says how many medium units one scene unit spans (seed 3.6.1: scale 100 makes a model that is one
// unit long 100 mm = 10 cm long), so coefficients per scene unit are sigma * scale.
#pragma once

#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

namespace translucent {

using Rgb = std::array<double, 3>;

inline constexpr const char* kChannelNames[3] = {"red", "green", "blue"};

// Thrown for bad parameters; the message names the parameter, channel and value.
class ParameterError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

// One colour channel of a medium: everything a radial profile model needs.
struct ScalarMedium {
  double sigma_a = 0.0;  // absorption coefficient σa [1/length]
  double sigma_s = 1.0;  // scattering coefficient σs [1/length]
  double g = 0.0;        // Henyey-Greenstein mean cosine
  double eta = 1.3;      // relative index of refraction n_medium / n_outside
  // Where the channel came from (Medium::channel): its RGB index (-1: a scalar medium of its own)
  // and the medium units per scene unit. Analytic models ignore both; a tabulated profile
  // (bssrdf/tabulated.h) is a measured R(r) per RGB channel in millimetres and needs them.
  int channel = -1;
  double scale = 1.0;

  double sigmaT() const { return sigma_a + sigma_s; }                   // σt
  double sigmaSPrime() const { return (1.0 - g) * sigma_s; }            // Eq. 2.24, σs'
  double sigmaTPrime() const { return sigma_a + sigmaSPrime(); }        // Eq. 2.23, σt'
  double albedo() const { return sigma_s / sigmaT(); }                  // α
  double reducedAlbedo() const { return sigmaSPrime() / sigmaTPrime(); }  // α' (Eq. 2.36)
  double D() const { return 1.0 / (3.0 * sigmaTPrime()); }              // Eq. 2.22
  double sigmaTr() const { return std::sqrt(sigma_a / D()); }           // σtr = sqrt(σa/D), Eq. 2.25
  double meanFreePath() const { return 1.0 / sigmaT(); }                // ℓ
  double reducedMeanFreePath() const { return 1.0 / sigmaTPrime(); }    // ℓ', Eq. 2.35
  double diffuseMeanFreePath() const { return 1.0 / sigmaTr(); }        // ℓd = 1/σtr (inf if σa=0)

  // Throws ParameterError unless all coefficients are finite, σa, σs >= 0, σt' > 0, |g| < 1 and
  // η > 0. `channel_name` is used in the message ("" for a scalar medium).
  void validate(const std::string& channel_name = "") const;
};

// A medium with per-RGB coefficients (seed 3.1.1: "material parameters").
struct Medium {
  Rgb sigma_a{0.0021, 0.0041, 0.0071};  // default: Jensen 2001 marble [1/mm]
  Rgb sigma_s{2.19, 2.62, 3.00};
  double g = 0.0;
  double eta = 1.3;
  double scale = 1.0;  // medium units per scene unit

  // The channel with coefficients per scene unit (σ · scale).
  ScalarMedium channel(int c) const {
    return {sigma_a[static_cast<size_t>(c)] * scale, sigma_s[static_cast<size_t>(c)] * scale, g,
            eta, c, scale};
  }
  // Throws ParameterError naming parameter, channel and value (also checks scale > 0).
  void validate() const;

  // Builds a medium from reduced coefficients σs' (as tabulated by Jensen 2001) for a given g.
  static Medium fromReduced(const Rgb& sigma_a, const Rgb& sigma_s_prime, double g, double eta,
                            double scale = 1.0);
};

// Average diffuse Fresnel reflectance, rational fit of Egan & Hilgeman (Eq. 2.30).
double fdrRational(double eta);
// The same quantity by numerical integration of the exact unpolarized Fresnel reflectance:
// Fdr = 2 ∫0^1 Fr(μ; 1/η) μ dμ, the cosine-weighted hemispherical average seen from inside.
// (Eq. 2.29 as printed in the seed omits the cosine and the 1/π normalisation; the physically
// meaningful quantity, and the one the fit of Eq. 2.30 approximates, includes both.)
double fdrIntegral(double eta);
// Internal reflection parameter A = (1 + Fdr) / (1 - Fdr) (Jensen 2001; Eq. 2.32), from the fit.
double internalReflectionA(double eta);

}  // namespace translucent
