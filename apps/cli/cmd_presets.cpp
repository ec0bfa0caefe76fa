// SPDX-License-Identifier: GPL-3.0-or-later
// translucent presets [--json]: the measured material table.
#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "translucent/optics/presets.h"

namespace translucent::cli {

void addPresetsCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand("presets", "Print the measured materials of Jensen et al. 2001");
  auto json = std::make_shared<bool>(false);
  cmd->add_flag("--json", *json, "Print JSON instead of a table");
  cmd->callback([json] {
    if (!beginWork()) return;  // no checks: the work is the table
    if (*json) {
      nlohmann::json j;
      j["source"] = presetsSource();
      j["units"] = presetsUnits();
      for (const auto& p : presets())
        j["materials"].push_back({{"name", p.name},
                                  {"sigma_s_prime", p.sigma_s_prime},
                                  {"sigma_a", p.sigma_a},
                                  {"g", p.g},
                                  {"eta", p.eta}});
      fmt::print("{}\n", j.dump(2));
      return;
    }
    fmt::print("# {}\n# sigma_s' and sigma_a in {}; g = {}, eta = {}\n", presetsSource(),
               presetsUnits(), presets().front().g, presets().front().eta);
    fmt::print("{:<11} {:>8} {:>8} {:>8}   {:>8} {:>8} {:>8}\n", "name", "σs'.r", "σs'.g", "σs'.b",
               "σa.r", "σa.g", "σa.b");
    for (const auto& p : presets())
      fmt::print("{:<11} {:>8.4g} {:>8.4g} {:>8.4g}   {:>8.4g} {:>8.4g} {:>8.4g}\n", p.name,
                 p.sigma_s_prime[0], p.sigma_s_prime[1], p.sigma_s_prime[2], p.sigma_a[0],
                 p.sigma_a[1], p.sigma_a[2]);
  });
}

}  // namespace translucent::cli
