// SPDX-License-Identifier: GPL-3.0-or-later
// translucent invert --model M --rd r,g,b --ld r,g,b [--eta 1.3]: (Rd, ℓd) -> (σa, σs'), seed 3.4.
#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include <filesystem>

#include "translucent/bssrdf/registry.h"
#include "bssrdf_models.h"
#include "commands.h"
#include "translucent/gpu/bssrdf_profiles.h"
#include "translucent/optics/inversion.h"
#include "options.h"

namespace translucent::cli {

void addInvertCommand(CLI::App& app) {
  struct Args {
    std::string model = "dipole", rd, ld;
    double eta = 1.3;
    bool json = false;
    std::vector<std::string> params;
  };
  auto args = std::make_shared<Args>();
  auto* cmd = app.add_subcommand(
      "invert", "Convert total diffuse reflectance Rd and diffuse mean free path ld to σa, σs'");
  cmd->add_option("--model", args->model,
                  "Model whose Rd(α') is inverted: a model name, or a .bssrdf file with a "
                  "diffuseReflectance section (inverted on the GPU)")
      ->capture_default_str();
  cmd->add_option("--param", args->params,
                  "NAME=VALUE for a parameter of a .bssrdf model (repeatable; default: the "
                  "file's)");
  cmd->add_option("--rd", args->rd, "Total diffuse reflectance Rd, 'v' or 'r,g,b'")->required();
  cmd->add_option("--ld", args->ld, "Diffuse mean free path ℓd = 1/σtr, 'v' or 'r,g,b' [mm]")
      ->required();
  cmd->add_option("--eta", args->eta, "Relative index of refraction η")->capture_default_str();
  cmd->add_flag("--json", args->json, "Print JSON");
  cmd->callback([args] {
    const double eta = args->eta;
    if (!std::isfinite(eta) || eta <= 0.0)
      throw ParameterError(fmt::format("--eta is {}: expected a positive index of refraction", eta));
    const Rgb rd = parseRgb(args->rd, "--rd"), ld = parseRgb(args->ld, "--ld");
    Medium med;
    if (isBssrdfFile(args->model)) {
      if (!std::filesystem::is_regular_file(args->model))
        throw ParameterError(fmt::format("--model {}: no such .bssrdf file", args->model));
      if (!beginWork()) return;  // the file is compiled and inverted on the GPU
      const auto gl = bssrdfContext("--model " + args->model);
      const auto e = loadBssrdfModel(args->model, args->params);
      checkParamsUsed(args->params, {e.get()});
      med = gpu::invertBssrdfMedium(*e, rd, ld, eta);
    } else {
      if (!args->params.empty())
        throw ParameterError("--param applies to .bssrdf models only");
      const auto& m = bssrdf::model(args->model);
      med = invertMedium([&](double a) { return m.totalReflectance(a, eta); }, rd, ld, eta);
      if (!beginWork()) return;  // a registered model's inversion is part of the checks
    }
    Rgb sp{};
    for (size_t c = 0; c < 3; ++c) sp[c] = med.channel(static_cast<int>(c)).sigmaSPrime();
    if (args->json) {
      nlohmann::json j{{"model", args->model}, {"eta", eta}, {"sigma_a", med.sigma_a},
                       {"sigma_s_prime", sp}, {"units", "1/mm"}};
      fmt::print("{}\n", j.dump(2));
      return;
    }
    fmt::print("model {} (eta {})\n", args->model, eta);
    fmt::print("sigma_a        {:.9g},{:.9g},{:.9g} [1/mm]\n", med.sigma_a[0], med.sigma_a[1],
               med.sigma_a[2]);
    fmt::print("sigma_s_prime  {:.9g},{:.9g},{:.9g} [1/mm]\n", sp[0], sp[1], sp[2]);
  });
}

}  // namespace translucent::cli
