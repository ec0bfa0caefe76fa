// SPDX-License-Identifier: GPL-3.0-or-later
// Quantized diffusion (d'Eon & Irving 2011) against independent computations: the continuous-time
// extended-source diffusion it quantizes (long-double beam integral, closed-form total), the photon
// beam integral away from the source, the better dipole far from the source, its own direct sum
// (the profile's interpolation table), and the improved-diffusion building blocks.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <utility>

#include "beam_reference.h"
#include "translucent/bssrdf/improved_diffusion.h"
#include "translucent/bssrdf/photon_beam.h"
#include "translucent/bssrdf/quantized_diffusion.h"
#include "translucent/bssrdf/registry.h"
#include "translucent/optics/presets.h"

namespace translucent::bssrdf {
namespace {

using test::LD;

// A spread of channels: high albedo (Marble red), skin, very low albedo (Ketchup blue), α' = 1.
std::vector<ScalarMedium> someChannels() {
  return {preset("Marble").medium().channel(0), preset("Skin1").medium().channel(2),
          preset("Ketchup").medium().channel(2), preset("Spectralon").medium().channel(1),
          ScalarMedium{0.05, 3.0, 0.6, 1.0}, ScalarMedium{0.2, 1.0, 0.0, 1.5}};
}

TEST(QuantizedDiffusion, ConvergesToTheContinuousExtendedSource) {
  // With time quanta of ratio 1.05 the frozen-variance (midpoint) rule leaves ~2e-4; the tolerance
  // 1e-3 covers it wherever the profile matters (σtr r <= 4, beyond which QD's quanta resolve the
  // tail's narrow time window less well).
  for (const auto& m : someChannels()) {
    const test::ImprovedConstants c(m);
    const double lp = m.reducedMeanFreePath();
    for (double x : {1e-4, 1e-3, 1e-2, 0.1, 0.5, 1.0, 3.0, 10.0}) {
      const double r = x * lp;
      if (double(c.str) * r > 4.0) continue;
      const double expected = double(test::beamIntegral(r, m, false));
      EXPECT_NEAR(quantizedDiffusionDirect(r, m), expected, 1e-3 * expected)
          << "sigma_a " << m.sigma_a << " r/l' " << x;
    }
  }
}

TEST(QuantizedDiffusion, TotalReflectanceMatchesTheContinuousClosedForm) {
  // Continuous time: Rd = α'² σt'/(σt' + σtr) [C_φ (1 - e^{-2σtr zb})/(2Dσtr) + C_E (1 + e^{-2σtr zb})/2]
  // (each depth's dipole integrated over the plane, then over the beam's e^{-σt' z}).
  for (const auto& m : someChannels()) {
    const test::ImprovedConstants c(m);
    const LD x = 2.0L * c.str * c.zb;
    const LD fluence = c.str > 0 ? -std::expm1(-x) / (2.0L * c.D * c.str) : c.zb / c.D;
    const LD expected = c.alpha * c.alpha * c.st / (c.st + c.str) *
                        (c.cphi * fluence + 0.5L * c.ce * (1.0L + std::exp(-x)));
    EXPECT_NEAR(quantizedDiffusionRd(m), double(expected), 5e-4 * double(expected))
        << "sigma_a " << m.sigma_a;
  }
  // Without absorption diffusion returns all the light: C_φ 2A + C_E = 1 for every η.
  const auto& qd = model("quantized-diffusion");
  for (double eta : {1.0, 1.3, 1.6}) EXPECT_NEAR(qd.totalReflectance(1.0, eta), 1.0, 5e-4) << eta;
  EXPECT_EQ(qd.totalReflectance(0.0, 1.3), 0.0);
}

// The classic boundary (quantized-diffusion-fdr-fit): the same closed form with A, C_φ, C_E from
// the Fdr fit (2C1 = 3C2 = Fdr), energy conserving at α' = 1, and a different Rd from the
// moments' boundary (it places the image higher: A 2.60 against 2.34 at η = 1.3).
TEST(QuantizedDiffusion, FdrFitBoundaryMatchesItsClosedForm) {
  const auto& fit = model("quantized-diffusion-fdr-fit");
  for (const auto& m : someChannels()) {
    test::ImprovedConstants c(m);
    const LD fdr = -1.440L / (m.eta * m.eta) + 0.710L / m.eta + 0.668L + 0.0636L * m.eta;
    c.zb = 2.0L * c.D * (1.0L + fdr) / (1.0L - fdr);
    c.cphi = 0.25L * (1.0L - fdr);
    c.ce = 0.5L * (1.0L - fdr);
    const LD x = 2.0L * c.str * c.zb;
    const LD fluence = c.str > 0 ? -std::expm1(-x) / (2.0L * c.D * c.str) : c.zb / c.D;
    const LD expected = c.alpha * c.alpha * c.st / (c.st + c.str) *
                        (c.cphi * fluence + 0.5L * c.ce * (1.0L + std::exp(-x)));
    EXPECT_NEAR(fit.profile(m)->Rd(), double(expected), 5e-4 * double(expected))
        << "sigma_a " << m.sigma_a;
  }
  for (double eta : {1.0, 1.3, 1.6}) EXPECT_NEAR(fit.totalReflectance(1.0, eta), 1.0, 5e-4) << eta;
  const double moments = model("quantized-diffusion").totalReflectance(0.9, 1.3);
  EXPECT_GT(std::abs(fit.totalReflectance(0.9, 1.3) - moments), 0.01 * moments);
}

TEST(QuantizedDiffusion, AgreesWithPhotonBeamAwayFromTheSource) {
  // Same extended source and boundary as photon beam diffusion's beam integral before its two
  // corrections: κ only acts within a few ℓ' of the entry point (e^{-2σt' r} <= 2.5e-3 at
  // r = 3ℓ'), so beyond it QD agrees with the κ-corrected beam integral to the quantization
  // error. (The registered photon-beam model also leaves the once-scattered light out of its
  // sources, which QD, having no single-scattering term, keeps.)
  for (const auto& m : someChannels()) {
    const test::ImprovedConstants c(m);
    const auto qd = model("quantized-diffusion").profile(m);
    const double lp = m.reducedMeanFreePath();
    for (double x : {3.0, 5.0, 10.0}) {
      const double r = x * lp;
      if (double(c.str) * r > 4.0) continue;
      const double pbd = double(test::beamIntegral(r, m, true));
      EXPECT_NEAR(qd->R(r), pbd, 2e-3 * pbd) << "sigma_a " << m.sigma_a << " r/l' " << x;
    }
  }
}

TEST(QuantizedDiffusion, FarFieldDecaysLikeTheBetterDipole) {
  // Far from the source the beam looks like one point source: QD decays at the rate of the better
  // dipole (same D, σtr, zb; -d ln R/dr -> σtr + 2/r), not at that of the classic dipole, whose
  // σtr = sqrt(3 σa σt') is larger by sqrt(2 - α'). At σtr r = 16 the rates agree to 0.3% of σtr
  // over the presets (the rest is the beam's depth spread and QD's coarser time resolution of the
  // tail); the classic dipole's is off by more than 3% once α' < 0.95.
  for (const auto& [name, channel] : {std::pair{"Skin1", 1}, {"Ketchup", 1}, {"Marble", 0}}) {
    const auto m = preset(name).medium().channel(channel);
    const double str = double(test::ImprovedConstants(m).str);
    const auto qd = model("quantized-diffusion").profile(m);
    const auto bd = model("better-dipole").profile(m);
    const auto cd = model("dipole").profile(m);
    const double r = 16.0 / str, rate = test::decayRate(*qd, r);
    EXPECT_NEAR(rate, test::decayRate(*bd, r), 0.005 * str) << name;
    if (m.reducedAlbedo() < 0.95) {
      EXPECT_GT(std::abs(rate - test::decayRate(*cd, r)), 0.03 * str) << name;
    }
  }
}

TEST(QuantizedDiffusion, TableMatchesTheDirectSum) {
  // The profile interpolates a log-grid table of the direct sum: 1e-6 relative wherever R is not
  // negligible (above 1e-30 of its value near the source).
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> logR(std::log(1e-6), std::log(1e3));
  for (const auto& m : someChannels()) {
    const auto p = model("quantized-diffusion").profile(m);
    const double lp = m.reducedMeanFreePath(), peak = p->R(1e-3 * lp);
    for (int i = 0; i < 60; ++i) {
      const double r = lp * std::exp(logR(rng));
      const double direct = quantizedDiffusionDirect(r, m);
      if (direct < 1e-30 * peak) continue;
      EXPECT_NEAR(p->R(r), direct, 1e-6 * direct) << "sigma_a " << m.sigma_a << " r " << r;
    }
    EXPECT_DOUBLE_EQ(p->Rd(), quantizedDiffusionRd(m));
  }
}

TEST(QuantizedDiffusion, ScaleInvariance) {
  // Multiplying every coefficient by k multiplies R by k² at radius r/k.
  const ScalarMedium a{0.01, 1.0, 0.0, 1.3}, b{0.1, 10.0, 0.0, 1.3};
  const auto pa = model("quantized-diffusion").profile(a),
             pb = model("quantized-diffusion").profile(b);
  for (double r : {0.01, 0.3, 2.0, 10.0})
    EXPECT_NEAR(pb->R(r / 10.0), 100.0 * pa->R(r), 1e-9 * pb->R(r / 10.0)) << r;
  EXPECT_NEAR(pb->Rd(), pa->Rd(), 1e-14);
}

TEST(QuantizedDiffusion, RejectsBadRadius) {
  const ScalarMedium m{0.01, 1.0, 0.0, 1.3};
  EXPECT_THROW((void)quantizedDiffusionDirect(-1.0, m), ParameterError);
  EXPECT_THROW((void)quantizedDiffusionDirect(std::nan(""), m), ParameterError);
}

TEST(ImprovedDiffusion, FresnelMomentsMatchTheDiffuseReflectance) {
  // 2 C1 is the hemispherical diffuse Fresnel reflectance from inside, computed independently by
  // optics::fdrIntegral; index-matched boundaries reflect nothing.
  for (double eta : {0.8, 1.0, 1.3, 1.5, 2.0})
    EXPECT_NEAR(2.0 * improved::fresnelMoment(1, eta), fdrIntegral(eta), 1e-10) << eta;
  EXPECT_NEAR(improved::fresnelMoment(2, 1.0), 0.0, 1e-15);
  // Long-double reference of C2 at η = 1.3.
  const test::ImprovedConstants c(ScalarMedium{0.0, 1.0, 0.0, 1.3});
  const double c2 = (1.0 - 2.0 * double(c.ce)) / 3.0;
  EXPECT_NEAR(improved::fresnelMoment(2, 1.3), c2, 1e-12);
}

TEST(ImprovedDiffusion, ScaledComplementaryErrorFunction) {
  for (double x : {0.0, 0.3, 1.0, 5.0, 24.9, 25.1, 40.0, 100.0, 1e4}) {
    const LD xl = x;
    // Long double erfc has the range for exp(x²) erfc(x) up to x = 100; beyond, the series
    // reference 1/(√π x) (1 - 1/(2x²) + 3/(4x⁴)) is exact to 1e-20.
    const LD ref = x <= 100.0 ? std::exp(xl * xl) * std::erfc(xl)
                              : (1.0L - 0.5L / (xl * xl) + 0.75L / (xl * xl * xl * xl)) /
                                    (std::sqrt(test::kPiL) * xl);
    // exp(x²) amplifies the rounding of x² by x²: relative 1.1e-16 (1 + 2x²) at most.
    EXPECT_NEAR(improved::erfcx(x), double(ref), 2e-16 * (1.0 + 2.0 * x * x) * double(ref)) << x;
    if (x > 0.0) {
      const LD deficit = 1.0L / (std::sqrt(test::kPiL) * xl) - ref;
      EXPECT_NEAR(improved::erfcxDeficit(x), double(deficit), 1e-9 * double(deficit)) << x;
    }
  }
}

}  // namespace
}  // namespace translucent::bssrdf
