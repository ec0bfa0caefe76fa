// SPDX-License-Identifier: GPL-3.0-or-later
// The layered slab (layered_slab.h): a scalar double-precision walker, the block driver of
// slab.cpp, and the layers file.
#include "translucent/reference/layered_slab.h"

#include "translucent/io/input_file.h"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>

#include "translucent/io/json.h"
#include "translucent/reference/block_driver.h"
#include "translucent/reference/walk.h"

namespace translucent::reference {

void LayeredSlabSetup::validate() const {
  if (layers.empty()) throw ParameterError("layered slab: no layers: expected at least one");
  for (size_t i = 0; i < layers.size(); ++i) {
    const SlabLayer& L = layers[i];
    auto bad = [&](const char* name, double v, const char* expected) {
      throw ParameterError(
          fmt::format("layered slab: layer {}: {} is {}: expected {}", i + 1, name, v, expected));
    };
    if (!std::isfinite(L.sigma_a) || L.sigma_a < 0.0) bad("sigma_a", L.sigma_a, "a finite value >= 0");
    if (!std::isfinite(L.sigma_s) || L.sigma_s < 0.0) bad("sigma_s", L.sigma_s, "a finite value >= 0");
    if (!(L.sigma_a + L.sigma_s >= 1e-20 && L.sigma_a + L.sigma_s <= 1e20))
      bad("sigma_a + sigma_s", L.sigma_a + L.sigma_s, "a value in [1e-20, 1e20] per length unit");
    if (!(std::abs(L.g) < 1.0)) bad("g", L.g, "a value in (-1, 1)");
    const bool last = i + 1 == layers.size();
    if (std::isinf(L.thickness) && L.thickness > 0.0) {
      if (!last) bad("thickness", L.thickness, "a finite length (only the last layer may be semi-infinite)");
    } else if (!(L.thickness >= 1e-30 && L.thickness <= 1e30)) {
      bad("thickness", L.thickness, "a length in [1e-30, 1e30]");
    }
  }
  // The surfaces and the beam: as for a homogeneous slab of the top layer.
  SlabSetup s;
  s.sigma_a = layers[0].sigma_a;
  s.sigma_s = layers[0].sigma_s;
  s.g = layers[0].g;
  s.n_inside = n_inside;
  s.n_above = n_above;
  s.n_below = n_below;
  s.theta = theta;
  s.phi = phi;
  s.validate();
}

double LayeredSlabSetup::totalThickness() const {
  double t = 0.0;
  for (const SlabLayer& L : layers) t += L.thickness;
  return t;
}

bool LayeredSlabSetup::finite() const { return std::isfinite(totalThickness()); }

namespace {

using detail::Tally;
using detail::Walk;

using detail::Layers;

double uniform01(Rng& rng) {  // 53 random bits from the upper bits of two draws (rng.h)
  const uint64_t hi = rng.next() >> 6;
  const uint64_t lo = rng.next() >> 5;
  return static_cast<double>((hi << 27) | lo) * 0x1.0p-53;
}

bool absorbs(Rng& rng, uint64_t threshold) {
  const uint32_t hi = rng.next();
  const uint32_t thi = static_cast<uint32_t>(threshold >> 32);
  if (hi != thi) return hi < thi;
  return detail::absorbsLowWord(rng.next(), threshold);
}

// The direction at cosine mu and azimuth phi about unit d (Duff et al. 2017, as phase.h).
void scatterDouble(double d[3], double mu, double phi) {
  const double sign = std::copysign(1.0, d[2]);
  const double a = -1.0 / (sign + d[2]);
  const double b = d[0] * d[1] * a;
  const double t1[3] = {1.0 + sign * d[0] * d[0] * a, sign * b, -sign * d[0]};
  const double t2[3] = {b, sign + d[1] * d[1] * a, -d[1]};
  const double st = std::sqrt(std::max(0.0, 1.0 - mu * mu));
  const double u = st * std::cos(phi), v = st * std::sin(phi);
  double o[3], n2 = 0.0;
  for (int k = 0; k < 3; ++k) {
    o[k] = u * t1[k] + v * t2[k] + mu * d[k];
    n2 += o[k] * o[k];
  }
  const double inv = 1.0 / std::sqrt(n2);
  for (int k = 0; k < 3; ++k) d[k] = o[k] * inv;
}

template <Absorption kAbs>
bool traceBlock(const Walk& W, const Layers& L, uint64_t seed, uint64_t block, uint64_t count,
                Tally& T, const std::atomic<bool>& stop) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const size_t nl = L.sigmaT.size();
  Rng rng(seed, block);
  for (uint64_t p = 0; p < count; ++p) {
    if (stop.load(std::memory_order_relaxed)) return false;
    double x = 0.0, y = 0.0, z = 0.0;
    double d[3] = {static_cast<double>(W.entry.x), static_cast<double>(W.entry.y),
                   static_cast<double>(W.entry.z)};
    double w = W.entryWeight, absorbed = 0.0;
    size_t layer = 0;
    uint64_t scatters = 0;
    for (;;) {
      // Free flight in optical depth, spent layer by layer.
      double tau = -std::log(1.0 - uniform01(rng));
      bool left = false;
      for (;;) {
        const double tb = d[2] > 0.0 ? (L.boundary[layer + 1] - z) / d[2]
                          : d[2] < 0.0 ? (L.boundary[layer] - z) / d[2]
                                       : kInf;
        const double s = tau / L.sigmaT[layer];
        if (s < tb) {
          x += s * d[0];
          y += s * d[1];
          z += s * d[2];
          break;
        }
        x += tb * d[0];
        y += tb * d[1];
        tau = std::max(0.0, tau - tb * L.sigmaT[layer]);
        if (d[2] > 0.0) {
          z = L.boundary[layer + 1];
          if (layer + 1 < nl) {  // into the next layer: index-matched, straight on
            ++layer;
            continue;
          }
        } else {
          z = L.boundary[layer];
          if (layer > 0) {
            --layer;
            continue;
          }
        }
        const bool top = d[2] < 0.0;
        const detail::Crossing c = detail::cross(top ? W.top : W.bottom, std::abs(d[2]));
        if (c.reflectance > 0.0 && uniform01(rng) < c.reflectance) {
          d[2] = -d[2];  // the rest of τ goes on along the mirrored direction
          continue;
        }
        if (top)
          detail::scoreTop(W, T, static_cast<float>(x), static_cast<float>(y), c.cosOut, scatters,
                           w);
        else
          detail::scoreBottom(T, scatters, w);
        left = true;
        break;
      }
      if (left) break;
      if constexpr (kAbs == Absorption::Analog) {
        if (absorbs(rng, L.absorbThreshold[layer])) {
          absorbed = w;
          break;
        }
      } else {
        absorbed += w * (1.0 - L.albedo[layer]);
        w *= L.albedo[layer];
      }
      const double mu = static_cast<double>(sampleHgCosine(L.g[layer], rng.uniform()));
      scatterDouble(d, mu, 2.0 * std::numbers::pi * uniform01(rng));
      ++scatters;
      if (kAbs == Absorption::Weighted && w < detail::kWeightThreshold) {
        if (rng.next() >= detail::kSurviveThreshold) break;
        w *= detail::kSurviveBoost;
      }
      if (W.longPath != 0 && scatters > W.longPath) {
        if (rng.next() >= detail::kSurviveThreshold) break;
        w *= detail::kSurviveBoost;
      }
    }
    T.absorbed.add(absorbed);
    T.events += scatters;
    ++T.photons;
  }
  return true;
}

// Entry, surfaces and tallies as for a homogeneous slab of the top layer and the total
// thickness; the coefficients per layer.
SlabSetup topLayerSlab(const LayeredSlabSetup& setup) {
  SlabSetup s;
  s.sigma_a = setup.layers[0].sigma_a;
  s.sigma_s = setup.layers[0].sigma_s;
  s.g = setup.layers[0].g;
  s.n_inside = setup.n_inside;
  s.n_above = setup.n_above;
  s.n_below = setup.n_below;
  s.theta = setup.theta;
  s.phi = setup.phi;
  s.thickness = setup.totalThickness();
  return s;
}

}  // namespace

