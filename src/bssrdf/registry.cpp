#include "bssrdf/registry.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "bssrdf/models.h"

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
  for (const auto& m : all())
    if (m->name() == name) return *m;
  throw UnknownModelError(
      fmt::format("unknown model '{}': valid models are {}", name, fmt::join(modelNames(), ", ")));
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
