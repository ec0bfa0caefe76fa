// SPDX-License-Identifier: GPL-3.0-or-later
// The Material dock (issue 12, §5): the scene's material type and its parameters.
//
//   - a type combo: homogeneous and every registered spatially varying type
//     (material::materialTypes()); changing the type starts from defaults built from the current
//     (representative) medium: two media (it and a more absorbing one), a period, cell or
//     thickness a quarter of the normalised mesh (in medium units), eta, scale and model kept;
//   - the material's parameters as a form generated from its JSON description (what
//     ExplorerState::materialJson() writes): numbers as spin boxes labelled by their key, arrays
//     of numbers as small vectors, a medium's "preset" as a preset combo, file keys ("file",
//     image keys of "map" and "rd_map" given as text) as a path field with a browse button,
//     booleans as check boxes, other text as a line edit, objects and arrays of objects as
//     nested groups.
// Every edit sends the whole edited description through ExplorerState::setMaterialJson (the
// scene parser's material parsing): when valid the scene changes and the viewport re-renders;
// when not, the parser's message (it names the key) goes to the console and the scene keeps its
// last good material while the form keeps the edit, so it can be corrected.
//
// The debug view below the form (material/debug_view.h): σa, σs', Rd or the 95% radius of one
// channel or the luminance, over the mesh from the scene's camera in false colour (viridis, its
// range printed beside it), recomputed on the CPU (a QtConcurrent task: the GUI stays responsive;
// an answer to an older request is dropped) 150 ms after the scene or the material last changed
// while a quantity is chosen; what it cannot show goes to the console.
//
// Widgets are named by their JSON path ("period", "media[1].sigma_a[0]", "layers[0].thickness"),
// the type combo "material_type", so that tests and scripts can find them.
#pragma once

#include <QtWidgets/QDockWidget>

#include <nlohmann/json.hpp>

#include <cstdint>
#include <memory>
#include <string>

#include "translucent/geometry/mesh.h"
#include "material/debug_view.h"

class QComboBox;
class QTimer;
class QFormLayout;
class QLabel;
class QWidget;

namespace translucent::explorer {

class ExplorerState;

class MaterialDock : public QDockWidget {
  Q_OBJECT

 public:
  explicit MaterialDock(ExplorerState& state, QWidget* parent = nullptr);

  // The description the form shows (the last edit, valid or not).
  const nlohmann::json& edited() const { return edited_; }
  // The default description of `type` for the current scene (see above).
  nlohmann::json defaults(const std::string& type) const;
  // The debug view's last image (empty before the first, or when the quantity is "off").
  const DebugImage& debugImage() const { return debug_; }

 signals:
  void debugViewUpdated();

 private:
  void refresh();                              // the form from the scene's material
  void rebuildForm();                          // widgets from edited_
  void addFields(QFormLayout* form, const nlohmann::json& value, const std::string& path);
  QWidget* fieldFor(const std::string& key, const nlohmann::json& value, const std::string& path);
  void setAt(const std::string& path, nlohmann::json value);  // edits edited_ and applies
  void apply();
  void onType(int index);
  void updateDebugView();

  QComboBox* debugQuantity_;
  QComboBox* debugChannel_;
  QLabel* debugImage_;
  QLabel* debugRange_;
  QTimer* debugTimer_;
  DebugImage debug_;
  std::string meshKey_;
  std::shared_ptr<const geometry::TriangleMesh> mesh_;  // placed, of meshKey_
  uint64_t debugRequest_ = 0;
  QString debugError_;

  ExplorerState& state_;
  nlohmann::json edited_;
  bool applying_ = false;
  QComboBox* type_;
  QLabel* note_;
  QWidget* formHost_;
  QFormLayout* form_ = nullptr;
};

}  // namespace translucent::explorer
