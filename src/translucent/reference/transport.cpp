// SPDX-License-Identifier: GPL-3.0-or-later
// Photon transport through a closed body (transport.h): parameters, light fluxes, and the walk
// for the abstract Body (transport_impl.h holds the walk itself).
#include "translucent/reference/transport.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <numbers>

#include "translucent/reference/transport_impl.h"

namespace translucent::reference {

Estimate Moments::estimate(uint64_t n, double measure) const {
  return meanAndError(s, s2, n, measure);
}

namespace {

bool finite3(const glm::dvec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

void requireDirection(glm::dvec3& d, const std::string& what, const char* field) {
  const double len = glm::length(d);
  if (!finite3(d) || !(len > 0.0))
    throw ParameterError(fmt::format("{}: {} is ({}, {}, {}): expected a finite non-zero vector",
                                     what, field, d.x, d.y, d.z));
  d /= len;
}

void requirePositive(double v, const std::string& what, const char* field) {
  if (!std::isfinite(v) || !(v > 0.0))
    throw ParameterError(fmt::format("{}: {} is {}: expected a finite value > 0", what, field, v));
}

}  // namespace

Light Light::validated(const std::string& what) const {
  Light self = *this;
  if (auto* dl = std::get_if<DirectionalLight>(&self.emitter)) {
    requireDirection(dl->direction, what, "direction");
    requirePositive(dl->irradiance, what, "irradiance");
  } else if (auto* pl = std::get_if<PointLight>(&self.emitter)) {
    if (!finite3(pl->position))
      throw ParameterError(fmt::format("{}: position is not finite", what));
    requirePositive(pl->intensity, what, "intensity");
  } else if (auto* el = std::get_if<EnvironmentLight>(&self.emitter)) {
    if (!el->map || el->map->width < 1 || el->map->height < 1)
      throw ParameterError(fmt::format("{}: environment light without a map", what));
    if (!std::isfinite(el->rotate))
      throw ParameterError(fmt::format("{}: rotate is {}: expected a finite angle", what, el->rotate));
    requirePositive(el->intensity, what, "intensity");
    if (!el->samplers[0] && !el->samplers[1] && !el->samplers[2])
      throw ParameterError(fmt::format(
          "{}: the environment map is black in every channel (or the light was not made with "
          "EnvironmentLight::make): nothing to emit", what));
  } else {
    auto& bl = std::get<BeamLight>(self.emitter);
    if (!finite3(bl.origin)) throw ParameterError(fmt::format("{}: origin is not finite", what));
    requireDirection(bl.direction, what, "direction");
    if (!std::isfinite(bl.radius) || bl.radius < 0.0)
      throw ParameterError(
          fmt::format("{}: radius is {}: expected a finite value >= 0", what, bl.radius));
    requirePositive(bl.power, what, "power");
  }
  for (int c = 0; c < 3; ++c) {
    const double v = color[static_cast<size_t>(c)];
    if (!std::isfinite(v) || v < 0.0)
      throw ParameterError(fmt::format("{}: color {} is {}: expected a finite value >= 0", what,
                                       kChannelNames[c], v));
  }
  return self;
}

void TransportOptions::validate() const {
  if (photons == 0) throw ParameterError("transport: photons is 0: expected at least 1");
  if (threads < 0)
    throw ParameterError(fmt::format("transport: threads is {}: expected >= 0 (0: all)", threads));
}

void TransportStats::merge(const TransportStats& o) {
  if (photons.empty()) {
    *this = o;
    return;
  }
  for (size_t c = 0; c < photons.size() && c < o.photons.size(); ++c) {
    photons[c] += o.photons[c];
    emitted[c].merge(o.emitted[c]);
    entered[c].merge(o.entered[c]);
    exited[c].merge(o.exited[c]);
    escaped[c].merge(o.escaped[c]);
    for (size_t k = 0; k < kScatteringOrders; ++k) exited_by_order[k][c].merge(o.exited_by_order[k][c]);
  }
  scattering_events += o.scattering_events;
  next_block = std::max(next_block, o.next_block);
  seconds += o.seconds;
  threads = o.threads;
  partial = partial || o.partial;
}

namespace {
// The flux sums of a channel, by name (write/read below).
template <class Stats>
auto fluxSums(Stats& st, size_t c) {
  using M = decltype(&st.emitted[c]);
  std::vector<std::pair<std::string, M>> sums{
      {"emitted", &st.emitted[c]}, {"entered", &st.entered[c]}, {"exited", &st.exited[c]},
      {"escaped", &st.escaped[c]}};
  for (ScatteringOrder o : kAllScatteringOrders)
    sums.emplace_back(std::string("exited_order.") + toString(o),
                      &st.exited_by_order[static_cast<size_t>(o)][c]);
  return sums;
}
}  // namespace

void TransportStats::write(RunState& state, const std::string& prefix) const {
  state.putCounts(prefix + ".photons", photons);
  state.putCounts(prefix + ".scattering_events", {scattering_events});
  for (size_t c = 0; c < photons.size(); ++c)
    for (const auto& [name, m] : fluxSums(*this, c)) {
      const std::string key = fmt::format("{}.{}.{}", prefix, name, c);
      state.putSums(key + ".s", m->scale().exponent(), {m->rawS()});
      state.putSums(key + ".s2", m->scale().squared().exponent(), {m->rawS2()});
    }
}

void TransportStats::read(const RunState& state, const std::string& prefix) {
  photons = state.getCounts(prefix + ".photons", photons.size());
  scattering_events = state.getCounts(prefix + ".scattering_events", 1)[0];
  for (size_t c = 0; c < photons.size(); ++c)
    for (const auto& [name, m] : fluxSums(*this, c)) {
      const std::string key = fmt::format("{}.{}.{}", prefix, name, c);
      m->setRaw(state.getSums(key + ".s", 1, m->scale().exponent())[0],
                state.getSums(key + ".s2", 1, m->scale().squared().exponent())[0]);
    }
}

uint64_t TransportStats::totalPhotons() const {
  uint64_t n = 0;
  for (uint64_t p : photons) n += p;
  return n;
}

double emittedFlux(const Light& light, const BoundingSphere& b, int channel) {
  double flux = 0.0;
  if (const auto* dl = std::get_if<DirectionalLight>(&light.emitter)) {
    flux = dl->irradiance * std::numbers::pi * b.radius * b.radius;
  } else if (const auto* pl = std::get_if<PointLight>(&light.emitter)) {
    const double dist = glm::length(b.center - pl->position);
    double solidAngle = 4.0 * std::numbers::pi;
    if (dist > b.radius) {
      const double cosMax = std::sqrt(std::max(0.0, 1.0 - (b.radius / dist) * (b.radius / dist)));
      solidAngle = 2.0 * std::numbers::pi * (1.0 - cosMax);
    }
    flux = pl->intensity * solidAngle;
  } else if (const auto* el = std::get_if<EnvironmentLight>(&light.emitter)) {
    // The radiance crossing the disc of radius R perpendicular to each direction: πR² ∫ L dω.
    const auto& sampler = el->samplers[static_cast<size_t>(channel)];
    flux = sampler ? el->intensity * std::numbers::pi * b.radius * b.radius * sampler->integral() : 0.0;
  } else {
    flux = std::get<BeamLight>(light.emitter).power;
  }
  return flux * light.color[static_cast<size_t>(channel)];
}

nlohmann::json fluxPerChannelJson(const TransportStats& s) {
  nlohmann::json j = nlohmann::json::array();
  for (size_t c = 0; c < s.photons.size(); ++c) {
    const auto em = s.emitted[c].estimate(s.photons[c]);
    const auto en = s.entered[c].estimate(s.photons[c]);
    const auto ex = s.exited[c].estimate(s.photons[c]);
    const auto es = s.escaped[c].estimate(s.photons[c]);
    nlohmann::json byOrder = nlohmann::json::object();
    for (ScatteringOrder o : kAllScatteringOrders) {
      const auto e = s.exited_by_order[static_cast<size_t>(o)][c].estimate(s.photons[c]);
      byOrder[toString(o)] = {{"exited", e.value}, {"exited_stderr", e.std_error}};
    }
    j.push_back({{"emitted", em.value}, {"entered", en.value}, {"entered_stderr", en.std_error},
                 {"exited", ex.value}, {"exited_stderr", ex.std_error},
                 {"escaped", es.value}, {"escaped_stderr", es.std_error},
                 {"exited_by_order", std::move(byOrder)}});
  }
  return j;
}

TransportStats emptyStats(const BoundingSphere& bounds, size_t channels,
                          std::span<const Light> lights) {
  TransportStats stats;
  stats.photons.assign(channels, 0);
  for (size_t c = 0; c < channels; ++c) {
    double flux = 0.0;  // summed as channelWalks sums ChannelWalk::totalFlux
    for (const Light& l : lights) flux += emittedFlux(l, bounds, static_cast<int>(c));
    const MomentSum zero(FixedScale::around(flux));
    stats.emitted.push_back(zero);
    stats.entered.push_back(zero);
    stats.exited.push_back(zero);
    stats.escaped.push_back(zero);
    for (auto& v : stats.exited_by_order) v.push_back(zero);
  }
  return stats;
}

std::vector<WalkChannel> walkChannels(const BoundingSphere& bounds,
                                      std::span<const ScalarMedium> channels,
                                      std::span<const Light> lights) {
  std::vector<WalkChannel> out;
  for (const auto& w : detail::channelWalks(bounds, channels, lights)) {
    WalkChannel c;
    c.sigma_t = w.sigmaT;
    c.absorb_probability = w.absorbProbability;
    c.g = static_cast<double>(w.g);
    c.eta = w.matched ? 1.0 : w.eta;
    c.flux = w.totalFlux;
    for (double f : w.lightCdf) c.light_cdf.push_back(w.totalFlux > 0.0 ? f / w.totalFlux : 1.0);
    out.push_back(std::move(c));
  }
  return out;
}

TransportStats scoreWalkedBlocks(const BoundingSphere& bounds, std::span<const Light> lights,
                                 std::span<const WalkChannel> channels, uint64_t first,
                                 uint64_t blocks, const WalkFunction& walk, ExitTally& tally,
                                 const ProgressCallback& progress) {
  const size_t nc = channels.size();
  TransportStats pass = emptyStats(bounds, nc, lights);
  const auto start = std::chrono::steady_clock::now();
  auto elapsed = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  const uint64_t perBlock = kBlockPhotons * nc, total = blocks * perBlock;
  uint64_t batch = 4, done = 0;
  std::vector<WalkedBatch> walked(nc);
  while (done < blocks) {
    const uint64_t nb = std::min(batch, blocks - done);
    const double t0 = elapsed();
    for (size_t c = 0; c < nc; ++c) walk(static_cast<int>(c), first + done, nb, walked[c]);
    for (uint64_t b = 0; b < nb; ++b) {
      // transport_impl.h traceBlocks: one tally block per block, its channels in order.
      auto block = tally.newBlock();
      detail::BlockCounters k(nc);
      for (size_t c = 0; c < nc; ++c) {
        const WalkedBatch& w = walked[c];
        for (uint64_t p = 0; p < kBlockPhotons; ++p) {
          const WalkedPhoton& ph = w.photons[b * kBlockPhotons + p];
          k.emitted[c].add(channels[c].flux);
          k.entered[c].add(ph.entered);
          std::array<double, kScatteringOrders> byOrder{};
          for (uint32_t e = 0; e < ph.exits; ++e) {
            const WalkedExit& x = w.exits[ph.first_exit + e];
            ExitRecord r;
            r.position = x.position;
            r.normal = x.normal;
            r.direction = x.direction;
            r.weight = x.weight;
            r.channel = static_cast<int>(c);
            r.order = x.order;
            block->record(r);
            byOrder[static_cast<size_t>(x.order)] += x.weight;
          }
          k.exited[c].add(ph.exited);
          k.addExitedByOrder(c, byOrder);
          k.escaped[c].add(ph.escaped);
          k.events += ph.scatters;
          block->endPhoton();
        }
      }
      tally.merge(*block);
      detail::addBlock(pass, k);
    }
    done += nb;
    if (elapsed() - t0 < 0.05) batch = std::min<uint64_t>(batch * 2, 256);
    if (progress && done < blocks && !progress(TraceProgress{done * perBlock, total, elapsed()})) {
      pass.partial = true;
      break;
    }
  }
  pass.next_block = first + done;
  pass.seconds = elapsed();
  pass.threads = 1;
  if (progress) progress(TraceProgress{done * perBlock, total, pass.seconds});
  return pass;
}

EnvironmentLight EnvironmentLight::make(std::shared_ptr<const lights::EnvironmentMap> map,
                                        double rotate, double intensity) {
  if (!map || map->width < 1 || map->height < 1)
    throw ParameterError("environment light: the map is empty");
  EnvironmentLight l;
  l.map = std::move(map);
  l.rotate = rotate;
  l.intensity = intensity;
  for (int c = 0; c < 3; ++c) {
    bool any = false;
    for (size_t i = static_cast<size_t>(c); i < l.map->rgb.size() && !any; i += 3) any = l.map->rgb[i] > 0.0f;
    if (any)
      l.samplers[static_cast<size_t>(c)] = std::make_shared<const lights::EnvironmentSampler>(
          *l.map, rotate, lights::SampleWeight(c + 1));
  }
  return l;
}

namespace detail {

std::vector<Light> validatedLights(std::span<const Light> lights) {
  if (lights.empty()) throw ParameterError("transport: no lights given: expected at least one");
  std::vector<Light> out;
  for (size_t i = 0; i < lights.size(); ++i)
    out.push_back(lights[i].validated(fmt::format("light {}", i + 1)));
  return out;
}

std::vector<ChannelWalk> channelWalks(const BoundingSphere& bounds,
                                      std::span<const ScalarMedium> channels,
                                      std::span<const Light> lights) {
  if (channels.empty()) throw ParameterError("transport: no medium channels given");
  std::vector<ChannelWalk> walks;
  for (size_t c = 0; c < channels.size(); ++c) {
    const ScalarMedium& m = channels[c];
    m.validate(channels.size() == 3 ? kChannelNames[c] : "");
    if (!(m.sigmaT() > 0.0))
      throw ParameterError("transport: sigma_a + sigma_s is 0: expected a scattering or "
                           "absorbing medium");
    ChannelWalk w;
    w.sigmaT = m.sigmaT();
    w.absorbProbability = m.sigma_a / m.sigmaT();
    w.g = static_cast<float>(m.g);
    w.eta = m.eta;
    w.matched = m.eta == 1.0;
    for (const Light& l : lights) {
      w.totalFlux += emittedFlux(l, bounds, static_cast<int>(c));
      w.lightCdf.push_back(w.totalFlux);
    }
    walks.push_back(std::move(w));
  }
  return walks;
}

}  // namespace detail

TransportStats tracePhotons(const Body& body, std::span<const ScalarMedium> channels,
                            std::span<const Light> lights, const TransportOptions& options,
                            ExitTally& tally, const ProgressCallback& progress) {
  options.validate();
  return detail::traceBlocks(body, channels, lights, options, tally, progress);
}

TransportStats tracePhotons(const Body& body, const VolumeMedium& medium,
                            std::span<const Light> lights, const TransportOptions& options,
                            ExitTally& tally, const ProgressCallback& progress) {
  options.validate();
  if (!medium.field || !medium.grid || !medium.majorant_violations)
    throw ParameterError("transport: heterogeneous medium without a field or a majorant grid");
  if (!std::isfinite(medium.eta) || !(medium.eta > 0.0))
    throw ParameterError(fmt::format("transport: eta is {}: expected a value > 0", medium.eta));
  // The channels carry η and the light fluxes; their coefficients are not used by the walk.
  const ScalarMedium ch{0.0, 1.0, 0.0, medium.eta};
  const std::vector<ScalarMedium> channels(3, ch);
  return detail::traceBlocks(body, channels, lights, options, tally, progress, &medium);
}

}  // namespace translucent::reference
