// SPDX-License-Identifier: GPL-3.0-or-later
// The parameters dock (seed 3.6.1, figure 3.7): the material of the scene and of the pencil plot.
//
//   - σa and σs per RGB channel on logarithmic sliders with numeric fields, or Rd and ℓd per
//     channel converted to σa, σs' by the model's inversion (seed 3.4: a registered model's
//     Rd(α', η), or the DiffuseReflectance section of a .bssrdf file on the GPU); g, η, scale;
//   - the presets of Jensen et al. 2001;
//   - "apply to all models" (the shared medium) or "tweak one model" (a per-model medium,
//     ExplorerState::setModelMedium);
//   - the scene's model, among the registered models and the loaded .bssrdf files;
//   - an approximate colour swatch: the diffuse reflectance Rd per channel of the scene's model,
//     as RGB rescaled to luminance 0.75 (seed 3.6.1), shown sRGB-encoded;
//   - .bssrdf files: load (dialog), reload (button, and automatically when the file changes on
//     disk), their declared parameters as generated widgets (float slider in [min, max], bool
//     check box, colour picker). Parse and GLSL errors go to the console as `file.bssrdf:LINE:
//     ...`; the previous good version stays in use.
// A spatially varying material (scene().material not homogeneous) is edited in the Material
// dock: here the preset, target and coefficients are disabled with a note (they would edit the
// representative medium, which such a material does not render); η, scale and the model still
// apply (the material's common keys).
// Bad input (not a number, negative coefficient, an Rd no model reaches) is refused with a message
// in the console; the medium stays as it was.
#pragma once

#include <QtWidgets/QDockWidget>

#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "translucent/optics/medium.h"

class QCheckBox;
class QComboBox;
class QFileSystemWatcher;
class QFormLayout;
class QGroupBox;
class QLabel;
class QStackedWidget;
class QVBoxLayout;

namespace translucent::explorer {

class ExplorerState;
class MaterialWorker;
class ValueSlider;

class ParametersDock : public QDockWidget {
  Q_OBJECT

 public:
  explicit ParametersDock(ExplorerState& state, QWidget* parent = nullptr);
  ~ParametersDock() override;

  // Loads a .bssrdf file asynchronously (what the "Load .bssrdf…" dialog calls): on success it
  // joins the plot's models and the scene-model list, and its parameters get widgets; on failure
  // the console says why (file:line). bssrdfLoaded(path, ok) is emitted either way.
  void loadBssrdf(const QString& path);
  // Re-reads a loaded file (the Reload button reloads all of them).
  void reloadBssrdf(const QString& path);
  const std::vector<std::string>& loadedFiles() const { return files_; }
  // Loads a tabulated profile (.csv, bssrdf/tabulated.h) as a model: it joins the plot and the
  // model list; on failure the console says why (file:line). profileLoaded(path, ok) either way.
  void loadProfile(const QString& path);
  const std::vector<std::string>& loadedProfiles() const { return tables_; }

  // The swatch colour (sRGB, 8 bits) and the linear RGB it encodes.
  Rgb swatchLinear() const { return swatch_; }

 signals:
  void bssrdfLoaded(const QString& path, bool ok);
  void profileLoaded(const QString& path, bool ok);
  void bssrdfReloaded(const QString& path, bool ok);

 private:
  struct FileWidgets;

  std::string target() const;           // "" (all models) or the tweaked model
  const Medium& editedMedium() const;   // the medium the sliders edit
  // Applies an edited medium to the target; ParameterError goes to the console, nothing changes.
  bool apply(const Medium& medium, const std::string& preset = "");
  void refresh();                        // widgets from the state
  void refreshTargets();
  void refreshModels();
  void updateReflectance();              // Rd fields (Rd, ℓd mode) and the swatch
  void showSwatch(const Rgb& rd);
  void onSigma(int which, int channel, double value);  // which: 0 σa, 1 σs
  void onRdLd();
  void onScalar();
  void onPreset(int index);
  void onModeChanged(int index);
  void rebuildFileWidgets(const std::string& path);
  void onFileChanged(const QString& path);

  ExplorerState& state_;
  MaterialWorker& worker_;
  bool updating_ = false;  // refresh() in progress: widget signals are not edits
  QComboBox* preset_;
  QComboBox* target_;
  QComboBox* model_;
  QComboBox* mode_;
  QStackedWidget* pages_;
  ValueSlider* sigma_[2][3];
  ValueSlider* rd_[3];
  ValueSlider* ld_[3];
  ValueSlider* g_;
  ValueSlider* eta_;
  ValueSlider* scale_;
  QLabel* swatchLabel_;
  QLabel* rdNote_;
  QLabel* heteroNote_;  // shown for a spatially varying material (its coefficients are disabled)
  QVBoxLayout* filesLayout_;
  QFileSystemWatcher* watcher_;
  std::vector<std::string> files_;
  std::vector<std::string> tables_;  // loaded tabulated profiles (absolute paths)
  QLabel* tablesList_ = nullptr;
  std::set<std::string> attempted_;  // files loaded or tried (the scene's model loads once)
  std::map<std::string, QGroupBox*> fileBoxes_;
  Rgb swatch_{};
  uint64_t rdRequest_ = 0;  // latest asynchronous Rd request (older answers are ignored)
};

}  // namespace translucent::explorer
