// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/bssrdf/registry.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <map>
#include <mutex>

#include "translucent/bssrdf/models.h"
#include "translucent/bssrdf/tabulated.h"

namespace translucent::bssrdf {
namespace {

using Factory = std::unique_ptr<Model> (*)();

// The registry: one line per model.
constexpr Factory kFactories[] = {
    &makeDipole,
    &makeBetterDipole,
    &makeNormalizedDiffusion,
    &makeNormalizedDiffusionFit,
    &makeQuantizedDiffusion,
    &makePhotonBeam,
    &makeDirectionalDipole,
    &makeDipoleExactFdr,
    &makeQuantizedDiffusionFdrFit,
};

const std::vector<std::unique_ptr<Model>>& all() {
  static const std::vector<std::unique_ptr<Model>> models = [] {
    std::vector<std::unique_ptr<Model>> v;
    for (Factory f : kFactories) v.push_back(f());
    return v;
  }();
  return models;
}

}  // namespace

const Model& model(std::string_view name) {
  if (isTabulatedFile(name)) {
    // Loaded once per path and kept for the program's lifetime, like the registered models.
    static std::mutex mutex;
    static std::map<std::string, std::unique_ptr<Model>, std::less<>> loaded;
    const std::lock_guard lock(mutex);
    auto it = loaded.find(name);
    if (it == loaded.end())
      it = loaded.emplace(std::string(name), std::make_unique<TabulatedModel>(
                                                 readProfileSamples(std::string(name)))).first;
    return *it->second;
  }
  for (const auto& m : all())
    if (m->name() == name) return *m;
  throw UnknownModelError(fmt::format(
      "unknown model '{}': valid models are {} (or a tabulated profile, a .csv file)", name,
      fmt::join(modelNames(), ", ")));
}

std::vector<std::string> modelNames() {
  std::vector<std::string> names;
  for (const auto& m : all()) names.emplace_back(m->name());
  return names;
}

RgbProfiles profiles(const Model& model, const Medium& medium) {
  medium.validate();
  RgbProfiles out;
  for (int c = 0; c < 3; ++c) out[static_cast<size_t>(c)] = model.profile(medium.channel(c));
  return out;
}

}  // namespace translucent::bssrdf
