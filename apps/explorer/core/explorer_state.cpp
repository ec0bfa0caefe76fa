// SPDX-License-Identifier: GPL-3.0-or-later
#include "core/explorer_state.h"

#include <algorithm>
#include <utility>

#include <filesystem>

#include <nlohmann/json.hpp>

#include "translucent/bssrdf/registry.h"
#include "translucent/io/json.h"

namespace translucent::explorer {

ExplorerState::ExplorerState(QObject* parent) : QObject(parent), scene_(scene::defaultScene()) {
  // The pencil plot starts with every built-in model, as the seed's explorer does (3.6.3).
  plot_models_ = bssrdf::modelNames();
}

void ExplorerState::setScene(scene::Scene scene) {
  scene.medium.validate();
  scene_ = std::move(scene);
  emit sceneChanged();
  emit materialChanged();
}

void ExplorerState::setTechnique(const std::string& name) {
  if (scene_.technique == name) return;
  scene_.technique = name;
  scene_.settings.clear();  // settings belong to a technique
  emit sceneChanged();
}

void ExplorerState::setTechniqueSetting(const std::string& name, const scene::Setting& value) {
  auto it = scene_.settings.find(name);
  if (it != scene_.settings.end() && it->second == value) return;
  scene_.settings[name] = value;
  emit sceneChanged();
}

void ExplorerState::setCamera(const reference::Camera& camera) {
  scene_.camera = camera;
  emit sceneChanged();
}

void ExplorerState::setLights(std::vector<scene::Light> lights) {
  scene_.lights = std::move(lights);
  emit sceneChanged();
}

void ExplorerState::setDisplay(double exposure, double gamma, analysis::ToneOperator tonemap,
                               double key) {
  if (!(gamma > 0.0)) throw ParameterError("display gamma must be > 0, got " + std::to_string(gamma));
  if (!(key > 0.0)) throw ParameterError("tone map key must be > 0, got " + std::to_string(key));
  scene_.exposure = exposure;
  scene_.gamma = gamma;
  scene_.tonemap = tonemap;
  scene_.tonemap_key = key;
  emit sceneChanged();
}

void ExplorerState::setMedium(const Medium& medium, const std::string& preset) {
  medium.validate();
  scene_.medium = medium;
  scene_.preset = preset;
  emit sceneChanged();
  emit materialChanged();
}

void ExplorerState::setModel(const std::string& model) {
  if (scene_.model == model) return;
  scene_.model = model;
  emit sceneChanged();
  emit materialChanged();
}

std::string ExplorerState::materialJson() const {
  const nlohmann::json doc = nlohmann::json::parse(scene::toJson(scene_));
  return doc.at("material").dump();
}

void ExplorerState::setMaterialJson(const std::string& material) {
  nlohmann::json mat;
  try {
    mat = io::parseJson(material, "material");
  } catch (const io::JsonError& e) {
    throw ParameterError(e.what());
  }
  nlohmann::json doc = nlohmann::json::parse(scene::toJson(scene_));
  doc["material"] = std::move(mat);
  const scene::Scene parsed =
      scene::parseScene(doc.dump(), std::filesystem::current_path(), "material edit");
  parsed.medium.validate();
  scene_.preset = parsed.preset;
  scene_.medium = parsed.medium;
  scene_.model = parsed.model;
  scene_.material = parsed.material;
  for (const auto& [path, name] : parsed.data_names) scene_.data_names[path] = name;
  emit sceneChanged();
  emit materialChanged();
}

void ExplorerState::setPlotModels(std::vector<std::string> models) {
  plot_models_ = std::move(models);
  emit plotModelsChanged();
  emit materialChanged();
}

void ExplorerState::setModelMedium(const std::string& model, std::optional<Medium> medium) {
  if (medium) {
    medium->validate();
    model_media_[model] = *medium;
  } else {
    model_media_.erase(model);
  }
  emit materialChanged();
}

const Medium& ExplorerState::mediumFor(const std::string& model) const {
  auto it = model_media_.find(model);
  return it != model_media_.end() ? it->second : scene_.medium;
}

bool ExplorerState::hasOwnMedium(const std::string& model) const {
  return model_media_.count(model) != 0;
}

void ExplorerState::log(MessageLevel level, const QString& text) { emit message(level, text); }

}  // namespace translucent::explorer
