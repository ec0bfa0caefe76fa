// SPDX-License-Identifier: GPL-3.0-or-later
// Directional dipole (bssrdf/directional_dipole.cpp): the kernel's geometric properties, its radial
// restriction, and its defining behaviour (oblique light comes out forward). The comparison with
// the path tracer is in tests/reference/test_sphere_integration_directional.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "translucent/bssrdf/registry.h"
#include "translucent/optics/presets.h"

namespace translucent::bssrdf {
namespace {

const Model& dd() { return model("directional-dipole"); }

glm::dvec3 randomUnit(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  return glm::normalize(glm::dvec3(n(rng), n(rng), n(rng)));
}

TEST(DirectionalDipole, IsRegisteredAndDirectional) {
  EXPECT_NE(dd().directional(ScalarMedium{0.01, 1.0, 0.0, 1.3}), nullptr);
  // Radial models have no kernel.
  EXPECT_EQ(model("dipole").directional(ScalarMedium{0.01, 1.0, 0.0, 1.3}), nullptr);
}

// The radial restriction is the kernel at normal incidence on a plane, in any position and
// orientation of the plane.
TEST(DirectionalDipole, ProfileIsTheKernelAtNormalIncidenceOnAPlane) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (const auto& p : presets()) {
    for (int c = 0; c < 3; ++c) {
      const ScalarMedium m = p.medium().channel(c);
      const auto radial = dd().profile(m);
      const auto kernel = dd().directional(m);
      const double l = m.reducedMeanFreePath();
      for (int k = 0; k < 20; ++k) {
        const glm::dvec3 n = randomUnit(rng);
        glm::dvec3 t = glm::normalize(glm::cross(n, randomUnit(rng)));
        const glm::dvec3 x_i = 10.0 * glm::dvec3(u(rng), u(rng), u(rng));
        const double r = l * 20.0 * u(rng) * u(rng);
        const double expected = radial->R(r);
        const double got = kernel->R(x_i, n, n, x_i + r * t, n);
        EXPECT_NEAR(got, expected, 1e-10 * expected + 1e-300) << p.name << " c" << c << " r " << r;
      }
    }
  }
}

// A rigid motion of the whole configuration leaves the kernel unchanged (no hidden frame).
TEST(DirectionalDipole, KernelIsInvariantUnderRigidMotions) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const ScalarMedium m = preset("Skin1").medium().channel(0);
  const auto kernel = dd().directional(m);
  const double l = m.reducedMeanFreePath();
  int nonzero = 0;
  for (int k = 0; k < 200; ++k) {
    // Points on a sphere of radius 5 ℓ' (curved geometry: n_i* differs from n_i), light in the
    // upper hemisphere of n_i.
    const double R = 5.0 * l;
    const glm::dvec3 n_i = randomUnit(rng), n_o = glm::normalize(n_i + 0.5 * randomUnit(rng));
    glm::dvec3 w = randomUnit(rng);
    if (glm::dot(w, n_i) < 0.0) w = -w;
    const glm::dvec3 x_i = R * n_i, x_o = R * n_o;
    const double v = kernel->R(x_i, n_i, w, x_o, n_o);
    const glm::dmat3 Q(glm::rotate(glm::dmat4(1.0), 3.0 * u(rng), randomUnit(rng)));
    const glm::dvec3 t = 3.0 * glm::dvec3(u(rng), u(rng), u(rng));
    const double moved = kernel->R(Q * x_i + t, Q * n_i, Q * w, Q * x_o + t, Q * n_o);
    EXPECT_NEAR(moved, v, 1e-9 * v + 1e-300) << k;
    if (v > 0.0) ++nonzero;
  }
  EXPECT_GT(nonzero, 100);
}

