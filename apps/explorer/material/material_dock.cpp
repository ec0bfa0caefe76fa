// SPDX-License-Identifier: GPL-3.0-or-later
#include "material/material_dock.h"

#include <QtConcurrent/QtConcurrentRun>
#include <QtCore/QFutureWatcher>
#include <QtCore/QSignalBlocker>
#include <QtCore/QTimer>
#include <QtGui/QImage>
#include <QtGui/QPixmap>
#include <QtWidgets/QCheckBox>
#include <QtWidgets/QComboBox>
#include <QtWidgets/QDoubleSpinBox>
#include <QtWidgets/QFileDialog>
#include <QtWidgets/QFormLayout>
#include <QtWidgets/QGroupBox>
#include <QtWidgets/QHBoxLayout>
#include <QtWidgets/QLabel>
#include <QtWidgets/QLineEdit>
#include <QtWidgets/QPushButton>
#include <QtWidgets/QScrollArea>
#include <QtWidgets/QSpinBox>
#include <QtWidgets/QVBoxLayout>

#include <algorithm>

#include "core/explorer_state.h"
#include "translucent/material/material_desc.h"
#include "translucent/optics/presets.h"

namespace translucent::explorer {
namespace {

using nlohmann::json;

QString q(const std::string& s) { return QString::fromStdString(s); }

// "/media/1/sigma_a/0" -> "media[1].sigma_a[0]" (widget names, messages).
QString displayPath(const std::string& pointer) {
  std::string out;
  size_t i = 0;
  while (i < pointer.size()) {
    const size_t next = pointer.find('/', i + 1);
    const std::string part = pointer.substr(i + 1, next == std::string::npos ? std::string::npos
                                                                              : next - i - 1);
    const bool index = !part.empty() && std::all_of(part.begin(), part.end(),
                                                    [](char c) { return c >= '0' && c <= '9'; });
    if (index)
      out += "[" + part + "]";
    else
      out += (out.empty() ? "" : ".") + part;
    i = next == std::string::npos ? pointer.size() : next;
  }
  return q(out);
}

json rgbJson(const Rgb& v) { return json::array({v[0], v[1], v[2]}); }

json mediumJson(const Medium& m) {
  return json{{"sigma_a", rgbJson(m.sigma_a)}, {"sigma_s", rgbJson(m.sigma_s)}, {"g", m.g}};
}

bool isNumberArray(const json& v) {
  return v.is_array() && !v.empty() &&
         std::all_of(v.begin(), v.end(), [](const json& e) { return e.is_number(); });
}

}  // namespace

MaterialDock::MaterialDock(ExplorerState& state, QWidget* parent)
    : QDockWidget(tr("Material"), parent), state_(state) {
  setObjectName(QStringLiteral("material"));
  auto* body = new QWidget;
  auto* layout = new QVBoxLayout(body);
  auto* top = new QFormLayout;
  type_ = new QComboBox;
  type_->setObjectName(QStringLiteral("material_type"));
  for (const std::string& t : material::materialTypes()) type_->addItem(q(t));
  top->addRow(tr("Type"), type_);
  layout->addLayout(top);
  note_ = new QLabel;
  note_->setObjectName(QStringLiteral("material_note"));
  note_->setWordWrap(true);
  layout->addWidget(note_);
  formHost_ = new QWidget;
  formHost_->setObjectName(QStringLiteral("material_form"));
  new QVBoxLayout(formHost_);
  layout->addWidget(formHost_);

  auto* debugBox = new QGroupBox(tr("Debug view"));
  auto* debugForm = new QFormLayout(debugBox);
  debugQuantity_ = new QComboBox;
  debugQuantity_->setObjectName(QStringLiteral("debug_quantity"));
  debugQuantity_->addItem(tr("Off"));
  for (DebugQuantity dq : {DebugQuantity::SigmaA, DebugQuantity::SigmaSPrime, DebugQuantity::Rd,
                           DebugQuantity::Radius95})
    debugQuantity_->addItem(QString::fromUtf8(debugQuantityName(dq)));
  debugForm->addRow(tr("Show"), debugQuantity_);
  debugChannel_ = new QComboBox;
  debugChannel_->setObjectName(QStringLiteral("debug_channel"));
  debugChannel_->addItems({tr("luminance"), tr("red"), tr("green"), tr("blue")});
  debugForm->addRow(tr("Channel"), debugChannel_);
  debugImage_ = new QLabel;
  debugImage_->setObjectName(QStringLiteral("debug_image"));
  debugImage_->setAlignment(Qt::AlignCenter);
  debugForm->addRow(debugImage_);
  debugRange_ = new QLabel;
  debugRange_->setObjectName(QStringLiteral("debug_range"));
  debugForm->addRow(debugRange_);
  layout->addWidget(debugBox);
  layout->addStretch(1);
  debugTimer_ = new QTimer(this);
  debugTimer_->setSingleShot(true);
  debugTimer_->setInterval(150);
  connect(debugTimer_, &QTimer::timeout, this, &MaterialDock::updateDebugView);
  connect(debugQuantity_, &QComboBox::currentIndexChanged, debugTimer_, qOverload<>(&QTimer::start));
  connect(debugChannel_, &QComboBox::currentIndexChanged, debugTimer_, qOverload<>(&QTimer::start));
  connect(&state_, &ExplorerState::sceneChanged, this, [this] {
    if (debugQuantity_->currentIndex() > 0) debugTimer_->start();
  });
  auto* scroll = new QScrollArea;
  scroll->setWidgetResizable(true);
  scroll->setWidget(body);
  setWidget(scroll);

  connect(type_, &QComboBox::currentIndexChanged, this, &MaterialDock::onType);
  connect(&state_, &ExplorerState::materialChanged, this, [this] {
    if (!applying_) refresh();
  });
  refresh();
}

json MaterialDock::defaults(const std::string& type) const {
  const scene::Scene& s = state_.scene();
  const Medium& m = s.medium;
  const double size = 0.25 * m.scale;  // a quarter of the normalised mesh, in medium units
  json mat;
  if (type == "homogeneous") {
    if (!s.preset.empty() && s.material.homogeneous()) {
      mat = json{{"preset", s.preset}, {"g", m.g}};
    } else {
      mat = mediumJson(m);
    }
  } else {
    Medium other = m;
    for (int c = 0; c < 3; ++c) other.sigma_a[size_t(c)] = 10.0 * m.sigma_a[size_t(c)] + 0.05;
    const json media = json::array({mediumJson(m), mediumJson(other)});
    mat["type"] = type;
    if (type == "layers") {
      mat["layers"] = json::array(
          {json{{"medium", mediumJson(other)}, {"thickness", 0.1 * size}}, json{{"medium", mediumJson(m)}}});
    } else if (type == "veins") {
      mat["media"] = media;
      mat["period"] = size;
    } else if (type == "checker") {
      mat["media"] = media;
      mat["cell"] = size;
    } else if (type == "gradient") {
      mat["media"] = media;
      mat["from"] = json::array({-2.0 * size, 0.0, 0.0});
      mat["to"] = json::array({2.0 * size, 0.0, 0.0});
    } else if (type == "surface_checker") {
      mat["media"] = media;
      mat["cells"] = 8;
    } else if (type == "voxels") {
      mat["file"] = "";
      mat["media"] = media;
    } else if (type == "map") {
      mat["sigma_a"] = "";
      mat["sigma_s_prime"] = "";
    } else if (type == "rd_map") {
      mat["rd"] = json::array({0.6, 0.5, 0.4});
      mat["ld"] = json::array({1.0, 0.5, 0.25});
    }
  }
  mat["eta"] = m.eta;
  mat["scale"] = m.scale;
  mat["model"] = s.model;
  return mat;
}

void MaterialDock::refresh() {
  json current;
  try {
    current = json::parse(state_.materialJson());
  } catch (const std::exception& e) {
    state_.error(QStringLiteral("material: %1").arg(e.what()));
    return;
  }
  if (current == edited_) return;
  edited_ = std::move(current);
  rebuildForm();
}

void MaterialDock::rebuildForm() {
  const std::string type = edited_.value("type", std::string("homogeneous"));
  {
    const QSignalBlocker block(type_);
    type_->setCurrentIndex(std::max(0, type_->findText(q(type))));
  }
  note_->setText(type == "homogeneous"
                     ? tr("One medium everywhere: its coefficients are also in the Parameters dock.")
                     : tr("Spatially varying (%1): media per medium unit, lengths in material space "
                          "(the normalised mesh × scale). Only the pointcloud and empirical "
                          "techniques render it.")
                           .arg(q(type)));
  // Replace the form (the old one may be the sender of the edit that got here: delete later).
  QLayout* host = formHost_->layout();
  while (QLayoutItem* item = host->takeAt(0)) {
    if (QWidget* w = item->widget()) {
      w->hide();
      w->deleteLater();
    }
    delete item;
  }
  auto* page = new QWidget;
  form_ = new QFormLayout(page);
  addFields(form_, edited_, "");
  host->addWidget(page);
}

void MaterialDock::addFields(QFormLayout* form, const json& value, const std::string& path) {
  if (value.is_object()) {
    for (const auto& [key, v] : value.items()) {
      if (path.empty() && (key == "type" || key == "model")) continue;  // the combo; Parameters
      QWidget* w = fieldFor(key, v, path + "/" + key);
      if (w) form->addRow(q(key), w);
    }
  } else if (value.is_array()) {
    for (size_t i = 0; i < value.size(); ++i) {
      QWidget* w = fieldFor(std::to_string(i), value[i], path + "/" + std::to_string(i));
      if (w) form->addRow(QStringLiteral("[%1]").arg(i), w);
    }
  }
}

QWidget* MaterialDock::fieldFor(const std::string& key, const json& value, const std::string& path) {
  const QString name = displayPath(path);
  const std::string type = edited_.value("type", std::string("homogeneous"));
  if (value.is_boolean()) {
    auto* c = new QCheckBox;
    c->setObjectName(name);
    c->setChecked(value.get<bool>());
    connect(c, &QCheckBox::toggled, this, [this, path](bool on) { setAt(path, on); });
    return c;
  }
  if (value.is_number_integer()) {
    auto* s = new QSpinBox;
    s->setObjectName(name);
    s->setRange(-1000000, 1000000);
    s->setKeyboardTracking(false);
    s->setValue(value.get<int>());
    connect(s, &QSpinBox::valueChanged, this, [this, path](int v) { setAt(path, v); });
    return s;
  }
  if (value.is_number()) {
    auto* s = new QDoubleSpinBox;
    s->setObjectName(name);
    s->setRange(-1e9, 1e9);
    s->setDecimals(6);
    s->setKeyboardTracking(false);
    const double v = value.get<double>();
    s->setSingleStep(v != 0.0 ? std::abs(v) * 0.1 : 0.1);
    s->setValue(v);
    connect(s, &QDoubleSpinBox::valueChanged, this, [this, path](double x) { setAt(path, x); });
    return s;
  }
  if (isNumberArray(value)) {
    auto* row = new QWidget;
    row->setObjectName(name);
    auto* h = new QHBoxLayout(row);
    h->setContentsMargins(0, 0, 0, 0);
    for (size_t i = 0; i < value.size(); ++i) {
      QWidget* w = fieldFor(std::to_string(i), value[i], path + "/" + std::to_string(i));
      h->addWidget(w);
    }
    return row;
  }
  if (value.is_string() && key == "preset") {
    auto* c = new QComboBox;
    c->setObjectName(name);
    for (const auto& p : presets()) c->addItem(q(p.name));
    c->addItem(tr("Coefficients"));
    c->setCurrentIndex(std::max(0, c->findText(q(value.get<std::string>()), Qt::MatchFixedString)));
    const std::string parent = path.substr(0, path.rfind('/'));
    connect(c, &QComboBox::currentIndexChanged, this, [this, c, path, parent](int i) {
      if (i < static_cast<int>(presets().size())) {
        setAt(path, c->itemText(i).toStdString());
        return;
      }
      // Coefficients: the preset's medium, written out.
      const json pointer = edited_.at(json::json_pointer(path));
      Medium m;
      try {
        m = preset(pointer.get<std::string>()).medium();
      } catch (const std::exception&) {
      }
      setAt(parent, mediumJson(m));
      QTimer::singleShot(0, this, [this] { rebuildForm(); });
    });
    return c;
  }
  if (value.is_string()) {
    const bool file = key == "file" || ((type == "map" || type == "rd_map") &&
                                        (key == "sigma_a" || key == "sigma_s_prime" || key == "g" ||
                                         key == "rd" || key == "ld"));
    auto* row = new QWidget;
    auto* h = new QHBoxLayout(row);
    h->setContentsMargins(0, 0, 0, 0);
    auto* e = new QLineEdit(q(value.get<std::string>()));
    e->setObjectName(name);
    h->addWidget(e, 1);
    connect(e, &QLineEdit::editingFinished, this,
            [this, e, path] { setAt(path, e->text().toStdString()); });
    if (file) {
      auto* browse = new QPushButton(tr("Browse…"));
      browse->setObjectName(name + QStringLiteral(".browse"));
      h->addWidget(browse);
      connect(browse, &QPushButton::clicked, this, [this, e, path, key] {
        const QString f = QFileDialog::getOpenFileName(
            this, tr("Material file (%1)").arg(q(key)), QString(),
            key == "file" ? tr("OpenVDB grids (*.vdb);;All files (*)")
                          : tr("Images (*.png *.exr *.hdr *.jpg *.pfm);;All files (*)"));
        if (f.isEmpty()) return;
        e->setText(f);
        setAt(path, f.toStdString());
      });
    }
    return row;
  }
  if (value.is_object() || value.is_array()) {
    auto* box = new QGroupBox;
    box->setObjectName(name);
    auto* f = new QFormLayout(box);
    addFields(f, value, path);
    return box;
  }
  return nullptr;
}

void MaterialDock::setAt(const std::string& path, json value) {
  edited_[json::json_pointer(path)] = std::move(value);
  apply();
}

void MaterialDock::apply() {
  applying_ = true;
  try {
    state_.setMaterialJson(edited_.dump());
  } catch (const std::exception& e) {
    state_.error(QStringLiteral("material not changed: %1").arg(e.what()));
  }
  applying_ = false;
}

namespace {
struct DebugResult {
  DebugImage image;
  std::shared_ptr<const geometry::TriangleMesh> mesh;
  std::string key;
  QString error;
};
}  // namespace

void MaterialDock::updateDebugView() {
  const uint64_t request = ++debugRequest_;
  const int qi = debugQuantity_->currentIndex();
  if (qi <= 0) {
    debug_ = {};
    debugImage_->clear();
    debugRange_->clear();
    emit debugViewUpdated();
    return;
  }
  const auto quantity = static_cast<DebugQuantity>(qi - 1);
  const int channel = debugChannel_->currentIndex() - 1;  // -1: luminance
  const QString channelName = debugChannel_->currentText();
  auto* watcher = new QFutureWatcher<DebugResult>(this);
  connect(watcher, &QFutureWatcher<DebugResult>::finished, this,
          [this, watcher, request, quantity, channelName] {
            watcher->deleteLater();
            DebugResult r = watcher->result();
            if (r.mesh) {
              mesh_ = r.mesh;
              meshKey_ = r.key;
            }
            if (request != debugRequest_) return;  // a newer request is on its way
            if (!r.error.isEmpty()) {
              if (r.error != debugError_) state_.error(QStringLiteral("debug view: %1").arg(r.error));
              debugError_ = r.error;
              debug_ = {};
              debugImage_->clear();
              debugRange_->setText(tr("not available"));
              emit debugViewUpdated();
              return;
            }
            debugError_.clear();
            debug_ = std::move(r.image);
            const QImage img(debug_.rgb.data(), debug_.width, debug_.height, 3 * debug_.width,
                             QImage::Format_RGB888);
            debugImage_->setPixmap(QPixmap::fromImage(img.copy()));
            debugRange_->setText(QStringLiteral("%1 (%2): %3 … %4 (viridis)")
                                     .arg(QString::fromUtf8(debugQuantityName(quantity)), channelName)
                                     .arg(debug_.lo, 0, 'g', 4)
                                     .arg(debug_.hi, 0, 'g', 4));
            emit debugViewUpdated();
          });
  // The task gets copies: it never touches the dock or the state.
  watcher->setFuture(QtConcurrent::run(
      [scene = state_.scene(), mesh = mesh_, key = meshKey_, quantity, channel]() -> DebugResult {
        DebugResult r;
        try {
          r.key = scene::meshKey(scene);
          r.mesh = mesh && key == r.key
                       ? mesh
                       : std::make_shared<const geometry::TriangleMesh>(scene::loadSceneMesh(scene));
          r.image = renderDebugView(scene, *r.mesh, quantity, channel);
        } catch (const std::exception& e) {
          r.error = QString::fromUtf8(e.what());
        }
        return r;
      }));
}

void MaterialDock::onType(int index) {
  if (index < 0) return;
  edited_ = defaults(type_->itemText(index).toStdString());
  rebuildForm();
  apply();
}

}  // namespace translucent::explorer
