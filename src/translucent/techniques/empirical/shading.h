// SPDX-License-Identifier: GPL-3.0-or-later
// The empirical translucency shader's per-pixel mathematics on the CPU (seed chapter 3,
// appendix C): the reference the GPU passes of the `empirical` technique are tested against.
//
//   linearDepth       window depth -> eye-space distance from the actual projection matrix
//                     (the seed's zNear/zFar formula, appendix C.2.4, holds only for a perspective
//                     projection; this one inverts any matrix with the usual third/fourth rows, so
//                     orthographic cameras work too)
//   thickness         t = (z_back - z_front) / D, D = diameter of the scene's bounding sphere,
//                     clamped to [0, 1] (appendix C.2.4)
//   smoothDepth       the depth-aware Gaussian of appendix C.2.2: weights
//                     w = g(dx, dy) · (1 - clamp(|z' - z| / threshold, 0, 1))   (Eq. C.1)
//                     over a k × k window, background texels skipped
//   shade             glColor = a·ka·Kd·Ia + wd·Kd·Id·(N·L) + ws·ks·Is·(N·H)^n
//                               + wb·(1 - t)^r·(Kd + Kb)                         (Eq. 3.6)
//   surveyPreset      the nine configurations of the seed's survey (Table 4.3)
//   randomLightDirection  the seed UI's "Random Lighting" mode (appendix A.1.1): a light that
//                     wanders over the whole sphere of directions, one step per frame
//
// Units: depths and thickness in scene units before normalisation; colours are linear RGB,
// dimensionless (the shader is empirical: no radiometric meaning).
#pragma once

#include <array>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

namespace translucent::empirical {

// Window depth d in [0, 1] (glDepthRange 0..1) -> distance in front of the eye (-z_eye), for a
// projection P whose clip z and w are affine in eye z: z_c = P[2][2] z + P[3][2],
// w_c = P[2][3] z + P[3][3] (glm's column-major indexing). Perspective and orthographic both.
double linearDepth(double windowDepth, const glm::dmat4& projection);

// Normalised thickness t = (back - front) / diameter, clamped to [0, 1]; back, front in scene
// units along the view direction.
double thickness(double frontDistance, double backDistance, double diameter);

// A depth image, rows from the top; texels equal to `background` have no surface.
struct DepthImage {
  int width = 0, height = 0;
  std::vector<float> depth;
  float background = 0.0f;
  float at(int x, int y) const { return depth[size_t(y) * size_t(width) + size_t(x)]; }
};

struct SmoothingOptions {
  int kernelSize = 5;        // k: odd, 1 .. 15 (seed: 5; 3 × 3 did not blur enough, seed 3.1)
  double sigma = 1.0;        // Gaussian σ [texels]; σ = 1 is close to the seed's integer table
  double threshold = 0.1;    // depth deviation at which a neighbour's weight reaches 0 (Eq. C.1)
};

// Gaussian weight of the offset (dx, dy), unnormalised (1 at the centre).
double gaussianWeight(int dx, int dy, double sigma);

// The smoothed depth at (x, y) (Eq. C.1; texels outside the image are skipped like the
// background); the background value where (x, y) itself is background. Throws ParameterError
// (optics/medium.h) for an even or out-of-range kernel size, σ <= 0 or threshold <= 0.
float smoothDepth(const DepthImage& image, int x, int y, const SmoothingOptions& options);
DepthImage smoothDepth(const DepthImage& image, const SmoothingOptions& options);

// The parameters of Eq. 3.6 (names as in the seed).
struct ShadingParameters {
  double ka = 0.2;                       // material ambient intensity
  glm::dvec3 Kd{0.8, 0.6, 0.5};          // material diffuse colour (albedo)
  glm::dvec3 Ia{1.0, 1.0, 1.0};          // light ambient intensity
  double wd = 1.0;                       // diffuse contribution (diffuseContribution, C.2.1)
  glm::dvec3 Id{1.0, 1.0, 1.0};          // light diffuse intensity
  double ws = 0.5;                       // specular contribution
  double ks = 0.5;                       // material specular intensity
  glm::dvec3 Is{1.0, 1.0, 1.0};          // light specular intensity
  double shininess = 32.0;               // n
  double wb = 1.2;                       // backlight contribution ("Backlight Contrib. (b)")
  double r = 25.0;                       // thickness exponent ("Thickness Exp. (t)")
  double Kb = 0.2;                       // diffuse weight ("Diffuse Weight (d)", Table 4.3;
                                         // diffuseWeigth in C.2.4), added to Kd in the backlight
};

// The terms of Eq. 3.6 separately (Eq. 3.7 - 3.10) and their sum.
struct ShadingTerms {
  glm::dvec3 ambient{0.0}, diffuse{0.0}, specular{0.0}, backlight{0.0};
  glm::dvec3 total() const { return ambient + diffuse + specular + backlight; }
};

// Eq. 3.6 for unit N, L (towards the light) and H (half vector), AO a in [0, 1] and normalised
// thickness t in [0, 1]. As in the seed's computeLight (C.2.3), the diffuse and specular terms
// are added only where N·L > 0, with N·L and N·H clamped at 0.
ShadingTerms shade(const ShadingParameters& p, double ao, const glm::dvec3& N, const glm::dvec3& L,
                   const glm::dvec3& H, double t);

// Table 4.3: image number 1 .. 9 -> (r, wb, Kb); the other parameters keep their values.
struct SurveyPreset {
  double thicknessExponent;  // r
  double backlight;          // wb
  double diffuseWeight;      // Kb: the table's "Diffuse Weight (d)"
};
constexpr int kSurveyPresetCount = 9;
SurveyPreset surveyPreset(int image);  // ParameterError for an image outside 1 .. 9
// Names "survey1" .. "survey9" (the technique's `preset` choices).
std::vector<std::string> surveyPresetNames();

// "Random Lighting" (seed appendix A.1.1: the light position "moved randomly across the scene"
// in real time). The seed does not say how; jumping to an unrelated direction every frame flickers, so
// the light follows a smooth random path instead: azimuth φ = φ0 + ω1·frame and
// cos θ = 0.9·sin(ω2·frame + φ1) (θ from +y), with φ0, φ1 and ω1, ω2 ∈ [0.02, 0.06] rad per
// frame drawn from `seed`. The path covers every azimuth and elevations up to ±64° from the
// horizon, so the light passes in front of and behind the object. Unit length; the same
// (seed, frame) always gives the same direction.
glm::dvec3 randomLightDirection(unsigned long long seed, long long frame);

}  // namespace translucent::empirical
