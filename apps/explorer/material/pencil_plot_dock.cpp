// SPDX-License-Identifier: GPL-3.0-or-later
#include "material/pencil_plot_dock.h"

#include <fmt/format.h>

#include <QtCharts/QChart>
#include <QtCharts/QChartView>
#include <QtCore/QFileInfo>
#include <QtCore/QMetaObject>
#include <QtCore/QSignalBlocker>
#include <QtWidgets/QCheckBox>
#include <QtWidgets/QComboBox>
#include <QtWidgets/QDoubleSpinBox>
#include <QtWidgets/QGraphicsLayout>
#include <QtWidgets/QGridLayout>
#include <QtWidgets/QLabel>
#include <QtWidgets/QVBoxLayout>

#include <algorithm>
#include <array>
#include <memory>
#include <numbers>
#include <optional>
#include <map>

#include "translucent/bssrdf/registry.h"
#include "translucent/bssrdf/tabulated.h"
#include "core/explorer_state.h"
#include "core/trace_device_box.h"
#include "translucent/gpu/bssrdf_profiles.h"
#include "material/material_worker.h"
#include "plot/chart_legend.h"
#include "plot/profile_plot.h"

namespace translucent::explorer {
namespace {

using analysis::Channel;
using analysis::Curve;

QString q(const std::string& s) { return QString::fromStdString(s); }

// The curves come in scene units (one unit spans `scale` mm: Jensen et al. 2001's scale
// parameter); they are shown in mm, as every length the CLI prints: r·scale, R(r)/scale² (per
// area), r·R(r)/scale (per length).
void toMillimetres(std::vector<Curve>& curves, double scale, bool times_r) {
  if (scale == 1.0) return;
  const double value = times_r ? 1.0 / scale : 1.0 / (scale * scale);
  for (Curve& c : curves) {
    for (double& r : c.r) r *= scale;
    for (double& v : c.value) v *= value;
    for (double& e : c.stderr_) e *= value;
  }
}

bool sameMedium(const Medium& a, const Medium& b) {
  return a.sigma_a == b.sigma_a && a.sigma_s == b.sigma_s && a.g == b.g && a.eta == b.eta &&
         a.scale == b.scale;
}

// Label of a model's curves: a registered name, or a .bssrdf file's stem (as `translucent
// profile` labels it), with ".bssrdf" where the stem is also a registered name.
std::string curveLabel(const std::string& entry) {
  if (bssrdf::isTabulatedFile(entry)) return QFileInfo(q(entry)).completeBaseName().toStdString();
  if (!isBssrdfPath(entry)) return entry;
  std::string stem = QFileInfo(q(entry)).completeBaseName().toStdString();
  const auto names = bssrdf::modelNames();
  if (std::find(names.begin(), names.end(), stem) != names.end()) stem += ".bssrdf";
  return stem;
}

}  // namespace

PencilPlotDock::PencilPlotDock(ExplorerState& state, QWidget* parent)
    : QDockWidget(tr("Pencil plot"), parent),
      state_(state),
      worker_(MaterialWorker::of(state)),
      generation_(std::make_shared<std::atomic<uint64_t>>(0)) {
  setObjectName(QStringLiteral("pencil_plot"));
  auto* body = new QWidget;
  auto* layout = new QVBoxLayout(body);
  auto* controls = new QGridLayout;
  yScale_ = new QComboBox;
  yScale_->setObjectName(QStringLiteral("y_scale"));
  yScale_->addItem(tr("linear"), static_cast<int>(plot::YScale::Linear));
  yScale_->addItem(tr("log"), static_cast<int>(plot::YScale::Log));
  yScale_->addItem(tr("square root"), static_cast<int>(plot::YScale::Sqrt));
  yScale_->setCurrentIndex(1);
  channel_ = new QComboBox;
  channel_->setObjectName(QStringLiteral("channel"));
  channel_->addItem(tr("red"), static_cast<int>(Channel::Red));
  channel_->addItem(tr("green"), static_cast<int>(Channel::Green));
  channel_->addItem(tr("blue"), static_cast<int>(Channel::Blue));
  channel_->addItem(tr("luminance"), static_cast<int>(Channel::Luminance));
  channel_->setCurrentIndex(3);
  solo_ = new QComboBox;
  solo_->setObjectName(QStringLiteral("solo"));
  solo_->setToolTip(tr("Show one model's three channels"));
  timesR_ = new QCheckBox(tr("r·R(r)"));
  timesR_->setObjectName(QStringLiteral("times_r"));
  reference_ = new QCheckBox(tr("Reference"));
  reference_->setObjectName(QStringLiteral("reference"));
  reference_->setChecked(true);
  reference_->setToolTip(tr("Path-traced pencil beam on a semi-infinite slab, ±1 standard error"));
  photons_ = new QDoubleSpinBox;
  photons_->setObjectName(QStringLiteral("photons"));
  photons_->setDecimals(0);
  photons_->setRange(1e4, 1e9);
  photons_->setSingleStep(1e5);
  photons_->setValue(1e6);
  photons_->setToolTip(tr("Reference photons per channel (refined in passes of doubling counts)"));
  device_ = makeTraceDeviceBox(QStringLiteral("reference_device"), tr("the reference"));
  theta_ = new QDoubleSpinBox;
  theta_->setObjectName(QStringLiteral("incidence"));
  theta_->setRange(0.0, 89.0);
  theta_->setDecimals(1);
  theta_->setSingleStep(5.0);
  theta_->setSuffix(QStringLiteral("°"));
  theta_->setToolTip(tr("Polar angle θL of the pencil beam: the reference is traced at it; a "
                        "directional model (directional-dipole) is drawn as its azimuthal average "
                        "there; radial models assume normal incidence"));
  // The seed's "multi + single scattering" selector (Fig. 3.6): which light of the reference is
  // drawn (Eq. 2.13); "split" draws the three curves. The tally keeps every order, so switching
  // redraws without tracing again.
  scattering_ = new QComboBox;
  scattering_->setObjectName(QStringLiteral("scattering"));
  scattering_->addItem(tr("multi + single"), QStringLiteral("all"));
  scattering_->addItem(tr("single"), QStringLiteral("single"));
  scattering_->addItem(tr("multiple"), QStringLiteral("multiple"));
  scattering_->addItem(tr("split"), QStringLiteral("split"));
  scattering_->setToolTip(tr("The reference's light: all of it, only what scattered once, only "
                             "what scattered more often, or all three curves"));
  status_ = new QLabel;
  status_->setObjectName(QStringLiteral("reference_status"));
  controls->addWidget(new QLabel(tr("y")), 0, 0);
  controls->addWidget(yScale_, 0, 1);
  controls->addWidget(new QLabel(tr("channel")), 0, 2);
  controls->addWidget(channel_, 0, 3);
  controls->addWidget(timesR_, 0, 4);
  controls->addWidget(new QLabel(tr("solo")), 1, 0);
  controls->addWidget(solo_, 1, 1);
  controls->addWidget(reference_, 1, 2);
  controls->addWidget(photons_, 1, 3);
  controls->addWidget(device_, 1, 4);
  controls->addWidget(new QLabel(tr("θL")), 2, 0);
  controls->addWidget(theta_, 2, 1);
  controls->addWidget(new QLabel(tr("scattering")), 2, 2);
  controls->addWidget(scattering_, 2, 3);
  controls->addWidget(status_, 3, 0, 1, 5);
  layout->addLayout(controls);
  view_ = new QChartView;
  view_->setRenderHint(QPainter::Antialiasing);
  view_->setMinimumSize(240, 120);
  layout->addWidget(view_, 1);
  legend_ = new plot::ChartLegend;
  legend_->setObjectName(QStringLiteral("pencil_plot_legend"));
  layout->addWidget(legend_);
  setWidget(body);

  auto refillSolo = [this] {
    const QString current = solo_->currentData().toString();
    const QSignalBlocker block(solo_);
    solo_->clear();
    solo_->addItem(tr("(all models)"), QString());
    for (const auto& m : state_.plotModels()) solo_->addItem(q(curveLabel(m)), q(m));
    solo_->setCurrentIndex(std::max(0, solo_->findData(current)));
  };
  refillSolo();
  auto onMaterial = [this] {
    stopReference();
    requestModels();
  };
  connect(&state_, &ExplorerState::materialChanged, this, onMaterial);
  connect(&state_, &ExplorerState::plotModelsChanged, this, refillSolo);
  connect(&worker_, &MaterialWorker::bssrdfChanged, this, onMaterial);
  connect(solo_, &QComboBox::currentIndexChanged, this, onMaterial);
  connect(channel_, &QComboBox::currentIndexChanged, this, [this] { requestModels(); });
  connect(timesR_, &QCheckBox::toggled, this, [this] { requestModels(); });
  connect(theta_, &QDoubleSpinBox::valueChanged, this, onMaterial);
  connect(yScale_, &QComboBox::currentIndexChanged, this, [this] { redraw(); });
  connect(scattering_, &QComboBox::currentIndexChanged, this, [this] { redraw(); });
  connect(reference_, &QCheckBox::toggled, this, [this](bool on) {
    if (on)
      restartReference();
    else
      stopReference();
    redraw();
  });
  connect(device_, &QComboBox::currentIndexChanged, this, [this] { restartReference(); });
  connect(photons_, &QDoubleSpinBox::editingFinished, this, [this] {
    if (ref_active_ && ref_budget_ == static_cast<uint64_t>(photons_->value())) return;
    restartReference();
  });
  requestModels();
}

PencilPlotDock::~PencilPlotDock() {
  stopReference();
  for (auto& r : ref_threads_) r.thread.join();
}

QChart* PencilPlotDock::chart() const { return view_->chart(); }

std::vector<Channel> PencilPlotDock::channels() const {
  if (!solo().empty()) return {Channel::Red, Channel::Green, Channel::Blue};
  return {static_cast<Channel>(channel_->currentData().toInt())};
}

std::string PencilPlotDock::solo() const { return solo_->currentData().toString().toStdString(); }

double PencilPlotDock::incidence() const { return theta_->value(); }

void PencilPlotDock::requestModels() {
  since_change_.restart();
  const uint64_t gen = ++*generation_;
  std::vector<std::string> models =
      solo().empty() ? state_.plotModels() : std::vector<std::string>{solo()};
  std::vector<std::pair<std::string, Medium>> work;
  for (const auto& m : models) work.emplace_back(m, state_.mediumFor(m));
  const auto chans = channels();
  const bool timesR = timesR_->isChecked();
  const double theta = theta_->value() * std::numbers::pi / 180.0;
  auto latest = generation_;
  worker_.post(
      this,
      [this, gen, latest, work, chans, timesR, theta](MaterialGl& gl) -> MaterialWorker::Continuation {
        if (latest->load() != gen) return {};  // a newer request is queued: skip this one
        // The range: the largest 95% radius over models and channels (the CLI's default). A
        // registered model's three profiles are built once (analysis::ModelCurve, building is the
        // costly part: ~60 ms for photon-beam) and serve both the range and the values, sampled by
        // the same analysis::sampleCurves as analysis::profileCurves.
        double rMax = 0.0;
        std::vector<std::string> errors;
        struct Ready {
          std::string model;
          Medium medium;
          std::shared_ptr<const analysis::ModelCurve> values;  // registered models only
        };
        std::vector<Ready> ok;
        for (const auto& [m, medium] : work) {
          if (latest->load() != gen) return {};
          try {
            if (isBssrdfPath(m)) {
              const Rgb r95 = gpu::bssrdfRadiusForFraction(gl.load(m), medium, 0.95).radius;
              rMax = std::max({rMax, r95[0], r95[1], r95[2]});
              ok.push_back({m, medium, nullptr});
            } else {
              auto values = std::make_shared<const analysis::ModelCurve>(bssrdf::model(m), medium, theta);
              for (const auto& p : values->profiles()) rMax = std::max(rMax, p->radiusForFraction(0.95));
              ok.push_back({m, medium, std::move(values)});
            }
          } catch (const std::exception& e) {
            errors.push_back(fmt::format("pencil plot: {}: {}", m, e.what()));
          }
        }
        std::vector<Curve> curves;
        if (rMax > 0.0 && std::isfinite(rMax)) {
          const auto grid = analysis::radiusGrid(rMax, 200);
          for (const auto& [m, medium, values] : ok) {
            try {
              // At oblique incidence a directional model is its kernel's azimuthal average; the
              // others say what they assume.
              const std::string normal = theta != 0.0 ? " (normal incidence)" : "";
              const auto c =
                  values ? analysis::sampleCurves(*values, curveLabel(m) + (values->directional() ? "" : normal),
                                                  chans, grid, timesR)
                         : gpu::bssrdfCurves(gl.load(m), curveLabel(m) + normal, medium, chans, grid, timesR);
              curves.insert(curves.end(), c.begin(), c.end());
            } catch (const std::exception& e) {
              errors.push_back(fmt::format("pencil plot: {}: {}", m, e.what()));
            }
          }
        } else if (!ok.empty()) {
          errors.push_back(fmt::format(
              "pencil plot: no finite plot range (the 95% radius is {}); does the medium absorb?",
              rMax));
        }
        return [this, gen, rMax, curves = std::move(curves), errors] {
          if (gen != generation_->load()) return;
          for (const auto& e : errors) state_.error(q(e));
          curves_ = curves;
          r_max_ = rMax;
          redraw();
          latency_ms_ = static_cast<double>(since_change_.nsecsElapsed()) * 1e-6;
          emit modelCurvesUpdated();
          // The reference follows the range and the medium; start it when it does not match.
          const Medium& m = solo().empty() ? state_.medium() : state_.mediumFor(solo());
          const bool current = ref_active_ && ref_r_max_ == r_max_ && sameMedium(ref_medium_, m) &&
                               ref_theta_ == theta_->value();
          if (reference_->isChecked() && r_max_ > 0.0 && !current)
            restartReference();
        };
      },
      [this](const QString& why) { state_.error(QStringLiteral("pencil plot: %1").arg(why)); });
}

void PencilPlotDock::stopReference() {
  for (auto& r : ref_threads_) r.stop->store(true);
  ++ref_runs_;  // passes of stopped runs arriving later are ignored
  ref_.reset();
  ref_photons_ = 0;
  ref_device_.clear();
  ref_active_ = false;
  status_->setText(tr("reference stopped"));
}

void PencilPlotDock::restartReference() {
  stopReference();
  // Threads that were stopped earlier have ended (or end within ~0.1 s); joining those that are
  // still winding down would block the interface, so they are joined later.
  std::erase_if(ref_threads_, [](RefRun& r) {
    if (!r.thread.joinable()) return true;
    if (!*r.done) return false;
    r.thread.join();
    return true;
  });
  if (!reference_->isChecked() || !(r_max_ > 0.0)) return;
  const Medium medium = solo().empty() ? state_.medium() : state_.mediumFor(solo());
  analysis::PencilReferenceOptions o;
  o.r_max = r_max_;
  o.bins = 100;
  o.photons = static_cast<uint64_t>(photons_->value());
  o.first_pass = std::min<uint64_t>(16'384, o.photons);
  o.seed = 1;
  o.device = device_->currentData().toString().toStdString();
  o.theta = theta_->value() * std::numbers::pi / 180.0;
  ref_theta_ = theta_->value();
  // Leave a core to the interface and the model curves.
  o.threads = std::max(1, static_cast<int>(std::thread::hardware_concurrency()) - 1);
  ref_r_max_ = r_max_;
  ref_medium_ = medium;
  ref_budget_ = o.photons;
  ref_active_ = true;
  const int run = ref_runs_;
  RefRun r{{}, std::make_shared<std::atomic<bool>>(false), std::make_shared<std::atomic<bool>>(false)};
  auto stop = r.stop;
  auto done = r.done;
  status_->setText(tr("reference: starting"));
  // The thread posts to `this`; the destructor stops and joins every thread before the dock goes.
  r.thread = std::thread([this, medium, o, run, stop, done] {
    try {
      analysis::tracePencilReference(
          medium, Channel::Luminance, o,
          [&](const analysis::PencilReferencePass& p) {
            if (stop->load()) return;
            QMetaObject::invokeMethod(
                this,
                [this, p, run] {
                  if (run != ref_runs_) return;
                  ref_ = p;
                  ref_photons_ = p.photons;
                  ref_device_ = p.device;
                  status_->setText(tr("reference: %1 photons/channel on %2%3")
                                       .arg(static_cast<double>(p.photons), 0, 'g', 3)
                                       .arg(q(p.device))
                                       .arg(p.last ? tr(" (done)") : QString()));
                  redraw();
                  emit referenceUpdated();
                },
                Qt::QueuedConnection);
          },
          stop.get());
    } catch (const std::exception& e) {
      const QString why = q(e.what());
      QMetaObject::invokeMethod(
          this,
          [this, why, run] {
            if (run != ref_runs_) return;
            status_->setText(tr("no reference"));
            state_.warning(QStringLiteral("pencil plot: %1").arg(why));
          },
          Qt::QueuedConnection);
    }
    done->store(true);
  });
  ref_threads_.push_back(std::move(r));
}

std::vector<Curve> PencilPlotDock::referenceCurves() const {
  std::vector<Curve> out;
  if (!ref_ || ref_r_max_ != r_max_) return out;
  const auto& res = ref_->results;
  const auto orders = analysis::scatteringSelection(scattering_->currentData().toString().toStdString());
  for (Channel ch : channels())
    for (const auto& order : orders)
      out.push_back(analysis::pencilReferenceCurve({&res[0], &res[1], &res[2]}, ch,
                                                   timesR_->isChecked(), order));
  return out;
}

void PencilPlotDock::redraw() {
  std::vector<Curve> shown = curves_;
  if (reference_->isChecked())
    for (auto& c : referenceCurves()) shown.push_back(std::move(c));
  plot::PlotOptions po;
  po.y_scale = static_cast<plot::YScale>(yScale_->currentData().toInt());
  po.times_r = timesR_->isChecked();
  const std::string s = solo();
  toMillimetres(shown, (s.empty() ? state_.medium() : state_.mediumFor(s)).scale, po.times_r);
  po.length_unit = "mm";
  QChart* old = view_->chart();
  auto chart = plot::makeProfileChart(shown, po);
  legend_->setChart(chart.get());  // before the view lays the chart out: no room for its legend
  QChart* c = chart.get();
  connect(c, &QChart::plotAreaChanged, c, [c] { plot::fitLogAxisLabels(*c); }, Qt::QueuedConnection);
  view_->setChart(chart.release());
  delete old;
  // Lay the new chart out now and fit its labels before it is first painted (the reference's
  // progress redraws the chart: a fit one event later would flash elided labels each time).
  if (QGraphicsLayout* l = c->layout()) l->activate();
  plot::fitLogAxisLabels(*c);
}

}  // namespace translucent::explorer
