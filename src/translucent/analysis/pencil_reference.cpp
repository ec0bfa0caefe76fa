// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/analysis/pencil_reference.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "translucent/reference/gpu/device.h"

namespace translucent::analysis {
namespace {

using reference::Estimate;
using reference::SlabResult;

// Per-photon sums behind an estimate (walk.h's Sums::estimate, inverted).
struct Sums {
  double s = 0.0, s2 = 0.0;
};

Sums sumsOf(const Estimate& e, uint64_t n) {
  const double N = static_cast<double>(n);
  const double var = N > 1.0 ? e.std_error * e.std_error * N : 0.0;  // per-photon variance
  return {e.value * N, N * (e.value * e.value + var * (N - 1.0) / N)};
}

Estimate estimateOf(const Sums& t, uint64_t n) {
  if (n == 0) return {};
  const double N = static_cast<double>(n);
  const double mean = t.s / N;
  const double var = n > 1 ? std::max(0.0, t.s2 / N - mean * mean) * N / (N - 1.0) : 0.0;
  return {mean, std::sqrt(var / N)};
}

std::array<bool, 3> channelsNeeded(Channel ch) {
  return {ch == Channel::Red || ch == Channel::Luminance,
          ch == Channel::Green || ch == Channel::Luminance,
          ch == Channel::Blue || ch == Channel::Luminance};
}

}  // namespace

Estimate poolEstimates(const Estimate& a, uint64_t n_a, const Estimate& b, uint64_t n_b) {
  const Sums sa = sumsOf(a, n_a), sb = sumsOf(b, n_b);
  return estimateOf({sa.s + sb.s, sa.s2 + sb.s2}, n_a + n_b);
}

void accumulateSlab(SlabResult& total, const SlabResult& pass) {
  if (total.photons == 0) {
    total = pass;
    return;
  }
  if (total.radial.rd.size() != pass.radial.rd.size() || total.radial.dr != pass.radial.dr)
    throw ParameterError(fmt::format(
        "accumulateSlab: radial tallies differ ({} bins of {} vs {} bins of {})",
        total.radial.rd.size(), total.radial.dr, pass.radial.rd.size(), pass.radial.dr));
  const uint64_t na = total.photons, nb = pass.photons;
  auto pool = [&](Estimate& t, const Estimate& p) { t = poolEstimates(t, na, p, nb); };
  pool(total.diffuse_reflectance, pass.diffuse_reflectance);
  pool(total.transmittance, pass.transmittance);
  pool(total.diffuse_transmittance, pass.diffuse_transmittance);
  pool(total.unscattered_transmittance, pass.unscattered_transmittance);
  pool(total.absorbed, pass.absorbed);
  auto poolRadial = [&](reference::RadialProfileTally& t, const reference::RadialProfileTally& p) {
    for (size_t i = 0; i < t.rd.size(); ++i) {
      Estimate e{t.rd[i], t.rd_stderr[i]};
      pool(e, {p.rd[i], p.rd_stderr[i]});
      t.rd[i] = e.value;
      t.rd_stderr[i] = e.std_error;
    }
    pool(t.beyond, p.beyond);
  };
  poolRadial(total.radial, pass.radial);
  for (size_t k = 0; k < total.orders.size(); ++k) {
    SlabResult::Order& t = total.orders[k];
    const SlabResult::Order& p = pass.orders[k];
    pool(t.diffuse_reflectance, p.diffuse_reflectance);
    pool(t.transmittance, p.transmittance);
    poolRadial(t.radial, p.radial);
    t.angular = {};
  }
  // The angular tallies are not pooled (the pencil plot does not ask for them).
  total.angular = {};
  total.photons = na + nb;
  total.scattering_events += pass.scattering_events;
  total.seconds += pass.seconds;
  total.partial = total.partial || pass.partial;
}

std::vector<std::optional<reference::ScatteringOrder>> scatteringSelection(std::string_view name) {
  using reference::ScatteringOrder;
  if (name == "all") return {std::nullopt};
  if (name == "single") return {ScatteringOrder::Single};
  if (name == "multiple") return {ScatteringOrder::Multiple};
  if (name == "split") return {std::nullopt, ScatteringOrder::Single, ScatteringOrder::Multiple};
  throw ParameterError(fmt::format("scattering '{}': expected all, single, multiple or split", name));
}

Curve pencilReferenceCurve(const std::array<const SlabResult*, 3>& results, Channel ch,
                           bool times_r, std::optional<reference::ScatteringOrder> order) {
  const auto needed = channelsNeeded(ch);
  const SlabResult* any = nullptr;
  for (size_t c = 0; c < 3; ++c) {
    if (!needed[c]) continue;
    if (results[c] == nullptr)
      throw ParameterError(fmt::format("reference curve ({}): the {} channel was not traced",
                                       channelName(ch), kChannelNames[c]));
    if (any == nullptr) any = results[c];
  }
  auto radialOf = [&](const SlabResult& r) -> const reference::RadialProfileTally& {
    return order ? r.order(*order).radial : r.radial;
  };
  Curve curve{order ? std::string("reference (") + reference::toString(*order) + ")"
                    : std::string("reference"),
              channelName(ch), any->radial.r, {}, {}};
  static constexpr double kLum[3] = {0.2126, 0.7152, 0.0722};
  for (size_t i = 0; i < curve.r.size(); ++i) {
    double v = 0.0, var = 0.0;
    for (size_t c = 0; c < 3; ++c) {
      if (!needed[c]) continue;
      const double w = (ch == Channel::Luminance ? kLum[c] : 1.0) /
                       (1.0 - results[c]->specular_reflectance.value);
      const reference::RadialProfileTally& rad = radialOf(*results[c]);
      v += w * rad.rd[i];
      var += w * w * rad.rd_stderr[i] * rad.rd_stderr[i];
    }
    const double k = times_r ? curve.r[i] : 1.0;
    curve.value.push_back(k * v);
    curve.stderr_.push_back(k * std::sqrt(var));
  }
  return curve;
}

bool tracePencilReference(const Medium& medium, Channel channel,
                          const PencilReferenceOptions& options,
                          const std::function<void(const PencilReferencePass&)>& on_pass,
                          const std::atomic<bool>* stop) {
  medium.validate();
  if (!(options.r_max > 0.0) || options.bins < 1)
    throw ParameterError(fmt::format(
        "pencil reference: needs r_max > 0 and at least one bin (got r_max {}, bins {})",
        options.r_max, options.bins));
  if (options.photons == 0 || options.first_pass == 0)
    throw ParameterError("pencil reference: the photon budget and first pass must be positive");
  const auto needed = channelsNeeded(channel);
  for (size_t c = 0; c < 3; ++c)
    if (needed[c] && !(medium.channel(static_cast<int>(c)).sigma_a > 0.0))
      throw ParameterError(fmt::format(
          "pencil reference: sigma_a ({} channel) is 0: a non-absorbing semi-infinite medium "
          "never lets every photon go; the path-traced reference needs absorption",
          kChannelNames[c]));

  const reference::TraceDevice device = reference::openTraceDevice(options.device, "reference device");
  PencilReferencePass state;
  uint64_t next = std::min(options.first_pass, options.photons);
  auto stopped = [&] { return stop != nullptr && stop->load(); };
  for (int pass = 0; state.photons < options.photons; ++pass) {
    const uint64_t n = std::min(next, options.photons - state.photons);
    std::array<SlabResult, 3> traced;
    for (size_t c = 0; c < 3; ++c) {
      if (!needed[c]) continue;
      if (stopped()) return false;
      reference::TraceOptions o;
      o.photons = n;
      o.seed = options.seed + 3 * static_cast<uint64_t>(pass) + c;
      o.threads = options.threads;
      o.radial_bins = options.bins;
      o.radial_max = options.r_max;
      reference::SlabSetup setup = reference::SlabSetup::semiInfinite(medium.channel(static_cast<int>(c)));
      setup.theta = options.theta;
      traced[c] = reference::traceSlab(
          device, setup, o,
          [&](const reference::TraceProgress&) { return !stopped(); });
      if (traced[c].partial) return false;
      state.device = traced[c].device;
    }
    for (size_t c = 0; c < 3; ++c)
      if (needed[c]) accumulateSlab(state.results[c], traced[c]);
    state.pass = pass;
    state.photons += n;
    state.last = state.photons >= options.photons;
    if (on_pass) on_pass(state);
    next = std::min<uint64_t>(2 * next, options.photons);
  }
  return true;
}

}  // namespace translucent::analysis
