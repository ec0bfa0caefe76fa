// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/analysis/model_study.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <numbers>
#include <stdexcept>

#include "translucent/bssrdf/registry.h"
#include "translucent/optics/presets.h"

namespace translucent::analysis {
namespace {

using reference::Estimate;

// 2π ∫_a^b R r dr of a model: Gauss-Legendre panels (integratePanel), graded by decades towards 0
// in the first annulus, where profiles may have an integrable 1/r singularity (r R finite).
double annulusEnergy(const bssrdf::RadialProfile& p, double a, double b) {
  double sum = 0.0;
  if (a == 0.0) {
    double lo = 0.0;
    for (double e = 1e-9 * b; e < b; e *= 10.0) {
      sum += bssrdf::integratePanel(p, lo, e);
      lo = e;
    }
    return sum + bssrdf::integratePanel(p, lo, b);
  }
  constexpr int kSub = 4;
  for (int k = 0; k < kSub; ++k)
    sum += bssrdf::integratePanel(p, a + (b - a) * k / kSub, a + (b - a) * (k + 1) / kSub);
  return sum;
}

// The reference's annuli as energies per unit flux entering, with their per-photon second
// moments (E[x_i²] for the photon's contribution x_i to annulus i; the last entry is beyond
// r_max), rebuilt from mean and standard error: E[x²] = N se² (N-1)/N + mean² ... (walk.h's
// var = (Σw²/N - mean²) N/(N-1)).
struct Annuli {
  std::vector<double> edges;  // N + 1 edges of the N tallied annuli
  std::vector<double> c, se, m2;
  double total = 0.0;
  uint64_t n = 0;
};

Annuli annuliOf(const reference::SlabResult& r) {
  const double entering = 1.0 - r.specular_reflectance.value;
  const auto& t = r.radial;
  Annuli a;
  a.n = r.photons;
  const double N = static_cast<double>(a.n);
  auto add = [&](double mean, double se) {
    a.c.push_back(mean / entering);
    a.se.push_back(se / entering);
    const double var = se * se * N * (N - 1.0) / N / (entering * entering);  // Σx²/N - mean²
    a.m2.push_back(var + (mean / entering) * (mean / entering));
  };
  for (size_t i = 0; i <= t.rd.size(); ++i) a.edges.push_back(t.dr * static_cast<double>(i));
  for (size_t i = 0; i < t.rd.size(); ++i) {
    const double area = std::numbers::pi * (a.edges[i + 1] * a.edges[i + 1] - a.edges[i] * a.edges[i]);
    add(t.rd[i] * area, t.rd_stderr[i] * area);
  }
  add(t.beyond.value, t.beyond.std_error);
  for (double c : a.c) a.total += c;
  return a;
}

// Standard error of a linear statistic Σ h_i c_i from the disjoint per-photon moments.
double linearStdError(const Annuli& a, const std::vector<double>& h) {
  double m2 = 0.0, mean = 0.0;
  for (size_t i = 0; i < h.size(); ++i) {
    m2 += h[i] * h[i] * a.m2[i];
    mean += h[i] * a.c[i];
  }
  // Sample variance (N - 1), as the tracer's own standard errors (walk.h).
  return std::sqrt(std::max(0.0, m2 - mean * mean) / static_cast<double>(a.n - 1));
}

// R95 of the reference and its standard error (delta method on C(R) - 0.95 T = 0).
Estimate referenceR95(const Annuli& a) {
  const size_t nb = a.edges.size() - 1;
  const double target = 0.95 * a.total;
  double acc = 0.0;
  for (size_t j = 0; j < nb; ++j) {
    if (acc + a.c[j] >= target && a.c[j] > 0.0) {
      const double f = (target - acc) / a.c[j];
      const double dr = a.edges[j + 1] - a.edges[j];
      const double R = a.edges[j] + f * dr;
      std::vector<double> h(a.c.size(), -0.95);
      for (size_t i = 0; i < j; ++i) h[i] = 0.05;
      h[j] = f - 0.95;
      const double density = a.c[j] / dr;  // dC/dR in the crossing annulus
      return {R, linearStdError(a, h) / density};
    }
    acc += a.c[j];
  }
  return {std::numeric_limits<double>::infinity(), 0.0};
}

std::string percent(double x, int digits = 1) {
  if (!std::isfinite(x)) return "—";
  return fmt::format("{:+.{}f}%", 100.0 * x, digits);
}

std::string plainPercent(double x, int digits = 1) {
  if (!std::isfinite(x)) return "—";
  return fmt::format("{:.{}f}%", 100.0 * x, digits);
}

std::ofstream openOut(const std::string& path) {
  std::ofstream f(path);
  if (!f) throw std::runtime_error(fmt::format("cannot write '{}'", path));
  return f;
}

void closeOut(std::ofstream& f, const std::string& path) {
  f.close();
  if (!f) throw std::runtime_error(fmt::format("error writing '{}'", path));
}

}  // namespace

std::vector<std::string> traceablePresets() {
  std::vector<std::string> out;
  for (const auto& p : presets())
    if (p.sigma_a[0] > 0.0 && p.sigma_a[1] > 0.0 && p.sigma_a[2] > 0.0) out.push_back(p.name);
  return out;
}

void ModelStudyOptions::validate() const {
  if (photons < 1000 || photons > 1'000'000'000'000ull)
    throw ParameterError(
        fmt::format("--photons is {}: expected between 1e3 and 1e12 per channel", photons));
  if (bins < 10 || bins > 100000)
    throw ParameterError(fmt::format("study bins is {}: expected 10 to 100000", bins));
  if (!(r_max_ld > 0.0) || !std::isfinite(r_max_ld))
    throw ParameterError(fmt::format("study r_max_ld is {}: expected > 0", r_max_ld));
  for (const auto& m : models) (void)bssrdf::model(m);
  for (const auto& p : presets) {
    const Preset& pr = preset(p);
    for (int c = 0; c < 3; ++c)
      if (!(pr.sigma_a[static_cast<size_t>(c)] > 0.0))
        throw ParameterError(fmt::format(
            "preset {}: sigma_a ({} channel) is 0: the path-traced reference needs absorption",
            pr.name, kChannelNames[c]));
  }
}

ModelStudy runModelStudy(const ModelStudyOptions& options, const StudyProgressCallback& progress) {
  options.validate();
  const auto start = std::chrono::steady_clock::now();
  ModelStudy study;
  study.options = options;
  study.models = options.models.empty() ? bssrdf::modelNames() : options.models;
  const std::vector<std::string> names =
      options.presets.empty() ? traceablePresets() : options.presets;
  const size_t total = names.size() * 3;
  for (size_t p = 0; p < names.size() && !study.partial; ++p) {
    const Medium medium = preset(names[p]).medium();
    for (int c = 0; c < 3; ++c) {
      const ScalarMedium m = medium.channel(c);
      StudyReference ref;
      ref.preset = preset(names[p]).name;
      ref.channel = c;
      ref.alpha_prime = m.reducedAlbedo();
      ref.eta = m.eta;
      ref.ld = 1.0 / std::sqrt(3.0 * m.sigma_a * m.sigmaTPrime());
      ref.r_max = options.r_max_ld * ref.ld;
      reference::TraceOptions o;
      o.photons = options.photons;
      o.seed = options.seed + 3 * p + static_cast<uint64_t>(c);
      o.threads = options.threads;
      o.radial_bins = options.bins;
      o.radial_max = ref.r_max;
      StudyProgress sp{3 * p + static_cast<size_t>(c), total, ref.preset, c, {}};
      reference::ProgressCallback cb;
      if (progress)
        cb = [&](const reference::TraceProgress& t) {
          sp.trace = t;
          return progress(sp);
        };
      const reference::SlabResult r = reference::traceSlab(reference::SlabSetup::semiInfinite(m), o, cb);
      if (r.partial) {
        study.partial = true;
        break;
      }
      const Annuli a = annuliOf(r);
      ref.photons = r.photons;
      ref.seconds = r.seconds;
      ref.rd = {a.total, linearStdError(a, std::vector<double>(a.c.size(), 1.0))};
      ref.r95 = referenceR95(a);
      double floor = 0.0;
      for (double s : a.se) floor += s;
      ref.noise_floor = std::sqrt(2.0 / std::numbers::pi) * floor / a.total;
      study.references.push_back(ref);
      for (const auto& name : study.models) {
        const auto prof = bssrdf::model(name).profile(m);
        StudyRow row;
        row.model = name;
        row.reference = study.references.size() - 1;
        row.rd = prof->Rd();
        row.r95 = prof->radiusForFraction(0.95);
        const size_t nb = a.edges.size() - 1;
        std::vector<double> sign(a.c.size()), absDiff(a.c.size());
        double l1 = 0.0, inside = 0.0;
        for (size_t i = 0; i <= nb; ++i) {
          double mi;
          if (i < nb) {
            mi = annulusEnergy(*prof, a.edges[i], a.edges[i + 1]);
            inside += mi;
          } else {
            mi = row.rd - inside;
          }
          const double d = mi - a.c[i];
          l1 += std::abs(d);
          absDiff[i] = std::abs(d);
          sign[i] = d > 0.0 ? 1.0 : (d < 0.0 ? -1.0 : 0.0);
        }
        const double L = l1 / a.total;
        // ∂L/∂c_i = (-sign_i - L) / T.
        std::vector<double> h(a.c.size());
        for (size_t i = 0; i < h.size(); ++i) h[i] = (-sign[i] - L) / a.total;
        row.l1 = {L, linearStdError(a, h)};
        double corrected = 0.0;
        for (size_t i = 0; i < absDiff.size(); ++i)
          corrected += foldedNormalMeanInverse(absDiff[i], a.se[i]);
        row.l1_corrected = {corrected / a.total, row.l1.std_error};
        row.at_noise_floor = L < 2.0 * ref.noise_floor;
        const double q = row.rd / a.total;
        row.rd_error = {q - 1.0, q * ref.rd.std_error / a.total};
        if (std::isfinite(ref.r95.value) && ref.r95.value > 0.0) {
          const double ratio = row.r95 / ref.r95.value;
          row.r95_ratio = {ratio, ratio * ref.r95.std_error / ref.r95.value};
        } else {
          row.r95_ratio = {std::numeric_limits<double>::quiet_NaN(), 0.0};
        }
        study.rows.push_back(row);
      }
    }
  }
  study.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return study;
}

double foldedNormalMeanInverse(double observed, double sigma) {
  if (!(sigma > 0.0)) return observed;
  const double floor = sigma * std::sqrt(2.0 / std::numbers::pi);  // F(0)
  if (observed <= floor) return 0.0;
  // F(μ) = σ sqrt(2/π) exp(−μ²/2σ²) + μ erf(μ/(σ√2)) rises from F(0) with F'(μ) = erf(μ/(σ√2))
  // and F(μ) − μ → 0: the root lies in (0, observed]. Bisection to 1e-12 relative (60 halvings).
  auto F = [sigma](double mu) {
    const double z = mu / sigma;
    return sigma * std::sqrt(2.0 / std::numbers::pi) * std::exp(-0.5 * z * z) +
           mu * std::erf(z / std::numbers::sqrt2);
  };
  double lo = 0.0, hi = observed;
  for (int k = 0; k < 60; ++k) {
    const double mid = 0.5 * (lo + hi);
    (F(mid) < observed ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

std::string modelStudySummaryMarkdown(const ModelStudy& study) {
  std::string out =
      "| model | mean L1 | mean L1, noise bias reduced | max L1 | mean Rd error | mean \\|Rd error\\| | "
      "max \\|Rd error\\| | R95 ratio (mean, min–max) |\n|---|---:|---:|---:|---:|---:|---:|---|\n";
  for (const auto& name : study.models) {
    double l1 = 0.0, l1c = 0.0, l1max = 0.0, rd = 0.0, rdabs = 0.0, rdmax = 0.0, r95 = 0.0;
    double r95min = std::numeric_limits<double>::infinity(), r95max = 0.0;
    int n = 0, n95 = 0;
    for (const auto& row : study.rows) {
      if (row.model != name) continue;
      ++n;
      l1 += row.l1.value;
      l1c += row.l1_corrected.value;
      l1max = std::max(l1max, row.l1.value);
      rd += row.rd_error.value;
      rdabs += std::abs(row.rd_error.value);
      if (std::abs(row.rd_error.value) > std::abs(rdmax)) rdmax = row.rd_error.value;
      if (std::isfinite(row.r95_ratio.value)) {
        ++n95;
        r95 += row.r95_ratio.value;
        r95min = std::min(r95min, row.r95_ratio.value);
        r95max = std::max(r95max, row.r95_ratio.value);
      }
    }
    if (n == 0) continue;
    out += fmt::format("| {} | {} | {} | {} | {} | {} | {} | {:.2f} ({:.2f}–{:.2f}) |\n", name,
                       plainPercent(l1 / n), plainPercent(l1c / n), plainPercent(l1max), percent(rd / n),
                       plainPercent(rdabs / n), percent(rdmax), n95 ? r95 / n95 : 0.0,
                       n95 ? r95min : 0.0, r95max);
  }
  return out;
}

void writeModelStudyMarkdown(const std::string& path, const ModelStudy& study,
                             const std::string& command) {
  std::ofstream f = openOut(path);
  const auto& o = study.options;
  f << "# BSSRDF model errors against the path-traced searchlight reference\n\n";
  f << fmt::format(
      "Generated by `{}` ({} photons per channel, {} annuli on [0, {:g} ℓd] plus the rest beyond, "
      "seed {}; {} reference channels, {:.0f} s of wall time{}).\n\n",
      command, o.photons, o.bins, o.r_max_ld, o.seed, study.references.size(), study.seconds,
      study.partial ? "; PARTIAL: stopped early" : "");
  f << "Reference: `reference::traceSlab`, a normally incident pencil beam on a semi-infinite slab "
       "of each preset channel (Jensen et al. 2001 coefficients, g = 0, η = 1.3; Spectralon is "
       "left out: without absorption the semi-infinite walk has no bounded length). Each RGB "
       "channel is a separate case (no luminance mixing). Everything is per unit flux entering "
       "the medium (tally / (1 − Rsp)), as the models' R(r).\n\n";
  f << "Definitions, with c_i the reference's energy 2π∫R r dr in annulus i (the last "
       "\"annulus\" is everything beyond the tallied radius), T = Σ c_i its total diffuse "
       "reflectance, and m_i the model's exact energy in the same annulus (beyond: Rd − the "
       "rest):\n\n"
       "- **L1** = Σ_i |m_i − c_i| / T: the photon-weighted L1 error of 2πrR(r) (0 = identical, "
       "2 = disjoint). Binning can only lower it. *floor* = sqrt(2/π) Σ_i se(c_i) / T is the L1 "
       "an exact model would get from the reference noise alone. L1 is biased upward by that noise "
       "(each |m_i − c_i| is a folded normal); *L1, noise bias reduced* inverts the folded normal's "
       "mean per annulus (0 where |m_i − c_i| ≤ sqrt(2/π) se(c_i)); that reduces the bias, it does "
       "not remove it.\n"
       "- **ΔRd** = Rd_model / T − 1.\n"
       "- **R95 ratio** = R95_model / R95_ref, R95 the radius within which 95% of Rd leaves "
       "(reference: linear interpolation of the cumulative within the crossing annulus).\n"
       "- Standard errors (±) are the reference's, by the delta method from its per-photon "
       "sums.\n\n";
  f << "## Summary over all channels\n\n" << modelStudySummaryMarkdown(study) << "\n";
  f << "## Reference\n\n| preset | ch | α′ | ℓd [mm] | Rd (ref) | R95 ref [mm] | L1 floor | "
       "photons | time [s] |\n|---|---|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const auto& r : study.references)
    f << fmt::format("| {} | {} | {:.5f} | {:.3g} | {:.4f} ± {:.4f} | {:.3g} ± {:.2g} | {} | {} | "
                     "{:.1f} |\n",
                     r.preset, kChannelNames[r.channel], r.alpha_prime, r.ld, r.rd.value,
                     r.rd.std_error, r.r95.value, r.r95.std_error, plainPercent(r.noise_floor, 2),
                     r.photons, r.seconds);
  f << "\n## Per model and channel\n\nEach cell: L1 (L1 with the noise's bias reduced) / ΔRd / R95 "
       "ratio; *noise*: L1 is below twice the floor, so the model's error is not resolved by this "
       "reference (standard errors in the CSV and JSON outputs).\n\n| preset | ch |";
  for (const auto& m : study.models) f << " " << m << " |";
  f << "\n|---|---|";
  for (size_t i = 0; i < study.models.size(); ++i) f << "---|";
  f << "\n";
  for (size_t r = 0; r < study.references.size(); ++r) {
    const auto& ref = study.references[r];
    f << "| " << ref.preset << " | " << kChannelNames[ref.channel] << " |";
    for (const auto& row : study.rows)
      if (row.reference == r)
        f << fmt::format(" {} ({}){} / {} / {:.2f} |", plainPercent(row.l1.value),
                         plainPercent(row.l1_corrected.value), row.at_noise_floor ? " *noise*" : "",
                         percent(row.rd_error.value), row.r95_ratio.value);
    f << "\n";
  }
  closeOut(f, path);
}

void writeModelStudyCsv(const std::string& path, const ModelStudy& study) {
  std::ofstream f = openOut(path);
  f << "model,preset,channel,alpha_prime,eta,photons,rd_ref,rd_ref_se,r95_ref,r95_ref_se,"
       "l1_floor,rd_model,r95_model,l1,l1_se,rd_error,rd_error_se,r95_ratio,r95_ratio_se,"
       "l1_corrected,at_noise_floor\n";
  for (const auto& row : study.rows) {
    const auto& r = study.references[row.reference];
    f << fmt::format("{},{},{},{:.9g},{:.9g},{},{:.9g},{:.3g},{:.9g},{:.3g},{:.4g},{:.9g},{:.9g},"
                     "{:.6g},{:.3g},{:.6g},{:.3g},{:.6g},{:.3g},{:.6g},{}\n",
                     row.model, r.preset, kChannelNames[r.channel], r.alpha_prime, r.eta,
                     r.photons, r.rd.value, r.rd.std_error, r.r95.value, r.r95.std_error,
                     r.noise_floor, row.rd, row.r95, row.l1.value, row.l1.std_error,
                     row.rd_error.value, row.rd_error.std_error, row.r95_ratio.value,
                     row.r95_ratio.std_error, row.l1_corrected.value, row.at_noise_floor ? 1 : 0);
  }
  closeOut(f, path);
}

void writeModelStudyJson(const std::string& path, const ModelStudy& study) {
  using nlohmann::json;
  auto est = [](const Estimate& e) {
    return json{{"value", std::isfinite(e.value) ? json(e.value) : json(nullptr)},
                {"std_error", e.std_error}};
  };
  json j;
  const auto& o = study.options;
  j["options"] = {{"photons", o.photons}, {"bins", o.bins}, {"r_max_ld", o.r_max_ld},
                  {"seed", o.seed}};
  j["models"] = study.models;
  j["seconds"] = study.seconds;
  j["partial"] = study.partial;
  json refs = json::array();
  for (const auto& r : study.references)
    refs.push_back({{"preset", r.preset}, {"channel", kChannelNames[r.channel]},
                    {"alpha_prime", r.alpha_prime}, {"eta", r.eta}, {"ld", r.ld},
                    {"r_max", r.r_max}, {"photons", r.photons}, {"seconds", r.seconds},
                    {"rd", est(r.rd)}, {"r95", est(r.r95)}, {"l1_floor", r.noise_floor}});
  j["references"] = refs;
  json rows = json::array();
  for (const auto& row : study.rows)
    rows.push_back({{"model", row.model}, {"reference", row.reference}, {"rd", row.rd},
                    {"r95", row.r95}, {"l1", est(row.l1)}, {"rd_error", est(row.rd_error)},
                    {"r95_ratio", est(row.r95_ratio)}, {"l1_corrected", est(row.l1_corrected)},
                    {"at_noise_floor", row.at_noise_floor}});
  j["rows"] = rows;
  std::ofstream f = openOut(path);
  f << j.dump(2) << "\n";
  closeOut(f, path);
}

}  // namespace translucent::analysis
