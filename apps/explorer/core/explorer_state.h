// SPDX-License-Identifier: GPL-3.0-or-later
// The explorer's document: the scene being edited (the same scene::Scene the CLI renders), the
// models shown in the pencil plot, and the console log. Docks read it and edit it through these
// calls; every edit emits a signal so that views refresh and background computations restart.
//
// One ExplorerState per main window, living on the GUI thread. Worker threads never touch it:
// they get copies (scene(), medium(), ...) when they start.
//
// Materials (seed 3.6.1): one medium applies to every model, unless a model has its own
// ("tweak one model"); mediumFor(model) resolves that.
#pragma once

#include <QtCore/QObject>
#include <QtCore/QString>

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "translucent/optics/medium.h"
#include "translucent/scene/scene.h"

namespace translucent::explorer {

enum class MessageLevel { Info, Warning, Error };

class ExplorerState : public QObject {
  Q_OBJECT

 public:
  explicit ExplorerState(QObject* parent = nullptr);  // starts on scene::defaultScene()

  const scene::Scene& scene() const { return scene_; }
  // Replaces the whole scene (load, or an edit of mesh, lights, camera, technique, settings).
  // Emits sceneChanged() and materialChanged().
  void setScene(scene::Scene scene);
  // Edits of parts of the scene; each emits sceneChanged() (and materialChanged() for material).
  void setTechnique(const std::string& name);
  void setTechniqueSetting(const std::string& name, const scene::Setting& value);
  void setCamera(const reference::Camera& camera);
  void setLights(std::vector<scene::Light> lights);
  void setDisplay(double exposure, double gamma,
                  analysis::ToneOperator tonemap = analysis::ToneOperator::Clamp, double key = 1.0);

  // The shared medium (scene().medium) and its preset name ("" for custom coefficients).
  // The medium is validated first: an invalid one throws ParameterError and nothing changes.
  const Medium& medium() const { return scene_.medium; }
  void setMedium(const Medium& medium, const std::string& preset = "");
  // The scene's model (what the viewport renders): a registered name or a .bssrdf path.
  void setModel(const std::string& model);
  // The scene's "material" object as a scene file writes it (scene::toJson), and its
  // replacement: `material` goes through scene::parseScene's material parsing (any type,
  // homogeneous included), so an invalid one throws ParameterError naming the key
  // ("material.period ...") and nothing changes. Relative file names are taken relative to
  // the working directory. Emits sceneChanged() and materialChanged().
  std::string materialJson() const;
  void setMaterialJson(const std::string& material);

  // Models in the pencil plot (registered names and .bssrdf paths), in display order.
  const std::vector<std::string>& plotModels() const { return plot_models_; }
  void setPlotModels(std::vector<std::string> models);  // emits plotModelsChanged()
  // Per-model medium override ("tweak one model"); nullopt: the shared medium.
  void setModelMedium(const std::string& model, std::optional<Medium> medium);
  const Medium& mediumFor(const std::string& model) const;
  bool hasOwnMedium(const std::string& model) const;

  // The console: every dock reports through here.
  void log(MessageLevel level, const QString& text);
  void info(const QString& text) { log(MessageLevel::Info, text); }
  void warning(const QString& text) { log(MessageLevel::Warning, text); }
  void error(const QString& text) { log(MessageLevel::Error, text); }

 signals:
  void sceneChanged();       // anything in the scene (including the material)
  void materialChanged();    // medium, model, per-model media
  void plotModelsChanged();
  void message(translucent::explorer::MessageLevel level, const QString& text);

 private:
  scene::Scene scene_;
  std::vector<std::string> plot_models_;
  std::map<std::string, Medium> model_media_;
};

}  // namespace translucent::explorer