// The model's point: light entering obliquely travels on along its refracted direction, so more
// of it leaves in front of the point of entry than behind it, and more the more grazing the light
// (Frisvad et al. 2014, Fig. 1). At normal incidence the kernel is symmetric. The classic dipole
// cannot tell the two apart.
TEST(DirectionalDipole, ObliqueLightLeavesForward) {
  const ScalarMedium m = preset("Marble").medium().channel(1);
  const auto kernel = dd().directional(m);
  const double l = m.reducedMeanFreePath();
  const glm::dvec3 n(0.0, 0.0, 1.0), x_i(0.0);
  double previousRatio = 1.0;
  for (const double thetaDeg : {0.0, 30.0, 60.0, 80.0}) {
    const double th = thetaDeg * std::numbers::pi / 180.0;
    // Light from the -x side: the refracted ray heads towards +x.
    const glm::dvec3 w(-std::sin(th), 0.0, std::cos(th));
    const double r = 2.0 * l;
    const double forward = kernel->R(x_i, n, w, glm::dvec3(r, 0.0, 0.0), n);
    const double backward = kernel->R(x_i, n, w, glm::dvec3(-r, 0.0, 0.0), n);
    const double side1 = kernel->R(x_i, n, w, glm::dvec3(0.0, r, 0.0), n);
    const double side2 = kernel->R(x_i, n, w, glm::dvec3(0.0, -r, 0.0), n);
    ASSERT_GT(backward, 0.0);
    EXPECT_NEAR(side1, side2, 1e-12 * side1) << thetaDeg;  // mirror symmetry in the plane of incidence
    const double ratio = forward / backward;
    std::printf("Marble green, %2.0f deg: forward/backward exitance at 2 l' = %.3f\n", thetaDeg, ratio);
    if (thetaDeg == 0.0) {
      EXPECT_NEAR(ratio, 1.0, 1e-12);
    } else {
      EXPECT_GT(ratio, previousRatio * 1.05) << thetaDeg << " deg";
    }
    previousRatio = ratio;
  }
  EXPECT_GT(previousRatio, 2.0);  // at 80 degrees the forward side is clearly brighter (2.64)
}

// Light from below the surface does not enter at x_i.
TEST(DirectionalDipole, LightFromBelowGivesNothing) {
  const ScalarMedium m = preset("Skin1").medium().channel(0);
  const auto kernel = dd().directional(m);
  const glm::dvec3 n(0.0, 0.0, 1.0);
  EXPECT_EQ(kernel->R(glm::dvec3(0.0), n, glm::dvec3(0.0, 0.6, -0.8), glm::dvec3(0.5, 0.0, 0.0), n), 0.0);
}

// The azimuthal average that the pencil plot shows at oblique incidence: the profile at normal
// incidence, converged with 64 azimuths (the periodic trapezoidal rule), between the backward and
// forward values, and not the normal-incidence profile at 60°.
TEST(DirectionalDipole, AzimuthalAverageAtObliqueIncidence) {
  const ScalarMedium m = preset("Marble").medium().channel(1);
  const auto radial = dd().profile(m);
  const auto kernel = dd().directional(m);
  const double l = m.reducedMeanFreePath();
  const double th = 60.0 * std::numbers::pi / 180.0;
  const glm::dvec3 n(0.0, 0.0, 1.0), w(std::sin(th), 0.0, std::cos(th));
  bool differs = false;
  for (const double r : {0.1 * l, l, 3.0 * l, 10.0 * l}) {
    EXPECT_NEAR(azimuthalAverage(*kernel, r, 0.0), radial->R(r), 1e-12 * radial->R(r));
    const double a64 = azimuthalAverage(*kernel, r, th), a1024 = azimuthalAverage(*kernel, r, th, 1024);
    EXPECT_NEAR(a64, a1024, 1e-6 * a1024) << r;
    // The light comes from +x, so the refracted ray heads to -x: forward is -x.
    const double forward = kernel->R(glm::dvec3(0.0), n, w, glm::dvec3(-r, 0.0, 0.0), n);
    const double backward = kernel->R(glm::dvec3(0.0), n, w, glm::dvec3(r, 0.0, 0.0), n);
    EXPECT_LT(a64, forward);
    EXPECT_GT(a64, backward);
    if (std::abs(a64 - radial->R(r)) > 0.01 * radial->R(r)) differs = true;
  }
  EXPECT_TRUE(differs);
}

}  // namespace
}  // namespace translucent::bssrdf