namespace detail {
Layers layeredWalk(const LayeredSlabSetup& setup, const TraceOptions& options, SlabSetup& slab) {
  setup.validate();
  options.validate();
  const SlabLayer& last = setup.layers.back();
  if (!setup.finite() && last.sigma_a == 0.0 && options.long_path_roulette == 0)
    throw ParameterError(fmt::format(
        "layered slab: layer {} (semi-infinite) has sigma_a 0: path lengths have infinite mean; "
        "give it a finite thickness, some absorption, or the long-path roulette",
        setup.layers.size()));
  slab = topLayerSlab(setup);
  Layers L;
  double z = 0.0;
  L.boundary.push_back(0.0);
  for (const SlabLayer& layer : setup.layers) {
    z += layer.thickness;
    L.boundary.push_back(z);
    const double st = layer.sigma_a + layer.sigma_s;
    L.sigmaT.push_back(st);
    const double pAbsorb = layer.sigma_a / st;
    L.absorbThreshold.push_back(absorbThreshold(pAbsorb));
    L.albedo.push_back(layer.sigma_s / st);
    L.g.push_back(static_cast<float>(layer.g));
  }
  return L;
}
}  // namespace detail

SlabResult traceLayeredSlab(const LayeredSlabSetup& setup, const TraceOptions& options,
                            const ProgressCallback& progress, RunState* state) {
  SlabSetup s;
  const Layers L = detail::layeredWalk(setup, options, s);
  double rsp = 0.0;
  const Walk W = detail::makeWalk(s, options, rsp);
  const auto kernel = options.absorption == Absorption::Analog ? &traceBlock<Absorption::Analog>
                                                               : &traceBlock<Absorption::Weighted>;
  return detail::runSlabBlocks(
      options, rsp,
      [&](uint64_t b, uint64_t count, Tally& t, const std::atomic<bool>& stop) {
        return kernel(W, L, options.seed, b, count, t, stop);
      },
      progress, state);
}

