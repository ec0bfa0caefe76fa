// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/techniques/common/profile_kernel.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <utility>

#include "translucent/bssrdf/exit_radiance.h"
#include "translucent/bssrdf/registry.h"
#include "translucent/gpu/bssrdf_profiles.h"

namespace translucent::techniques {

ParameterInfo tableSizeParameter(std::string help) {
  return ParameterInfo::integer("table_size", 4096, 64, 65536, std::move(help));
}

ParameterInfo radianceConventionParameter() {
  return ParameterInfo::enumeration("radiance_convention", kDefaultRadianceConvention,
                                    bssrdf::exitConventionNames(),
                                    "radiance from the exitance B (Bitterli 2013, Eq. 2.16): jensen Ft B/π, or "
                                    "normalized Ft B/(π 4Cφ(1/η)), which carries out exactly B; see "
                                    "docs/radiance-convention.md");
}

RgbProfileTable tabulateRgbProfile(const scene::Scene& s, size_t n, gpu::BssrdfEvaluator* evaluator) {
  RgbProfileTable out;
  auto& tables = out.tables;
  std::array<std::vector<double>, 3> values;
  double rMax = 0.0;
  if (evaluator == nullptr) {
    const bssrdf::Model& model = bssrdf::model(s.model);
    const bssrdf::RgbProfiles prof = bssrdf::profiles(model, s.medium);
    for (const auto& p : prof) rMax = std::max(rMax, p->radiusForFraction(kProfileTableFraction));
    for (size_t c = 0; c < 3; ++c) {
      values[c].resize(n);
      for (size_t i = 0; i < n; ++i) values[c][i] = prof[c]->R(rMax * double(i) / double(n - 1));
      if (!std::isfinite(values[c][0])) values[c][0] = prof[c]->R(0.25 * rMax / double(n - 1));
      tables[c].rd = prof[c]->Rd();
    }
  } else {
    // The radius and Rd from the file's own GPU values (gpu/bssrdf_profiles.h: Gauss-Legendre
    // panels on a log grid), then R on the table grid, evaluated by the same kernel.
    const gpu::BssrdfEnergy energy =
        gpu::bssrdfRadiusForFraction(*evaluator, s.medium, kProfileTableFraction);
    for (size_t c = 0; c < 3; ++c) {
      rMax = std::max(rMax, energy.radius[c]);
      tables[c].rd = energy.rd[c];
    }
    std::vector<double> grid(n);
    for (size_t i = 0; i < n; ++i) grid[i] = rMax * double(i) / double(n - 1);
    const std::vector<Rgb> g = gpu::bssrdfProfile(*evaluator, s.medium, grid);
    // R may diverge at r = 0: entry 0 then holds R a quarter step out (as bssrdf::tabulate).
    const std::vector<Rgb> quarter =
        gpu::bssrdfProfile(*evaluator, s.medium, {0.25 * rMax / double(n - 1)});
    for (size_t c = 0; c < 3; ++c) {
      values[c].resize(n);
      for (size_t i = 0; i < n; ++i) values[c][i] = g[i][c];
      if (!std::isfinite(values[c][0])) values[c][0] = quarter[0][c];
    }
  }
  out.gpu.resize(n);
  for (size_t c = 0; c < 3; ++c) {
    tables[c].r_max = rMax;
    tables[c].R.resize(n);
    for (size_t i = 0; i < n; ++i) {
      if (!std::isfinite(values[c][i]))
        throw ParameterError(fmt::format("model '{}': R(r = {}) of the {} channel is {}: expected a "
                                         "finite profile", s.model, rMax * double(i) / double(n - 1),
                                         kChannelNames[c], values[c][i]));
      tables[c].R[i] = static_cast<float>(values[c][i]);
      out.gpu[i][int(c)] = tables[c].R[i];
    }
  }
  return out;
}

}  // namespace translucent::techniques
