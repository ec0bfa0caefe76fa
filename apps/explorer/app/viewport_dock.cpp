// SPDX-License-Identifier: GPL-3.0-or-later
#include "app/viewport_dock.h"

#include <QtCore/QDir>
#include <QtCore/QFileInfo>
#include <QtCore/QMimeData>
#include <QtCore/QSignalBlocker>
#include <QtCore/QStandardPaths>
#include <QtGui/QDragEnterEvent>
#include <QtGui/QDropEvent>
#include <QtGui/QFontDatabase>
#include <QtWidgets/QCheckBox>
#include <QtWidgets/QComboBox>
#include <QtWidgets/QDoubleSpinBox>
#include <QtWidgets/QFileDialog>
#include <QtWidgets/QFormLayout>
#include <QtWidgets/QGroupBox>
#include <QtWidgets/QLabel>
#include <QtWidgets/QPushButton>
#include <QtWidgets/QSlider>
#include <QtWidgets/QScrollArea>
#include <QtWidgets/QVBoxLayout>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <stdexcept>

#include "translucent/io/image_io.h"
#include "app/parameter_form.h"
#include "app/viewport_widget.h"
#include "core/explorer_state.h"
#include "translucent/techniques/registry.h"

namespace translucent::explorer {

void FrameStats::add(double frame_ms) {
  const double fps = frame_ms > 0.0 ? 1000.0 / frame_ms : 0.0;
  current = fps;
  min = frames == 0 ? fps : std::min(min, fps);
  max = frames == 0 ? fps : std::max(max, fps);
  sum_ms += frame_ms;
  ++frames;
}

std::string defaultEnvironmentMap() {
  const QDir blender(QStringLiteral("/usr/share/blender/datafiles/studiolights/world"));
  if (blender.exists()) {
    const auto files = blender.entryInfoList({QStringLiteral("*.exr"), QStringLiteral("*.hdr")},
                                             QDir::Files, QDir::Name);
    if (!files.isEmpty()) return files.first().absoluteFilePath().toStdString();
  }
  // A built-in sky (latitude-longitude, +y up, rows from the top): a blue-white gradient over a
  // dark ground and a warm sun 35 degrees up, so that the lighting has a direction.
  QString dir = QStandardPaths::writableLocation(QStandardPaths::CacheLocation);
  if (dir.isEmpty()) dir = QDir::tempPath() + QStringLiteral("/translucent-explorer");
  QDir().mkpath(dir);
  const std::string path = (dir + QStringLiteral("/builtin-sky-v1.exr")).toStdString();
  if (std::filesystem::exists(path)) return path;
  const int w = 256, h = 128;
  std::vector<float> rgb(size_t(w) * h * 3);
  const double sunEl = 35.0 * std::numbers::pi / 180.0, sunAz = 0.6;
  const double sx = std::cos(sunEl) * std::sin(sunAz), sy = std::sin(sunEl),
               sz = -std::cos(sunEl) * std::cos(sunAz);
  for (int j = 0; j < h; ++j) {
    const double theta = std::numbers::pi * (j + 0.5) / h;
    for (int i = 0; i < w; ++i) {
      const double phi = 2.0 * std::numbers::pi * ((i + 0.5) / w - 0.5);
      const double x = std::sin(theta) * std::sin(phi), y = std::cos(theta),
                   z = -std::sin(theta) * std::cos(phi);
      double r, g, b;
      if (y >= 0.0) {
        const double t = std::pow(y, 0.5);
        r = 0.9 - 0.5 * t, g = 0.95 - 0.35 * t, b = 1.0;
      } else {
        r = 0.12, g = 0.1, b = 0.08;
      }
      const double c = x * sx + y * sy + z * sz;
      const double sun = 40.0 * std::exp((c - 1.0) / 0.002);
      float* p = &rgb[(size_t(j) * w + i) * 3];
      p[0] = float(r + sun * 1.0), p[1] = float(g + sun * 0.85), p[2] = float(b + sun * 0.65);
    }
  }
  analysis::writeExr(path, w, h, rgb);
  return path;
}

namespace {

QDoubleSpinBox* spin(double min, double max, double value, int decimals, double step,
                     const QString& suffix = QString()) {
  auto* s = new QDoubleSpinBox;
  s->setRange(min, max);
  s->setDecimals(decimals);
  s->setSingleStep(step);
  s->setValue(value);
  s->setSuffix(suffix);
  s->setKeyboardTracking(false);
  return s;
}

bool settingIsTrue(const scene::Scene& s, const char* name) {
  const auto it = s.settings.find(name);
  if (it == s.settings.end()) return false;
  if (const auto* b = std::get_if<bool>(&it->second)) return *b;
  if (const auto* t = std::get_if<std::string>(&it->second)) return *t == "true" || *t == "on" || *t == "1";
  return false;
}

const char* kModes[] = {"Directional", "Filtered directional", "IBL", "Occluded IBL"};

}  // namespace

ViewportDock::ViewportDock(ExplorerState& state, QWidget* parent)
    : QDockWidget(QStringLiteral("Viewport"), parent), state_(state) {
  setObjectName(QStringLiteral("viewport_dock"));
  setAcceptDrops(true);

  view_ = new ViewportWidget(state_);
  view_->setObjectName(QStringLiteral("viewport"));
  setWidget(view_);
  // The technique's settings, the scene, camera and display controls are a dock of their own:
  // beside the picture they took a third of its width at 1280 px (the picture became a strip).
  controls_ = new QDockWidget(QStringLiteral("Render settings"), parent);
  controls_->setObjectName(QStringLiteral("technique_dock"));
  auto* scroll = new QScrollArea;
  scroll->setWidgetResizable(true);
  auto* panel = new QWidget;
  buildControls(panel);
  scroll->setWidget(panel);
  controls_->setWidget(scroll);

  rest_timer_.setSingleShot(true);
  rest_timer_.setInterval(300);  // at rest for 300 ms: full resolution
  connect(&rest_timer_, &QTimer::timeout, this, [this] { request(true); });
  rotate_timer_.setInterval(40);
  connect(&rotate_timer_, &QTimer::timeout, this, [this] {
    // 20 degrees per second, whatever the frame rate.
    const double dt = rotate_clock_.restart() / 1000.0;
    reference::Camera c = state_.scene().camera;
    const glm::dvec3 off = c.position - c.look_at;
    const double a = -20.0 * std::numbers::pi / 180.0 * dt;
    c.position = c.look_at + glm::dvec3(off.x * std::cos(a) + off.z * std::sin(a), off.y,
                                        -off.x * std::sin(a) + off.z * std::cos(a));
    state_.setCamera(c);
  });
  play_timer_.setInterval(40);
  connect(&play_timer_, &QTimer::timeout, this, [this] {
    // Scene time advances with the wall clock (one unit per second), so a deformation's period
    // plays at its own speed whatever the frame rate; frames that cannot keep up are skipped by
    // the worker, which renders the newest request.
    scene::Scene s = state_.scene();
    s.time += play_clock_.restart() / 1000.0;
    state_.setScene(std::move(s));
  });

  worker_ = new RenderWorker(this);
  connect(worker_, &RenderWorker::contextReady, this, [this](const QString& d) {
    renderer_ok_ = true;
    state_.info(QStringLiteral("viewport renderer: %1").arg(d));
    if (!scale_fixed_ &&
        (d.contains(QStringLiteral("llvmpipe")) || d.contains(QStringLiteral("softpipe")))) {
      state_.info(QStringLiteral("viewport: software rendering, render scale 25% (Display > Render scale)"));
      setRenderScale(0.25);
    }
  });
  connect(worker_, &RenderWorker::contextFailed, this, [this](const QString& m) {
    renderer_ok_ = false;
    state_.error(QStringLiteral("viewport: %1").arg(m));
    view_->setMessage(QStringLiteral("No OpenGL 4.5 core context: the viewport cannot render.\n\n%1").arg(m));
  });
  connect(worker_, &RenderWorker::frameReady, this, &ViewportDock::onFrame);
  connect(worker_, &RenderWorker::prepareFailed, this, &ViewportDock::onPrepareFailed);
  connect(view_, &ViewportWidget::glInfo, this, [this](const QString& text, bool ok) {
    if (ok)
      state_.info(QStringLiteral("viewport %1").arg(text));
    else
      state_.error(QStringLiteral("viewport: %1").arg(text));
  });
  connect(&state_, &ExplorerState::sceneChanged, this, &ViewportDock::onSceneChanged);
  connect(view_, &ViewportWidget::resized, this, [this] {
    request(false);
    rest_timer_.start();
  });
  worker_->start();
  syncControls();
}

ViewportDock::~ViewportDock() = default;

void ViewportDock::buildControls(QWidget* panel) {
  auto* v = new QVBoxLayout(panel);

  auto* tech = new QGroupBox(QStringLiteral("Technique"));
  auto* tv = new QVBoxLayout(tech);
  technique_ = new QComboBox;
  technique_->setObjectName(QStringLiteral("technique"));
  for (const auto& n : techniques::names()) technique_->addItem(QString::fromStdString(n));
  technique_help_ = new QLabel;
  technique_help_->setWordWrap(true);
  tv->addWidget(technique_);
  auto* reload = new QPushButton(QStringLiteral("Reload shaders"));
  reload->setObjectName(QStringLiteral("reload_shaders"));
  reload->setToolTip(QStringLiteral("Read the technique's shaders from disk again and rebuild them "
                                    "(a GLSL error goes to the console; the previous ones stay)"));
  tv->addWidget(reload);
  connect(reload, &QPushButton::clicked, this, &ViewportDock::reloadShaders);
  tv->addWidget(technique_help_);
  settings_box_ = new QVBoxLayout;
  tv->addLayout(settings_box_);
  v->addWidget(tech);
  connect(technique_, &QComboBox::currentTextChanged, this, [this](const QString& name) {
    if (name.toStdString() != state_.scene().technique) state_.setTechnique(name.toStdString());
  });

  auto* sceneBox = new QGroupBox(QStringLiteral("Mesh and lighting"));
  auto* sf = new QFormLayout(sceneBox);
  mesh_label_ = new QLabel;
  mesh_label_->setWordWrap(true);
  auto* load = new QPushButton(QStringLiteral("Load mesh…"));
  connect(load, &QPushButton::clicked, this, [this] {
    const QString f = QFileDialog::getOpenFileName(this, QStringLiteral("Load mesh"), QString(),
                                                   QStringLiteral("Meshes and point clouds (*.obj *.ply *.off);;All files (*)"));
    if (!f.isEmpty()) loadMesh(f);
  });
  sf->addRow(QStringLiteral("Mesh"), mesh_label_);
  sf->addRow(QString(), load);
  lighting_ = new QComboBox;
  lighting_->setObjectName(QStringLiteral("lighting"));
  for (const char* m : kModes) lighting_->addItem(QString::fromLatin1(m));
  lighting_->setToolTip(QStringLiteral("Right-drag in the picture turns the light. The empirical "
                                       "technique's random lighting is its random_lighting setting."));
  connect(lighting_, &QComboBox::activated, this, [this](int i) { setLightingMode(i); });
  sf->addRow(QStringLiteral("Lighting"), lighting_);
  auto* texture = new QPushButton(QStringLiteral("Filter texture…"));
  texture->setObjectName(QStringLiteral("filter_texture"));
  texture->setToolTip(QStringLiteral("Image projected by the filtered directional light"));
  connect(texture, &QPushButton::clicked, this, [this] {
    const QString f = QFileDialog::getOpenFileName(
        this, QStringLiteral("Filter texture"), QString(),
        QStringLiteral("Images (*.png *.jpg *.jpeg *.exr *.hdr *.tif *.tiff);;All files (*)"));
    if (!f.isEmpty()) setFilterTexture(f);
  });
  auto* envmap = new QPushButton(QStringLiteral("Environment map…"));
  envmap->setObjectName(QStringLiteral("environment_map"));
  envmap->setToolTip(QStringLiteral("Latitude-longitude map of the IBL modes (EXR, HDR)"));
  connect(envmap, &QPushButton::clicked, this, [this] {
    const QString f = QFileDialog::getOpenFileName(
        this, QStringLiteral("Environment map"), QString(),
        QStringLiteral("Environment maps (*.exr *.hdr);;All files (*)"));
    if (!f.isEmpty()) setEnvironmentMap(f);
  });
  sf->addRow(QString(), texture);
  sf->addRow(QString(), envmap);
  v->addWidget(sceneBox);

  auto* cam = new QGroupBox(QStringLiteral("Camera"));
  auto* cf = new QFormLayout(cam);
  fov_ = spin(1.0, 170.0, 35.0, 1, 1.0, QStringLiteral("°"));
  near_ = spin(0.0, 1000.0, 0.0, 4, 0.01);
  far_ = spin(0.0, 10000.0, 0.0, 3, 0.5);
  near_->setSpecialValueText(QStringLiteral("auto"));
  far_->setSpecialValueText(QStringLiteral("auto"));
  rotate_ = new QCheckBox(QStringLiteral("auto-rotate"));
  rotate_->setObjectName(QStringLiteral("auto_rotate"));
  cf->addRow(QStringLiteral("Field of view"), fov_);
  zoom_ = new QSlider(Qt::Horizontal);
  zoom_->setObjectName(QStringLiteral("zoom"));
  zoom_->setRange(0, 1000);  // log distance from 0.05 to 50 scene units
  zoom_->setToolTip(QStringLiteral("Camera distance to its look-at point"));
  cf->addRow(QStringLiteral("Zoom"), zoom_);
  connect(zoom_, &QSlider::valueChanged, this, [this](int step) {
    setCameraDistance(0.05 * std::pow(1000.0, step / 1000.0));
  });
  cf->addRow(QStringLiteral("Near clip"), near_);
  cf->addRow(QStringLiteral("Far clip"), far_);
  cf->addRow(QString(), rotate_);
  auto* hint = new QLabel(QStringLiteral("left drag: orbit · middle: pan · wheel: zoom · right: light"));
  hint->setWordWrap(true);
  cf->addRow(hint);
  v->addWidget(cam);
  connect(fov_, &QDoubleSpinBox::valueChanged, this, [this](double f) {
    reference::Camera c = state_.scene().camera;
    if (c.fov == f) return;
    c.fov = f;
    state_.setCamera(c);
  });
  auto clip = [this] {
    scene::Scene s = state_.scene();
    if (s.clip_near == near_->value() && s.clip_far == far_->value()) return;
    if (far_->value() > 0.0 && near_->value() >= far_->value()) {
      state_.warning(QStringLiteral("clip planes: near %1 must be below far %2 (0: automatic)")
                         .arg(near_->value()).arg(far_->value()));
      return;
    }
    s.clip_near = near_->value();
    s.clip_far = far_->value();
    state_.setScene(std::move(s));
  };
  connect(near_, &QDoubleSpinBox::valueChanged, this, clip);
  connect(far_, &QDoubleSpinBox::valueChanged, this, clip);
  connect(rotate_, &QCheckBox::toggled, this, [this](bool on) {
    if (on) {
      rotate_clock_.start();
      rotate_timer_.start();
    } else {
      rotate_timer_.stop();
    }
  });

  auto* def = new QGroupBox(QStringLiteral("Deformation"));
  def->setToolTip(QStringLiteral("The scene's mesh.deform: its time (the magnitude is "
                                 "amount · sin(2π time / period)); play advances it in real time"));
  auto* tf = new QFormLayout(def);
  time_ = spin(-1e6, 1e6, 0.0, 3, 0.05);
  time_->setObjectName(QStringLiteral("deform_time"));
  play_ = new QCheckBox(QStringLiteral("play"));
  play_->setObjectName(QStringLiteral("deform_play"));
  tf->addRow(QStringLiteral("Time"), time_);
  tf->addRow(QString(), play_);
  v->addWidget(def);
  connect(time_, &QDoubleSpinBox::valueChanged, this, [this](double t) {
    if (state_.scene().time == t) return;
    scene::Scene s = state_.scene();
    s.time = t;
    state_.setScene(std::move(s));
  });
  connect(play_, &QCheckBox::toggled, this, [this](bool on) {
    if (on) {
      play_clock_.start();
      play_timer_.start();
    } else {
      play_timer_.stop();
    }
  });

  auto* disp = new QGroupBox(QStringLiteral("Display"));
  auto* df = new QFormLayout(disp);
  scale_ = new QComboBox;
  scale_->addItems({QStringLiteral("100%"), QStringLiteral("50%"), QStringLiteral("25%")});
  scale_->setToolTip(QStringLiteral("Full-resolution size relative to the picture (software "
                                    "renderers start at 25%)"));
  connect(scale_, &QComboBox::currentIndexChanged, this,
          [this](int i) { setRenderScale(i == 0 ? 1.0 : i == 1 ? 0.5 : 0.25); });
  exposure_ = spin(-12.0, 12.0, 0.0, 2, 0.25, QStringLiteral(" stops"));
  gamma_ = spin(0.5, 4.0, 2.2, 2, 0.1);
  df->addRow(QStringLiteral("Render scale"), scale_);
  df->addRow(QStringLiteral("Exposure"), exposure_);
  df->addRow(QStringLiteral("Gamma"), gamma_);
  tonemap_ = new QComboBox;
  tonemap_->setObjectName(QStringLiteral("tonemap"));
  tonemap_->addItems({QStringLiteral("clamp"), QStringLiteral("Reinhard")});
  tonemap_->setToolTip(QStringLiteral(
      "clamp: exposure, clamped to white; Reinhard: s/(1+s) with s = key x exposure / the "
      "rendered pixels' average (Reinhard et al. 2002, as Chang 2007 applies it): nothing "
      "burns out"));
  key_ = spin(0.01, 100.0, 1.0, 2, 0.1);
  key_->setObjectName(QStringLiteral("tonemap_key"));
  key_->setToolTip(QStringLiteral("Reinhard: the average maps to key/(1+key)"));
  df->addRow(QStringLiteral("Tone map"), tonemap_);
  df->addRow(QStringLiteral("Key"), key_);
  auto* box = new QCheckBox(QStringLiteral("bounding box"));
  box->setObjectName(QStringLiteral("show_bounding_box"));
  auto* axes = new QCheckBox(QStringLiteral("axes (x red, y green, z blue)"));
  axes->setObjectName(QStringLiteral("show_axes"));
  df->addRow(QString(), box);
  df->addRow(QString(), axes);
  auto overlay = [this, box, axes] { view_->setOverlay(box->isChecked(), axes->isChecked()); };
  connect(box, &QCheckBox::toggled, this, overlay);
  connect(axes, &QCheckBox::toggled, this, overlay);
  v->addWidget(disp);
  auto display = [this] {
    state_.setDisplay(exposure_->value(), gamma_->value(),
                      tonemap_->currentIndex() == 1 ? analysis::ToneOperator::Reinhard
                                                    : analysis::ToneOperator::Clamp,
                      key_->value());
  };
  connect(exposure_, &QDoubleSpinBox::valueChanged, this, display);
  connect(gamma_, &QDoubleSpinBox::valueChanged, this, display);
  connect(tonemap_, &QComboBox::currentIndexChanged, this, display);
  connect(key_, &QDoubleSpinBox::valueChanged, this, display);

  auto* timing = new QGroupBox(QStringLiteral("GPU time per pass"));
  auto* tl = new QVBoxLayout(timing);
  passes_ = new QLabel(QStringLiteral("(no frame yet)"));
  passes_->setObjectName(QStringLiteral("passes"));
  passes_->setFont(QFontDatabase::systemFont(QFontDatabase::FixedFont));
  passes_->setWordWrap(true);
  passes_->setTextInteractionFlags(Qt::TextSelectableByMouse);
  tl->addWidget(passes_);
  v->addWidget(timing);
  v->addStretch(1);
}

void ViewportDock::rebuildSettings() {
  const std::string name = state_.scene().technique;
  if (settings_ != nullptr && settings_for_ == name) {
    settings_->setValues(state_.scene().settings);
    return;
  }
  delete settings_;
  settings_ = nullptr;
  settings_for_ = name;
  try {
    const auto t = techniques::make(name);
    technique_help_->setText(QString::fromStdString(std::string(t->description())));
    settings_ = new ParameterForm(t->parameters());
    settings_->setObjectName(QStringLiteral("technique_settings"));
    settings_->setValues(state_.scene().settings);
    connect(settings_, &ParameterForm::edited, this,
            [this](const QString& n, const scene::Setting& value) {
              state_.setTechniqueSetting(n.toStdString(), value);
            });
    settings_box_->addWidget(settings_);
  } catch (const std::exception& e) {
    technique_help_->setText(QString::fromUtf8(e.what()));
  }
}

void ViewportDock::syncControls() {
  const scene::Scene& s = state_.scene();
  {
    QSignalBlocker b(technique_);
    technique_->setCurrentText(QString::fromStdString(s.technique));
  }
  rebuildSettings();
  mesh_label_->setText(QString::fromStdString(s.mesh_file.filename().string()));
  mesh_label_->setToolTip(QString::fromStdString(s.mesh_file.string()));
  {
    QSignalBlocker b(lighting_);
    lighting_->setCurrentIndex(lightingMode());
  }
  for (auto [box, value] : {std::pair{fov_, s.camera.fov}, std::pair{near_, s.clip_near},
                            std::pair{far_, s.clip_far}, std::pair{exposure_, s.exposure},
                            std::pair{gamma_, s.gamma}, std::pair{time_, s.time},
                            std::pair{key_, s.tonemap_key}}) {
    QSignalBlocker b(box);
    box->setValue(value);
  }
  {
    QSignalBlocker b(tonemap_);
    tonemap_->setCurrentIndex(s.tonemap == analysis::ToneOperator::Reinhard ? 1 : 0);
  }
  {
    QSignalBlocker b(zoom_);
    const double d = glm::length(s.camera.position - s.camera.look_at);
    zoom_->setValue(int(std::lround(1000.0 * std::log(std::clamp(d, 0.05, 50.0) / 0.05) /
                                    std::log(1000.0))));
  }
  // Only a deforming mesh has a time to change; a scene without one stops playing.
  const bool deforms = !s.mesh_deform.empty();
  time_->setEnabled(deforms);
  play_->setEnabled(deforms);
  if (!deforms && play_->isChecked()) play_->setChecked(false);
}

int ViewportDock::lightingMode() const {
  int mode = 0;
  for (const auto& l : state_.scene().lights) {
    if (const auto* e = std::get_if<scene::EnvironmentLight>(&l.emitter)) return e->occlusion ? 3 : 2;
    if (std::holds_alternative<scene::FilteredDirectionalLight>(l.emitter)) mode = 1;
  }
  return mode;
}

void ViewportDock::setLightingMode(int mode) {
  // The key light's direction carries over between the directional modes.
  const scene::Scene def = scene::defaultScene();
  glm::dvec3 key = std::get<reference::DirectionalLight>(def.lights.at(0).emitter).direction;
  for (const auto& l : state_.scene().lights) {
    if (const auto* d = std::get_if<reference::DirectionalLight>(&l.emitter)) {
      key = d->direction;
      break;
    }
    if (const auto* f = std::get_if<scene::FilteredDirectionalLight>(&l.emitter)) {
      key = f->direction;
      break;
    }
  }
  std::vector<scene::Light> lights = def.lights;
  switch (mode) {
    case 0:
      std::get<reference::DirectionalLight>(lights[0].emitter).direction = key;
      break;
    case 1: {
      scene::FilteredDirectionalLight f;
      f.direction = key;
      f.irradiance = 5.0;
      f.texture = filter_texture_.toStdString();
      f.texture_size = 0.25;
      lights[0].emitter = f;
      lights[0].color = {1.0, 1.0, 1.0};
      break;
    }
    default: {
      try {
        scene::EnvironmentLight e;
        e.file = environment_map_.isEmpty() ? std::filesystem::path(defaultEnvironmentMap())
                                            : std::filesystem::path(environment_map_.toStdString());
        e.occlusion = mode == 3;
        scene::Light l;
        l.emitter = e;
        lights = {l};
      } catch (const std::exception& err) {
        state_.error(QStringLiteral("IBL: no environment map: %1").arg(err.what()));
        syncControls();
        return;
      }
    }
  }
  state_.setLights(std::move(lights));
}

void ViewportDock::setFilterTexture(const QString& file) {
  filter_texture_ = file;
  setLightingMode(1);
}

void ViewportDock::setEnvironmentMap(const QString& file) {
  environment_map_ = file;
  setLightingMode(lightingMode() == 3 ? 3 : 2);
}

void ViewportDock::setCameraDistance(double distance) {
  reference::Camera c = state_.scene().camera;
  const glm::dvec3 offset = c.position - c.look_at;
  const double now = glm::length(offset);
  if (!(now > 0.0) || !(distance > 0.0) || std::abs(now - distance) <= 1e-12 * now) return;
  c.position = c.look_at + offset * (distance / now);
  state_.setCamera(c);
}

QSize ViewportDock::pictureSize() const { return view_->size(); }

QSize ViewportDock::renderSize() const {
  const double dpr = view_->devicePixelRatioF();
  const int w = std::max(8, int(std::lround(view_->width() * dpr * render_scale_)));
  const int h = std::max(8, int(std::lround(view_->height() * dpr * render_scale_)));
  return {w, h};
}

void ViewportDock::setRenderScale(double scale) {
  render_scale_ = std::clamp(scale, 0.05, 1.0);
  {
    QSignalBlocker b(scale_);
    scale_->setCurrentIndex(render_scale_ >= 1.0 ? 0 : render_scale_ >= 0.5 ? 1 : 2);
  }
  onSceneChanged();
}

void ViewportDock::fixRenderScale(double scale) {
  scale_fixed_ = true;
  setRenderScale(scale);
}

int ViewportDock::pointCount() const {
  try {
    const auto t = techniques::make(state_.scene().technique);
    for (const auto& p : t->parameters()) {
      if (p.name != "points") continue;
      const auto it = state_.scene().settings.find("points");
      if (it != state_.scene().settings.end())
        if (const auto* d = std::get_if<double>(&it->second)) return int(*d);
      return std::get<int>(p.value);
    }
  } catch (const std::exception&) {
  }
  return -1;
}

void ViewportDock::loadMesh(const QString& path) {
  scene::Scene s = state_.scene();
  s.mesh_file = std::filesystem::absolute(path.toStdString());
  state_.info(QStringLiteral("loading mesh %1").arg(path));
  state_.setScene(std::move(s));
}

void ViewportDock::setContinuous(bool on) {
  continuous_ = on;
  requestFullFrame();
}

void ViewportDock::setViewsWanted(bool on) {
  if (on == views_) return;
  views_ = on;
  if (on) requestFullFrame();
}

void ViewportDock::requestFullFrame() {
  rest_timer_.stop();
  request(true);
}

void ViewportDock::onSceneChanged() {
  syncControls();
  // While the view changes: half resolution now, full resolution once at rest (seed 3.6.4).
  request(false);
  rest_timer_.start();
}

void ViewportDock::reloadShaders() {
  rest_timer_.stop();
  request(true, true);
}

void ViewportDock::request(bool full, bool reload) {
  RenderRequest r;
  r.reload = reload;
  r.scene = state_.scene();
  QSize size = renderSize();
  if (!full) size = QSize(std::max(8, size.width() / 2), std::max(8, size.height() / 2));
  r.width = size.width();
  r.height = size.height();
  r.continuous = continuous_ || settingIsTrue(r.scene, "random_lighting");
  r.views = views_ && full;
  last_request_ = worker_->request(std::move(r));
  // Only the newest request counts as the full-resolution view of the current state: a full
  // frame of an older state arriving later is shown, but not as "full".
  last_full_request_ = full ? last_request_ : 0;
}

void ViewportDock::onFrame(std::shared_ptr<const RenderedFrame> frame) {
  const bool full = frame->request_id == last_full_request_;
  if (frame->technique != stats_technique_) {
    stats_ = FrameStats{};
    stats_technique_ = frame->technique;
  }
  stats_.add(frame->prepare_ms + frame->render_ms);
  last_ = frame;
  if (full) last_full_ = frame;
  view_->showFrame(frame);

  QString text;
  for (const auto& p : frame->frame.passes)
    text += QStringLiteral("%1%2 %3 ms\n")
                .arg(QString(2 * p.depth, QLatin1Char(' ')))
                .arg(QString::fromStdString(p.name), -22)
                .arg(p.ms, 9, 'f', 3);
  text += QStringLiteral("%1 %2 ms\n").arg(QStringLiteral("total"), -22).arg(frame->frame.totalMs(), 9, 'f', 3);
  text += QStringLiteral("%1x%2%3, wall %4 ms (prepare %5 ms)")
              .arg(frame->frame.width)
              .arg(frame->frame.height)
              .arg(full ? QString() : QStringLiteral(" (interactive)"))
              .arg(frame->render_ms, 0, 'f', 1)
              .arg(frame->prepare_ms, 0, 'f', 1);
  for (const auto& n : frame->frame.notes) text += QStringLiteral("\n") + QString::fromStdString(n);
  passes_->setText(text);
  emit statsChanged();
  emit frameShown(frame, full);
}

void ViewportDock::onPrepareFailed(quint64 id, const QString& message,
                                   std::shared_ptr<const scene::Scene> restored) {
  state_.error(message);
  if (restored == nullptr) {
    view_->setMessage(QStringLiteral("Nothing to show: %1").arg(message));
    return;
  }
  state_.warning(QStringLiteral("viewport: kept the last good scene"));
  // Revert what the failed request changed, unless a newer request is on its way.
  if (id != last_request_ && id != last_full_request_) return;
  scene::Scene s = state_.scene();
  s.mesh_file = restored->mesh_file;
  s.mesh_normalize = restored->mesh_normalize;
  s.mesh_rotate = restored->mesh_rotate;
  s.mesh_scale = restored->mesh_scale;
  s.mesh_translate = restored->mesh_translate;
  s.technique = restored->technique;
  s.settings = restored->settings;
  s.lights = restored->lights;
  s.model = restored->model;
  if (scene::toJson(s) != scene::toJson(state_.scene())) state_.setScene(std::move(s));
}

void ViewportDock::dragEnterEvent(QDragEnterEvent* e) {
  if (e->mimeData()->hasUrls()) e->acceptProposedAction();
}

void ViewportDock::dropEvent(QDropEvent* e) {
  for (const QUrl& url : e->mimeData()->urls()) {
    if (url.isLocalFile()) {
      loadMesh(url.toLocalFile());
      e->acceptProposedAction();
      return;
    }
  }
}

}  // namespace translucent::explorer
