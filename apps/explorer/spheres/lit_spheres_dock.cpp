// SPDX-License-Identifier: GPL-3.0-or-later
#include "spheres/lit_spheres_dock.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <QtCore/QMetaObject>
#include <QtCore/QTimer>
#include <QtGui/QPainter>
#include <QtWidgets/QCheckBox>
#include <QtWidgets/QComboBox>
#include <QtWidgets/QDoubleSpinBox>
#include <QtWidgets/QGridLayout>
#include <QtWidgets/QHBoxLayout>
#include <QtWidgets/QLabel>
#include <QtWidgets/QProgressBar>
#include <QtWidgets/QSlider>
#include <QtWidgets/QSpinBox>
#include <QtWidgets/QStackedWidget>
#include <QtWidgets/QTabWidget>
#include <QtWidgets/QVBoxLayout>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <exception>
#include <utility>
#include <variant>

#include "translucent/analysis/colormap.h"
#include "translucent/io/image_io.h"
#include "translucent/bssrdf/registry.h"
#include "translucent/analysis/pencil_reference.h"
#include "core/explorer_state.h"
#include "core/pixel_image_view.h"
#include "core/trace_device_box.h"
#include "translucent/gpu/bssrdf_profiles.h"
#include "material/material_worker.h"
#include "translucent/reference/slab.h"  // kBlockPhotons

