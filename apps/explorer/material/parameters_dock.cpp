// SPDX-License-Identifier: GPL-3.0-or-later
#include "material/parameters_dock.h"

#include <fmt/format.h>

#include <QtCore/QFileInfo>
#include <QtCore/QFileSystemWatcher>
#include <QtCore/QSignalBlocker>
#include <QtWidgets/QCheckBox>
#include <QtWidgets/QColorDialog>
#include <QtWidgets/QComboBox>
#include <QtWidgets/QFileDialog>
#include <QtWidgets/QFormLayout>
#include <QtWidgets/QGroupBox>
#include <QtWidgets/QHBoxLayout>
#include <QtWidgets/QLabel>
#include <QtWidgets/QPushButton>
#include <QtWidgets/QScrollArea>
#include <QtWidgets/QStackedWidget>
#include <QtWidgets/QVBoxLayout>

#include <algorithm>
#include <cmath>

#include "translucent/bssrdf/profile_curves.h"
#include "translucent/bssrdf/registry.h"
#include "core/explorer_state.h"
#include "translucent/gpu/bssrdf_profiles.h"
#include "material/material_worker.h"
#include "material/value_slider.h"
#include "translucent/bssrdf/tabulated.h"
#include "translucent/optics/inversion.h"
#include "translucent/optics/presets.h"

