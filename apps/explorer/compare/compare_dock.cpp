// SPDX-License-Identifier: GPL-3.0-or-later
#include "compare/compare_dock.h"

#include <fmt/format.h>

#include <QtCore/QLocale>
#include <QtCore/QMetaObject>
#include <QtCore/QTimer>
#include <QtWidgets/QComboBox>
#include <QtWidgets/QGridLayout>
#include <QtWidgets/QHBoxLayout>
#include <QtWidgets/QLabel>
#include <QtWidgets/QProgressBar>
#include <QtWidgets/QSpinBox>
#include <QtWidgets/QVBoxLayout>

#include <algorithm>
#include <cmath>
#include <exception>
#include <utility>

#include "translucent/analysis/colormap.h"
#include "translucent/analysis/metrics.h"
#include "translucent/bssrdf/bssrdf_file.h"
#include "core/explorer_state.h"
#include "core/pixel_image_view.h"
#include "core/trace_device_box.h"
#include "translucent/reference/slab.h"  // kBlockPhotons

namespace translucent::explorer {
namespace {

constexpr uint64_t kSeed = 1;  // the CLI's default --seed: the same images as `translucent compare`
// The path tracer's first pass: a few blocks, so that the first reference comes within a second
// or two on two cores at 64 pixels; passes double up to the cap, then a refresh every few seconds.
constexpr uint64_t kFirstPhotons = 16 * reference::kBlockPhotons;
constexpr uint64_t kCapPhotons = 512 * reference::kBlockPhotons;
constexpr uint64_t kFirstSamples = 10000;  // model reference: the first pass's surface samples

// The scene as the reference sees it: the technique and the display change nothing there.
std::string sceneKey(scene::Scene s) {
  s.technique.clear();
  s.settings.clear();
  s.exposure = 0.0;
  s.gamma = 2.2;
  return scene::toJson(s);
}

// The scene as the technique frame sees it (the display is applied afterwards).
std::string frameKey(scene::Scene s) {
  s.exposure = 0.0;
  s.gamma = 2.2;
  return scene::toJson(s);
}

QString count(uint64_t n) { return QLocale().toString(static_cast<qulonglong>(n)); }

QString percent(double v, int digits = 2) {
  return std::isfinite(v) ? QString::number(100.0 * v, 'f', digits) + QStringLiteral("%")
                          : QStringLiteral("–");
}

QString number(double v, int digits) {
  return std::isfinite(v) ? QString::number(v, 'f', digits) : QStringLiteral("–");
}

}  // namespace

CompareDock::CompareDock(ExplorerState& state, QWidget* parent)
    : QDockWidget(tr("Compare"), parent), state_(state) {
  setObjectName("compare");
  buildUi();
  worker_ = std::make_unique<RenderWorker>();
  connect(worker_.get(), &RenderWorker::frameReady, this, &CompareDock::onFrame);
  connect(worker_.get(), &RenderWorker::prepareFailed, this,
          [this](quint64 id, const QString& message, std::shared_ptr<const scene::Scene>) {
            onPrepareFailed(id, message);
          });
  connect(worker_.get(), &RenderWorker::contextFailed, this, [this](const QString& message) {
    technique_error_ = message;
    state_.error(tr("Compare: no OpenGL 4.5 core context for the technique: %1").arg(message));
    updateStatus();
  });
  restart_timer_ = new QTimer(this);
  restart_timer_->setSingleShot(true);
  restart_timer_->setInterval(kRestartDelayMs);
  connect(restart_timer_, &QTimer::timeout, this, [this] { restart(false); });
  connect(&state_, &ExplorerState::sceneChanged, this, [this] {
    // Exposure and gamma change the display and SSIM/ꟻLIP (taken on the displayed images).
    updateComparison();
    restart_timer_->start();
  });
  // Nothing is computed while the dock is hidden (a tab behind the lit spheres costs no render
  // thread, no technique prepare and no photons): hiding it stops a running reference (the last
  // pass stays on screen), showing it again starts one for the current scene.
  // The signal's argument, not isVisible(): a dock raised in a tab group says so before it is
  // shown.
  connect(this, &QDockWidget::visibilityChanged, this, [this](bool visible) {
    visible_ = visible;
    if (visible) {
      restart(!started_);
    } else if (run_) {
      stopRun();
      run_key_.clear();
      updateStatus();
    }
  });
}

CompareDock::~CompareDock() {
  // Both stop together; then each join waits for its own thread only.
  if (run_) run_->requestStop();
  for (auto& r : retiring_) r.run->requestStop();
  run_.reset();
  retiring_.clear();
  // Its frame or prepare in hand can take seconds: not waited for here.
  retireInBackground(std::move(worker_));
  // Calls queued to this object by the threads before they ended are discarded with it.
}

void CompareDock::buildUi() {
  auto* root = new QWidget(this);
  auto* layout = new QVBoxLayout(root);
  layout->setContentsMargins(4, 4, 4, 4);

  auto* controls = new QGridLayout;
  kind_box_ = new QComboBox(root);
  kind_box_->setObjectName("reference_kind");
  kind_box_->addItem(tr("Physical (path tracer)"));
  kind_box_->addItem(tr("Model (BSSRDF integrated over the mesh)"));
  kind_box_->addItem(tr("Physical, paths from the camera (true radiance)"));
  kind_box_->setToolTip(tr("Physical: volumetric photon tracing, the total error of the technique. "
                           "Model: the scene's BSSRDF integrated over the whole surface, the "
                           "technique's own error. Physical from the camera: camera paths per "
                           "pixel, whose true radiance has a standard error per pixel (slower "
                           "to converge where the light comes through the body)."));
  quantity_box_ = new QComboBox(root);
  quantity_box_->setObjectName("quantity");
  quantity_box_->addItem(tr("Radiance L = Ft·B/π"));
  quantity_box_->addItem(tr("True radiance (cone, physical)"));
  quantity_box_->addItem(tr("Exitance B"));
  width_box_ = new QSpinBox(root);
  width_box_->setObjectName("image_width");
  width_box_->setRange(16, 512);
  width_box_->setSuffix(tr(" px wide"));
  width_box_->setValue(width_);
  width_box_->setKeyboardTracking(false);
  photons_box_ = new QSpinBox(root);
  photons_box_->setObjectName("photons");
  photons_box_->setRange(16, 10'000'000);
  photons_box_->setSuffix(tr(" k photons"));
  photons_box_->setToolTip(tr("Path tracer budget: thousands of photons per colour channel, all "
                              "passes together"));
  photons_box_->setValue(static_cast<int>(photon_budget_ / 1024));
  photons_box_->setKeyboardTracking(false);
  samples_box_ = new QSpinBox(root);
  samples_box_->setObjectName("samples");
  samples_box_->setRange(1, 16'000);
  samples_box_->setSuffix(tr(" k samples"));
  samples_box_->setToolTip(tr("Model reference: thousands of surface samples of the last pass "
                              "(passes double from 10 k; each is a new image)"));
  samples_box_->setValue(static_cast<int>(sample_budget_ / 1000));
  samples_box_->setKeyboardTracking(false);
  paths_box_ = new QSpinBox(root);
  paths_box_->setObjectName("paths");
  paths_box_->setRange(4, 65536);
  paths_box_->setSuffix(tr(" paths per pixel"));
  paths_box_->setToolTip(tr("Camera method budget: camera paths per pixel and colour channel, all "
                            "passes together (passes double from 4)"));
  paths_box_->setValue(static_cast<int>(path_budget_));
  paths_box_->setKeyboardTracking(false);
  controls->addWidget(new QLabel(tr("Reference"), root), 0, 0);
  controls->addWidget(kind_box_, 0, 1);
  controls->addWidget(new QLabel(tr("Compare"), root), 0, 2);
  controls->addWidget(quantity_box_, 0, 3);
  controls->addWidget(new QLabel(tr("Size"), root), 1, 0);
  controls->addWidget(width_box_, 1, 1);
  controls->addWidget(new QLabel(tr("Budget"), root), 1, 2);
  auto* budgets = new QHBoxLayout;
  budgets->addWidget(photons_box_);
  budgets->addWidget(samples_box_);
  budgets->addWidget(paths_box_);
  device_box_ = makeTraceDeviceBox(QStringLiteral("tracer_device"), tr("the path tracer"), root);
  budgets->addWidget(device_box_);
  controls->addLayout(budgets, 1, 3);
  controls->setColumnStretch(1, 1);
  controls->setColumnStretch(3, 1);
  layout->addLayout(controls);

  auto* images = new QHBoxLayout;
  auto makePane = [&](const QString& title, PixelImageView*& view, QLabel*& label,
                      const char* name) {
    auto* w = new QWidget(root);
    w->setObjectName(name);
    auto* l = new QVBoxLayout(w);
    l->setContentsMargins(0, 0, 0, 0);
    l->addWidget(new QLabel(QStringLiteral("<b>%1</b>").arg(title), w));
    view = new PixelImageView(w);
    l->addWidget(view, 1);
    label = new QLabel(w);
    label->setWordWrap(true);
    l->addWidget(label);
    images->addWidget(w);
  };
  makePane(tr("Technique"), technique_view_, technique_label_, "technique_pane");
  makePane(tr("Reference"), reference_view_, reference_label_, "reference_pane");
  makePane(tr("(technique − reference) / reference"), difference_view_, difference_label_,
           "difference_pane");
  difference_label_->setText(tr("White 0, red: the technique is brighter, blue: darker, saturated "
                                "at ±%1%; grey: not compared (silhouette, background).")
                                 .arg(static_cast<double>(kDifferenceRange) * 100.0));
  layout->addLayout(images, 1);
  progress_ = new QProgressBar(root);
  progress_->setRange(0, 1000);
  progress_->setTextVisible(false);
  progress_->setMaximumHeight(8);
  layout->addWidget(progress_);
  metrics_label_ = new QLabel(root);
  metrics_label_->setObjectName("metrics");
  metrics_label_->setWordWrap(true);
  metrics_label_->setTextInteractionFlags(Qt::TextSelectableByMouse);
  layout->addWidget(metrics_label_);
  setWidget(root);

  connect(kind_box_, &QComboBox::currentIndexChanged, this, [this](int i) {
    if (i != 1) setCameraMethod(i == 2);
    setReferenceKind(i == 1 ? analysis::ReferenceKind::Model : analysis::ReferenceKind::Physical);
  });
  connect(quantity_box_, &QComboBox::currentIndexChanged, this,
          [this](int i) { setQuantity(static_cast<Quantity>(i)); });
  connect(width_box_, &QSpinBox::valueChanged, this, &CompareDock::setImageWidth);
  connect(photons_box_, &QSpinBox::valueChanged, this,
          [this](int k) { setPhotonBudget(static_cast<uint64_t>(k) * 1024); });
  connect(samples_box_, &QSpinBox::valueChanged, this,
          [this](int k) { setSampleBudget(static_cast<uint64_t>(k) * 1000); });
  connect(paths_box_, &QSpinBox::valueChanged, this,
          [this](int n) { setPathBudget(static_cast<uint64_t>(n)); });
  connect(device_box_, &QComboBox::currentIndexChanged, this, [this](int i) {
    setTracerDevice(device_box_->itemData(i).toString().toStdString());
  });
  updateBudgetBoxes();
}

void CompareDock::updateBudgetBoxes() {
  const bool physical = kind_ == analysis::ReferenceKind::Physical;
  photons_box_->setVisible(physical && !camera_);
  paths_box_->setVisible(physical && camera_);
  samples_box_->setVisible(!physical);
  device_box_->setVisible(physical && !camera_);
}

// ---------------------------------------------------------------------------------------------
// Settings.

int CompareDock::imageHeight() const {
  const auto& c = state_.scene().camera;
  const double aspect = c.width > 0 && c.height > 0 ? static_cast<double>(c.height) / c.width : 1.0;
  return std::clamp(static_cast<int>(std::lround(width_ * aspect)), 8, 1024);
}

void CompareDock::setReferenceKind(analysis::ReferenceKind kind) {
  if (kind == kind_) return;
  kind_ = kind;
  const QSignalBlocker block(kind_box_);
  kind_box_->setCurrentIndex(kind == analysis::ReferenceKind::Model ? 1 : camera_ ? 2 : 0);
  updateBudgetBoxes();
  dropReference();
}

void CompareDock::setImageWidth(int pixels) {
  pixels = std::clamp(pixels, 16, 512);
  if (pixels == width_) return;
  width_ = pixels;
  const QSignalBlocker block(width_box_);
  width_box_->setValue(pixels);
  restart(false);
}

void CompareDock::setCameraMethod(bool camera) {
  if (camera == camera_) return;
  camera_ = camera;
  if (kind_ == analysis::ReferenceKind::Physical) {
    const QSignalBlocker block(kind_box_);
    kind_box_->setCurrentIndex(camera_ ? 2 : 0);
  }
  updateBudgetBoxes();
  dropReference();
}

void CompareDock::dropReference() {
  // The last images are of the other reference (kind or method): not shown beside the new one.
  snapshot_.reset();
  reference_image_ = QImage();
  reference_view_->setImage(reference_image_);
  restart(false);
  updateComparison();
}

void CompareDock::setPathBudget(uint64_t paths) {
  paths = std::clamp<uint64_t>(paths, 4, 65536);
  if (paths == path_budget_) return;
  path_budget_ = paths;
  const QSignalBlocker block(paths_box_);
  paths_box_->setValue(static_cast<int>(paths));
  restart(false);
}

void CompareDock::setPhotonBudget(uint64_t photons) {
  photons = std::max<uint64_t>(photons, kFirstPhotons);
  if (photons == photon_budget_) return;
  photon_budget_ = photons;
  const QSignalBlocker block(photons_box_);
  photons_box_->setValue(static_cast<int>(std::min<uint64_t>(photons / 1024, 10'000'000)));
  restart(false);
}

void CompareDock::setTracerDevice(const std::string& device) {
  if (device == tracer_device_) return;
  tracer_device_ = device;
  const QSignalBlocker block(device_box_);
  device_box_->setCurrentIndex(device_box_->findData(QString::fromStdString(device)));
  restart(false);
}

void CompareDock::setSampleBudget(uint64_t samples) {
  samples = std::clamp<uint64_t>(samples, 1000, (uint64_t{1} << 24) - 1);
  if (samples == sample_budget_) return;
  sample_budget_ = samples;
  const QSignalBlocker block(samples_box_);
  samples_box_->setValue(static_cast<int>(samples / 1000));
  restart(false);
}

void CompareDock::setQuantity(Quantity quantity) {
  quantity_ = quantity;
  const QSignalBlocker block(quantity_box_);
  quantity_box_->setCurrentIndex(static_cast<int>(quantity));
  updateComparison();
}

analysis::MetricOptions CompareDock::displayOptions() const {
  analysis::MetricOptions o;
  o.exposure = state_.scene().exposure;
  o.gamma = state_.scene().gamma;
  return o;
}

// ---------------------------------------------------------------------------------------------
// Computation.

scene::Scene CompareDock::compareScene() const {
  scene::Scene s = state_.scene();
  s.camera.width = width_;
  s.camera.height = imageHeight();
  return s;
}

void CompareDock::restart(bool force) {
  if (!visible_) return;  // shown again: restart(false) then catches up
  if (!started_) {
    started_ = true;
    worker_->start();
    force = true;
  }
  const scene::Scene s = compareScene();
  const std::string sk = sceneKey(s);
  std::string fk = frameKey(s);
  if (force || fk != frame_key_) requestFrame(s, std::move(fk), sk);

  const bool physical = kind_ == analysis::ReferenceKind::Physical;
  std::string key = fmt::format("{}|{}|{}|{}|{}", analysis::toString(kind_),
                                physical ? (camera_ ? path_budget_ : photon_budget_) : sample_budget_,
                                physical ? tracer_device_ : std::string(),
                                physical && camera_ ? "camera" : "light", sk);
  if (!force && key == run_key_) {
    if (stale_) {  // back to the scene of the reference shown (after a failed change)
      stale_ = false;
      updateStatus();
      updateComparison();
    }
    return;
  }
  // What the reference cannot handle fails here, before a thread and a mesh load.
  try {
    s.camera.validate();
    s.medium.validate();
    (void)scene::referenceLights(s);
    if (!physical && bssrdf::hasBssrdfExtension(s.model))
      throw ParameterError(fmt::format(
          "the model reference integrates a registered model; '{}' is a .bssrdf file (use the "
          "physical reference)", s.model));
  } catch (const std::exception& e) {
    stopRun();
    run_key_.clear();
    stale_ = snapshot_ != nullptr;
    updateStatus();
    updateComparison();
    const QString message = tr("Compare: no %1 reference for this scene: %2")
                                .arg(QString::fromLatin1(analysis::toString(kind_)),
                                     QString::fromUtf8(e.what()));
    // Once per reason: turning a light the reference cannot take by dragging is one error, not
    // hundreds.
    if (message != last_error_) state_.error(message);
    last_error_ = message;
    return;
  }
  last_error_.clear();
  run_scene_key_ = sk;
  startRun(s, std::move(key));
}

void CompareDock::stopRun() {
  if (!run_) return;
  // Not joined here (up to a block's time on the GUI thread): joined when it says it finished.
  run_->requestStop();
  retiring_.push_back({generation_, std::move(run_)});
}

void CompareDock::startRun(const scene::Scene& scene, std::string key) {
  stopRun();
  run_key_ = std::move(key);
  stale_ = false;
  fraction_ = 0.0;
  const int generation = ++generation_;
  CompareRunConfig c;
  c.scene = scene;
  c.kind = kind_;
  c.seed = kSeed;
  c.device = tracer_device_;
  if (kind_ == analysis::ReferenceKind::Physical && camera_) {
    c.method = "camera";
    c.first = 4;
    c.budget = path_budget_;
    c.cap = 0;
  } else if (kind_ == analysis::ReferenceKind::Physical) {
    c.first = kFirstPhotons;
    c.budget = photon_budget_;
    c.cap = kCapPhotons;
  } else {
    c.first = std::min(kFirstSamples, sample_budget_);
    c.budget = sample_budget_;
  }
  CompareRunCallbacks cb;
  // On the run's thread: everything goes to the GUI thread. The run is joined before the dock
  // is destroyed, so `this` outlives every call; calls still queued go with the dock.
  cb.pass = [this, generation](std::shared_ptr<const CompareSnapshot> s) {
    QMetaObject::invokeMethod(
        this, [this, generation, s = std::move(s)]() mutable { onPass(generation, std::move(s)); },
        Qt::QueuedConnection);
  };
  cb.progress = [this, generation](double f) {
    QMetaObject::invokeMethod(this, [this, generation, f] { onProgress(generation, f); },
                              Qt::QueuedConnection);
  };
  cb.finished = [this, generation](bool stopped, const std::string& error) {
    QMetaObject::invokeMethod(
        this,
        [this, generation, stopped, e = QString::fromStdString(error)] {
          onFinished(generation, stopped, e);
        },
        Qt::QueuedConnection);
  };
  run_ = std::make_unique<CompareRun>(std::move(c), std::move(cb));
  updateStatus();
  updateComparison();
  emit runStarted();
}

void CompareDock::requestFrame(const scene::Scene& scene, std::string fk, std::string sk) {
  RenderRequest r;
  r.scene = scene;
  r.width = scene.camera.width;
  r.height = scene.camera.height;
  r.continuous = false;
  r.converge = true;  // as `translucent compare`: progressive techniques finish in one frame
  frame_key_ = std::move(fk);
  frame_request_scene_ = std::move(sk);
  technique_error_.clear();
  frame_request_ = worker_->request(std::move(r));
  if (metrics_) metrics_label_->setText(metricsText());  // marks the frame shown as previous
  updateStatus();
}

void CompareDock::onPass(int generation, std::shared_ptr<const CompareSnapshot> s) {
  if (generation != generation_) return;  // a cancelled run's last pass
  snapshot_ = std::move(s);
  snapshot_generation_ = generation;
  snapshot_scene_key_ = run_scene_key_;
  fraction_ = static_cast<double>(snapshot_->computed) / static_cast<double>(snapshot_->budget);
  updateComparison();
  updateStatus();
  emit passCompleted(snapshot_->pass);
}

void CompareDock::onProgress(int generation, double fraction) {
  if (generation != generation_) return;
  fraction_ = fraction;
  progress_->setValue(static_cast<int>(std::lround(1000.0 * fraction)));
}

void CompareDock::onFinished(int generation, bool stopped, const QString& error) {
  (void)stopped;
  auto it = std::find_if(retiring_.begin(), retiring_.end(),
                         [&](const Retiring& r) { return r.generation == generation; });
  if (it != retiring_.end()) {
    retiring_.erase(it);  // joins a thread that has returned or is about to
    return;
  }
  if (generation != generation_ || !run_) return;
  run_.reset();
  if (!error.isEmpty()) {
    stale_ = snapshot_ != nullptr;
    run_key_.clear();  // the same scene again is a new try
    const QString message = tr("Compare (%1 reference): %2")
                                .arg(QString::fromLatin1(analysis::toString(kind_)), error);
    if (message != last_error_) state_.error(message);
    last_error_ = message;
  }
  updateStatus();
  emit runFinished();
}

void CompareDock::onFrame(std::shared_ptr<const RenderedFrame> frame) {
  // Only the newest request's converged frame; after a failed prepare the worker renders its
  // last good scene under the same id, which is not the scene asked for.
  if (frame->request_id != frame_request_ || failed_requests_.contains(frame->request_id)) return;
  if (!frame->frame.converged) return;  // the worker renders on until it is
  frame_ = std::move(frame);
  frame_scene_key_ = frame_request_scene_;
  shown_frame_key_ = frame_key_;
  last_technique_error_.clear();
  updateComparison();
  updateStatus();
  emit techniqueFrameReceived();
}

void CompareDock::onPrepareFailed(quint64 id, const QString& message) {
  failed_requests_.insert(id);
  if (id != frame_request_) return;
  technique_error_ = message;
  if (message != last_technique_error_)
    state_.error(tr("Compare: the technique cannot render this scene: %1").arg(message));
  last_technique_error_ = message;
  updateStatus();
  updateComparison();
}

// ---------------------------------------------------------------------------------------------
// Display.

void CompareDock::redraw() {
  const double exposure = state_.scene().exposure, gamma = state_.scene().gamma;
  technique_image_ = QImage();
  if (frame_) {
    const auto& f = frame_->frame;
    const std::vector<float>* rgb = &f.rgb;
    if (quantity_ == Quantity::Exitance)
      if (auto it = f.layers.find("exitance"); it != f.layers.end()) rgb = &it->second;
    technique_image_ = toneMappedImage(*rgb, f.width, f.height, exposure, gamma);
  }
  technique_view_->setImage(technique_image_);
  reference_image_ = QImage();
  if (snapshot_) {
    const auto& r = snapshot_->reference;
    const analysis::CompareImage& img =
        quantity_ == Quantity::Exitance ? r.exitance
        : quantity_ == Quantity::ConeRadiance && !r.cone_radiance.empty()
            ? r.cone_radiance
            : r.radiance;  // Jensen; the converted one only differs by a constant
    const analysis::CompareImage shown =
        quantity_ == Quantity::Radiance && frame_
            ? r.radianceFor(frame_->convention, snapshot_->eta)
            : img;
    reference_image_ = toneMappedImage(shown.rgb, shown.width, shown.height, exposure, gamma);
  }
  reference_view_->setImage(reference_image_);
}

void CompareDock::updateComparison() {
  metrics_.reset();
  test_ = {};
  reference_ = {};
  mask_.clear();
  difference_image_ = QImage();
  QString why;
  // The reference of a run that was replaced stays on screen until the new one's first pass,
  // but is compared with nothing: its scene is not the current one (unless the restart failed,
  // and then the numbers say so).
  const bool same = frame_ && snapshot_ && frame_scene_key_ == snapshot_scene_key_ &&
                    (snapshot_generation_ == generation_ || stale_);
  if (!frame_ || !snapshot_)
    why = tr("waiting for the technique frame and the first reference pass");
  else if (!same)
    why = tr("waiting for the technique frame and a reference of the same scene");
  else if (quantity_ == Quantity::ConeRadiance && snapshot_->reference.cone_radiance.empty())
    why = tr("the true radiance comes from the physical reference only");
  else if (quantity_ == Quantity::Exitance && !frame_->frame.layers.contains("exitance"))
    why = tr("technique %1 has no exitance image").arg(QString::fromStdString(frame_->technique));
  if (why.isEmpty()) {
    const auto& f = frame_->frame;
    const analysis::Reference& r = snapshot_->reference;
    switch (quantity_) {
      case Quantity::Radiance:
        test_ = {f.width, f.height, f.rgb, {}};
        reference_ = r.radianceFor(frame_->convention, snapshot_->eta);
        mask_ = snapshot_->masks.interior;
        break;
      case Quantity::ConeRadiance:
        test_ = {f.width, f.height, f.rgb, {}};
        reference_ = r.cone_radiance;
        mask_ = snapshot_->masks.cone;
        break;
      case Quantity::Exitance:
        test_ = {f.width, f.height, f.layers.at("exitance"), {}};
        reference_ = r.exitance;
        mask_ = snapshot_->masks.interior;
        break;
    }
    try {
      metrics_ = analysis::compareImages(test_, reference_, mask_, displayOptions());
      difference_image_ = rgb8Image(
          analysis::falseColor(analysis::relativeDifferenceMap(test_.ref(), reference_.ref(), mask_),
                               test_.width, test_.height, analysis::ColorMap::Diverging,
                               -static_cast<double>(kDifferenceRange),
                               static_cast<double>(kDifferenceRange)),
          test_.width, test_.height);
    } catch (const std::exception& e) {
      metrics_.reset();
      why = QString::fromUtf8(e.what());
    }
  }
  difference_view_->setImage(difference_image_);
  redraw();
  if (!metrics_) {
    metrics_label_->setText(tr("Technique against the %1 reference: %2.")
                                .arg(QString::fromLatin1(analysis::toString(kind_)), why));
  } else {
    metrics_label_->setText(metricsText());
  }
  emit comparisonChanged();
}

QString CompareDock::metricsText() const {
  if (!metrics_) return {};
  const analysis::Metrics& m = *metrics_;
  const char* what = quantity_ == Quantity::Radiance       ? "L"
                     : quantity_ == Quantity::ConeRadiance ? "L vs true radiance"
                                                           : "B";
  QString text =
      tr("%1 against the %2 reference (%3, %4 interior pixels): relative RMSE %5 with the noise "
         "taken out (%6 raw), bias %7 ± %8, SSIM %9, ꟻLIP %10, |z| > 3 in %11 of the pixels")
          .arg(QString::fromStdString(frame_->technique),
               QString::fromLatin1(analysis::toString(kind_)), QString::fromLatin1(what))
          .arg(m.pixels)
          .arg(percent(m.rel_rmse), percent(m.rel_rmse_raw), percent(m.bias), percent(m.bias_stderr))
          .arg(number(m.ssim, 4), number(m.flip, 4), percent(m.fraction_abs_z_above_3, 1));
  if (stale_) text += tr(" (the reference is of the previous scene: see the console)");
  if (!technique_error_.isEmpty())
    text += tr(" (the technique frame is of the previous settings: see the console)");
  else if (shown_frame_key_ != frame_key_)
    text += tr(" (the technique frame is of the previous settings: rendering the new ones)");
  return text;
}

CompareDock::Status CompareDock::status() const {
  Status s;
  s.generation = generation_;
  s.running = run_ != nullptr;
  s.technique = frame_ && frame_scene_key_ == run_scene_key_;
  if (snapshot_ && snapshot_generation_ == generation_) {
    s.passes = snapshot_->pass + 1;
    s.count = snapshot_->count;
    s.computed = snapshot_->computed;
    s.budget = snapshot_->budget;
    s.seconds = snapshot_->seconds;
  }
  return s;
}

void CompareDock::updateStatus() {
  const Status s = status();
  const bool physical = kind_ == analysis::ReferenceKind::Physical;
  QString text;
  if (s.passes > 0) {
    text = physical ? tr(camera_ ? "pass %1/%2: %3 camera paths per pixel and channel in %4 s"
                                 : "pass %1/%2: %3 photons per channel in %4 s")
                          .arg(s.passes)
                          .arg(snapshot_->passes)
                          .arg(count(s.count))
                          .arg(s.seconds, 0, 'f', 2)
                    : tr("pass %1/%2: %3 surface samples (%4 computed) in %5 s")
                          .arg(s.passes)
                          .arg(snapshot_->passes)
                          .arg(count(s.count), count(s.computed))
                          .arg(s.seconds, 0, 'f', 2);
    if (physical && snapshot_->reference.request.device == "gpu") text += tr(" on the GPU");
    if (!run_ && s.computed == s.budget) text += tr(", done");
  } else if (run_) {
    text = tr("computing the first pass…");
  }
  if (stale_) text += tr(" (previous scene: see the console)");
  reference_label_->setText(text);
  progress_->setValue(static_cast<int>(
      std::lround(1000.0 * (run_ ? fraction_ : (s.passes > 0 ? 1.0 : 0.0)))));

  QString t;
  if (frame_)
    t = tr("%1, %2×%3, %4 ms (prepare %5 s)")
            .arg(QString::fromStdString(frame_->technique))
            .arg(frame_->frame.width)
            .arg(frame_->frame.height)
            .arg(frame_->render_ms, 0, 'f', 1)
            .arg(frame_->prepare_ms / 1000.0, 0, 'f', 2);
  if (!technique_error_.isEmpty()) t += tr(" (this scene failed: see the console)");
  else if (frame_ && shown_frame_key_ != frame_key_) t += tr(" (rendering the new scene…)");
  else if (!frame_) t = tr("rendering…");
  technique_label_->setText(t);
}

}  // namespace translucent::explorer
