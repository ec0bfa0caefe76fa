// SPDX-License-Identifier: GPL-3.0-or-later
// The pencil-plot dock (seed 3.6.3, figure 3.8): the radial profile R(r) of every plotted model on
// a semi-infinite slab lit by a pencil beam, drawn by plot::makeProfileChart (the CLI's PNG/SVG
// code), plus the path-traced reference with ±1 standard-error bands.
//
//   - Model curves are computed on the material worker (MaterialWorker: registered models with
//     analysis::profileCurves, .bssrdf files on the GPU with gpu::bssrdfCurves), each model with
//     its own medium (ExplorerState::mediumFor); a newer request makes older queued ones void.
//   - The reference (analysis::tracePencilReference) runs on its own thread in passes of doubling
//     photon counts, redrawn after each pass, up to the photon budget; a material change stops it
//     and starts it again. All three channels are traced, so channel, solo and r·R(r) switches
//     redraw without restarting it. It uses the shared medium, or the solo model's.
//   - Options: y axis linear, log or square root; r·R(r); red, green, blue or luminance; "solo"
//     one model to show its three channels; the reference on/off and its photon budget; the
//     beam's incidence θL (the reference is traced at it, a directional model is drawn as its
//     kernel's azimuthal average there, and radial models' curves say "normal incidence").
#pragma once

#include <QtCore/QElapsedTimer>
#include <QtWidgets/QDockWidget>

#include <atomic>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "translucent/analysis/pencil_reference.h"
#include "translucent/bssrdf/profile_curves.h"

class QChart;
class QChartView;
class QCheckBox;
class QComboBox;
class QDoubleSpinBox;
class QLabel;

namespace translucent::plot {
class ChartLegend;
}

namespace translucent::explorer {

class ExplorerState;
class MaterialWorker;

class PencilPlotDock : public QDockWidget {
  Q_OBJECT

 public:
  explicit PencilPlotDock(ExplorerState& state, QWidget* parent = nullptr);
  ~PencilPlotDock() override;

  QChart* chart() const;
  // What is drawn: the model curves of the last completed request and the reference so far.
  const std::vector<analysis::Curve>& modelCurves() const { return curves_; }
  std::vector<analysis::Curve> referenceCurves() const;
  uint64_t referencePhotons() const { return ref_photons_; }  // per channel, pooled so far
  // What traced the reference shown: "cpu" or "gpu (<renderer>)" (empty before its first pass).
  const std::string& referenceDevice() const { return ref_device_; }
  // Generation of the reference: grows at every stop and restart (a material change).
  int referenceRuns() const { return ref_runs_; }
  double radiusMax() const { return r_max_; }
  // The beam's polar angle θL [degrees] (the "incidence" spin box).
  double incidence() const;
  // Milliseconds from the last material change to the redraw with its model curves.
  double lastModelLatencyMs() const { return latency_ms_; }

 signals:
  void modelCurvesUpdated();     // after a redraw with new model curves
  void referenceUpdated();       // after a redraw with a new reference pass

 private:
  void requestModels();          // material or model list changed: recompute curves
  void redraw();
  void restartReference();
  void stopReference();
  std::vector<analysis::Channel> channels() const;
  std::string solo() const;

  ExplorerState& state_;
  MaterialWorker& worker_;
  QChartView* view_;
  plot::ChartLegend* legend_;  // wraps into columns under the chart
  QComboBox* yScale_;
  QComboBox* channel_;
  QComboBox* solo_;
  QCheckBox* timesR_;
  QCheckBox* reference_;
  QComboBox* device_;  // "reference_device": auto, cpu, gpu
  QDoubleSpinBox* photons_;
  QDoubleSpinBox* theta_;  // "incidence" [degrees]
  QComboBox* scattering_;  // "scattering": all, single, multiple, split (seed Eq. 2.13)
  QLabel* status_;

  std::vector<analysis::Curve> curves_;  // model curves (all channels, R(r))
  double r_max_ = 0.0;
  std::shared_ptr<std::atomic<uint64_t>> generation_;  // latest model request
  QElapsedTimer since_change_;
  double latency_ms_ = 0.0;

  // The reference: its thread, stop flag, latest pooled results (GUI thread copy).
  struct RefRun {
    std::thread thread;
    std::shared_ptr<std::atomic<bool>> stop;
    std::shared_ptr<std::atomic<bool>> done;  // the thread function returned
  };
  std::vector<RefRun> ref_threads_;
  std::optional<analysis::PencilReferencePass> ref_;
  uint64_t ref_photons_ = 0;
  std::string ref_device_;
  int ref_runs_ = 0;
  double ref_r_max_ = 0.0;
  Medium ref_medium_;
  double ref_theta_ = 0.0;  // incidence of the reference shown [degrees]
  uint64_t ref_budget_ = 0;
  bool ref_active_ = false;  // a run for (ref_medium_, ref_r_max_) is going or finished
};

}  // namespace translucent::explorer
