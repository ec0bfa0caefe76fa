// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/gpu/bssrdf_profiles.h"

#include <fmt/format.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

#include "translucent/optics/inversion.h"
#include "translucent/optics/quadrature.h"

namespace translucent::gpu {
namespace {


std::vector<Rgb> evaluate(BssrdfEvaluator& e, const std::vector<double>& radii) {
  std::vector<float> r(radii.size());
  for (size_t i = 0; i < r.size(); ++i) r[i] = static_cast<float>(radii[i]);
  const auto v = e.profile(r);
  std::vector<Rgb> out(v.size());
  for (size_t i = 0; i < v.size(); ++i)
    out[i] = {double(v[i][0]), double(v[i][1]), double(v[i][2])};
  return out;
}

// The profile samples lie on the x axis with normal incidence; a renderer evaluates Bssrdf()
// at every azimuth and direction. A shader that returns NaN or inf only there (an atan2, a
// division by Xo.y) rendered without a word: it is probed at every 16th radius, at 4 azimuths
// with tilted directions, and named as on the axis.
void checkOffAxis(BssrdfEvaluator& e, const std::vector<double>& radii) {
  std::vector<BssrdfQuery> queries;
  for (size_t i = 0; i < radii.size(); i += 16)
    for (int k = 0; k < 4; ++k) {
      const double phi = 2.0 * std::numbers::pi * (k + 0.37) / 4.0;
      const auto r = static_cast<float>(radii[i]);
      BssrdfQuery q;
      q.x_o = glm::vec3(r * static_cast<float>(std::cos(phi)), r * static_cast<float>(std::sin(phi)), 0.0f);
      q.w_i = glm::normalize(glm::vec3(0.3f * static_cast<float>(k - 1), 0.2f, 1.0f));
      q.w_o = glm::normalize(glm::vec3(-0.2f, 0.25f * static_cast<float>(k - 2), 1.0f));
      queries.push_back(q);
    }
  const auto v = e.evaluate(queries);
  for (size_t c = 0; c < 3; ++c) {
    size_t bad = 0, first = 0;
    for (size_t i = 0; i < v.size(); ++i)
      if (!std::isfinite(v[i][c]) && bad++ == 0) first = i;
    if (bad == 0) continue;
    const BssrdfQuery& q = queries[first];
    throw ParameterError(fmt::format(
        "{}: Bssrdf() returned {} NaN or infinite values in the {} channel of {} samples off the "
        "x axis (the first, {}, at Xi = (0, 0, 0), Xo = ({:.4g}, {:.4g}, 0), Wi = ({:.3g}, {:.3g}, "
        "{:.3g}), Wo = ({:.3g}, {:.3g}, {:.3g})): expected finite values everywhere a renderer "
        "evaluates it",
        e.file().path, bad, kChannelNames[c], v.size(), v[first][c], q.x_o.x, q.x_o.y, q.w_i.x,
        q.w_i.y, q.w_i.z, q.w_o.x, q.w_o.y, q.w_o.z));
  }
}

// Appends the 8 Gauss-Legendre nodes of [a, b] to `nodes`.
void appendNodes(std::vector<double>& nodes, double a, double b) {
  const double h = 0.5 * (b - a), m = 0.5 * (a + b);
  for (double x : kGauss8X) nodes.push_back(m + h * x);
}

// 2π ∫ R r dr over panel p (nodes 8p..8p+7 of `values` for channel c).
double panelIntegral(const std::vector<double>& nodes, const std::vector<Rgb>& values, size_t p,
                     size_t c, double a, double b) {
  double s = 0.0;
  for (size_t k = 0; k < 8; ++k) s += kGauss8W[k] * nodes[8 * p + k] * values[8 * p + k][c];
  return 2.0 * M_PI * 0.5 * (b - a) * s;
}

}  // namespace

std::vector<Rgb> bssrdfProfile(BssrdfEvaluator& evaluator, const Medium& medium,
                               const std::vector<double>& radii) {
  evaluator.setMedium(medium);
  return evaluate(evaluator, radii);
}

std::unique_ptr<bssrdf::TabulatedModel> bssrdfTabulatedModel(BssrdfEvaluator& evaluator,
                                                             const Medium& medium,
                                                             const std::string& name, int n) {
  const BssrdfEnergy energy = bssrdfRadiusForFraction(evaluator, medium, 1.0 - 1e-7);
  const double rMax = std::max({energy.radius[0], energy.radius[1], energy.radius[2]});
  std::vector<double> radii(static_cast<size_t>(std::max(n, 2)));
  for (size_t i = 0; i < radii.size(); ++i)
    radii[i] = 1e-6 * rMax * std::pow(1e6, double(i) / double(radii.size() - 1));
  const auto values = bssrdfProfile(evaluator, medium, radii);
  bssrdf::ProfileSamples t;
  t.source = name;
  t.eta = medium.eta;
  for (size_t i = 0; i < radii.size(); ++i) {
    t.r_mm.push_back(radii[i] * medium.scale);
    // Tiny negative float values far out (cancellation in a shader) are clamped to 0.
    for (size_t c = 0; c < 3; ++c)
      t.R_mm[c].push_back(std::max(0.0, values[i][c]) / (medium.scale * medium.scale));
  }
  return std::make_unique<bssrdf::TabulatedModel>(std::move(t));
}

std::vector<analysis::Curve> bssrdfCurves(BssrdfEvaluator& evaluator, const std::string& label,
                                          const Medium& medium,
                                          const std::vector<analysis::Channel>& channels,
                                          const std::vector<double>& grid, bool times_r) {
  const auto values = bssrdfProfile(evaluator, medium, grid);
  std::vector<analysis::Curve> curves;
  for (analysis::Channel ch : channels) {
    analysis::Curve c{label, analysis::channelName(ch), grid, {}, {}};
    c.value.reserve(grid.size());
    for (size_t i = 0; i < grid.size(); ++i) {
      double y = ch == analysis::Channel::Luminance ? analysis::luminance(values[i])
                                                    : values[i][static_cast<size_t>(ch)];
      if (times_r) y *= grid[i];
      c.value.push_back(y);
    }
    curves.push_back(std::move(c));
  }
  return curves;
}

BssrdfEnergy bssrdfRadiusForFraction(BssrdfEvaluator& evaluator, const Medium& medium,
                                     double fraction) {
  if (!(fraction > 0.0 && fraction < 1.0))
    throw ParameterError(fmt::format("energy fraction is {}: expected in (0, 1)", fraction));
  evaluator.setMedium(medium);
  // Range: from 1e-6 of the shortest reduced mean free path ℓ' (the inner disc [0, lo] is one
  // linear panel) to well past the diffusion decay length 1/σtr of every channel: e^(-σtr r)
  // is below 1e-17 at 40/σtr. Without absorption the profile decays only algebraically; the
  // range then ends at 1e8 ℓ' and the tail check below decides.
  double lMin = std::numeric_limits<double>::infinity(), hi = 0.0;
  for (int c = 0; c < 3; ++c) {
    const ScalarMedium m = medium.channel(c);
    const double sigmaTPrime = m.sigmaTPrime(), l = 1.0 / sigmaTPrime;
    lMin = std::min(lMin, l);
    const double sigmaTr = std::sqrt(3.0 * m.sigma_a * sigmaTPrime);
    hi = std::max(hi,
                  std::min(1e8 * l, std::max(1e3 * l, sigmaTr > 0.0 ? 40.0 / sigmaTr : 1e8 * l)));
  }
  const double lo = 1e-6 * lMin;
  // A valid profile may decay more slowly than the diffusion models (a power-law tail, a wider
  // multiple-scattering lobe): where the last panel still holds more than the tail bound of Rd
  // below, the range grows tenfold, up to 1e8 ℓ' of the longest channel, before the profile is
  // called not integrable.
  double lMax = 0.0;
  for (int c = 0; c < 3; ++c) lMax = std::max(lMax, 1.0 / medium.channel(c).sigmaTPrime());
  const double hiCap = std::max(hi, 1e8 * lMax);
  constexpr double kTailBound = 1e-9;  // of Rd, in the last panel
  // Log panels, 20 per decade (ratio 1.12: 8-point Gauss-Legendre is exact to ~1e-12 there for
  // the smooth profiles of diffusion models); panel 0 is [0, lo].
  const int perDecade = 20;
  std::vector<double> edges, nodes;
  std::vector<Rgb> values;
  for (;;) {
    const size_t panels = 1 + static_cast<size_t>(std::ceil(perDecade * std::log10(hi / lo)));
    edges = {0.0, lo};
    for (size_t p = 1; p < panels; ++p) edges.push_back(lo * std::pow(10.0, double(p) / perDecade));
    nodes.clear();
    for (size_t p = 0; p + 1 < edges.size(); ++p) appendNodes(nodes, edges[p], edges[p + 1]);
    values = evaluate(evaluator, nodes);
    if (hi >= hiCap) break;
    bool converged = true, finite = true;
    for (size_t c = 0; c < 3; ++c) {
      double total = 0.0, last = 0.0;
      for (size_t p = 0; p + 1 < edges.size(); ++p) {
        last = panelIntegral(nodes, values, p, c, edges[p], edges[p + 1]);
        total += last;
      }
      if (!std::isfinite(total)) finite = false;
      if (!(total > 0.0) || last > kTailBound * total) converged = false;
    }
    if (converged || !finite) break;  // NaN and inf are named below
    hi = std::min(hiCap, 10.0 * hi);
  }
  // A shader that returns NaN or inf somewhere (often only off-axis or far out) is named as
  // such, with where: the integral below would only say "not integrable ... needs absorption".
  // Negative values are counted for that message too.
  std::array<size_t, 3> negative{};
  for (size_t c = 0; c < 3; ++c) {
    size_t bad = 0, first = 0;
    for (size_t i = 0; i < values.size(); ++i) {
      if (!std::isfinite(values[i][c])) {
        if (bad++ == 0) first = i;
      } else if (values[i][c] < 0.0) {
        ++negative[c];
      }
    }
    if (bad > 0)
      throw ParameterError(fmt::format(
          "{}: Bssrdf() returned {} NaN or infinite values in the {} channel of {} profile samples "
          "on [0, {:.3g}] (the first, {}, at r = {:.4g}): expected finite values",
          evaluator.file().path, bad, kChannelNames[c], values.size(), hi, values[first][c],
          nodes[first]));
  }

  checkOffAxis(evaluator, nodes);

  BssrdfEnergy out;
  for (size_t c = 0; c < 3; ++c) {
    std::vector<double> cum{0.0};
    for (size_t p = 0; p + 1 < edges.size(); ++p)
      cum.push_back(cum.back() + panelIntegral(nodes, values, p, c, edges[p], edges[p + 1]));
    const double total = cum.back();
    // The last panel must hold a negligible part of Rd, or the integral has not converged.
    const double lastPanel = total - cum[cum.size() - 2];
    if (!std::isfinite(total) || total <= 0.0 || lastPanel > kTailBound * total)
      throw ParameterError(fmt::format(
          "{}: the {} channel's profile is not integrable on [0, {:.3g}] (Rd so far {:.6g}, {:.3g} "
          "of it in the last panel{}): it needs absorption or a decaying, non-negative profile",
          evaluator.file().path, kChannelNames[c], hi, total, lastPanel / total,
          negative[c] > 0 ? fmt::format("; {} of {} samples negative", negative[c], values.size())
                          : std::string()));
    out.rd[c] = total;
    const double target = fraction * total;
    const size_t k = static_cast<size_t>(std::lower_bound(cum.begin(), cum.end(), target) -
                                         cum.begin());  // cum[k-1] < target
    const double a = edges[k - 1], b = edges[k];
    // Refine inside the crossing panel: 64 sub-panels, then linear interpolation in one of them
    // (relative width 2e-3: the interpolation error is far below float noise).
    const int sub = 64;
    std::vector<double> subEdges, subNodes;
    for (int s = 0; s <= sub; ++s) subEdges.push_back(a + (b - a) * s / sub);
    for (int s = 0; s < sub; ++s) appendNodes(subNodes, subEdges[s], subEdges[s + 1]);
    const auto subValues = evaluate(evaluator, subNodes);
    double acc = cum[k - 1];
    double radius = b;
    for (int s = 0; s < sub; ++s) {
      const double piece = panelIntegral(subNodes, subValues, s, c, subEdges[s], subEdges[s + 1]);
      if (acc + piece >= target) {
        radius = subEdges[s] + (subEdges[s + 1] - subEdges[s]) * (target - acc) / piece;
        break;
      }
      acc += piece;
    }
    out.radius[c] = radius;
  }
  return out;
}

bssrdf::ProfileTable tabulateBssrdf(BssrdfEvaluator& evaluator, const Medium& medium, int channel,
                                    size_t n, double fraction) {
  if (n < 2) throw ParameterError("tabulateBssrdf: a profile table needs at least 2 entries");
  if (channel < 0 || channel > 2)
    throw ParameterError(fmt::format("tabulateBssrdf: channel {} is not 0, 1 or 2", channel));
  const auto c = static_cast<size_t>(channel);
  const BssrdfEnergy energy = bssrdfRadiusForFraction(evaluator, medium, fraction);
  bssrdf::ProfileTable t;
  t.rd = energy.rd[c];
  t.r_max = energy.radius[c];
  t.R.resize(n);
  t.r_times_R.resize(n);
  t.cdf.resize(n);
  // One dispatch: the n grid radii, 8 nodes per interval, and the two radii of the r = 0 fallback.
  std::vector<double> radii(n);
  for (size_t i = 0; i < n; ++i) radii[i] = t.radius(i);
  std::vector<double> nodes;
  for (size_t i = 1; i < n; ++i) appendNodes(nodes, t.radius(i - 1), t.radius(i));
  const double eps = 1e-7 * t.radius(1), quarter = 0.25 * t.radius(1);
  std::vector<double> all = radii;
  all.insert(all.end(), nodes.begin(), nodes.end());
  all.push_back(eps);
  all.push_back(quarter);
  const auto values = evaluate(evaluator, all);
  const std::vector<Rgb> nodeValues(values.begin() + static_cast<std::ptrdiff_t>(n),
                                    values.end() - 2);
  double cumulative = 0.0;
  for (size_t i = 0; i < n; ++i) {
    double value = values[i][c], rValue = radii[i] * value;
    if (i == 0 && !std::isfinite(value)) {
      rValue = eps * values[values.size() - 2][c];
      value = values.back()[c];
    } else if (i == 0 && bssrdf::isClampedSingularity(value, values.back()[c])) {
      // A shader that clamps r at the source (1/max(r, 1e-6)): as bssrdf::tabulate does.
      value = values.back()[c];
      rValue = quarter * value;
    }
    t.R[i] = static_cast<float>(value);
    t.r_times_R[i] = static_cast<float>(rValue);
    if (i > 0)
      cumulative += panelIntegral(nodes, nodeValues, i - 1, c, t.radius(i - 1), t.radius(i));
    t.cdf[i] = static_cast<float>(std::min(1.0, cumulative / t.rd));
  }
  return t;
}

Medium invertBssrdfMedium(BssrdfEvaluator& evaluator, const Rgb& rd, const Rgb& ld, double eta,
                          double g) {
  if (!evaluator.hasDiffuseReflectance())
    throw ParameterError(fmt::format(
        "{}: no diffuseReflectance section: inverting (Rd, ld) needs DiffuseReflectance(alpha') "
        "(Bitterli 2013, appendix A.2)",
        evaluator.file().path));
  Medium m;  // only η (and g) reach DiffuseReflectance(); the coefficients are placeholders
  m.eta = eta;
  m.g = g;
  evaluator.setMedium(m);
  for (size_t c = 0; c < 3; ++c) {
    if (!std::isfinite(ld[c]) || ld[c] <= 0.0)
      throw ParameterError(fmt::format("ld ({} channel) is {}: expected a positive length",
                                       kChannelNames[c], ld[c]));
    if (!std::isfinite(rd[c]))
      throw ParameterError(
          fmt::format("Rd ({} channel) is {}: expected a finite value", kChannelNames[c], rd[c]));
  }
  // Parallel subdivision (seed 3.4): every channel's bracket [lo, hi] is cut into 512
  // subintervals, Rdr is evaluated at all 3 x 513 edges in one dispatch and the subinterval
  // holding Rd is kept. Edges are kept as the floats actually evaluated, so f(lo) < Rd <= f(hi)
  // holds exactly from one round to the next. Four rounds shrink the bracket below float spacing.
  constexpr int kSub = 512;
  std::array<float, 3> lo{0.0f, 0.0f, 0.0f}, hi{1.0f, 1.0f, 1.0f};
  std::array<double, 3> fLo{}, fHi{};
  for (int round = 0; round < 4; ++round) {
    std::vector<float> alphas;
    alphas.reserve(3 * (kSub + 1));
    for (size_t c = 0; c < 3; ++c)
      for (int k = 0; k <= kSub; ++k)
        alphas.push_back(
            k == kSub
                ? hi[c]
                : static_cast<float>(double(lo[c]) + (double(hi[c]) - double(lo[c])) * k / kSub));
    const auto f = evaluator.diffuseReflectance(alphas);
    for (size_t c = 0; c < 3; ++c) {
      const size_t base = c * (kSub + 1);
      auto at = [&](int k) { return double(f[base + static_cast<size_t>(k)][c]); };
      if (round == 0 && !(rd[c] > at(0) && rd[c] < at(kSub)))
        throw ParameterError(fmt::format(
            "Rd ({} channel) is {}: not reachable, the model reaches total diffuse reflectances "
            "in ({:.6g}, {:.6g}) for this index of refraction",
            kChannelNames[c], rd[c], at(0), at(kSub)));
      int k = 1;
      while (k < kSub && at(k) < rd[c]) ++k;
      const float newLo = alphas[base + static_cast<size_t>(k - 1)];
      const float newHi = alphas[base + static_cast<size_t>(k)];
      fLo[c] = at(k - 1);
      fHi[c] = at(k);
      lo[c] = newLo;
      hi[c] = newHi;
    }
  }
  Rgb sigmaA{}, sigmaSPrime{};
  for (size_t c = 0; c < 3; ++c) {
    // Linear interpolation inside the last bracket (a few float ulps wide).
    const double t =
        fHi[c] > fLo[c] ? std::clamp((rd[c] - fLo[c]) / (fHi[c] - fLo[c]), 0.0, 1.0) : 0.5;
    const double alpha = double(lo[c]) + t * (double(hi[c]) - double(lo[c]));
    const auto k = coefficientsFromAlbedo(alpha, ld[c]);
    sigmaA[c] = k.sigma_a;
    sigmaSPrime[c] = k.sigma_s_prime;
  }
  return Medium::fromReduced(sigmaA, sigmaSPrime, g, eta);
}

}  // namespace translucent::gpu