namespace translucent::explorer {
namespace {

const char* kChannelLetters[3] = {"r", "g", "b"};

QString q(const std::string& s) { return QString::fromStdString(s); }

// Label of a model entry in lists: a registered name, or a file name for a .bssrdf or .csv path.
QString modelLabel(const std::string& entry) {
  return isBssrdfPath(entry) || bssrdf::isTabulatedFile(entry) ? QFileInfo(q(entry)).fileName()
                                                               : q(entry);
}

// Rd per channel of a registered model (Rd(α', η), seed 3.4), or a tabulated profile's own Rd
// (fixed: the table ignores σa, σs and g).
Rgb registeredRd(const std::string& name, const Medium& m) {
  const bssrdf::Model& model = bssrdf::model(name);
  Rgb rd{};
  if (model.tabulated()) {
    const auto ps = bssrdf::profiles(model, m);
    for (size_t c = 0; c < 3; ++c) rd[c] = ps[c]->Rd();
    return rd;
  }
  for (int c = 0; c < 3; ++c)
    rd[static_cast<size_t>(c)] = model.totalReflectance(m.channel(c).reducedAlbedo(), m.eta);
  return rd;
}

// sRGB encoding of a linear value in [0, 1].
int srgb8(double v) {
  v = std::clamp(v, 0.0, 1.0);
  const double e = v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
  return static_cast<int>(std::lround(255.0 * e));
}

QString nonNegative(const QString& what, double v) {
  return v >= 0.0 ? QString() : QStringLiteral("%1 must be >= 0, got %2").arg(what).arg(v);
}

}  // namespace

ParametersDock::ParametersDock(ExplorerState& state, QWidget* parent)
    : QDockWidget(tr("Parameters"), parent), state_(state), worker_(MaterialWorker::of(state)) {
  setObjectName(QStringLiteral("parameters"));
  auto* body = new QWidget;
  auto* layout = new QVBoxLayout(body);

  // Material: preset, what the edit applies to, the scene's model.
  auto* top = new QFormLayout;
  preset_ = new QComboBox;
  preset_->setObjectName(QStringLiteral("preset"));
  preset_->addItem(tr("Custom"));
  for (const auto& p : presets()) preset_->addItem(q(p.name));
  top->addRow(tr("Preset"), preset_);
  target_ = new QComboBox;
  target_->setObjectName(QStringLiteral("target"));
  target_->setToolTip(tr("Apply the parameters to all models, or tweak one model's own medium"));
  auto* resetTarget = new QPushButton(tr("Use shared"));
  resetTarget->setObjectName(QStringLiteral("reset_target"));
  resetTarget->setToolTip(tr("Drop the selected model's own medium"));
  auto* targetRow = new QHBoxLayout;
  targetRow->addWidget(target_, 1);
  targetRow->addWidget(resetTarget);
  top->addRow(tr("Apply to"), targetRow);
  model_ = new QComboBox;
  model_->setObjectName(QStringLiteral("model"));
  model_->setToolTip(tr("The model the scene renders"));
  top->addRow(tr("Scene model"), model_);
  mode_ = new QComboBox;
  mode_->setObjectName(QStringLiteral("mode"));
  mode_->addItems({tr("σa, σs"), tr("Rd, ℓd")});
  top->addRow(tr("Coefficients"), mode_);
  layout->addLayout(top);
  heteroNote_ = new QLabel;
  heteroNote_->setObjectName(QStringLiteral("hetero_note"));
  heteroNote_->setWordWrap(true);
  heteroNote_->hide();
  layout->addWidget(heteroNote_);

  // Coefficients per channel: two pages.
  pages_ = new QStackedWidget;
  auto* sigmaPage = new QWidget;
  auto* sigmaForm = new QFormLayout(sigmaPage);
  const char* sigmaNames[2] = {"sigma_a", "sigma_s"};
  const char* sigmaLabels[2] = {"σa", "σs"};
  for (int w = 0; w < 2; ++w)
    for (int c = 0; c < 3; ++c) {
      const QString what = QStringLiteral("%1 (%2 channel)").arg(sigmaLabels[w], kChannelNames[c]);
      auto* s = w == 0 ? new ValueSlider(what, 1e-5, 1e2, ValueSlider::Scale::Log)
                       : new ValueSlider(what, 1e-3, 1e3, ValueSlider::Scale::Log);
      s->setObjectName(QStringLiteral("%1_%2").arg(sigmaNames[w], kChannelLetters[c]));
      s->setAcceptor([what](double v) { return nonNegative(what, v); });
      sigma_[w][c] = s;
      sigmaForm->addRow(QStringLiteral("%1 %2 [1/mm]").arg(sigmaLabels[w], kChannelLetters[c]), s);
      connect(s, &ValueSlider::valueChanged, this, [this, w, c](double v) { onSigma(w, c, v); });
      connect(s, &ValueSlider::rejected, this, [this](const QString& why) { state_.error(why); });
    }
  auto* rdPage = new QWidget;
  auto* rdForm = new QFormLayout(rdPage);
  for (int c = 0; c < 3; ++c) {
    const QString rdWhat = QStringLiteral("Rd (%1 channel)").arg(kChannelNames[c]);
    rd_[c] = new ValueSlider(rdWhat, 0.001, 0.999, ValueSlider::Scale::Linear);
    rd_[c]->setObjectName(QStringLiteral("rd_%1").arg(kChannelLetters[c]));
    rd_[c]->setAcceptor([rdWhat](double v) {
      return v > 0.0 && v < 1.0 ? QString()
                                : QStringLiteral("%1 must be in (0, 1), got %2").arg(rdWhat).arg(v);
    });
    rdForm->addRow(QStringLiteral("Rd %1").arg(kChannelLetters[c]), rd_[c]);
    const QString ldWhat = QStringLiteral("ℓd (%1 channel)").arg(kChannelNames[c]);
    ld_[c] = new ValueSlider(ldWhat, 1e-3, 1e3, ValueSlider::Scale::Log);
    ld_[c]->setObjectName(QStringLiteral("ld_%1").arg(kChannelLetters[c]));
    ld_[c]->setAcceptor([ldWhat](double v) {
      return v > 0.0 ? QString() : QStringLiteral("%1 must be > 0, got %2").arg(ldWhat).arg(v);
    });
    rdForm->addRow(QStringLiteral("ℓd %1 [mm]").arg(kChannelLetters[c]), ld_[c]);
    for (ValueSlider* s : {rd_[c], ld_[c]}) {
      connect(s, &ValueSlider::valueChanged, this, [this] { onRdLd(); });
      connect(s, &ValueSlider::rejected, this, [this](const QString& why) { state_.error(why); });
    }
  }
  rdNote_ = new QLabel;
  rdNote_->setWordWrap(true);
  rdForm->addRow(rdNote_);
  pages_->addWidget(sigmaPage);
  pages_->addWidget(rdPage);
  layout->addWidget(pages_);

  // Channel-independent parameters.
  auto* common = new QFormLayout;
  g_ = new ValueSlider(QStringLiteral("g"), -0.95, 0.95, ValueSlider::Scale::Linear);
  g_->setObjectName(QStringLiteral("g"));
  g_->setAcceptor([](double v) {
    return std::abs(v) < 1.0 ? QString() : QStringLiteral("g must be in (-1, 1), got %1").arg(v);
  });
  eta_ = new ValueSlider(QStringLiteral("η"), 1.0, 2.0, ValueSlider::Scale::Linear);
  eta_->setObjectName(QStringLiteral("eta"));
  eta_->setAcceptor([](double v) {
    return v > 0.0 ? QString() : QStringLiteral("η must be > 0, got %1").arg(v);
  });
  scale_ = new ValueSlider(QStringLiteral("scale"), 1e-3, 1e3, ValueSlider::Scale::Log);
  scale_->setObjectName(QStringLiteral("scale"));
  scale_->setToolTip(tr("Medium units (mm) per scene unit"));
  scale_->setAcceptor([](double v) {
    return v > 0.0 ? QString() : QStringLiteral("scale must be > 0, got %1").arg(v);
  });
  common->addRow(tr("g"), g_);
  common->addRow(tr("η"), eta_);
  common->addRow(tr("scale"), scale_);
  for (ValueSlider* s : {g_, eta_, scale_}) {
    connect(s, &ValueSlider::valueChanged, this, [this] { onScalar(); });
    connect(s, &ValueSlider::rejected, this, [this](const QString& why) { state_.error(why); });
  }
  swatchLabel_ = new QLabel;
  swatchLabel_->setObjectName(QStringLiteral("swatch"));
  swatchLabel_->setMinimumSize(64, 24);
  swatchLabel_->setAutoFillBackground(true);
  common->addRow(tr("Colour"), swatchLabel_);
  layout->addLayout(common);

  // .bssrdf files.
  auto* files = new QGroupBox(tr(".bssrdf models"));
  filesLayout_ = new QVBoxLayout(files);
  auto* buttons = new QHBoxLayout;
  auto* load = new QPushButton(tr("Load .bssrdf…"));
  load->setObjectName(QStringLiteral("load_bssrdf"));
  auto* reload = new QPushButton(tr("Reload"));
  reload->setObjectName(QStringLiteral("reload_bssrdf"));
  buttons->addWidget(load);
  buttons->addWidget(reload);
  filesLayout_->addLayout(buttons);
  layout->addWidget(files);

  // Tabulated (measured or path-traced) profiles: CSV models (bssrdf/tabulated.h), seed 3.1.1's
  // list of loaded analytic and measured models.
  auto* tables = new QGroupBox(tr("Measured profiles (.csv)"));
  auto* tablesLayout = new QVBoxLayout(tables);
  auto* loadTable = new QPushButton(tr("Load profile…"));
  loadTable->setObjectName(QStringLiteral("load_profile"));
  loadTable->setToolTip(tr("A tabulated R(r): r,R_r,R_g,R_b with a '# units: mm' line, or the CSV "
                           "of translucent profile --reference --save-profile"));
  tablesLayout->addWidget(loadTable);
  tablesList_ = new QLabel(tr("(none)"));
  tablesList_->setObjectName(QStringLiteral("profile_list"));
  tablesList_->setWordWrap(true);
  tablesLayout->addWidget(tablesList_);
  layout->addWidget(tables);
  layout->addStretch(1);

  auto* scroll = new QScrollArea;
  scroll->setWidgetResizable(true);
  scroll->setWidget(body);
  setWidget(scroll);

  watcher_ = new QFileSystemWatcher(this);
  connect(watcher_, &QFileSystemWatcher::fileChanged, this, &ParametersDock::onFileChanged);
  connect(load, &QPushButton::clicked, this, [this] {
    const QString path = QFileDialog::getOpenFileName(this, tr("Load a .bssrdf model"), QString(),
                                                      tr("BSSRDF models (*.bssrdf)"));
    if (!path.isEmpty()) loadBssrdf(path);
  });
  connect(loadTable, &QPushButton::clicked, this, [this] {
    const QString path = QFileDialog::getOpenFileName(this, tr("Load a tabulated profile"),
                                                      QString(), tr("Profiles (*.csv)"));
    if (!path.isEmpty()) loadProfile(path);
  });
  connect(reload, &QPushButton::clicked, this, [this] {
    for (const auto& f : files_) reloadBssrdf(q(f));
  });
  connect(preset_, &QComboBox::activated, this, &ParametersDock::onPreset);
  connect(mode_, &QComboBox::currentIndexChanged, this, &ParametersDock::onModeChanged);
  connect(target_, &QComboBox::currentIndexChanged, this, [this] {
    if (!updating_) refresh();
  });
  connect(resetTarget, &QPushButton::clicked, this, [this] {
    if (!target().empty()) state_.setModelMedium(target(), std::nullopt);
  });
  connect(model_, &QComboBox::activated, this, [this](int i) {
    state_.setModel(model_->itemData(i).toString().toStdString());
  });
  connect(&state_, &ExplorerState::materialChanged, this, [this] { refresh(); });
  connect(&state_, &ExplorerState::plotModelsChanged, this, [this] {
    refreshTargets();
    refresh();
  });
  connect(&worker_, &MaterialWorker::bssrdfChanged, this, [this] { updateReflectance(); });
  refreshTargets();
  refreshModels();
  refresh();
}

ParametersDock::~ParametersDock() = default;

std::string ParametersDock::target() const {
  return target_->currentData().toString().toStdString();
}

const Medium& ParametersDock::editedMedium() const {
  const std::string t = target();
  return t.empty() ? state_.medium() : state_.mediumFor(t);
}

bool ParametersDock::apply(const Medium& medium, const std::string& preset) {
  try {
    const std::string t = target();
    if (t.empty())
      state_.setMedium(medium, preset);
    else
      state_.setModelMedium(t, medium);
    return true;
  } catch (const ParameterError& e) {
    state_.error(QStringLiteral("parameters: %1 (the medium is unchanged)").arg(e.what()));
    refresh();
    return false;
  }
}

void ParametersDock::refreshTargets() {
  updating_ = true;
  const QString current = target_->currentData().toString();
  const QSignalBlocker block(target_);
  target_->clear();
  target_->addItem(tr("All models"), QString());
  for (const auto& m : state_.plotModels())
    target_->addItem(tr("Only %1").arg(modelLabel(m)), q(m));
  const int i = target_->findData(current);
  target_->setCurrentIndex(std::max(0, i));
  updating_ = false;
}

void ParametersDock::refreshModels() {
  const QSignalBlocker block(model_);
  model_->clear();
  for (const auto& name : bssrdf::modelNames()) model_->addItem(q(name), q(name));
  for (const auto& f : files_) model_->addItem(modelLabel(f), q(f));
  for (const auto& f : tables_) model_->addItem(modelLabel(f), q(f));
  const int i = model_->findData(q(state_.scene().model));
  if (i < 0 && !state_.scene().model.empty())
    model_->addItem(modelLabel(state_.scene().model), q(state_.scene().model));
  model_->setCurrentIndex(std::max(0, model_->findData(q(state_.scene().model))));
}

void ParametersDock::refresh() {
  updating_ = true;
  const Medium& m = editedMedium();
  for (int c = 0; c < 3; ++c) {
    sigma_[0][c]->setValue(m.sigma_a[static_cast<size_t>(c)]);
    sigma_[1][c]->setValue(m.sigma_s[static_cast<size_t>(c)]);
  }
  g_->setValue(m.g);
  eta_->setValue(m.eta);
  scale_->setValue(m.scale);
  {
    const QSignalBlocker block(preset_);
    const int i = target().empty() && !state_.scene().preset.empty()
                      ? preset_->findText(q(state_.scene().preset))
                      : 0;
    preset_->setCurrentIndex(std::max(0, i));
  }
  refreshModels();
  // A spatially varying material: the coefficients here are its representative medium only.
  const bool hetero = !state_.scene().material.homogeneous();
  for (QWidget* w : {static_cast<QWidget*>(preset_), static_cast<QWidget*>(target_),
                     static_cast<QWidget*>(mode_), static_cast<QWidget*>(pages_),
                     static_cast<QWidget*>(g_)})
    w->setEnabled(!hetero);
  heteroNote_->setVisible(hetero);
  if (hetero)
    heteroNote_->setText(
        tr("The material is spatially varying (%1): edit its media in the Material dock. The "
           "coefficients below are its representative medium; η, scale and the model apply.")
            .arg(q(state_.scene().material.type())));
  updating_ = false;
  // A scene whose model is a .bssrdf file (loaded from JSON): load it once, so that its
  // parameters get widgets and it joins the plot.
  const std::string& sceneModel = state_.scene().model;
  if (isBssrdfPath(sceneModel) && !attempted_.count(sceneModel)) {
    attempted_.insert(sceneModel);
    loadBssrdf(QString::fromStdString(sceneModel));
  }
  updateReflectance();
}

void ParametersDock::showSwatch(const Rgb& rd) {
  // Seed 3.6.1: Rd as RGB rescaled to a constant luminance of 0.75.
  const double lum = analysis::luminance(rd);
  Rgb c = rd;
  if (lum > 0.0)
    for (auto& v : c) v *= 0.75 / lum;
  swatch_ = c;
  QPalette p = swatchLabel_->palette();
  p.setColor(QPalette::Window, QColor(srgb8(c[0]), srgb8(c[1]), srgb8(c[2])));
  swatchLabel_->setPalette(p);
  swatchLabel_->setToolTip(
      QStringLiteral("Rd = (%1, %2, %3)").arg(rd[0], 0, 'g', 4).arg(rd[1], 0, 'g', 4).arg(rd[2], 0, 'g', 4));
}

void ParametersDock::updateReflectance() {
  // The model whose Rd(α') the swatch and the Rd, ℓd fields use: the tweaked model, else the
  // scene's model.
  const std::string model = target().empty() ? state_.scene().model : target();
  const Medium m = editedMedium();
  auto showRd = [this, m](const Rgb& rd) {
    showSwatch(rd);
    for (int c = 0; c < 3; ++c) {
      // ℓd = 1/σtr in medium units (the sliders' σ are per mm, not per scene unit).
      const ScalarMedium s{m.sigma_a[static_cast<size_t>(c)], m.sigma_s[static_cast<size_t>(c)], m.g,
                           m.eta};
      rd_[c]->setValue(rd[static_cast<size_t>(c)]);
      ld_[c]->setValue(s.diffuseMeanFreePath());
    }
  };
  const uint64_t request = ++rdRequest_;
  if (!isBssrdfPath(model)) {
    try {
      showRd(registeredRd(model, m));
      const bool table = bssrdf::isTabulatedFile(model);
      rdNote_->setText(table ? tr("%1 is a measured profile: its Rd is fixed, nothing to invert")
                                   .arg(modelLabel(model))
                             : tr("Inverted with %1's Rd(α')").arg(q(model)));
      pages_->widget(1)->setEnabled(!table);
    } catch (const std::exception& e) {
      state_.error(QStringLiteral("parameters: %1").arg(e.what()));
    }
    return;
  }
  // A .bssrdf model: its DiffuseReflectance(α') on the GPU; without one, the swatch uses the
  // classical dipole's Rd and the Rd, ℓd page is off.
  worker_.post(
      this,
      [this, model, m, request, showRd](MaterialGl& gl) -> MaterialWorker::Continuation {
        gpu::BssrdfEvaluator* e = gl.find(model);
        const bool has = e != nullptr && e->hasDiffuseReflectance();
        Rgb rd{};
        if (has) {
          e->setMedium(m);
          std::vector<float> alpha(3);
          for (int c = 0; c < 3; ++c)
            alpha[static_cast<size_t>(c)] = static_cast<float>(m.channel(c).reducedAlbedo());
          const auto v = e->diffuseReflectance(alpha);
          rd = Rgb{v[0][0], v[1][1], v[2][2]};
        } else {
          rd = registeredRd("dipole", m);
        }
        return [this, request, rd, has, model, showRd] {
          if (request != rdRequest_) return;
          showRd(rd);
          pages_->widget(1)->setEnabled(has);
          rdNote_->setText(has ? tr("Inverted with %1's DiffuseReflectance(α')").arg(modelLabel(model))
                               : tr("%1 has no diffuseReflectance section: Rd, ℓd are off (the "
                                    "colour uses the classical dipole's Rd)")
                                     .arg(modelLabel(model)));
        };
      },
      [this](const QString& why) { state_.error(QStringLiteral("parameters: %1").arg(why)); });
}

void ParametersDock::onSigma(int which, int channel, double value) {
  if (updating_) return;
  Medium m = editedMedium();
  (which == 0 ? m.sigma_a : m.sigma_s)[static_cast<size_t>(channel)] = value;
  apply(m);
}

void ParametersDock::onScalar() {
  if (updating_) return;
  Medium m = editedMedium();
  m.g = g_->value();
  m.eta = eta_->value();
  m.scale = scale_->value();
  // Custom from here: a scene's preset keeps σs' and rederives σs from g (Medium::fromReduced),
  // which is not what moving g here does.
  apply(m);
}

void ParametersDock::onRdLd() {
  if (updating_) return;
  const std::string model = target().empty() ? state_.scene().model : target();
  const Medium current = editedMedium();
  Rgb rd{}, ld{};
  for (size_t c = 0; c < 3; ++c) {
    rd[c] = rd_[c]->value();
    ld[c] = ld_[c]->value();
  }
  if (!isBssrdfPath(model)) {
    try {
      const bssrdf::Model& mdl = bssrdf::model(model);
      Medium m = invertMedium([&](double a) { return mdl.totalReflectance(a, current.eta); }, rd, ld,
                              current.eta, current.g);
      m.scale = current.scale;
      apply(m);
    } catch (const std::exception& e) {
      state_.error(QStringLiteral("parameters: %1 (the medium is unchanged)").arg(e.what()));
      refresh();
    }
    return;
  }
  worker_.post(
      this,
      [this, model, current, rd, ld](MaterialGl& gl) -> MaterialWorker::Continuation {
        gpu::BssrdfEvaluator* e = gl.find(model);
        if (e == nullptr) throw ParameterError(model + " is not loaded");
        Medium m = gpu::invertBssrdfMedium(*e, rd, ld, current.eta, current.g);
        m.scale = current.scale;
        return [this, m] { apply(m); };
      },
      [this](const QString& why) {
        state_.error(QStringLiteral("parameters: %1 (the medium is unchanged)").arg(why));
        refresh();
      });
}

void ParametersDock::onPreset(int index) {
  if (index <= 0) return;  // "Custom": keep the coefficients
  const Preset& p = presets()[static_cast<size_t>(index - 1)];
  apply(p.medium(editedMedium().scale), target().empty() ? p.name : "");
}

void ParametersDock::onModeChanged(int index) {
  pages_->setCurrentIndex(index);
  updateReflectance();
}

void ParametersDock::loadBssrdf(const QString& qpath) {
  const std::string path = QFileInfo(qpath).absoluteFilePath().toStdString();
  attempted_.insert(path);
  worker_.post(
      this,
      [this, path](MaterialGl& gl) -> MaterialWorker::Continuation {
        gl.load(path);
        return [this, path] {
          if (std::find(files_.begin(), files_.end(), path) == files_.end()) {
            files_.push_back(path);
            watcher_->addPath(q(path));
          }
          rebuildFileWidgets(path);
          auto models = state_.plotModels();
          if (std::find(models.begin(), models.end(), path) == models.end()) {
            models.push_back(path);
            state_.setPlotModels(std::move(models));
          }
          refreshModels();
          state_.info(QStringLiteral("loaded %1").arg(q(path)));
          emit bssrdfLoaded(q(path), true);
        };
      },
      [this, qpath](const QString& why) {
        state_.error(why);
        emit bssrdfLoaded(qpath, false);
      });
}

void ParametersDock::loadProfile(const QString& qpath) {
  const std::string path = QFileInfo(qpath).absoluteFilePath().toStdString();
  try {
    // Read and validated on this thread: a table is a small CSV (bssrdf::model caches it).
    const bssrdf::Model& m = bssrdf::model(path);
    (void)bssrdf::profiles(m, state_.medium());
  } catch (const std::exception& e) {
    state_.error(QStringLiteral("profile: %1").arg(e.what()));
    emit profileLoaded(qpath, false);
    return;
  }
  if (std::find(tables_.begin(), tables_.end(), path) == tables_.end()) tables_.push_back(path);
  QStringList names;
  for (const auto& t : tables_) names << modelLabel(t);
  tablesList_->setText(names.join(QStringLiteral(", ")));
  auto models = state_.plotModels();
  if (std::find(models.begin(), models.end(), path) == models.end()) {
    models.push_back(path);
    state_.setPlotModels(std::move(models));
  }
  refreshModels();
  state_.info(QStringLiteral("loaded %1 (%2)")
                  .arg(q(path), q(std::string(bssrdf::model(path).description()))));
  emit profileLoaded(qpath, true);
}

void ParametersDock::reloadBssrdf(const QString& qpath) {
  const std::string path = QFileInfo(qpath).absoluteFilePath().toStdString();
  worker_.post(
      this,
      [this, path](MaterialGl& gl) -> MaterialWorker::Continuation {
        gl.reload(path);
        return [this, path] {
          rebuildFileWidgets(path);
          state_.info(QStringLiteral("reloaded %1").arg(q(path)));
          emit worker_.bssrdfChanged();
          emit bssrdfReloaded(q(path), true);
        };
      },
      [this, qpath](const QString& why) {
        state_.error(QStringLiteral("%1 (the previous version stays in use)").arg(why));
        emit bssrdfReloaded(qpath, false);
      });
}

void ParametersDock::onFileChanged(const QString& path) {
  // Editors often replace the file (write a new one, rename): the watch is then lost; re-add it.
  if (!watcher_->files().contains(path) && QFileInfo::exists(path)) watcher_->addPath(path);
  reloadBssrdf(path);
}

void ParametersDock::rebuildFileWidgets(const std::string& path) {
  // The declarations and current values, read on the worker; the widgets built here.
  struct Param {
    bssrdf::BssrdfParameter decl;
    gpu::ParameterValue value;
  };
  worker_.post(this, [this, path](MaterialGl& gl) -> MaterialWorker::Continuation {
    gpu::BssrdfEvaluator* e = gl.find(path);
    if (e == nullptr) return {};
    std::vector<Param> params;
    for (const auto& p : e->file().parameters) params.push_back({p, e->parameter(p.name)});
    return [this, path, params] {
      if (auto it = fileBoxes_.find(path); it != fileBoxes_.end()) {
        delete it->second;
        fileBoxes_.erase(it);
      }
      auto* box = new QGroupBox(modelLabel(path));
      box->setObjectName(q("bssrdf:" + path));
      box->setToolTip(q(path));
      auto* form = new QFormLayout(box);
      auto set = [this, path](const std::string& name, gpu::ParameterValue v) {
        worker_.post(
            this,
            [this, path, name, v](MaterialGl& worker) -> MaterialWorker::Continuation {
              gpu::BssrdfEvaluator* loaded = worker.find(path);
              if (loaded == nullptr) return {};
              loaded->setParameter(name, v);
              return [this] { emit worker_.bssrdfChanged(); };
            },
            [this](const QString& why) { state_.error(why); });
      };
      for (const auto& p : params) {
        const QString name = q(p.decl.name);
        const QString where = QStringLiteral("%1 (%2:%3)").arg(name, q(path)).arg(p.decl.line);
        if (const auto* f = std::get_if<bssrdf::FloatParameter>(&p.decl.spec)) {
          auto* s = new ValueSlider(where, f->min, f->max, ValueSlider::Scale::Linear);
          const double lo = f->min, hi = f->max;
          s->setAcceptor([where, lo, hi](double v) {
            return v >= lo && v <= hi
                       ? QString()
                       : QStringLiteral("%1 must be in [%2, %3], got %4").arg(where).arg(lo).arg(hi).arg(v);
          });
          s->setValue(std::get<double>(p.value));
          s->setObjectName(name);
          connect(s, &ValueSlider::valueChanged, this,
                  [set, n = p.decl.name](double v) { set(n, v); });
          connect(s, &ValueSlider::rejected, this, [this](const QString& why) { state_.error(why); });
          form->addRow(name, s);
        } else if (std::holds_alternative<bssrdf::BoolParameter>(p.decl.spec)) {
          auto* b = new QCheckBox;
          b->setObjectName(name);
          b->setChecked(std::get<bool>(p.value));
          connect(b, &QCheckBox::toggled, this, [set, n = p.decl.name](bool v) { set(n, v); });
          form->addRow(name, b);
        } else {
          auto* button = new QPushButton;
          button->setObjectName(name);
          auto paint = [button](const Rgb& c) {
            button->setText(QStringLiteral("%1, %2, %3").arg(c[0], 0, 'g', 3).arg(c[1], 0, 'g', 3).arg(c[2], 0, 'g', 3));
            button->setStyleSheet(QStringLiteral("background-color: rgb(%1,%2,%3)")
                                      .arg(srgb8(c[0])).arg(srgb8(c[1])).arg(srgb8(c[2])));
          };
          paint(std::get<Rgb>(p.value));
          connect(button, &QPushButton::clicked, this,
                  [this, set, paint, button, n = p.decl.name] {
                    const QColor c = QColorDialog::getColor(button->palette().button().color(), this,
                                                            QString::fromStdString(n));
                    if (!c.isValid()) return;
                    const Rgb v{c.redF(), c.greenF(), c.blueF()};
                    paint(v);
                    set(n, v);
                  });
          form->addRow(name, button);
        }
      }
      if (params.empty()) form->addRow(new QLabel(tr("No parameters declared")));
      fileBoxes_[path] = box;
      filesLayout_->addWidget(box);
    };
  });
}

}  // namespace translucent::explorer
