// SPDX-License-Identifier: GPL-3.0-or-later
// The model error study: every registered BSSRDF model against the path-traced searchlight
// reference (reference::traceSlab: a normally incident pencil beam on a semi-infinite slab of the
// medium) for every traceable preset and each RGB channel separately (`translucent profile
// --study`, docs/model-error.md).
//
// Per preset channel (σa, σs', g, η of Medium::channel), the reference tallies Rd(r) in `bins`
// equal annuli on [0, r_max] plus everything beyond r_max, with r_max = r_max_ld · ℓd,
// ℓd = 1/sqrt(3 σa σt'). All quantities are per unit flux entering the medium (the tally per
// incident photon divided by 1 - Rsp), as the models' R(r). With c_i the reference's energy in
// annulus i (c_N: beyond r_max), T = Σ c_i its total diffuse reflectance, and m_i = 2π∫ R r dr
// of the model over the same annulus (m_N = Rd - Σ_{i<N} m_i):
//   L1        = Σ_i |m_i - c_i| / T          photon-weighted L1 error of 2π r R(r) on the
//                                            annuli (0: identical, 2: disjoint); binning can
//                                            only lower it (triangle inequality)
//   Rd error  = Rd_model / T - 1
//   R95 ratio = R95_model / R95_ref, R95 the radius holding 95% of Rd (reference: linear in
//               the cumulative within the annulus where it crosses 0.95 T)
// Standard errors come from the reference's per-photon sums by the delta method (exact second
// moments: a photon lands in one annulus, so the annuli's per-photon variables are disjoint).
// `noise_floor` = sqrt(2/π) Σ_i se(c_i) / T is the L1 that an exact model would show from the
// reference's noise alone: L1 values near it do not resolve the model's error.
// L1 is biased upward by that noise: the observed |d_i| = |m_i − c_i| has the mean of a folded
// normal, E|d_i| = F(μ_i) = σ_i sqrt(2/π) exp(−μ_i²/2σ_i²) + μ_i erf(μ_i / (σ_i √2)), with μ_i the
// true difference and σ_i = se(c_i), so L1 falls as photons are added (a cell moved by ~20 of its
// standard errors from 1e6 to 4e6 photons). `l1_corrected` = Σ_i μ̂_i / T inverts it per annulus:
// μ̂_i = F⁻¹(|d_i|), 0 where |d_i| ≤ σ_i sqrt(2/π) (moment matching on one observation). That
// reduces the bias but does not remove it: no unbiased estimator of |μ| from one normal
// observation exists, and where μ_i ~ 0 the draws above the threshold still count. Measured on
// photon beam diffusion, Skin1, 300 annuli: from 1e6 to 4e6 photons the raw L1 of the blue channel
// fell by 0.0117 (3.6 standard errors), the corrected one by 0.0052 (1.6). Its standard error is
// L1's (the same delta method on the same annuli).
// `at_noise_floor`: the raw L1 is below twice `noise_floor`, where the noise's bias is at least
// half of it: the model's error is not resolved by this reference (more photons would resolve it).
//
// Determinism: channel k of preset p uses the seed seed + 3p + k; the result is bit-identical for
// any thread count (reference/slab.h).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "translucent/reference/slab.h"

namespace translucent::analysis {

// Presets whose every channel absorbs (σa > 0): the semi-infinite walk then ends with
// probability 1 in bounded expected time. Table order.
std::vector<std::string> traceablePresets();

struct ModelStudyOptions {
  std::vector<std::string> models;   // empty: all registered
  std::vector<std::string> presets;  // empty: traceablePresets()
  uint64_t photons = 1'000'000;      // per channel
  int bins = 300;
  double r_max_ld = 6.0;  // tally radius in diffuse mean free paths
  uint64_t seed = 1;
  int threads = 0;  // 0: all

  void validate() const;  // ParameterError naming the option
};

struct StudyReference {
  std::string preset;
  int channel = 0;
  double alpha_prime = 0.0, eta = 1.0, ld = 0.0, r_max = 0.0;  // ℓd, r_max [mm]
  uint64_t photons = 0;
  double seconds = 0.0;
  reference::Estimate rd;   // T, per unit flux entering
  reference::Estimate r95;  // [mm]; value +inf when beyond r_max
  double noise_floor = 0.0;
};

struct StudyRow {
  std::string model;
  size_t reference = 0;  // index into ModelStudy::references
  double rd = 0.0;       // model Rd
  double r95 = 0.0;      // model R95 [mm]
  reference::Estimate l1, rd_error, r95_ratio;
  reference::Estimate l1_corrected;  // the noise's bias reduced (above)
  bool at_noise_floor = false;
};

// μ ≥ 0 whose folded-normal mean F(μ) with standard deviation σ is `observed` (0 where observed
// ≤ σ sqrt(2/π), `observed` where σ = 0): the bias correction of one annulus (above).
double foldedNormalMeanInverse(double observed, double sigma);

struct ModelStudy {
  ModelStudyOptions options;
  std::vector<std::string> models;
  std::vector<StudyReference> references;
  std::vector<StudyRow> rows;  // per reference, per model
  double seconds = 0.0;
  bool partial = false;  // stopped before every reference was traced
};

struct StudyProgress {
  size_t index = 0, total = 0;  // reference channel being traced
  std::string preset;
  int channel = 0;
  reference::TraceProgress trace;
};
// Return false to stop (the references traced so far are kept; partial = true).
using StudyProgressCallback = std::function<bool(const StudyProgress&)>;

ModelStudy runModelStudy(const ModelStudyOptions& options,
                         const StudyProgressCallback& progress = {});

// Outputs. Each throws std::runtime_error naming the file when it cannot be written.
// `command` is the command line that produced the study (quoted in the Markdown).
void writeModelStudyMarkdown(const std::string& path, const ModelStudy& study,
                             const std::string& command);
void writeModelStudyCsv(const std::string& path, const ModelStudy& study);
void writeModelStudyJson(const std::string& path, const ModelStudy& study);

// The per-model summary (mean and max of |L1|, mean and max |Rd error|, R95 ratio range) as a
// Markdown table, the part README.md quotes.
std::string modelStudySummaryMarkdown(const ModelStudy& study);

}  // namespace translucent::analysis
