// SPDX-License-Identifier: GPL-3.0-or-later
// Fitting a technique's parameters to a reference image: `translucent fit`. The objective is the
// relative RMSE of the technique's radiance against the reference's over compare's interior mask
// (analysis/metrics.h, without the noise correction, which is flat at zero near a noisy
// optimum), minimised by BOBYQA (Powell 2009; NLopt's LN_BOBYQA), a derivative-free method for
// bound-constrained problems, over the parameters' ranges (each mapped to [0, 1], linearly or
// logarithmically), starting from the technique's present values and started again from the
// best point while a run still gains 1%.
//
// The empirical shader (Gascons 2011) has no physical calibration: its parameters are an artist's
// (Eqs. 3.6–3.10). empiricalFitParameters() lists the ones that shape the translucency and the
// diffuse colour; the fitted values are a starting point that the artist keeps tuning (a scene file
// carries them to the explorer).
#pragma once

#include <functional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "translucent/compare/compare.h"
#include "translucent/techniques/technique.h"

namespace translucent::analysis {

struct FitParameter {
  std::string name;      // a float parameter of the technique
  double lo = 0.0, hi = 1.0;
  bool log = false;      // searched in log(value) (lo > 0)
};

// k_a, K_d (red, green, blue), w_d, w_s, w_b, the thickness exponent r and K_b.
std::vector<FitParameter> empiricalFitParameters();

struct FitOptions {
  int max_evaluations = 1000;
  double relative_tolerance = 1e-4;  // on the objective
};

struct FitResult {
  std::vector<std::pair<std::string, double>> before, after;  // parameter values
  Metrics before_metrics, after_metrics;  // technique vs reference over the mask
  int evaluations = 0;
  int starts = 0;  // BOBYQA runs (each from the best point so far)
  double seconds = 0.0;
  std::string stop_reason;  // NLopt's
};

// Fits `params` of the prepared technique `t` (scene `s`: its camera size) to `reference`
// (radiance under the technique's convention) over `mask`; leaves the technique at the fitted
// values. ParameterError naming a parameter that is not a float of the technique or whose range
// is empty (or not positive where `log`). `progress(evaluation, objective)` may return false to
// stop early (the best values so far are kept).
FitResult fitTechnique(techniques::Technique& t, const scene::Scene& s,
                       const CompareImage& reference, std::span<const uint8_t> mask,
                       std::span<const FitParameter> params, const FitOptions& options = {},
                       const std::function<bool(int, double)>& progress = {});

}  // namespace translucent::analysis
