// SPDX-License-Identifier: GPL-3.0-or-later
// The progressive pencil-beam reference (analysis/pencil_reference.h): pooling of estimates is
// exact, passes double, a stop request ends the run, and the pooled tally agrees with an
// independent single run within its standard error.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <random>
#include <vector>

#include "translucent/analysis/pencil_reference.h"
#include "translucent/optics/presets.h"

namespace translucent::analysis {
namespace {

// Mean and standard error of samples, as reference/walk.h computes them.
reference::Estimate estimateOf(const std::vector<double>& w) {
  double s = 0.0, s2 = 0.0;
  for (double x : w) {
    s += x;
    s2 += x * x;
  }
  const double n = static_cast<double>(w.size());
  const double mean = s / n;
  const double var = (s2 / n - mean * mean) * n / (n - 1.0);
  return {mean, std::sqrt(var / n)};
}

TEST(PencilReference, PoolingEqualsOneEstimateOverAllSamples) {
  std::mt19937_64 rng(7);
  std::exponential_distribution<double> dist(3.0);
  std::vector<double> a(1000), b(3000);
  for (auto& x : a) x = dist(rng);
  for (auto& x : b) x = dist(rng) * 1.5;
  std::vector<double> all = a;
  all.insert(all.end(), b.begin(), b.end());
  const auto pooled = poolEstimates(estimateOf(a), a.size(), estimateOf(b), b.size());
  const auto whole = estimateOf(all);
  // Only rounding separates the two (sums of a few thousand terms).
  EXPECT_NEAR(pooled.value, whole.value, 1e-12 * whole.value);
  EXPECT_NEAR(pooled.std_error, whole.std_error, 1e-9 * whole.std_error);
}

TEST(PencilReference, PassesDoubleAndPoolAgreesWithASingleRun) {
  const Medium m = preset("Skin1").medium();
  PencilReferenceOptions o;
  o.r_max = 5.0;
  o.bins = 20;
  o.photons = 4096 * 7;  // passes of 4096, 8192, 16384
  o.first_pass = 4096;
  o.seed = 11;
  std::vector<uint64_t> counts;
  std::vector<bool> last;
  PencilReferencePass final_pass;
  const bool done = tracePencilReference(m, Channel::Green, o, [&](const PencilReferencePass& p) {
    counts.push_back(p.photons);
    last.push_back(p.last);
    final_pass = p;
  });
  EXPECT_TRUE(done);
  EXPECT_EQ(counts, (std::vector<uint64_t>{4096, 12288, 28672}));
  EXPECT_EQ(last, (std::vector<bool>{false, false, true}));
  const auto& pooled = final_pass.results[1];
  EXPECT_EQ(pooled.photons, 28672u);
  EXPECT_EQ(final_pass.results[0].photons, 0u);  // red not traced for the green channel

  // An independent run (another seed) of the same photon count: the difference of the two
  // estimates of Rd is within 4 combined standard errors (a false alarm ~6e-5).
  reference::TraceOptions t;
  t.photons = o.photons;
  t.seed = 999;
  t.radial_bins = o.bins;
  t.radial_max = o.r_max;
  const auto single =
      reference::traceSlab(reference::SlabSetup::semiInfinite(m.channel(1)), t);
  const double diff = pooled.diffuse_reflectance.value - single.diffuse_reflectance.value;
  const double se = std::hypot(pooled.diffuse_reflectance.std_error,
                               single.diffuse_reflectance.std_error);
  EXPECT_LT(std::abs(diff), 4.0 * se);
  // The pooled standard error scales like 1/sqrt(n): close to the single run's (same n), within
  // 10% (the estimate of a standard error from ~3e4 photons fluctuates by well under that).
  EXPECT_NEAR(pooled.diffuse_reflectance.std_error, single.diffuse_reflectance.std_error,
              0.1 * single.diffuse_reflectance.std_error);

  const Curve c = pencilReferenceCurve({nullptr, &pooled, nullptr}, Channel::Green, true);
  ASSERT_EQ(c.r.size(), 20u);
  const double entry = 1.0 - pooled.specular_reflectance.value;
  EXPECT_DOUBLE_EQ(c.value[3], c.r[3] * pooled.radial.rd[3] / entry);
  EXPECT_DOUBLE_EQ(c.stderr_[3], c.r[3] * pooled.radial.rd_stderr[3] / entry);
}

TEST(PencilReference, StopEndsTheRunAndBadInputIsRejected) {
  const Medium m = preset("Marble").medium();
  PencilReferenceOptions o;
  o.r_max = 10.0;
  o.photons = 1'000'000'000;  // far more than the test would trace
  o.first_pass = 2048;
  std::atomic<bool> stop{false};
  int passes = 0;
  const bool done = tracePencilReference(
      m, Channel::Luminance, o,
      [&](const PencilReferencePass& p) {
        ++passes;
        EXPECT_EQ(p.results[0].photons, p.photons);
        EXPECT_EQ(p.results[2].photons, p.photons);
        if (p.pass == 1) stop = true;
      },
      &stop);
  EXPECT_FALSE(done);
  EXPECT_EQ(passes, 2);

  Medium clear = m;
  clear.sigma_a[2] = 0.0;
  EXPECT_THROW(tracePencilReference(clear, Channel::Blue, o, {}), ParameterError);
  o.r_max = -1.0;
  EXPECT_THROW(tracePencilReference(m, Channel::Red, o, {}), ParameterError);
  o.r_max = 10.0;
  o.device = "tpu";
  try {
    tracePencilReference(m, Channel::Red, o, {});
    ADD_FAILURE() << "device tpu accepted";
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("reference device 'tpu': expected cpu, gpu or auto"),
              std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace translucent::analysis
