// SPDX-License-Identifier: GPL-3.0-or-later
// The photon walker of slab.h and its deterministic multithreaded driver.
#include "translucent/reference/slab.h"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <numbers>

#include "translucent/optics/fresnel.h"
#include "translucent/reference/block_driver.h"
#include "translucent/reference/walk.h"

namespace translucent::reference {

// ---------------------------------------------------------------------------------------------
// Parameters

const char* toString(ScatteringOrder order) {
  switch (order) {
    case ScatteringOrder::Unscattered: return "unscattered";
    case ScatteringOrder::Single: return "single";
    case ScatteringOrder::Multiple: return "multiple";
  }
  return "?";
}

SlabSetup SlabSetup::semiInfinite(const ScalarMedium& m) {
  SlabSetup s;
  s.sigma_a = m.sigma_a;
  s.sigma_s = m.sigma_s;
  s.g = m.g;
  s.n_inside = m.eta;
  return s;
}

void SlabSetup::validate() const {
  auto bad = [](const char* name, double v, const char* expected) {
    throw ParameterError(fmt::format("slab: {} is {}: expected {}", name, v, expected));
  };
  if (!std::isfinite(sigma_a) || sigma_a < 0.0) bad("sigma_a", sigma_a, "a finite value >= 0");
  if (!std::isfinite(sigma_s) || sigma_s < 0.0) bad("sigma_s", sigma_s, "a finite value >= 0");
  // The walker keeps positions and 1/σt in float: keep the mean free path in a safe float range.
  if (!(sigma_a + sigma_s >= 1e-20 && sigma_a + sigma_s <= 1e20))
    bad("sigma_a + sigma_s", sigma_a + sigma_s, "a value in [1e-20, 1e20] per length unit");
  if (!(std::abs(g) < 1.0)) bad("g", g, "a value in (-1, 1)");
  if (!std::isfinite(n_inside) || !(n_inside > 0.0)) bad("n_inside (eta)", n_inside, "a value > 0");
  if (!std::isfinite(n_above) || !(n_above > 0.0)) bad("n_above", n_above, "a value > 0");
  if (!std::isfinite(n_below) || !(n_below > 0.0)) bad("n_below", n_below, "a value > 0");
  if (!(thickness >= 1e-30 && (thickness <= 1e30 || !finite())))
    bad("thickness", thickness, "a length in [1e-30, 1e30] (infinity: semi-infinite)");
  if (!(theta >= 0.0 && theta < 0.5 * std::numbers::pi))
    bad("theta", theta, "an incidence angle in [0, pi/2) radians");
  if (!std::isfinite(phi)) bad("phi", phi, "a finite azimuth");
}

void TraceOptions::validate() const {
  if (photons == 0) throw ParameterError("trace: photons is 0: expected at least 1");
  if (threads < 0)
    throw ParameterError(fmt::format("trace: threads is {}: expected >= 0 (0: all)", threads));
  if (radial_bins < 0)
    throw ParameterError(fmt::format("trace: radial_bins is {}: expected >= 0", radial_bins));
  if (radial_bins > 0 && !(std::isfinite(radial_max) && radial_max > 0.0))
    throw ParameterError(fmt::format(
        "trace: radial_max is {}: expected a positive radius when radial bins are asked",
        radial_max));
  if (angle_bins < 0)
    throw ParameterError(fmt::format("trace: angle_bins is {}: expected >= 0", angle_bins));
  // Either alone too (angle bins alone size their own tallies: 10^9 ended in std::bad_alloc).
  if (static_cast<int64_t>(std::max(radial_bins, 1)) * std::max(angle_bins, 1) > (1 << 24))
    throw ParameterError(fmt::format("trace: radial_bins ({}) x angle_bins ({}) exceeds 2^24 bins",
                                     radial_bins, angle_bins));
}

namespace detail {

Walk makeWalk(const SlabSetup& S, const TraceOptions& O, double& rsp) {
  Walk W;
  const double sigmaT = S.sigma_a + S.sigma_s;
  W.invSigmaT = static_cast<float>(1.0 / sigmaT);
  W.g = static_cast<float>(S.g);
  W.thickness = S.finite() ? static_cast<float>(S.thickness) : 0.0f;
  // Specular reflection and refraction at the entry point (Snell: n_above sin θ = n_in sin θt).
  const double cosI = std::cos(S.theta);
  const double etaIn = S.n_inside / S.n_above;
  rsp = S.n_inside == S.n_above ? 0.0 : fresnelReflectance(cosI, etaIn);
  const double sinT = std::sin(S.theta) / etaIn;
  const double cosT = std::sqrt(std::max(0.0, 1.0 - sinT * sinT));
  W.entry = {static_cast<float>(sinT * std::cos(S.phi)), static_cast<float>(sinT * std::sin(S.phi)),
             static_cast<float>(cosT)};
  W.entryWeight = 1.0 - rsp;
  const double pAbsorb = S.sigma_a / sigmaT;
  W.albedo = S.sigma_s / sigmaT;
  W.absorbThreshold = absorbThreshold(pAbsorb);
  W.top = {S.n_above == S.n_inside, S.n_above / S.n_inside};
  W.bottom = {S.n_below == S.n_inside, S.n_below / S.n_inside};
  W.nr = O.radial_bins;
  W.na = O.angle_bins;
  if (W.nr > 0) W.invDr = static_cast<float>(O.radial_bins / O.radial_max);
  if (W.na > 0) W.invDtheta = O.angle_bins / (0.5 * std::numbers::pi);
  W.longPath = O.long_path_roulette;
  return W;
}

namespace {

// The radial and angular estimates of one class of exits (finishSlab).
void finishProfiles(const ExitSums& E, const TraceOptions& O, uint64_t n, RadialProfileTally& rad,
                    AngularTally& ang) {
  if (O.radial_bins > 0) {
    rad.dr = O.radial_max / O.radial_bins;
    for (int i = 0; i < O.radial_bins; ++i) {
      // Annulus area π (r_{i+1}² - r_i²) = 2π r_i dr at the centre r_i (MCML's Rd_r).
      const double rc = (i + 0.5) * rad.dr;
      const Estimate e = E.radial[static_cast<size_t>(i)].estimate(n, 2.0 * std::numbers::pi * rc * rad.dr);
      rad.r.push_back(rc);
      rad.rd.push_back(e.value);
      rad.rd_stderr.push_back(e.std_error);
    }
    rad.beyond = E.radial.back().estimate(n);
  }
  if (O.angle_bins > 0) {
    ang.dtheta = 0.5 * std::numbers::pi / O.angle_bins;
    std::vector<double> solid(static_cast<size_t>(O.angle_bins));
    for (int j = 0; j < O.angle_bins; ++j) {
      // Solid angle of the cone ring [θj, θj+1]: 2π (cos θj - cos θj+1).
      solid[static_cast<size_t>(j)] =
          2.0 * std::numbers::pi * (std::cos(j * ang.dtheta) - std::cos((j + 1) * ang.dtheta));
      const Estimate e = E.angular[static_cast<size_t>(j)].estimate(n, solid[static_cast<size_t>(j)]);
      ang.theta.push_back((j + 0.5) * ang.dtheta);
      ang.rd.push_back(e.value);
      ang.rd_stderr.push_back(e.std_error);
    }
    for (int i = 0; i < O.radial_bins; ++i) {
      const double area = 2.0 * std::numbers::pi * rad.r[static_cast<size_t>(i)] * rad.dr;
      for (int j = 0; j < O.angle_bins; ++j) {
        const size_t k = static_cast<size_t>(i) * static_cast<size_t>(O.angle_bins) + static_cast<size_t>(j);
        const Estimate e = E.radialAngle[k].estimate(n, area * solid[static_cast<size_t>(j)]);
        ang.rd_r_theta.push_back(e.value);
        ang.rd_r_theta_stderr.push_back(e.std_error);
      }
    }
  }
}

}  // namespace

SlabResult finishSlab(const Tally& T, const TraceOptions& O, double rsp) {
  SlabResult R;
  const uint64_t n = T.photons;
  R.photons = n;
  R.scattering_events = T.events;
  R.seed = O.seed;
  R.specular_reflectance = {rsp, 0.0};
  R.diffuse_reflectance = T.reflected.estimate(n);
  R.transmittance = T.transmitted.estimate(n);
  R.unscattered_transmittance = T.unscattered.estimate(n);
  Sums diffuseT{T.transmitted.s - T.unscattered.s, T.transmitted.s2 - T.unscattered.s2};
  R.diffuse_transmittance = diffuseT.estimate(n);
  R.absorbed = T.absorbed.estimate(n);
  finishProfiles(T, O, n, R.radial, R.angular);
  for (size_t k = 0; k < kScatteringOrders; ++k) {
    SlabResult::Order& o = R.orders[k];
    o.diffuse_reflectance = T.orders[k].reflected.estimate(n);
    o.transmittance = T.orders[k].transmitted.estimate(n);
    finishProfiles(T.orders[k], O, n, o.radial, o.angular);
  }
  return R;
}

}  // namespace detail

namespace {
using detail::Tally;
using detail::Walk;
}  // namespace

// ---------------------------------------------------------------------------------------------
// Driver: the block-parallel loop of block_driver.h: workers claim blocks in increasing order and
// tallies are merged strictly in block order, so floating-point sums do not depend on timing.

SlabResult traceSlab(const SlabSetup& setup, const TraceOptions& options,
                     const ProgressCallback& progress, RunState* state) {
  setup.validate();
  options.validate();
  // Without absorption a random walk in a half space returns to the surface with probability 1,
  // but after a number of steps with infinite mean: the trace would not end in practice.
  if (!setup.finite() && setup.sigma_a == 0.0 && options.long_path_roulette == 0)
    throw ParameterError(
        "slab: sigma_a is 0 in a semi-infinite medium: path lengths have infinite mean; give a "
        "finite thickness, some absorption, or the long-path roulette");
  double rsp = 0.0;
  const Walk W = detail::makeWalk(setup, options, rsp);
  const detail::BlockKernel scalar = detail::scalarKernel(options.absorption, setup.finite());
  const detail::LanesKernel lanes = detail::lanesKernel(
      options.absorption, setup.finite(), W.g, options.kernel == Kernel::LanesPortable);
  return detail::runSlabBlocks(
      options, rsp,
      [&](uint64_t b, uint64_t count, Tally& t, const std::atomic<bool>& stop_) {
        return options.kernel == Kernel::Scalar
                   ? scalar(W, options.seed, b, count, t, stop_)
                   : lanes.run(W, lanes.pass, options.seed, b, count, t, stop_);
      },
      progress, state);
}

SlabResult slabResult(const SlabSetup& setup, const TraceOptions& options, const RunState& state) {
  setup.validate();
  options.validate();
  double rsp = 0.0;
  detail::makeWalk(setup, options, rsp);
  return detail::slabFromState(options, rsp, state);
}

uint64_t TraceOptions::photonsInBlocks(uint64_t first, uint64_t count) const {
  const uint64_t begin = std::min(first * kBlockPhotons, photons);
  const uint64_t end = std::min((first + count) * kBlockPhotons, photons);
  return end - begin;
}

namespace detail {

void ExactExitSums::merge(const ExitSums& t) {
  // Adding a zero changes no exact sum: skipping the bins a block never reached keeps the merge
  // cheap for the orders' tallies (most of their bins stay empty in a block).
  auto add = [](MomentSum& m, const Sums& x) {
    if (x.s != 0.0 || x.s2 != 0.0) m.add(x.s, x.s2);
  };
  add(reflected, t.reflected);
  add(transmitted, t.transmitted);
  for (size_t i = 0; i < radial.size(); ++i) add(radial[i], t.radial[i]);
  for (size_t i = 0; i < angular.size(); ++i) add(angular[i], t.angular[i]);
  for (size_t i = 0; i < radialAngle.size(); ++i) add(radialAngle[i], t.radialAngle[i]);
}

void ExactExitSums::toSums(ExitSums& t) const {
  auto get = [](const MomentSum& m) { return Sums{m.s(), m.s2()}; };
  t.reflected = get(reflected);
  t.transmitted = get(transmitted);
  for (size_t i = 0; i < radial.size(); ++i) t.radial[i] = get(radial[i]);
  for (size_t i = 0; i < angular.size(); ++i) t.angular[i] = get(angular[i]);
  for (size_t i = 0; i < radialAngle.size(); ++i) t.radialAngle[i] = get(radialAngle[i]);
}

void ExactTally::merge(const Tally& t) {
  photons += t.photons;
  events += t.events;
  ExactExitSums::merge(t);
  unscattered.add(t.unscattered.s, t.unscattered.s2);
  absorbed.add(t.absorbed.s, t.absorbed.s2);
  for (size_t k = 0; k < orders.size(); ++k) orders[k].merge(t.orders[k]);
}

Tally ExactTally::toTally() const {
  const int nr = radial.empty() ? 0 : static_cast<int>(radial.size()) - 1;
  Tally t(nr, static_cast<int>(angular.size()));
  t.photons = photons;
  t.events = events;
  toSums(t);
  t.unscattered = Sums{unscattered.s(), unscattered.s2()};
  t.absorbed = Sums{absorbed.s(), absorbed.s2()};
  for (size_t k = 0; k < orders.size(); ++k) orders[k].toSums(t.orders[k]);
  return t;
}

namespace {
// Calls f(name, sums) for every array of MomentSums of the tally (scalars as arrays of one).
template <class Self, class F>
void forEachSums(Self& t, F&& f) {
  using M = std::conditional_t<std::is_const_v<Self>, const MomentSum, MomentSum>;
  auto one = [](M& m) { return std::vector<M*>{&m}; };
  auto all = [](auto& v) {
    std::vector<M*> p;
    for (auto& m : v) p.push_back(&m);
    return p;
  };
  auto exits = [&](auto& e, const std::string& prefix) {
    f(prefix + "reflected", one(e.reflected));
    f(prefix + "transmitted", one(e.transmitted));
    f(prefix + "radial", all(e.radial));
    f(prefix + "angular", all(e.angular));
    f(prefix + "radial_angle", all(e.radialAngle));
  };
  exits(t, "");
  f("unscattered", one(t.unscattered));
  f("absorbed", one(t.absorbed));
  for (ScatteringOrder o : kAllScatteringOrders)
    exits(t.orders[static_cast<size_t>(o)], std::string("order.") + toString(o) + ".");
}
}  // namespace

void ExactTally::write(RunState& state) const {
  state.putCounts("photons", {photons});
  state.putCounts("scattering_events", {events});
  forEachSums(*this, [&](const std::string& name, const std::vector<const MomentSum*>& sums) {
    std::vector<Fixed> s, s2;
    for (const MomentSum* m : sums) {
      s.push_back(m->rawS());
      s2.push_back(m->rawS2());
    }
    state.putSums(name + ".s", 0, std::move(s));
    state.putSums(name + ".s2", 0, std::move(s2));
  });
}

void ExactTally::read(const RunState& state) {
  photons = state.getCounts("photons", 1)[0];
  events = state.getCounts("scattering_events", 1)[0];
  forEachSums(*this, [&](const std::string& name, const std::vector<MomentSum*>& sums) {
    const auto& s = state.getSums(name + ".s", sums.size(), 0);
    const auto& s2 = state.getSums(name + ".s2", sums.size(), 0);
    for (size_t i = 0; i < sums.size(); ++i) sums[i]->setRaw(s[i], s2[i]);
  });
}

// The block-parallel loop of block_driver.h: workers claim blocks in increasing order and block
// tallies are merged into the exact total (in block order, though the total does not depend on
// it).
BlockShare blockShare(const TraceOptions& options) {
  const uint64_t all = options.totalBlocks();
  BlockShare share;
  share.first = std::min(options.first_block, all);
  share.count = options.blocks == 0 ? all - share.first : std::min(options.blocks, all - share.first);
  share.photons = options.photonsInBlocks(share.first, share.count);
  return share;
}

SlabResult finishSlabRun(const ExactTally& total, const TraceOptions& options, double rsp,
                         uint64_t expected, double seconds, int threads,
                         const ProgressCallback& progress, RunState* state) {
  SlabResult result = detail::finishSlab(total.toTally(), options, rsp);
  result.seconds = seconds;
  result.threads = threads;
  result.partial = total.photons < expected;
  if (state) total.write(*state);
  if (progress) progress({total.photons, expected, result.seconds});
  return result;
}

SlabResult runSlabBlocks(const TraceOptions& options, double rsp, const SlabBlock& block,
                         const ProgressCallback& progress, RunState* state) {
  const BlockShare share = blockShare(options);
  const uint64_t expected = share.photons;
  auto photonsIn = [&](uint64_t blocks) { return std::min(blocks * kBlockPhotons, expected); };
  ExactTally total(options.radial_bins, options.angle_bins);
  // After a stop the driver also hands over the blocks finished beyond one that was abandoned;
  // they are left out, so that a partial run is a prefix of its blocks [first, next) and a
  // stopped shard resumes from it (apps/cli/shard.h, readCheckpoint).
  uint64_t next = share.first;
  const detail::BlockRun run = detail::runBlocks<Tally>(
      share.first, share.count, options.threads,
      [&] { return Tally(options.radial_bins, options.angle_bins); },
      [&](uint64_t b, Tally& t, const std::atomic<bool>& stop_) {
        return block(b, std::min(kBlockPhotons, options.photons - b * kBlockPhotons), t, stop_);
      },
      [&](uint64_t b, const Tally& t) {
        if (b != next) return;
        total.merge(t);
        ++next;
      },
      [&](uint64_t blocks, double seconds) {
        return !progress || progress({photonsIn(blocks), expected, seconds});
      });
  return finishSlabRun(total, options, rsp, expected, run.seconds, run.threads, progress, state);
}

SlabResult slabFromState(const TraceOptions& options, double rsp, const RunState& state) {
  ExactTally total(options.radial_bins, options.angle_bins);
  total.read(state);
  SlabResult result = detail::finishSlab(total.toTally(), options, rsp);
  result.partial = total.photons < options.photons;
  return result;
}

}  // namespace detail

}  // namespace translucent::reference
