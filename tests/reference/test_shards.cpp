// SPDX-License-Identifier: GPL-3.0-or-later
// Runs traced in shards and merged (issue 17): the order-independent sums (exact_sum.h) against
// long-double sums and under permutation, the run-state files (run_state.h), and — the contract —
// the slab, sphere and mesh tracers' shards added up equal, bit for bit, the run traced at once.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <vector>

#include "translucent/geometry/mesh.h"
#include "translucent/reference/mesh_tracer.h"
#include "translucent/reference/run_state.h"
#include "translucent/reference/slab.h"
#include "translucent/reference/sphere.h"

namespace translucent::reference {
namespace {

TEST(ExactSum, TermsOnTheGridRoundTripExactly) {
  const FixedScale unit(0);
  // Doubles whose last mantissa bit lies on the grid 2^-64 (|v| >= 2^-12, or few bits).
  for (const double v : {1.0, -1.0, 0.5, 3.141592653589793, 1e-3, 123456.789, -0x1.8p-40})
    EXPECT_EQ(unit.toDouble(unit.toFixed(v)), v) << v;
  // A term far below the grid rounds to 0; one beyond the range is an error, as is a NaN.
  EXPECT_EQ(unit.toFixed(1e-25), 0);
  EXPECT_THROW(unit.toFixed(1e40), std::overflow_error);
  EXPECT_THROW(unit.toFixed(std::nan("")), std::overflow_error);
  const FixedScale big = FixedScale::around(3e12);
  EXPECT_EQ(big.exponent(), 41);  // 2^41 <= 3e12 < 2^42
  EXPECT_EQ(big.toDouble(big.toFixed(3e12 + 0.25)), 3e12 + 0.25);
}

// The grid of a light of any legal power: 2^(64 - e) overflowed to inf for e below ~-960 (a
// light of 1e-300, or 1e-320 in one channel), and the squares' grid 2^(2e) below 2^-1074, so
// every score "exceeded the accumulator's range" and `pathtrace mesh` aborted.
TEST(ExactSum, ScoresOfTinyAndHugeLightsFitTheirGrid) {
  for (const double typical : {1e-300, 1e-320, 4.9e-324, 1e-30, 1e12}) {
    const FixedScale scale = FixedScale::around(typical);
    MomentSum m(scale);
    const double w = typical * 0.75;
    for (int i = 0; i < 1000; ++i) EXPECT_NO_THROW(m.add(w, w * w)) << typical;
    EXPECT_TRUE(std::isfinite(m.s()) && std::isfinite(m.s2())) << typical;
    EXPECT_NEAR(m.s(), 1000.0 * w, 1e-9 * 1000.0 * w + 1e-323) << typical;
    const Estimate e = m.estimate(1000);
    EXPECT_TRUE(std::isfinite(e.value) && std::isfinite(e.std_error)) << typical;
    EXPECT_NEAR(e.value, w, 1e-9 * w + 1e-323) << typical;
    // Sums of one grid merge as before.
    MomentSum other(scale);
    other.add(w, w * w);
    EXPECT_NO_THROW(m.merge(other));
  }
  // A scale far below the doubles' range round-trips its terms exactly, as the unit scale does.
  const FixedScale tiny = FixedScale::around(1e-300);
  EXPECT_EQ(tiny.toDouble(tiny.toFixed(1e-300)), 1e-300);
  EXPECT_EQ(tiny.squared().exponent(), FixedScale::kMinSquaredExponent);
}

TEST(ExactSum, AnyOrderGivesTheSameSumCloseToTheExactOne) {
  // 20000 terms over twelve orders of magnitude, of both signs: three orders of addition (and a
  // split into uneven groups summed separately, as shards are) give one bit pattern, within
  // 1e-15 of a long-double sum (which double summation misses by far more in some orders).
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<double> terms(20000);
  for (double& t : terms) t = u(rng) * std::pow(10.0, 6.0 * u(rng));
  const FixedScale scale = FixedScale::around(1.0);
  auto exactSum = [&](const std::vector<double>& v) {
    MomentSum m(scale);
    for (const double t : v) m.add(t, t * t);
    return m;
  };
  const MomentSum forward = exactSum(terms);
  std::vector<double> shuffled = terms;
  std::shuffle(shuffled.begin(), shuffled.end(), rng);
  const MomentSum other = exactSum(shuffled);
  MomentSum grouped(scale);
  for (size_t a = 0, b = 7; a < terms.size(); a = b, b = std::min(terms.size(), b * 3))
    grouped.merge(exactSum(std::vector<double>(terms.begin() + long(a), terms.begin() + long(b))));
  EXPECT_EQ(forward.rawS(), other.rawS());
  EXPECT_EQ(forward.rawS2(), other.rawS2());
  EXPECT_EQ(forward.rawS(), grouped.rawS());
  EXPECT_EQ(forward.rawS2(), grouped.rawS2());
  long double ref = 0.0L, ref2 = 0.0L, abs = 0.0L;
  for (const double t : terms) {
    ref += t;
    abs += std::fabs(t);
    ref2 += static_cast<long double>(t) * t;
  }
  EXPECT_NEAR(forward.s(), static_cast<double>(ref), 1e-15 * static_cast<double>(abs));
  EXPECT_NEAR(forward.s2(), static_cast<double>(ref2), 1e-15 * static_cast<double>(ref2));
  // Sums on different grids do not mix.
  MomentSum copy = forward;
  EXPECT_THROW(copy.merge(MomentSum(FixedScale(3))), std::logic_error);
}

TEST(RunState, FilesRoundTripAndDamageIsDetected) {
  RunState s;
  s.putSums("a", -3, {Fixed(1) << 100, -5, 0});
  s.putCounts("n", {7, 1ull << 62});
  const std::string bytes = encodeRunState(R"({"shard": 2})", s);
  const DecodedRunState d = decodeRunState(bytes);
  EXPECT_EQ(d.header_json, R"({"shard":2})");
  EXPECT_EQ(d.state.getSums("a", 3, -3), s.sums.at("a").values);
  EXPECT_EQ(d.state.getCounts("n", 2), s.counts.at("n"));
  std::string flipped = bytes;
  flipped[flipped.size() - 3] ^= 0x10;
  EXPECT_THROW(decodeRunState(flipped), std::runtime_error);
  EXPECT_THROW(decodeRunState(bytes.substr(0, bytes.size() - 1)), std::runtime_error);
  EXPECT_THROW(decodeRunState("P3\n1 1\n"), std::runtime_error);
  // Layouts must agree to merge.
  RunState other = s;
  other.sums["a"].exponent = 0;
  EXPECT_THROW(s.merge(other), std::runtime_error);
  RunState twice = s;
  twice.merge(s);
  EXPECT_EQ(twice.sums.at("a").values[1], -10);
  EXPECT_THROW(twice.merge(twice), std::overflow_error);  // the count 2^63 + 2^63 overflows
}

// Shards [edges[i], edges[i+1]) of a run of `total` blocks.
std::vector<uint64_t> edges(uint64_t total, uint64_t shards) {
  std::vector<uint64_t> e;
  for (uint64_t i = 0; i <= shards; ++i) e.push_back(i * total / shards);
  return e;
}

void expectSameSlab(const SlabResult& a, const SlabResult& b) {
  EXPECT_EQ(a.photons, b.photons);
  EXPECT_EQ(a.scattering_events, b.scattering_events);
  for (const auto& [x, y] : {std::pair{a.diffuse_reflectance, b.diffuse_reflectance},
                             {a.transmittance, b.transmittance},
                             {a.unscattered_transmittance, b.unscattered_transmittance},
                             {a.diffuse_transmittance, b.diffuse_transmittance},
                             {a.absorbed, b.absorbed}}) {
    EXPECT_EQ(x.value, y.value);
    EXPECT_EQ(x.std_error, y.std_error);
  }
  EXPECT_EQ(a.radial.rd, b.radial.rd);
  EXPECT_EQ(a.radial.rd_stderr, b.radial.rd_stderr);
  EXPECT_EQ(a.angular.rd_r_theta, b.angular.rd_r_theta);
  EXPECT_EQ(a.angular.rd_r_theta_stderr, b.angular.rd_r_theta_stderr);
  EXPECT_EQ(a.partial, b.partial);
}

TEST(Shards, SlabShardsAddUpToTheWholeRunBitForBit) {
  SlabSetup s;
  s.sigma_a = 0.05;
  s.sigma_s = 4.0;
  s.g = 0.6;
  s.n_inside = 1.4;
  s.thickness = 2.0;
  TraceOptions o;
  o.photons = 23 * kBlockPhotons + 300;  // a short last block
  o.seed = 9;
  o.radial_bins = 20;
  o.radial_max = 3.0;
  o.angle_bins = 6;
  o.threads = 2;
  RunState whole;
  const SlabResult once = traceSlab(s, o, {}, &whole);
  EXPECT_GT(once.diffuse_reflectance.value, 0.1);
  // Five shards of 24 blocks, one thread each, traced in reverse order.
  const std::vector<uint64_t> e = edges(o.totalBlocks(), 5);
  RunState merged;
  for (int i = 4; i >= 0; --i) {
    TraceOptions shard = o;
    shard.first_block = e[size_t(i)];
    shard.blocks = e[size_t(i) + 1] - e[size_t(i)];
    shard.threads = 1;
    RunState part;
    const SlabResult r = traceSlab(s, shard, {}, &part);
    EXPECT_EQ(r.photons, o.photonsInBlocks(shard.first_block, shard.blocks));
    EXPECT_FALSE(r.partial);
    if (i == 4) merged = part;
    else merged.merge(part);
  }
  EXPECT_EQ(merged.sums, whole.sums);
  EXPECT_EQ(merged.counts, whole.counts);
  expectSameSlab(slabResult(s, o, merged), once);
}

void expectSameImages(const CameraImages& a, const CameraImages& b) {
  for (const auto& [x, y] : {std::pair{&a.exitance, &b.exitance}, {&a.radiance, &b.radiance},
                             {&a.cone_radiance, &b.cone_radiance}}) {
    EXPECT_EQ(x->rgb(), y->rgb());
    EXPECT_EQ(x->rgbStdError(), y->rgbStdError());
  }
}

void expectSameStats(const TransportStats& a, const TransportStats& b) {
  EXPECT_EQ(a.photons, b.photons);
  EXPECT_EQ(a.scattering_events, b.scattering_events);
  for (size_t c = 0; c < a.photons.size(); ++c) {
    EXPECT_EQ(a.exited[c].rawS(), b.exited[c].rawS());
    EXPECT_EQ(a.exited[c].rawS2(), b.exited[c].rawS2());
    EXPECT_EQ(a.entered[c].rawS(), b.entered[c].rawS());
    EXPECT_EQ(a.escaped[c].rawS2(), b.escaped[c].rawS2());
  }
}

TEST(Shards, SphereShardsAddUpToTheProgressiveRunBitForBit) {
  SphereScene scene;
  scene.radius = 1.0;
  scene.light_direction = {0.4, 0.8, 0.5};
  scene.width = scene.height = 12;
  Medium m;
  m.scale = 3.0;
  // Two passes of 5 blocks (the unsharded run) against three shards of its 10 blocks.
  SpherePathTracer once(scene, m, {21, 2});
  once.addPass(5 * kBlockPhotons - 17);  // rounded up to 5 blocks
  once.addPass(5 * kBlockPhotons);
  const std::vector<uint64_t> e = edges(10, 3);
  RunState merged;
  for (size_t i = 0; i < 3; ++i) {
    SpherePathTracer shard(scene, m, {21, 1});
    shard.addBlocks(e[i], e[i + 1] - e[i]);
    RunState part;
    shard.write(part);
    if (i == 0) merged = part;
    else merged.merge(part);
  }
  SpherePathTracer fromState(scene, m, {21, 2});
  fromState.read(merged);
  expectSameImages(fromState.images(), once.images());
  expectSameStats(fromState.stats(), once.stats());
  double total = 0.0;
  for (const float v : once.images().exitance.rgb()) total += static_cast<double>(v);
  EXPECT_GT(total, 0.0);
}

TEST(Shards, MeshShardsAddUpBitForBitAndAStateOfAnotherSceneIsRefused) {
  const auto cube = geometry::makeBox({-0.5, -0.5, -0.5}, {0.5, 0.5, 0.5});
  Medium medium;
  medium.scale = 4.0;
  const std::vector<Light> lights = {
      Light{DirectionalLight{{-0.3, 1.0, 0.5}, 1.0}, {1.0, 1.0, 1.0}},
      Light{PointLight{{1.5, 0.5, 1.0}, 0.4}, {1.0, 0.7, 0.5}}};
  Camera cam;
  cam.position = {1.6, 1.2, 2.2};
  cam.width = cam.height = 10;
  MeshPathTracer once(cube, medium, lights, cam, 5.0, {17, 2});
  once.addPass(7 * kBlockPhotons);
  RunState merged;
  for (const auto& [first, count] : {std::pair<uint64_t, uint64_t>{4, 3}, {0, 0}, {0, 4}}) {
    MeshPathTracer shard(cube, medium, lights, cam, 5.0, {17, 1});
    shard.addBlocks(first, count);
    RunState part;
    shard.write(part);
    if (merged.sums.empty()) merged = part;
    else merged.merge(part);
  }
  MeshPathTracer fromState(cube, medium, lights, cam, 5.0, {17, 2});
  fromState.read(merged);
  expectSameImages(fromState.images(), once.images());
  expectSameStats(fromState.stats(), once.stats());
  EXPECT_EQ(fromState.severalPixelPhotons(), once.severalPixelPhotons());
  // Another camera size: the arrays do not fit.
  Camera other = cam;
  other.width = 11;
  MeshPathTracer wrong(cube, medium, lights, other, 5.0, {17, 2});
  EXPECT_THROW(wrong.read(merged), std::runtime_error);
}

}  // namespace
}  // namespace translucent::reference
