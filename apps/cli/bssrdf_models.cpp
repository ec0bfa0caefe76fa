// SPDX-License-Identifier: GPL-3.0-or-later
#include "bssrdf_models.h"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>

#include "translucent/bssrdf/bssrdf_file.h"
#include "translucent/gpu/gl.h"
#include "options.h"

namespace translucent::cli {
namespace {

std::pair<std::string, std::string> splitParam(const std::string& p) {
  const auto eq = p.find('=');
  if (eq == std::string::npos || eq == 0)
    throw ParameterError(fmt::format("--param '{}': expected NAME=VALUE", p));
  return {p.substr(0, eq), p.substr(eq + 1)};
}

double parseNumber(const std::string& text, const std::string& what) {
  size_t used = 0;
  double v = 0.0;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size())
    throw ParameterError(fmt::format("{} is '{}': expected a number", what, text));
  return v;
}

}  // namespace

bool isBssrdfFile(const std::string& entry) { return bssrdf::isPluginFile(entry); }

std::unique_ptr<gpu::Context> bssrdfContext(const std::string& what) {
  try {
    return std::make_unique<gpu::Context>();
  } catch (const gpu::ContextError& e) {
    throw ParameterError(
        fmt::format("{} needs an OpenGL 4.5 core context (the .bssrdf shader runs "
                    "on the GPU), and none could be created: {}",
                    what, e.what()));
  }
}

std::unique_ptr<gpu::BssrdfEvaluator> loadBssrdfModel(const std::string& path,
                                                      const std::vector<std::string>& params) {
  std::unique_ptr<gpu::BssrdfEvaluator> e = gpu::openBssrdf(path);
  for (const auto& p : params) {
    const auto [name, value] = splitParam(p);
    const bssrdf::BssrdfParameter* decl = e->file().findParameter(name);
    if (decl == nullptr) continue;
    const std::string what = fmt::format("--param {} ({}:{})", name, e->file().path, decl->line);
    if (std::holds_alternative<bssrdf::FloatParameter>(decl->spec)) {
      e->setParameter(name, parseNumber(value, what));
    } else if (std::holds_alternative<bssrdf::BoolParameter>(decl->spec)) {
      if (value != "true" && value != "false" && value != "1" && value != "0")
        throw ParameterError(fmt::format("{} is '{}': expected true, false, 1 or 0", what, value));
      e->setParameter(name, value == "true" || value == "1");
    } else {
      e->setParameter(name, parseRgb(value, what));
    }
  }
  return e;
}

void checkParamsUsed(const std::vector<std::string>& params,
                     const std::vector<const gpu::BssrdfEvaluator*>& models) {
  for (const auto& p : params) {
    const auto name = splitParam(p).first;
    const bool used = std::any_of(models.begin(), models.end(), [&](const auto* m) {
      return m->file().findParameter(name) != nullptr;
    });
    if (!used)
      throw ParameterError(fmt::format(
          "--param {}: no .bssrdf model given with --model declares a parameter '{}'", p, name));
  }
}

}  // namespace translucent::cli
