// SPDX-License-Identifier: GPL-3.0-or-later
// The model reference (src/reference/model_reference.h): the analytic flat-slab value, agreement
// with the independent sphere integrator (sphere_integration.h) on an icosphere, insensitivity to
// the near-field radius, determinism and noise-consistency across seeds, the exit conventions,
// stopping and input errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include "translucent/bssrdf/registry.h"
#include "translucent/geometry/icosphere.h"
#include "translucent/optics/fresnel.h"
#include "translucent/reference/model_reference.h"
#include "translucent/reference/sphere.h"
#include "translucent/reference/sphere_integration.h"
#include "flat_slab.h"

namespace translucent::reference {
namespace {

using testing::flatSlab;
using testing::flatSlabCamera;
using testing::shortRangeMedium;

std::vector<Light> lightFrom(const glm::dvec3& direction, double irradiance = 1.0) {
  return {Light{DirectionalLight{direction, irradiance}, {1.0, 1.0, 1.0}}};
}

// The flat slab (flat_slab.h), lit along its normal: the light reaches only the top face (the
// sides have n·l = 0, the bottom faces away), so B = Ft(η, 1) E Rd in every pixel.
void expectFlatSlab(const std::string& modelName, int subpixels = 2) {
  const Medium medium = shortRangeMedium();
  const Camera cam = flatSlabCamera();
  ModelReferenceOptions o;
  o.samples = 1000000;
  o.tail = 1e-3;
  o.threads = 2;
  o.subpixels = subpixels;
  const bssrdf::Model& model = bssrdf::model(modelName);
  const auto img = renderModelReference(flatSlab(), medium, model, lightFrom({0, 0, 1}), cam, o);
  ASSERT_FALSE(img.partial);
  const double ft = fresnelTransmittance(1.0, medium.eta);
  std::array<double, 3> expected{};
  for (int c = 0; c < 3; ++c) expected[size_t(c)] = ft * model.profile(medium.channel(c))->Rd();
  testing::expectFlatSlab(img, cam, expected, 0.015, modelName);
}

TEST(ModelReference, FlatSlabGivesFresnelTimesIrradianceTimesRdDipole) { expectFlatSlab("dipole"); }

// 3x3 rays per pixel: more than one group of four hits (the two-pass sums of the inner loop).
TEST(ModelReference, FlatSlabWithNineRaysPerPixel) { expectFlatSlab("dipole", 3); }

// Normalized diffusion has R ~ 1/r at the source: the analytic near-field disc is what keeps its
// variance finite.
TEST(ModelReference, FlatSlabGivesFresnelTimesIrradianceTimesRdNormalizedDiffusion) {
  expectFlatSlab("normalized-diffusion");
}

// The other lights on the flat slab, against the directional light of irradiance 1 with the same
// samples: a beam wider than the window plus r_max gives exactly its irradiance P/(π r²) (here
// 2) times the directional result; a distant point light straight above gives I/D² (here 1) times
// it, less the fall-off of I cos θ / d² within r_max of the window (at most 1.5 r²/D² ≈ 1.4e-3).
TEST(ModelReference, BeamAndPointLightsScaleTheDirectionalResult) {
  const Medium medium = shortRangeMedium();
  const auto mesh = geometry::makeBox({-1.8, -1.8, -0.5}, {1.8, 1.8, 0.0});
  Camera cam;
  cam.projection = Camera::Projection::Orthographic;
  cam.position = {0.0, 0.0, 3.0};
  cam.view_height = 0.4;
  cam.width = cam.height = 3;
  ModelReferenceOptions o;
  o.samples = 300000;
  o.tail = 1e-3;
  o.threads = 2;
  const bssrdf::Model& model = bssrdf::model("dipole");
  const auto dir = renderModelReference(mesh, medium, model, lightFrom({0, 0, 1}), cam, o);
  const double radius = 1.7, D = 50.0;
  ASSERT_LT(dir.prune_radius + 0.3, radius);
  const std::vector<Light> beam{Light{BeamLight{{0, 0, 5}, {0, 0, -1}, radius,
                                                2.0 * std::numbers::pi * radius * radius}, {1, 1, 1}}};
  const std::vector<Light> point{Light{PointLight{{0, 0, D}, D * D}, {1, 1, 1}}};
  const auto b = renderModelReference(mesh, medium, model, beam, cam, o);
  const auto p = renderModelReference(mesh, medium, model, point, cam, o);
  for (size_t k = 0; k < dir.exitance.size(); ++k) {
    const double d = dir.exitance[k];
    ASSERT_GT(d, 0.0);
    EXPECT_NEAR(double(b.exitance[k]) / d, 2.0, 2e-6) << k;
    const double ratio = double(p.exitance[k]) / d;
    EXPECT_LE(ratio, 1.0 + 1e-6) << k;
    EXPECT_GE(ratio, 1.0 - 1.5 * std::pow(dir.prune_radius + 0.3, 2) / (D * D)) << k;
  }
}

// The lit sphere of sphere.h (radius 1, light and camera along +z) and an icosphere mesh of it.
SphereScene litSphere(int size) {
  SphereScene s;
  s.radius = 1.0;
  s.light_direction = {0.0, 0.0, 1.0};
  s.view_direction = {0.0, 0.0, 1.0};
  s.width = s.height = size;
  return s;
}

// Pixels whose centre lies within `fraction` of the radius on the image (away from the
// silhouette, where the facets and the sphere see different outlines).
std::vector<size_t> innerPixels(const SphereScene& s, double fraction) {
  const CameraModel cam(s.camera());
  std::vector<size_t> out;
  for (int j = 0; j < s.height; ++j)
    for (int i = 0; i < s.width; ++i) {
      glm::dvec3 o, d;
      cam.ray(i + 0.5, j + 0.5, o, d);
      const double rho = std::hypot(o.x, o.y);
      if (rho < fraction * s.radius) out.push_back(size_t(j) * size_t(s.width) + size_t(i));
    }
  return out;
}

// Two independent computations of the same integral: the sphere integrator (importance-sampled
// probe rays on the analytic sphere, per-pixel samples) and the model reference on an icosphere
// of 20480 triangles (shared area-uniform samples, interpolated radial normals). The mesh's
// faceting changes B by about its area deficit (1 - A_mesh / 4πR², 4e-4 here: the samples lie on
// chords, up to 1.4e-4 R inside the sphere) -- added to the tolerance as 3x that fraction of B.
TEST(ModelReference, AgreesWithTheSphereIntegratorOnAnIcosphere) {
  const Medium medium = shortRangeMedium();
  const SphereScene scene = litSphere(16);
  const bssrdf::Model& model = bssrdf::model("dipole");
  IntegrationOptions io;
  io.seed = 7;
  io.threads = 2;
  SphereIntegrator sphere(model, scene, medium, io);
  sphere.addPass(1024);
  const auto mesh = geometry::makeIcosphere(5, scene.radius);
  const double deficit = 1.0 - mesh.area() / (4.0 * std::numbers::pi);
  ASSERT_GT(deficit, 0.0);
  ASSERT_LT(deficit, 1e-3);
  ModelReferenceOptions o;
  o.samples = 1000000;
  o.threads = 2;
  const std::vector<Light> lights{scene.light()};
  const auto img = renderModelReference(mesh, medium, model, lights, scene.camera(), o);
  const auto pixels = innerPixels(scene, 0.8);
  ASSERT_GT(pixels.size(), 80u);
  const McImage& ref = sphere.images().exitance;
  for (int c = 0; c < 3; ++c) {
    double sumA = 0.0, sumB = 0.0, maxZ = 0.0;
    int outliers = 0;
    for (size_t p : pixels) {
      const int i = int(p % size_t(scene.width)), j = int(p / size_t(scene.width));
      const Estimate e = ref.pixel(i, j, c);
      const double a = img.exitance[3 * p + size_t(c)], se = img.exitance_se[3 * p + size_t(c)];
      EXPECT_EQ(img.coverage[p], 1.0f);
      const double tol = std::hypot(e.std_error, se) + 3.0 * deficit * e.value;
      const double z = std::abs(a - e.value) / tol;
      maxZ = std::max(maxZ, z);
      if (z > 3.0) ++outliers;
      sumA += a;
      sumB += e.value;
    }
    // Per pixel: no pixel beyond 5 combined standard errors, at most 2% beyond 3 (0.3% expected).
    EXPECT_LT(maxZ, 5.0) << "channel " << c;
    EXPECT_LE(outliers, int(0.02 * double(pixels.size())) + 1) << "channel " << c;
    // Mean over the inner disc: the model reference's pixels share their samples, so its error of
    // the mean is bounded by the largest pixel error (perfect correlation); the sphere
    // integrator's pixels are independent.
    double seA = 0.0, varB = 0.0;
    for (size_t p : pixels) {
      seA = std::max(seA, double(img.exitance_se[3 * p + size_t(c)]));
      const Estimate e = ref.pixel(int(p % size_t(scene.width)), int(p / size_t(scene.width)), c);
      varB += e.std_error * e.std_error;
    }
    const double n = double(pixels.size());
    const double meanA = sumA / n, meanB = sumB / n;
    EXPECT_NEAR(meanA, meanB, 3.0 * std::hypot(seA, std::sqrt(varB) / n) + 3.0 * deficit * meanB)
        << "channel " << c;
    std::printf("channel %d: %zu pixels, max |z| %.2f, %d beyond 3; mean %.5f vs %.5f (rel %.2e, "
                "area deficit %.2e)\n", c, pixels.size(), maxZ, outliers, meanA, meanB,
                meanA / meanB - 1.0, deficit);
  }
}

// The analytic disc assumes a locally flat surface and E ≈ E(x_o); on the sphere, where both
// assumptions are only approximate, a disc 4x wider (16x the area) changes nothing above the
// noise.
TEST(ModelReference, NearFieldRadiusLeavesNoBiasAboveTheNoise) {
  const Medium medium = shortRangeMedium();
  const SphereScene scene = litSphere(8);
  const auto mesh = geometry::makeIcosphere(5, scene.radius);
  ModelReferenceOptions o;
  o.samples = 400000;
  o.threads = 2;
  std::vector<Light> lights{scene.light()};
  o.near_field = 1.5;
  const auto small = renderModelReference(mesh, medium, bssrdf::model("normalized-diffusion"),
                                          lights, scene.camera(), o);
  o.near_field = 6.0;
  o.seed = 2;
  const auto large = renderModelReference(mesh, medium, bssrdf::model("normalized-diffusion"),
                                          lights, scene.camera(), o);
  EXPECT_NEAR(large.near_radius / small.near_radius, 4.0, 1e-12);
  // The disc holds a real share of Rd in the large case (the test is not vacuous).
  EXPECT_GT(large.near_fraction[2], 0.1);
  for (size_t p : innerPixels(scene, 0.8))
    for (size_t c = 0; c < 3; ++c) {
      const double a = small.exitance[3 * p + c], b = large.exitance[3 * p + c];
      const double se = std::hypot(small.exitance_se[3 * p + c], large.exitance_se[3 * p + c]);
      EXPECT_NEAR(a, b, 4.0 * se) << "pixel " << p << " channel " << c;
    }
}

// Same seed: bit-identical on 1 and 2 threads (and with the rays jittered).
TEST(ModelReference, SameSeedIsBitIdenticalOnAnyThreadCount) {
  const Medium medium = shortRangeMedium();
  const SphereScene scene = litSphere(12);
  const auto mesh = geometry::makeIcosphere(4, scene.radius);
  std::vector<Light> lights{scene.light(), Light{DirectionalLight{{1.0, 0.0, 0.2}, 0.5}, {1.0, 0.5, 0.25}}};
  const bssrdf::Model& model = bssrdf::model("dipole");
  for (const bool jitter : {false, true}) {
    ModelReferenceOptions o;
    o.samples = 100000;
    o.jitter = jitter;
    o.threads = 1;
    const auto one = renderModelReference(mesh, medium, model, lights, scene.camera(), o);
    o.threads = 2;
    const auto two = renderModelReference(mesh, medium, model, lights, scene.camera(), o);
    EXPECT_EQ(one.exitance, two.exitance);
    EXPECT_EQ(one.exitance_se, two.exitance_se);
    EXPECT_EQ(one.radiance, two.radiance);
    EXPECT_EQ(one.radiance_se, two.radiance_se);
    EXPECT_EQ(one.coverage, two.coverage);
  }
}

// The AVX2 inner loop and the portable one compute the same sums (to float rounding).
TEST(ModelReference, PortableAndVectorKernelsAgree) {
  const Medium medium = shortRangeMedium();
  const SphereScene scene = litSphere(8);
  const auto mesh = geometry::makeIcosphere(4, scene.radius);
  const std::vector<Light> lights{scene.light()};
  ModelReferenceOptions o;
  o.samples = 50000;
  o.subpixels = 3;  // 9 rays: three groups of four, the split (non-fused) path too
  const auto fast = renderModelReference(mesh, medium, bssrdf::model("dipole"), lights,
                                         scene.camera(), o);
  o.portable = true;
  const auto portable = renderModelReference(mesh, medium, bssrdf::model("dipole"), lights,
                                             scene.camera(), o);
  for (size_t k = 0; k < fast.exitance.size(); ++k) {
    EXPECT_NEAR(fast.exitance[k], portable.exitance[k], 1e-5 * std::abs(double(portable.exitance[k])) + 1e-12) << k;
    EXPECT_NEAR(fast.exitance_se[k], portable.exitance_se[k], 1e-4 * double(portable.exitance_se[k]) + 1e-12) << k;
  }
  EXPECT_EQ(fast.coverage, portable.coverage);
}

// Different seeds: the images differ by noise only, as their standard errors say. Over 8 seeds,
// the variance of each covered pixel about its mean, summed, against the sum of the reported
// variances: ≈ 1 (the noise-aware MSE of one image against another is ≈ 0 -- a technique that
// were the model reference itself would show an error within noise of zero). The band is wide
// because the pixels share their samples (their errors are correlated, so the sums have fewer
// independent terms than pixels). With jitter the reported variance is conservative (header):
// the ratio stays below 1.
TEST(ModelReference, SeedsAgreeWithinTheirStandardErrors) {
  const Medium medium = shortRangeMedium();
  const SphereScene scene = litSphere(10);
  const auto mesh = geometry::makeIcosphere(4, scene.radius);
  std::vector<Light> lights{scene.light(), Light{DirectionalLight{{1.0, 0.0, 0.2}, 0.5}, {1.0, 0.5, 0.25}}};
  const bssrdf::Model& model = bssrdf::model("dipole");
  for (const bool jitter : {false, true}) {
    std::vector<ModelReferenceImages> runs;
    for (uint64_t seed = 1; seed <= 8; ++seed) {
      ModelReferenceOptions o;
      o.samples = 100000;
      o.jitter = jitter;
      o.seed = seed;
      o.threads = 2;
      runs.push_back(renderModelReference(mesh, medium, model, lights, scene.camera(), o));
    }
    double spread = 0.0, reported = 0.0;
    int pixels = 0;
    for (size_t p = 0; p < runs[0].coverage.size(); ++p) {
      if (std::any_of(runs.begin(), runs.end(), [&](const auto& r) { return r.coverage[p] < 1.0f; }))
        continue;
      ++pixels;
      for (size_t c = 0; c < 3; ++c) {
        double m = 0.0, m2 = 0.0, v = 0.0;
        for (const auto& r : runs) {
          const double x = r.exitance[3 * p + c], se = r.exitance_se[3 * p + c];
          m += x;
          m2 += x * x;
          v += se * se;
        }
        const double n = double(runs.size());
        spread += (m2 - m * m / n) / (n - 1.0);
        reported += v / n;
        // Pairwise, every pixel within 5 combined standard errors.
        const double a = runs[0].exitance[3 * p + c], b = runs[1].exitance[3 * p + c];
        EXPECT_NEAR(a, b, 5.0 * std::hypot(double(runs[0].exitance_se[3 * p + c]), double(runs[1].exitance_se[3 * p + c])))
            << "pixel " << p << " channel " << c << " jitter " << jitter;
      }
    }
    ASSERT_GT(pixels, 40);
    const double ratio = spread / reported;
    std::printf("jitter %d: variance over 8 seeds / reported variance = %.3f\n", int(jitter), ratio);
    if (jitter) {
      EXPECT_GT(ratio, 0.15);
      EXPECT_LT(ratio, 1.3);
    } else {
      EXPECT_GT(ratio, 0.6);
      EXPECT_LT(ratio, 1.6);
    }
  }
}

// The two exit conventions differ by the constant 4Cφ(1/η) = diffuseTransmittanceFromOutside(η):
// the exitance is the same bit for bit, the radiance in the ratio of the conventions (to float
// rounding of the sums).
TEST(ModelReference, NormalizedRadianceIsJensenOverDiffuseTransmittance) {
  const Medium medium = shortRangeMedium();
  const SphereScene scene = litSphere(8);
  const auto mesh = geometry::makeIcosphere(3, scene.radius);
  std::vector<Light> lights{scene.light()};
  ModelReferenceOptions o;
  o.samples = 50000;
  const auto jensen = renderModelReference(mesh, medium, bssrdf::model("dipole"), lights,
                                           scene.camera(), o);
  o.convention = bssrdf::ExitConvention::Normalized;
  const auto normalized = renderModelReference(mesh, medium, bssrdf::model("dipole"), lights,
                                               scene.camera(), o);
  EXPECT_EQ(jensen.exitance, normalized.exitance);
  const double norm = bssrdf::diffuseTransmittanceFromOutside(medium.eta);
  int nonzero = 0;
  for (size_t k = 0; k < jensen.radiance.size(); ++k) {
    if (jensen.radiance[k] == 0.0f) continue;
    ++nonzero;
    EXPECT_NEAR(double(normalized.radiance[k]) * norm / double(jensen.radiance[k]), 1.0, 2e-6) << k;
    EXPECT_NEAR(double(normalized.radiance_se[k]) * norm / double(jensen.radiance_se[k]), 1.0, 2e-5) << k;
  }
  EXPECT_GT(nonzero, 60);
}

TEST(ModelReference, ProgressCallbackStopsWithAPartialImage) {
  const Medium medium = shortRangeMedium();
  const SphereScene scene = litSphere(32);
  const auto mesh = geometry::makeIcosphere(3, scene.radius);
  std::vector<Light> lights{scene.light()};
  ModelReferenceOptions o;
  o.threads = 1;
  // The callback runs every 100 ms (block_driver.h), so the stopped run must last longer than
  // that on any machine: 256² pixels × 4 rays × 200k samples (tens of seconds if it ran to the
  // end; it stops at the first call, after ~0.1 s).
  const SphereScene large = litSphere(256);
  o.samples = 200000;
  o.subpixels = 2;
  uint64_t calls = 0, lastTotal = 0;
  const auto img = renderModelReference(mesh, medium, bssrdf::model("dipole"), lights,
                                        large.camera(), o, [&](const TraceProgress& p) {
                                          ++calls;
                                          lastTotal = p.photons_total;
                                          return false;
                                        });
  EXPECT_TRUE(img.partial);
  EXPECT_GE(calls, 1u);
  EXPECT_EQ(lastTotal, 256u * 256u);
  // Without a stop the (small) run completes.
  o.samples = 20000;
  o.subpixels = 1;
  const auto full = renderModelReference(mesh, medium, bssrdf::model("dipole"), lights,
                                         scene.camera(), o, [](const TraceProgress&) { return true; });
  EXPECT_FALSE(full.partial);
}

TEST(ModelReference, BadInputIsAClearError) {
  const Medium medium = shortRangeMedium();
  const SphereScene scene = litSphere(4);
  const auto mesh = geometry::makeIcosphere(2, 1.0);
  const bssrdf::Model& model = bssrdf::model("dipole");
  std::vector<Light> lights{scene.light()};
  auto expectError = [&](const ModelReferenceOptions& o, const std::vector<Light>& l,
                         const std::string& needle) {
    try {
      renderModelReference(mesh, medium, model, l, scene.camera(), o);
      ADD_FAILURE() << "expected an error naming " << needle;
    } catch (const ParameterError& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  ModelReferenceOptions o;
  o.samples = 0;
  expectError(o, lights, "samples is 0");
  o = {};
  o.subpixels = 0;
  expectError(o, lights, "subpixels is 0");
  o = {};
  o.tail = 0.5;
  expectError(o, lights, "tail is 0.5");
  o = {};
  o.samples = 10;
  expectError(o, lights, "expected more samples");
  expectError({}, {Light{BeamLight{{0, 0, 5}, {0, 0, -1}, 0.0, 1.0}, {1, 1, 1}}}, "radius > 0");
  // An open mesh (one face of a box removed) has no inside.
  auto open = geometry::makeBox({-1, -1, -1}, {1, 1, 1});
  open.triangles.pop_back();
  EXPECT_THROW(renderModelReference(open, medium, model, lights, scene.camera(), {}),
               geometry::MeshError);
}

}  // namespace
}  // namespace translucent::reference
