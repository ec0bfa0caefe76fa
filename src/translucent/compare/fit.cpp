// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/compare/fit.h"

#include <fmt/format.h>
#include <nlopt.hpp>

#include <algorithm>
#include <chrono>
#include <exception>
#include <cmath>
#include <functional>
#include <limits>
#include <variant>

#include "translucent/compare/compare_run.h"

namespace translucent::analysis {
namespace {

double fromUnit(const FitParameter& p, double u) {
  u = std::clamp(u, 0.0, 1.0);
  return p.log ? std::exp(std::log(p.lo) + u * (std::log(p.hi) - std::log(p.lo)))
               : p.lo + u * (p.hi - p.lo);
}

double toUnit(const FitParameter& p, double v) {
  v = std::clamp(v, p.lo, p.hi);
  return p.log ? (std::log(v) - std::log(p.lo)) / (std::log(p.hi) - std::log(p.lo))
               : (v - p.lo) / (p.hi - p.lo);
}

const char* resultName(nlopt::result r) {
  switch (r) {
    case nlopt::SUCCESS: return "success";
    case nlopt::STOPVAL_REACHED: return "objective reached";
    case nlopt::FTOL_REACHED: return "converged (objective tolerance)";
    case nlopt::XTOL_REACHED: return "converged (parameter tolerance)";
    case nlopt::MAXEVAL_REACHED: return "evaluation limit";
    case nlopt::MAXTIME_REACHED: return "time limit";
    default: return "stopped";
  }
}

}  // namespace

std::vector<FitParameter> empiricalFitParameters() {
  return {{"ka", 0.0, 2.0, false},
          {"kd_red", 0.0, 1.0, false},
          {"kd_green", 0.0, 1.0, false},
          {"kd_blue", 0.0, 1.0, false},
          {"diffuse_contribution", 0.0, 4.0, false},
          {"specular_contribution", 0.0, 1.0, false},
          {"backlight", 0.0, 10.0, false},
          {"thickness_exponent", 0.1, 1000.0, true},
          {"diffuse_weight", 0.0, 2.0, false}};
}

FitResult fitTechnique(techniques::Technique& t, const scene::Scene& s,
                       const CompareImage& reference, std::span<const uint8_t> mask,
                       std::span<const FitParameter> params, const FitOptions& options,
                       const std::function<bool(int, double)>& progress) {
  if (params.empty()) throw ParameterError("fit: no parameters to fit");
  for (const FitParameter& p : params) {
    const auto& info = t.parameters();
    const auto it = std::find_if(info.begin(), info.end(), [&](const auto& i) { return i.name == p.name; });
    if (it == info.end() || it->type != techniques::ParameterType::Float)
      throw ParameterError(fmt::format("fit: {} is not a number parameter of {}", p.name, t.name()));
    if (!(p.hi > p.lo) || (p.log && !(p.lo > 0.0)))
      throw ParameterError(fmt::format("fit: {} range [{}, {}] is empty{}", p.name, p.lo, p.hi,
                                       p.log ? " or not positive" : ""));
  }
  const auto t0 = std::chrono::steady_clock::now();
  auto set = [&](const std::vector<double>& u) {
    for (size_t k = 0; k < params.size(); ++k) t.setParameter(params[k].name, fromUnit(params[k], u[k]));
  };
  auto measure = [&] {
    const TimedRender r = renderTimed(t, std::string(t.name()), s, 0, 0);
    return compareImages(r.images.radiance, reference, mask);
  };
  FitResult out;
  std::vector<double> u(params.size());
  for (size_t k = 0; k < params.size(); ++k) {
    const techniques::ParameterValue pv = t.parameter(params[k].name);
    const double v = std::holds_alternative<double>(pv) ? std::get<double>(pv) : params[k].lo;
    out.before.emplace_back(params[k].name, v);
    u[k] = toUnit(params[k], v);
  }
  out.before_metrics = measure();
  double best = std::numeric_limits<double>::infinity();
  std::vector<double> best_u = u;
  bool stopped = false;
  std::exception_ptr failure;
  struct Data {
    std::function<double(const std::vector<double>&)> f;
  } data{[&](const std::vector<double>& x) {
    double e = 0.0;
    // NLopt's C++ wrapper turns an exception from the objective into its own ("nlopt failure"):
    // a render's error is kept here and thrown again after optimize() returns.
    try {
      set(x);
      e = measure().rel_rmse_raw;
    } catch (...) {
      failure = std::current_exception();
      throw nlopt::forced_stop();
    }
    ++out.evaluations;
    const double value = std::isfinite(e) ? e : 1e30;  // a NaN image is the worst, never the best
    if (value < best) {
      best = value;
      best_u = x;
    }
    if (progress && !progress(out.evaluations, best)) {
      stopped = true;
      throw nlopt::forced_stop();
    }
    return value;
  }};
  // BOBYQA stops when its trust region has shrunk around a point; started again there with a
  // fresh region it often finds more (the objective is not convex in the shader's parameters).
  // Restarts until one gains less than 1% of the error or the evaluations are spent.
  std::vector<double> x = u;
  for (int start = 0; !stopped && out.evaluations < options.max_evaluations; ++start) {
    const double before_start = best;
    nlopt::opt opt(nlopt::LN_BOBYQA, static_cast<unsigned>(params.size()));
    opt.set_lower_bounds(std::vector<double>(params.size(), 0.0));
    opt.set_upper_bounds(std::vector<double>(params.size(), 1.0));
    opt.set_min_objective(
        [](const std::vector<double>& v, std::vector<double>&, void* d) {
          return static_cast<Data*>(d)->f(v);
        },
        &data);
    opt.set_maxeval(options.max_evaluations - out.evaluations);
    opt.set_ftol_rel(options.relative_tolerance);
    opt.set_initial_step(start == 0 ? 0.1 : 0.05);
    double value = 0.0;
    x = best_u;
    try {
      out.stop_reason = resultName(opt.optimize(x, value));
    } catch (const nlopt::forced_stop&) {
      out.stop_reason = "stopped";
    } catch (const nlopt::roundoff_limited&) {
      out.stop_reason = "converged (round-off)";
    }
    ++out.starts;
    if (failure) std::rethrow_exception(failure);
    if (start > 0 && !(best < 0.99 * before_start)) break;
  }
  if (stopped) out.stop_reason = "stopped";
  set(best_u);
  for (size_t k = 0; k < params.size(); ++k)
    out.after.emplace_back(params[k].name, fromUnit(params[k], best_u[k]));
  out.after_metrics = measure();
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

}  // namespace translucent::analysis
