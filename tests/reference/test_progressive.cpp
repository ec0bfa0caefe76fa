// Progressive runs (src/reference/progressive.h) and the comparison of two Monte Carlo images
// (mc_compare.h): the doubling schedule's sums, the equality of a progressive path-traced run
// with one pass of the same photons and seed, the integrator's schedule-determinism over thread
// counts, cancellation before and during a pass, and the comparison's statistics against values
// computed by hand and against two independent estimates of the same image.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <numeric>
#include <thread>
#include <vector>

#include "bssrdf/registry.h"
#include "reference/mc_compare.h"
#include "reference/progressive.h"
#include "reference/sphere.h"
#include "reference/sphere_integration.h"

namespace translucent::reference {
namespace {

SphereScene smallSphere(int size) {
  SphereScene s;  // the CLI's default scene (radius 1, light 1,1,1, view 0,0,1), fewer pixels
  s.width = s.height = size;
  return s;
}

const ScalarMedium kMedium{0.05, 2.0, 0.0, 1.3};

// A one-channel per-pixel image with every pixel's mean and standard error times k: the sums of
// n samples rebuilt from the mean m and sample variance v as n m and n (m² + v (n - 1) / n).
McImage scaledCopy(const McImage& src, double k) {
  McImage out(src.width(), src.height(), 1, McImage::Statistics::PerPixel);
  for (int y = 0; y < src.height(); ++y)
    for (int x = 0; x < src.width(); ++x) {
      const size_t p = static_cast<size_t>(y) * static_cast<size_t>(src.width()) + static_cast<size_t>(x);
      const double n = static_cast<double>(src.pixelCount(p));
      const Estimate e = src.pixel(x, y, 0);
      const double mean = k * e.value;
      const double var = n > 1.0 ? k * k * e.std_error * e.std_error * n : 0.0;
      out.addSums(out.index(x, y, 0), mean * n, n * (mean * mean + var * (n - 1.0) / n));
      out.addPixelCount(p, src.pixelCount(p));
    }
  return out;
}

TEST(DoublingPasses, DoublesAndAddsUpToTheBudget) {
  const auto p = doublingPasses(3, 100);
  EXPECT_EQ(p, (std::vector<uint64_t>{3, 6, 12, 24, 48, 7}));
  const auto q = doublingPasses(1000, 20000, kBlockPhotons);  // whole blocks
  EXPECT_EQ(q.front(), kBlockPhotons);
  const uint64_t total = std::accumulate(q.begin(), q.end(), uint64_t{0});
  EXPECT_EQ(total, 20 * kBlockPhotons);  // 20000 rounded up to whole blocks
  for (size_t k = 0; k < q.size(); ++k) {
    EXPECT_EQ(q[k] % kBlockPhotons, 0u) << k;
    if (k + 1 < q.size()) {
      EXPECT_EQ(q[k], kBlockPhotons << k) << k;
    }
  }
  EXPECT_EQ(doublingPasses(50, 10), std::vector<uint64_t>{10});
  // A cap stops the growth; passes still add up to the budget.
  EXPECT_EQ(doublingPasses(1, 30, 1, 5), (std::vector<uint64_t>{1, 2, 4, 5, 5, 5, 5, 3}));
  EXPECT_EQ(doublingPasses(2, 20, 1, 6), (std::vector<uint64_t>{2, 4, 6, 6, 2}));
  EXPECT_EQ(doublingPasses(1024, 5000, 1024, 2000), (std::vector<uint64_t>{1024, 2048, 2048}));
  EXPECT_THROW(doublingPasses(4, 10, 1, 3), ParameterError);
  EXPECT_THROW(doublingPasses(0, 10), ParameterError);
  EXPECT_THROW(doublingPasses(1, 0), ParameterError);
  EXPECT_THROW(doublingPasses(1, 10, 0), ParameterError);
}

TEST(RunProgressive, PathTracerPassesEqualOneRunOfTheSamePhotons) {
  const SphereScene scene = smallSphere(16);
  const auto passes = doublingPasses(kBlockPhotons, 7 * kBlockPhotons, kBlockPhotons);  // 1, 2, 4
  ASSERT_EQ(passes.size(), 3u);
  SpherePathTracer progressive(scene, kMedium, {5, 2});
  std::atomic<bool> stop{false};
  std::vector<uint64_t> seen;
  const ProgressiveResult r = runProgressive(progressive, passes, stop, [&](int k, uint64_t done) {
    EXPECT_EQ(k, static_cast<int>(seen.size()));
    seen.push_back(done);
    EXPECT_EQ(progressive.stats().photons[0], done);  // the images hold exactly the passes done
  });
  EXPECT_EQ(r.passes, 3);
  EXPECT_FALSE(r.stopped);
  EXPECT_EQ(seen, (std::vector<uint64_t>{kBlockPhotons, 3 * kBlockPhotons, 7 * kBlockPhotons}));

  SpherePathTracer single(scene, kMedium, {5, 1});  // one thread: also thread-count independent
  single.addPass(7 * kBlockPhotons);
  EXPECT_EQ(progressive.images().exitance.rgb(), single.images().exitance.rgb());
  EXPECT_EQ(progressive.images().radiance.rgbStdError(), single.images().radiance.rgbStdError());
}

TEST(RunProgressive, IntegratorIsAFunctionOfTheScheduleNotOfTheThreads) {
  const SphereScene scene = smallSphere(12);
  const auto passes = doublingPasses(1, 7);
  IntegrationOptions o1, o2;
  o1.seed = o2.seed = 3;
  o1.threads = 1;
  o2.threads = 2;
  const auto& dipole = bssrdf::model("dipole");
  SphereIntegrator a(dipole, scene, kMedium, o1), b(dipole, scene, kMedium, o2), manual(dipole, scene, kMedium, o1);
  std::atomic<bool> stop{false};
  runProgressive(a, passes, stop, [](int, uint64_t) {});
  runProgressive(b, passes, stop, [](int, uint64_t) {});
  for (uint64_t n : passes) manual.addPass(n);
  EXPECT_EQ(a.images().exitance.rgb(), b.images().exitance.rgb());
  EXPECT_EQ(a.images().exitance.rgb(), manual.images().exitance.rgb());
  EXPECT_EQ(a.stats().samples, 7u);
}

TEST(RunProgressive, StopBeforeAPassRunsNothingAndStopInOnPassEndsAfterIt) {
  const SphereScene scene = smallSphere(8);
  SpherePathTracer t(scene, kMedium, {1, 2});
  const auto passes = doublingPasses(kBlockPhotons, 15 * kBlockPhotons, kBlockPhotons);
  std::atomic<bool> stop{true};
  ProgressiveResult r = runProgressive(t, passes, stop, [](int, uint64_t) { ADD_FAILURE(); });
  EXPECT_TRUE(r.stopped);
  EXPECT_EQ(r.passes, 0);
  EXPECT_EQ(t.passes(), 0);

  stop = false;
  int calls = 0;
  r = runProgressive(t, passes, stop, [&](int, uint64_t) {
    ++calls;
    if (calls == 2) stop = true;
  });
  EXPECT_TRUE(r.stopped);
  EXPECT_EQ(r.passes, 2);
  EXPECT_EQ(r.done, 3 * kBlockPhotons);
  EXPECT_EQ(t.stats().photons[0], 3 * kBlockPhotons);
}

TEST(RunProgressive, StopDuringAPassEndsItPartial) {
  // A pass far larger than the test's run time: the stop, set from another thread, is seen by
  // the progress callback, and the workers drop the blocks in hand. The pass is reported stopped,
  // not complete, and it traced fewer photons than asked.
  const SphereScene scene = smallSphere(8);
  SpherePathTracer t(scene, kMedium, {1, 2});
  const std::vector<uint64_t> passes = {uint64_t{1} << 40};
  std::atomic<bool> stop{false};
  std::atomic<int> progressCalls{0};
  std::thread stopper([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    stop = true;
  });
  const ProgressiveResult r = runProgressive(
      t, passes, stop, [](int, uint64_t) { ADD_FAILURE(); },
      [&](int pass, uint64_t done, const TraceProgress& p) {
        EXPECT_EQ(pass, 0);
        EXPECT_EQ(done, 0u);
        EXPECT_LE(p.photons_done, p.photons_total);
        ++progressCalls;
      });
  stopper.join();
  EXPECT_TRUE(r.stopped);
  EXPECT_EQ(r.passes, 0);
  EXPECT_TRUE(t.stats().partial);
  EXPECT_GT(t.stats().photons[0], 0u);
  EXPECT_LT(t.stats().photons[0], passes[0]);
  EXPECT_GE(progressCalls.load(), 1);
}

TEST(CompareImages, StatisticsMatchAHandComputation) {
  // Two 2x1 one-channel per-pixel images with known samples: pixel 0 has samples {1, 3} in the
  // reference and {2, 2} in the test; pixel 1 is empty in both (not compared).
  McImage r(2, 1, 1, McImage::Statistics::PerPixel), t(2, 1, 1, McImage::Statistics::PerPixel);
  r.add(0, 1.0);
  r.add(0, 3.0);
  r.addPixelCount(0, 2);
  t.add(0, 2.0);
  t.add(0, 2.0);
  t.addPixelCount(0, 2);
  const ImageComparison c = compareImages(r, t);
  EXPECT_EQ(c.pixels, 1u);
  EXPECT_DOUBLE_EQ(c.mean_reference, 2.0);
  EXPECT_DOUBLE_EQ(c.mean_test, 2.0);
  EXPECT_DOUBLE_EQ(c.rmse, 0.0);
  // Reference: sample variance 2, standard error sqrt(2 / 2) = 1; test: 0.
  EXPECT_DOUBLE_EQ(c.noise_rmse, 1.0);
  EXPECT_DOUBLE_EQ(c.systematic_rmse, 0.0);
  EXPECT_FLOAT_EQ(c.relative[0], 0.0f);
  EXPECT_TRUE(std::isnan(c.relative[1]));
  EXPECT_THROW(compareImages(r, McImage(1, 1, 1, McImage::Statistics::PerPixel)), ParameterError);
}

TEST(CompareImages, TwoEstimatesOfTheSameImageDifferByTheirNoiseAndAScaledOneByItsScale) {
  // Two integrations of the same scene with different seeds estimate the same image: their RMSE
  // must be explained by their standard errors (rmse² ≈ noise², within the spread of a mean of
  // many squared normal deviates, here bounded at ±20%). A copy scaled by 1.5 differs
  // systematically by 50% of every pixel.
  const SphereScene scene = smallSphere(24);
  IntegrationOptions o;
  o.threads = 2;
  o.seed = 1;
  const auto& dipole = bssrdf::model("dipole");
  SphereIntegrator a(dipole, scene, kMedium, o);
  o.seed = 2;
  SphereIntegrator b(dipole, scene, kMedium, o);
  a.addPass(128);
  b.addPass(128);
  const ImageComparison same = compareImages(a.images().exitance, b.images().exitance);
  ASSERT_GT(same.pixels, 300u);
  EXPECT_NEAR(same.rmse / same.noise_rmse, 1.0, 0.2);
  EXPECT_NEAR(same.mean_test / same.mean_reference, 1.0, 3.0 * same.noise_rmse / same.mean_reference / std::sqrt(static_cast<double>(same.pixels)));

  // The independent estimate b scaled by 1.5 (mean and standard error by 1.5): now
  // E[(1.5 t - r)²] = the standard errors' share + (0.5 r)², so the systematic part must be half
  // the reference's RMS value, within the spread of its estimate (±15% at these counts, where the
  // noise is about 40% of the offset).
  const McImage scaled = scaledCopy(b.images().exitance, 1.5);
  const ImageComparison off = compareImages(a.images().exitance, scaled);
  EXPECT_NEAR(off.mean_test / off.mean_reference, 1.5,
              3.0 * off.noise_rmse / off.mean_reference / std::sqrt(static_cast<double>(off.pixels)));
  double rms = 0.0;
  const McImage& ref = a.images().exitance;
  for (int y = 0; y < ref.height(); ++y)
    for (int x = 0; x < ref.width(); ++x) rms += ref.pixel(x, y, 0).value * ref.pixel(x, y, 0).value;
  rms = std::sqrt(rms / static_cast<double>(off.pixels));
  EXPECT_NEAR(off.systematic_rmse / (0.5 * rms), 1.0, 0.15)
      << "rmse " << off.rmse << " noise " << off.noise_rmse << " systematic " << off.systematic_rmse;
  // The scaled copy against its source: every compared pixel 50% brighter.
  const ImageComparison self = compareImages(b.images().exitance, scaled);
  for (size_t p = 0; p < self.relative.size(); ++p) {
    if (std::isfinite(self.relative[p])) {
      EXPECT_NEAR(self.relative[p], 0.5, 1e-5) << p;
    }
  }
}

TEST(DifferenceColor, WhiteAtZeroRedAboveBlueBelowGreyForNaN) {
  EXPECT_EQ(differenceColor(0.0f, 0.5f), (std::array<unsigned char, 3>{255, 255, 255}));
  EXPECT_EQ(differenceColor(0.5f, 0.5f), (std::array<unsigned char, 3>{255, 0, 0}));
  EXPECT_EQ(differenceColor(2.0f, 0.5f), (std::array<unsigned char, 3>{255, 0, 0}));  // saturates
  const auto below = differenceColor(-0.5f, 0.5f);
  EXPECT_EQ(below[2], 255);
  EXPECT_LT(below[0], 10);
  EXPECT_EQ(differenceColor(std::nanf(""), 0.5f), (std::array<unsigned char, 3>{128, 128, 128}));
}

}  // namespace
}  // namespace translucent::reference