namespace translucent::explorer {

struct LitSpheresDock::PaneData {
  QString title;
  std::unique_ptr<SphereRun> run;  // the current run (null when none is running)
  int generation = 0;
  std::string key;  // the current run's inputs: a material change with the same key is no restart
  std::string model;  // the model of the current run (integration)
  bool stale = false;  // the last restart failed: the images are of the previous material
  std::shared_ptr<const SphereSnapshot> snapshot;  // the last complete pass shown
  int snapshot_generation = 0;
  double fraction = 0.0;
  QImage image;
  QWidget* widget = nullptr;
  PixelImageView* view = nullptr;
  QProgressBar* progress = nullptr;
  QLabel* status = nullptr;
};

namespace {

constexpr int kSeed = 1;  // the CLI's default --seed
// The path tracer's first pass: a few blocks, so that the first image comes within a fraction of
// a second at the default material (25 mm marble sphere: about 5·10^4 photons/s per thread).
constexpr uint64_t kFirstPhotons = 8 * reference::kBlockPhotons;
// Passes double up to these sizes, then stay: a refresh every second or two at the default
// material (about 10^5 photons/s and 2·10^5 samples/s at 128² on two cores).
constexpr uint64_t kCapPhotons = 128 * reference::kBlockPhotons;
constexpr uint64_t kCapSamples = 16;

// A run's inputs. The path tracer's do not include the model's name: only its medium matters.
std::string key(const SphereRunConfig& c, const std::string& model) {
  const Medium& m = c.medium;
  const bool integrated = c.model || !c.bssrdf_file.empty();
  const std::string traced = "path traced on " + c.device + " (" +
                            (c.order ? reference::toString(*c.order) : "all") + ")";
  return fmt::format("{}|{}x{}|{},{},{}|{}|{}|{}|{}|{}|{}|{}", integrated ? model : traced,
                     c.scene.width, c.scene.height, c.scene.light_direction.x,
                     c.scene.light_direction.y, c.scene.light_direction.z, fmt::join(m.sigma_a, ","),
                     fmt::join(m.sigma_s, ","), m.g, m.eta, m.scale, c.first, c.budget);
}

}  // namespace

LitSpheresDock::LitSpheresDock(ExplorerState& state, QWidget* parent)
    : QDockWidget(tr("Lit spheres"), parent), state_(state) {
  setObjectName("lit_spheres");
  panes_[0] = std::make_unique<PaneData>();
  panes_[1] = std::make_unique<PaneData>();
  pane(Pane::PathTraced).title = tr("Path traced");
  pane(Pane::Integrated).title = tr("Sphere integration");
  buildUi();
  restart_timer_ = new QTimer(this);
  restart_timer_->setSingleShot(true);
  restart_timer_->setInterval(kRestartDelayMs);
  connect(restart_timer_, &QTimer::timeout, this, &LitSpheresDock::restartForMaterial);
  connect(&state_, &ExplorerState::materialChanged, restart_timer_,
          static_cast<void (QTimer::*)()>(&QTimer::start));
  restart(Pane::PathTraced, true);
  restart(Pane::Integrated, true);
}

LitSpheresDock::~LitSpheresDock() {
  // Ask every run to stop first, so that they wind down together; then join them.
  for (auto& p : panes_)
    if (p->run) p->run->requestStop();
  for (auto& r : retiring_) r.run->requestStop();
  for (auto& p : panes_) p->run.reset();
  retiring_.clear();
  // Calls the runs queued to this object before they ended are discarded with it.
}

LitSpheresDock::PaneData& LitSpheresDock::pane(Pane p) { return *panes_[static_cast<int>(p)]; }
const LitSpheresDock::PaneData& LitSpheresDock::pane(Pane p) const {
  return *panes_[static_cast<int>(p)];
}

void LitSpheresDock::buildUi() {
  auto* root = new QWidget(this);
  auto* layout = new QVBoxLayout(root);
  layout->setContentsMargins(4, 4, 4, 4);

  auto* controls = new QGridLayout;
  side_by_side_ = new QCheckBox(tr("Side by side"), root);
  side_by_side_->setObjectName("side_by_side");
  side_by_side_->setToolTip(tr("Show the two spheres and their difference next to each other "
                               "instead of in tabs"));
  quantity_box_ = new QComboBox(root);
  quantity_box_->setObjectName("quantity");
  quantity_box_->addItem(tr("Radiant exitance B"));
  quantity_box_->addItem(tr("Radiance Ft·B/π"));
  exposure_slider_ = new QSlider(Qt::Horizontal, root);
  exposure_slider_->setObjectName("exposure");
  exposure_slider_->setRange(-100, 100);  // tenths of a stop
  exposure_slider_->setValue(0);
  exposure_value_ = new QLabel(root);
  gamma_slider_ = new QSlider(Qt::Horizontal, root);
  gamma_slider_->setObjectName("gamma");
  gamma_slider_->setRange(5, 40);  // tenths
  gamma_slider_->setValue(22);
  gamma_value_ = new QLabel(root);
  resolution_box_ = new QSpinBox(root);
  resolution_box_->setObjectName("resolution");
  resolution_box_->setRange(8, 1024);
  resolution_box_->setSuffix(tr(" px"));
  resolution_box_->setValue(resolution_);
  resolution_box_->setKeyboardTracking(false);
  photons_box_ = new QSpinBox(root);
  photons_box_->setObjectName("photons");
  photons_box_->setRange(8, 1'000'000);
  photons_box_->setSuffix(tr(" k photons"));
  photons_box_->setToolTip(tr("Path tracer budget: thousands of photons per colour channel, all "
                              "passes together"));
  photons_box_->setValue(static_cast<int>(photon_budget_ / 1024));
  photons_box_->setKeyboardTracking(false);
  samples_box_ = new QSpinBox(root);
  samples_box_->setObjectName("samples");
  samples_box_->setRange(1, 1'000'000);
  samples_box_->setSuffix(tr(" spp"));
  samples_box_->setToolTip(tr("Sphere integration budget: samples per pixel and channel, all "
                              "passes together"));
  samples_box_->setValue(static_cast<int>(sample_budget_));
  samples_box_->setKeyboardTracking(false);
  device_box_ = makeTraceDeviceBox(QStringLiteral("tracer_device"), tr("the path tracer"), root);
  light_box_ = new QComboBox(root);
  light_box_->setObjectName("tracer_light");
  light_box_->addItem(tr("multi + single"), QStringLiteral("all"));
  light_box_->addItem(tr("single scattering"), QStringLiteral("single"));
  light_box_->addItem(tr("multiple scattering"), QStringLiteral("multiple"));
  light_box_->setToolTip(tr("The path tracer's light by scattering order (Bitterli 2013, Eq. 2.13): the "
                            "diffusion models describe multiple scattering only"));
  auto angleBox = [&](const char* name, double lo, double hi, double value, const QString& tip) {
    auto* b = new QDoubleSpinBox(root);
    b->setObjectName(name);
    b->setRange(lo, hi);
    b->setDecimals(1);
    b->setSingleStep(5.0);
    b->setSuffix(QStringLiteral("°"));
    b->setValue(value);
    b->setKeyboardTracking(false);
    b->setToolTip(tip);
    return b;
  };
  light_theta_box_ = angleBox("light_theta", 0.0, 180.0, light_theta_,
                              tr("θL: angle between the light and the view axis (0: from the "
                                 "camera, 90: from the side, 180: from behind)"));
  light_phi_box_ = angleBox("light_phi", -360.0, 360.0, light_phi_,
                            tr("φL: azimuth of the light about the view axis, from the image's "
                               "right"));

  // Four short rows rather than two long ones: the dock shares a column with the plot, and its
  // minimum width decides how much of the window the viewport gets.
  controls->addWidget(side_by_side_, 0, 0, 1, 3);
  controls->addWidget(new QLabel(tr("Show"), root), 0, 3);
  controls->addWidget(quantity_box_, 0, 4, 1, 2);
  controls->addWidget(new QLabel(tr("Exposure"), root), 1, 0);
  controls->addWidget(exposure_slider_, 1, 1);
  controls->addWidget(exposure_value_, 1, 2);
  controls->addWidget(new QLabel(tr("Gamma"), root), 1, 3);
  controls->addWidget(gamma_slider_, 1, 4);
  controls->addWidget(gamma_value_, 1, 5);
  controls->addWidget(new QLabel(tr("Size"), root), 2, 0);
  controls->addWidget(resolution_box_, 2, 1, 1, 2);
  controls->addWidget(new QLabel(tr("Path tracer"), root), 2, 3);
  controls->addWidget(photons_box_, 2, 4, 1, 2);
  controls->addWidget(new QLabel(tr("Integration"), root), 3, 0);
  controls->addWidget(samples_box_, 3, 1, 1, 2);
  controls->addWidget(new QLabel(tr("Tracer on"), root), 3, 3);
  controls->addWidget(device_box_, 3, 4, 1, 2);
  controls->addWidget(new QLabel(tr("Light θL"), root), 4, 0);
  controls->addWidget(light_theta_box_, 4, 1, 1, 2);
  controls->addWidget(new QLabel(tr("φL"), root), 4, 3);
  controls->addWidget(light_phi_box_, 4, 4, 1, 2);
  controls->addWidget(new QLabel(tr("Traced light"), root), 5, 0);
  controls->addWidget(light_box_, 5, 1, 1, 2);
  controls->setColumnStretch(1, 1);
  controls->setColumnStretch(4, 1);
  layout->addLayout(controls);

  auto makePane = [&](const QString& title, PixelImageView*& view, QProgressBar** progress,
                      QLabel*& status) {
    auto* w = new QWidget(root);
    auto* l = new QVBoxLayout(w);
    l->setContentsMargins(0, 0, 0, 0);
    auto* heading = new QLabel(QStringLiteral("<b>%1</b>").arg(title), w);
    l->addWidget(heading);
    view = new PixelImageView(w);
    l->addWidget(view, 1);
    if (progress) {
      *progress = new QProgressBar(w);
      (*progress)->setRange(0, 1000);
      (*progress)->setTextVisible(false);
      (*progress)->setMaximumHeight(8);
      l->addWidget(*progress);
    }
    status = new QLabel(w);
    status->setWordWrap(true);
    l->addWidget(status);
    return w;
  };
  for (Pane p : {Pane::PathTraced, Pane::Integrated}) {
    PaneData& d = pane(p);
    d.widget = makePane(d.title, d.view, &d.progress, d.status);
    d.widget->setObjectName(p == Pane::PathTraced ? "path_traced_pane" : "integration_pane");
  }
  difference_pane_ = makePane(tr("Relative difference (integration − path traced) / path traced"),
                              difference_view_, nullptr, difference_label_);
  difference_pane_->setObjectName("difference_pane");
  difference_label_->setText(tr("Waiting for both images. Colours: white 0, red: the model is "
                                "brighter, blue: darker, saturated at ±%1%.")
                                 .arg(static_cast<double>(kDifferenceRange) * 100.0));

  views_ = new QStackedWidget(root);
  tabs_ = new QTabWidget(views_);
  side_ = new QWidget(views_);
  new QHBoxLayout(side_);
  side_->layout()->setContentsMargins(0, 0, 0, 0);
  views_->addWidget(tabs_);
  views_->addWidget(side_);
  layout->addWidget(views_, 1);
  summary_label_ = new QLabel(root);
  summary_label_->setObjectName("comparison");
  summary_label_->setWordWrap(true);
  summary_label_->setTextInteractionFlags(Qt::TextSelectableByMouse);
  layout->addWidget(summary_label_);
  setWidget(root);
  setSideBySide(false);  // seed 3.6.2: initially grouped into a tabbed view
  updateStatus(Pane::PathTraced);
  updateStatus(Pane::Integrated);
  exposure_value_->setText(QString::number(exposure_, 'f', 1));
  gamma_value_->setText(QString::number(gamma_, 'f', 1));

  connect(side_by_side_, &QCheckBox::toggled, this, &LitSpheresDock::setSideBySide);
  connect(quantity_box_, &QComboBox::currentIndexChanged, this, [this](int i) {
    setQuantity(i == 1 ? Quantity::Radiance : Quantity::Exitance);
  });
  connect(exposure_slider_, &QSlider::valueChanged, this,
          [this](int v) { setExposure(v / 10.0); });
  connect(gamma_slider_, &QSlider::valueChanged, this, [this](int v) { setGamma(v / 10.0); });
  connect(resolution_box_, &QSpinBox::valueChanged, this, &LitSpheresDock::setResolution);
  connect(light_theta_box_, &QDoubleSpinBox::valueChanged, this,
          [this](double t) { setLightAngles(t, light_phi_); });
  connect(light_phi_box_, &QDoubleSpinBox::valueChanged, this,
          [this](double p) { setLightAngles(light_theta_, p); });
  connect(photons_box_, &QSpinBox::valueChanged, this,
          [this](int k) { setPhotonBudget(static_cast<uint64_t>(k) * 1024); });
  connect(samples_box_, &QSpinBox::valueChanged, this,
          [this](int n) { setSampleBudget(static_cast<uint64_t>(n)); });
  connect(device_box_, &QComboBox::currentIndexChanged, this, [this](int i) {
    setTracerDevice(device_box_->itemData(i).toString().toStdString());
  });
  connect(light_box_, &QComboBox::currentIndexChanged, this, [this](int i) {
    setTracerLight(light_box_->itemData(i).toString().toStdString());
  });
}

// ---------------------------------------------------------------------------------------------
// Display.

void LitSpheresDock::setExposure(double stops) {
  if (!std::isfinite(stops)) return;
  exposure_ = stops;
  const QSignalBlocker block(exposure_slider_);
  exposure_slider_->setValue(static_cast<int>(std::lround(stops * 10.0)));
  exposure_value_->setText(QString::number(stops, 'f', 1));
  redraw();
}

void LitSpheresDock::setGamma(double gamma) {
  if (!(gamma > 0.0) || !std::isfinite(gamma)) return;
  gamma_ = gamma;
  const QSignalBlocker block(gamma_slider_);
  gamma_slider_->setValue(static_cast<int>(std::lround(gamma * 10.0)));
  gamma_value_->setText(QString::number(gamma, 'f', 1));
  redraw();
}

void LitSpheresDock::setQuantity(Quantity quantity) {
  quantity_ = quantity;
  const QSignalBlocker block(quantity_box_);
  quantity_box_->setCurrentIndex(quantity == Quantity::Radiance ? 1 : 0);
  updateComparison();
  redraw();
}

bool LitSpheresDock::sideBySide() const { return views_->currentWidget() == side_; }

void LitSpheresDock::setSideBySide(bool sideBySide) {
  const QSignalBlocker block(side_by_side_);
  side_by_side_->setChecked(sideBySide);
  QWidget* widgets[] = {pane(Pane::PathTraced).widget, pane(Pane::Integrated).widget,
                        difference_pane_};
  while (tabs_->count() > 0) tabs_->removeTab(0);  // the pages stay alive
  if (sideBySide) {
    for (QWidget* w : widgets) {
      side_->layout()->addWidget(w);
      w->show();  // the tab widget hid the pages that were not current
    }
    views_->setCurrentWidget(side_);
  } else {
    tabs_->addTab(widgets[0], tr("Path traced"));
    tabs_->addTab(widgets[1], tr("Sphere integration"));
    tabs_->addTab(widgets[2], tr("Difference"));
    views_->setCurrentWidget(tabs_);
  }
}

std::vector<float> LitSpheresDock::linearImage(Pane p) const {
  const auto& s = pane(p).snapshot;
  if (!s) return {};
  return (quantity_ == Quantity::Radiance ? s->radiance : s->exitance).rgb();
}

void LitSpheresDock::redraw() {
  for (Pane p : {Pane::PathTraced, Pane::Integrated}) {
    PaneData& d = pane(p);
    if (!d.snapshot) continue;
    const auto& img = quantity_ == Quantity::Radiance ? d.snapshot->radiance : d.snapshot->exitance;
    d.image = toneMappedImage(img.rgb(), img.width(), img.height(), exposure_, gamma_);
    d.view->setImage(d.image);
  }
  emit displayChanged();
}

QImage LitSpheresDock::image(Pane p) const { return pane(p).image; }
QImage LitSpheresDock::differenceImage() const { return difference_image_; }

LitSpheresDock::PaneStatus LitSpheresDock::status(Pane p) const {
  const PaneData& d = pane(p);
  PaneStatus s;
  s.generation = d.generation;
  s.running = d.run != nullptr;
  if (d.snapshot && d.snapshot_generation == d.generation) {
    s.passes = d.snapshot->pass + 1;
    s.done = d.snapshot->done;
    s.budget = d.snapshot->budget;
    s.seconds = d.snapshot->seconds;
    s.device = d.snapshot->device;
  }
  return s;
}

void LitSpheresDock::updateStatus(Pane p) {
  PaneData& d = pane(p);
  const PaneStatus s = status(p);
  const char* unit = p == Pane::PathTraced ? "photons per channel" : "samples per pixel";
  QString text;
  if (s.passes > 0)
    text = tr("pass %1/%2: %3 %4 in %5 s")
               .arg(s.passes)
               .arg(d.snapshot->passes)
               .arg(QLocale().toString(static_cast<qulonglong>(s.done)))
               .arg(QString::fromLatin1(unit))
               .arg(s.seconds, 0, 'f', 2);
  if (s.passes > 0 && !s.device.empty()) text += tr(" (%1)").arg(QString::fromStdString(s.device));
  else if (s.passes == 0 && d.run)
    text = tr("computing the first pass…");
  if (d.stale) text += tr(" (previous material: see the console)");
  if (!d.run && s.passes > 0 && s.done == s.budget) text += tr(", done");
  d.status->setText(text);
  d.progress->setValue(static_cast<int>(std::lround(1000.0 * (d.run ? d.fraction : (s.passes > 0 ? 1.0 : 0.0)))));
}

void LitSpheresDock::updateComparison() {
  const auto& a = pane(Pane::PathTraced).snapshot;
  const auto& b = pane(Pane::Integrated).snapshot;
  comparison_.reset();
  difference_image_ = QImage();
  if (a && b && a->exitance.width() == b->exitance.width() &&
      a->exitance.height() == b->exitance.height()) {
    const bool radiance = quantity_ == Quantity::Radiance;
    comparison_ = analysis::compareImages(radiance ? a->radiance : a->exitance,
                                          radiance ? b->radiance : b->exitance);
    const auto& c = *comparison_;
    const std::vector<uint8_t> rgb =
        analysis::falseColor(c.relative, c.width, c.height, analysis::ColorMap::Diverging,
                             -static_cast<double>(kDifferenceRange),
                             static_cast<double>(kDifferenceRange));
    difference_image_ = rgb8Image(rgb, c.width, c.height);
  }
  difference_view_->setImage(difference_image_);
  if (!comparison_ || comparison_->metrics.pixels == 0) {
    summary_label_->setText(tr("Model against reference: waiting for both images."));
    return;
  }
  const auto& c = *comparison_;
  const QString model = QString::fromStdString(pane(Pane::Integrated).model);
  summary_label_->setText(
      tr("%1 against the path-traced reference (%2 pixels): relative RMSE %3% = Monte Carlo noise "
         "%4% ⊕ systematic %5%; mean ratio %6%7")
          .arg(model)
          .arg(c.metrics.pixels)
          .arg(100.0 * c.metrics.rel_rmse_raw, 0, 'f', 1)
          .arg(100.0 * c.relativeNoise(), 0, 'f', 1)
          .arg(100.0 * c.metrics.rel_rmse, 0, 'f', 1)
          .arg(c.metrics.mean_test / c.metrics.mean_reference, 0, 'f', 3)
          .arg(pane(Pane::PathTraced).stale || pane(Pane::Integrated).stale
                   ? tr(" (one image is of the previous material)")
                   : QString()));
  difference_label_->setText(
      tr("Per pixel (sum of the channels). White 0, red: the model is brighter, blue: darker, "
         "saturated at ±%1%; grey: no reference signal yet.")
          .arg(static_cast<double>(kDifferenceRange) * 100.0));
}

// ---------------------------------------------------------------------------------------------
// Computation.

reference::SphereScene LitSpheresDock::sphereScene() const {
  reference::SphereScene s;  // the CLI's defaults: radius 1, light (1,1,1), view (0,0,1)
  s.width = s.height = resolution_;
  s.light_direction = light_direction_;
  return s;
}

void LitSpheresDock::setLightAngles(double thetaDeg, double phiDeg) {
  if (!std::isfinite(thetaDeg) || !std::isfinite(phiDeg)) return;
  thetaDeg = std::clamp(thetaDeg, 0.0, 180.0);
  if (thetaDeg == light_theta_ && phiDeg == light_phi_) return;
  light_theta_ = thetaDeg;
  light_phi_ = phiDeg;
  const double t = thetaDeg * std::numbers::pi / 180.0, p = phiDeg * std::numbers::pi / 180.0;
  light_direction_ = {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
  {
    const QSignalBlocker a(light_theta_box_), b(light_phi_box_);
    light_theta_box_->setValue(thetaDeg);
    light_phi_box_->setValue(phiDeg);
  }
  restart(Pane::PathTraced, false);
  restart(Pane::Integrated, false);
}

void LitSpheresDock::setResolution(int pixels) {
  pixels = std::clamp(pixels, 8, 1024);
  if (pixels == resolution_) return;
  resolution_ = pixels;
  const QSignalBlocker block(resolution_box_);
  resolution_box_->setValue(pixels);
  restart(Pane::PathTraced, false);
  restart(Pane::Integrated, false);
}

void LitSpheresDock::setPhotonBudget(uint64_t photons) {
  photons = std::max<uint64_t>(photons, reference::kBlockPhotons);
  if (photons == photon_budget_) return;
  photon_budget_ = photons;
  const QSignalBlocker block(photons_box_);
  photons_box_->setValue(static_cast<int>(std::min<uint64_t>(photons / 1024, 1'000'000)));
  restart(Pane::PathTraced, false);
}

void LitSpheresDock::setSampleBudget(uint64_t samples) {
  samples = std::max<uint64_t>(samples, 1);
  if (samples == sample_budget_) return;
  sample_budget_ = samples;
  const QSignalBlocker block(samples_box_);
  samples_box_->setValue(static_cast<int>(std::min<uint64_t>(samples, 1'000'000)));
  restart(Pane::Integrated, false);
}

void LitSpheresDock::setTracerDevice(const std::string& device) {
  if (device == tracer_device_) return;
  tracer_device_ = device;
  const QSignalBlocker block(device_box_);
  device_box_->setCurrentIndex(device_box_->findData(QString::fromStdString(device)));
  restart(Pane::PathTraced, false);
}

void LitSpheresDock::setTracerLight(const std::string& light) {
  if (light == tracer_light_) return;
  if (light == "split" || std::find(analysis::kScatteringSelections.begin(),
                                    analysis::kScatteringSelections.end(),
                                    light) == analysis::kScatteringSelections.end()) {
    state_.error(tr("Lit spheres: traced light '%1': expected all, single or multiple")
                     .arg(QString::fromStdString(light)));
    return;
  }
  tracer_light_ = light;
  const QSignalBlocker block(light_box_);
  light_box_->setCurrentIndex(light_box_->findData(QString::fromStdString(light)));
  restart(Pane::PathTraced, false);
}

void LitSpheresDock::restartForMaterial() {
  restart(Pane::PathTraced, false);
  restart(Pane::Integrated, false);
}

void LitSpheresDock::restart(Pane p, bool force) {
  PaneData& d = pane(p);
  const std::string model = state_.scene().model;
  SphereRunConfig c;
  c.scene = sphereScene();
  c.seed = kSeed;
  c.threads = 0;
  c.device = tracer_device_;
  c.order = analysis::scatteringSelection(tracer_light_).front();  // one image: never "split"
  try {
    // Both spheres use the medium the model is shown with, so that they compare like with like.
    c.medium = state_.mediumFor(model);
    c.medium.validate();
    c.scene.validate();
    if (p == Pane::Integrated) {
      c.first = 1;
      c.budget = sample_budget_;
      c.cap = kCapSamples;
      if (bssrdf::isPluginFile(model)) {
        restartPlugin(std::move(c), model, force);
        return;
      }
      c.model = &bssrdf::model(model);
    } else {
      c.first = kFirstPhotons;
      c.budget = photon_budget_;
      c.cap = kCapPhotons;
    }
  } catch (const bssrdf::UnknownModelError& e) {
    d.stale = d.snapshot != nullptr;
    updateStatus(p);
    state_.error(tr("Lit spheres: '%1' is neither a registered model nor a .csv or .bssrdf file "
                    "(%2). The integration keeps its previous image.")
                     .arg(QString::fromStdString(model), QString::fromUtf8(e.what())));
    return;
  } catch (const std::exception& e) {
    d.stale = d.snapshot != nullptr;
    updateStatus(p);
    state_.error(tr("Lit spheres (%1): %2; the previous image stays.")
                     .arg(d.title, QString::fromUtf8(e.what())));
    return;
  }
  std::string k = key(c, model);
  startIfChanged(p, std::move(c), std::move(k), model, force);
}

void LitSpheresDock::startIfChanged(Pane p, SphereRunConfig c, std::string k,
                                    const std::string& model, bool force) {
  PaneData& d = pane(p);
  if (p == Pane::Integrated && k != d.key) d.model = model;
  if (!force && k == d.key) {
    // Back to the inputs of the images shown (after a failed change): they are current again.
    if (d.stale) {
      d.stale = false;
      updateStatus(p);
      updateComparison();
    }
    return;
  }
  startRun(p, std::move(c), std::move(k));
}

// A .bssrdf model (issue 14 §3), prepared on the material worker, where the file is loaded with
// the parameter values the parameters dock set: a radial file becomes a table of its GPU values
// for the medium (gpu::bssrdfTabulatedModel: the CPU integrator samples and evaluates it like a
// registered model); a directional one is handed over as its path and parameter values, for
// the GPU integrator with the light's direction on the run's thread.
void LitSpheresDock::restartPlugin(SphereRunConfig c, const std::string& model, bool force) {
  const uint64_t ticket = ++plugin_ticket_;
  MaterialWorker::of(state_).post(
      this,
      [c = std::move(c), model, force, ticket, this](MaterialGl& gl) mutable -> MaterialWorker::Continuation {
        gpu::BssrdfEvaluator& e = gl.load(model);
        std::string params;
        if (e.file().attributes.radial) {
          c.owned_model = gpu::bssrdfTabulatedModel(e, c.medium, model);
          c.model = c.owned_model.get();
        } else {
          c.bssrdf_file = model;
          for (const auto& decl : e.file().parameters)
            c.bssrdf_parameters.emplace_back(decl.name, e.parameter(decl.name));
        }
        for (const auto& decl : e.file().parameters) {
          const gpu::ParameterValue v = e.parameter(decl.name);
          if (const auto* d = std::get_if<double>(&v)) params += fmt::format("{}={};", decl.name, *d);
          else if (const auto* b = std::get_if<bool>(&v)) params += fmt::format("{}={};", decl.name, *b);
          else params += fmt::format("{}={};", decl.name, fmt::join(std::get<Rgb>(v), ","));
        }
        return [this, c = std::move(c), model, force, ticket, params]() mutable {
          if (ticket != plugin_ticket_) return;  // a newer change is on its way
          std::string k = key(c, model) + "|" + params;  // before c is moved
          startIfChanged(Pane::Integrated, std::move(c), std::move(k), model, force);
        };
      },
      [this](const QString& why) {
        PaneData& d = pane(Pane::Integrated);
        d.stale = d.snapshot != nullptr;
        updateStatus(Pane::Integrated);
        state_.error(tr("Lit spheres (sphere integration): %1; the previous image stays.").arg(why));
      });
}

void LitSpheresDock::stopRun(Pane p) {
  PaneData& d = pane(p);
  if (!d.run) return;
  // Not joined here (that could take a block's time on the GUI thread): the run goes on winding
  // down and is joined when it reports that it has finished.
  d.run->requestStop();
  retiring_.push_back({p, d.generation, std::move(d.run)});
}

void LitSpheresDock::startRun(Pane p, SphereRunConfig config, std::string k) {
  stopRun(p);
  PaneData& d = pane(p);
  d.key = std::move(k);
  d.stale = false;
  d.fraction = 0.0;
  const int generation = ++d.generation;
  SphereRunCallbacks cb;
  // Called on the run's thread: hand everything to the GUI thread. The run is joined before this
  // dock is destroyed, so `this` outlives every call; a call still queued when the dock goes is
  // discarded with it.
  cb.pass = [this, p, generation](std::shared_ptr<const SphereSnapshot> s) {
    QMetaObject::invokeMethod(
        this, [this, p, generation, s = std::move(s)]() mutable { onPass(p, generation, std::move(s)); },
        Qt::QueuedConnection);
  };
  cb.progress = [this, p, generation](double f) {
    QMetaObject::invokeMethod(this, [this, p, generation, f] { onProgress(p, generation, f); },
                              Qt::QueuedConnection);
  };
  cb.finished = [this, p, generation](bool stopped, const std::string& error) {
    QMetaObject::invokeMethod(
        this,
        [this, p, generation, stopped, e = QString::fromStdString(error)] {
          onFinished(p, generation, stopped, e);
        },
        Qt::QueuedConnection);
  };
  d.run = std::make_unique<SphereRun>(std::move(config), std::move(cb));
  updateStatus(p);
  emit runStarted(p);
}

void LitSpheresDock::onPass(Pane p, int generation, std::shared_ptr<const SphereSnapshot> s) {
  PaneData& d = pane(p);
  if (generation != d.generation) return;  // a cancelled run's last pass
  d.snapshot = std::move(s);
  d.snapshot_generation = generation;
  d.fraction = static_cast<double>(d.snapshot->done) / static_cast<double>(d.snapshot->budget);
  updateComparison();
  redraw();
  updateStatus(p);
  emit passCompleted(p, d.snapshot->pass);
}

void LitSpheresDock::onProgress(Pane p, int generation, double fraction) {
  PaneData& d = pane(p);
  if (generation != d.generation) return;
  d.fraction = fraction;
  d.progress->setValue(static_cast<int>(std::lround(1000.0 * fraction)));
}

void LitSpheresDock::onFinished(Pane p, int generation, bool stopped, const QString& error) {
  (void)stopped;
  PaneData& d = pane(p);
  auto it = std::find_if(retiring_.begin(), retiring_.end(), [&](const Retiring& r) {
    return r.pane == p && r.generation == generation;
  });
  if (it != retiring_.end()) {
    retiring_.erase(it);  // joins a thread that has returned or is about to
    return;
  }
  if (generation != d.generation || !d.run) return;
  d.run.reset();
  if (!error.isEmpty()) {
    d.stale = d.snapshot != nullptr;
    state_.error(tr("Lit spheres (%1): %2").arg(d.title, error));
  }
  updateStatus(p);
  emit runFinished(p);
}

}  // namespace translucent::explorer
