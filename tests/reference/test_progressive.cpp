// SPDX-License-Identifier: GPL-3.0-or-later
// Progressive runs (src/reference/progressive.h): the doubling schedule's sums, the equality of a
// progressive path-traced run with one pass of the same photons and seed, the integrator's
// schedule-determinism over thread counts, cancellation before and during a pass. (The comparison
// of two such images is tested in tests/analysis/test_mc_compare.cpp.)
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <numeric>
#include <thread>
#include <vector>

#include "translucent/bssrdf/registry.h"
#include "translucent/reference/progressive.h"
#include "translucent/reference/sphere.h"
#include "translucent/reference/sphere_integration.h"

namespace translucent::reference {
namespace {

SphereScene smallSphere(int size) {
  SphereScene s;  // the CLI's default scene (radius 1, light 1,1,1, view 0,0,1), fewer pixels
  s.width = s.height = size;
  return s;
}

const ScalarMedium kMedium{0.05, 2.0, 0.0, 1.3};

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

}  // namespace
}  // namespace translucent::reference