SlabResult layeredSlabResult(const LayeredSlabSetup& setup, const TraceOptions& options,
                             const RunState& state) {
  setup.validate();
  options.validate();
  double rsp = 0.0;
  detail::makeWalk(topLayerSlab(setup), options, rsp);
  return detail::slabFromState(options, rsp, state);
}

// ---------------------------------------------------------------------------------------------
// The layers file

std::vector<SlabLayer> parseSlabLayers(const std::string& text, const std::string& what) {
  nlohmann::json j;
  try {
    j = io::parseJson(text, what);
  } catch (const io::JsonError& e) {
    throw ParameterError(e.what());
  }
  if (!j.is_array() || j.empty())
    throw ParameterError(fmt::format(
        "{}: expected a non-empty JSON array of layers, top first, each {{\"thickness\": t or "
        "null, \"sigma_a\": ..., \"sigma_s\": ..., \"g\": ...}}", what));
  std::vector<SlabLayer> layers;
  for (size_t i = 0; i < j.size(); ++i) {
    const nlohmann::json& e = j[i];
    const std::string at = fmt::format("{}: layer [{}]", what, i);
    if (!e.is_object()) throw ParameterError(fmt::format("{}: expected a JSON object", at));
    for (const auto& [key, value] : e.items())
      if (key != "thickness" && key != "sigma_a" && key != "sigma_s" && key != "g")
        throw ParameterError(fmt::format(
            "{}: unknown key \"{}\": expected thickness, sigma_a, sigma_s, g", at, key));
    auto number = [&](const char* key, bool required, double fallback) {
      if (!e.contains(key)) {
        if (required) throw ParameterError(fmt::format("{}: \"{}\" is missing", at, key));
        return fallback;
      }
      if (!e[key].is_number())
        throw ParameterError(fmt::format("{}: \"{}\" is {}: expected a number", at, key, e[key].dump()));
      return e[key].get<double>();
    };
    SlabLayer L;
    if (!e.contains("thickness"))
      throw ParameterError(fmt::format("{}: \"thickness\" is missing (null: semi-infinite)", at));
    if (e["thickness"].is_null()) {
      if (i + 1 != j.size())
        throw ParameterError(fmt::format(
            "{}: \"thickness\" is null (semi-infinite): only the last layer may be", at));
      L.thickness = std::numeric_limits<double>::infinity();
    } else {
      L.thickness = number("thickness", true, 0.0);
      if (!(std::isfinite(L.thickness) && L.thickness > 0.0))
        throw ParameterError(fmt::format(
            "{}: \"thickness\" is {}: expected a positive length or null", at, L.thickness));
    }
    L.sigma_a = number("sigma_a", true, 0.0);
    L.sigma_s = number("sigma_s", true, 0.0);
    L.g = number("g", false, 0.0);
    if (!(std::isfinite(L.sigma_a) && L.sigma_a >= 0.0))
      throw ParameterError(fmt::format("{}: \"sigma_a\" is {}: expected a value >= 0", at, L.sigma_a));
    if (!(std::isfinite(L.sigma_s) && L.sigma_s >= 0.0))
      throw ParameterError(fmt::format("{}: \"sigma_s\" is {}: expected a value >= 0", at, L.sigma_s));
    if (!(L.sigma_a + L.sigma_s > 0.0))
      throw ParameterError(fmt::format("{}: \"sigma_a\" + \"sigma_s\" is 0: expected a scattering "
                                       "or absorbing layer", at));
    if (!(std::abs(L.g) < 1.0))
      throw ParameterError(fmt::format("{}: \"g\" is {}: expected a value in (-1, 1)", at, L.g));
    layers.push_back(L);
  }
  return layers;
}

std::vector<SlabLayer> loadSlabLayers(const std::string& path) {
  if (const std::string why = io::irregularInput(path); !why.empty())
    throw ParameterError(fmt::format("{}: {}: expected a layers file (JSON)", path, why));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ParameterError(fmt::format("{}: cannot open the layers file", path));
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw ParameterError(fmt::format("{}: cannot read the layers file", path));
  return parseSlabLayers(text.str(), path);
}

}  // namespace translucent::reference
