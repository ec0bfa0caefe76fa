// SPDX-License-Identifier: GPL-3.0-or-later
// The Compare dock: the viewport's technique against a reference of the same scene and camera,
// as `translucent compare` computes them (analysis/compare.h), at a small size and refined while
// the user watches: the technique's frame, the reference (the volumetric path tracer by default,
// or the scene's BSSRDF model integrated over the whole surface), the per-pixel relative
// difference (diverging colours) and the metrics of the pair (noise-aware relative RMSE, bias
// with its standard error, SSIM, ꟻLIP, |z| > 3), updated after each reference pass.
//
// Same resolution, nothing resampled: the scene is taken with its camera at the dock's size
// (width from the Size box, height from the scene camera's aspect), the technique is rendered at
// exactly that camera by a render thread of the dock's own (RenderWorker: the viewport's code,
// the frames the CLI renders, converged), and the reference is computed for that camera
// (compare_run.h). Metrics are over the interior pixels (analysis::compareMasks: silhouette
// pixels are left out), through analysis::compareImages, with the scene's exposure and gamma for
// SSIM and ꟻLIP; the reference's radiance is converted to the technique's radiance convention
// (Reference::radianceFor), as in the CLI's report.
//
// Quantities: L (the diffusion radiance Ft B / π, the reference's image of what the technique
// computes), the true cone-averaged radiance (physical reference only: what L should be), and
// the exitance B (techniques with an exitance layer).
//
// Nothing runs while the dock is hidden (it starts as a tab behind the lit spheres): hiding it
// stops the reference, showing it again catches up with the scene.
// Restarts: any scene change (material, light, camera, mesh; coalesced over kRestartDelayMs)
// restarts the reference when its inputs changed and asks for a new technique frame when the
// frame's inputs changed (a technique setting needs no new reference). A scene the reference
// cannot handle (a filtered light, an unreadable environment map, a .bssrdf model for the model
// reference, an open mesh)
// goes to the console; the last images stay, marked as of the previous scene.
#pragma once

#include <QtGui/QImage>
#include <QtWidgets/QDockWidget>

#include <cstdint>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "translucent/compare/compare.h"
#include "app/render_worker.h"
#include "compare/compare_run.h"

class QComboBox;
class QLabel;
class QProgressBar;
class QSpinBox;
class QTimer;

namespace translucent::explorer {

class ExplorerState;
class PixelImageView;

class CompareDock : public QDockWidget {
  Q_OBJECT

 public:
  enum class Quantity { Radiance, ConeRadiance, Exitance };

  explicit CompareDock(ExplorerState& state, QWidget* parent = nullptr);
  // Stops the reference run and joins it (a tenth of a second once its passes run, the current
  // setup step before: compare_run.h); the render thread is
  // retired in the background (retireInBackground: a technique prepare in progress, seconds on
  // llvmpipe, is not waited for).
  ~CompareDock() override;

  // Each restarts what it affects at once.
  void setReferenceKind(analysis::ReferenceKind kind);
  void setImageWidth(int pixels);           // 16..512; height from the scene camera's aspect
  void setPhotonBudget(uint64_t photons);   // physical: photons per channel, all passes
  void setSampleBudget(uint64_t samples);   // model: samples of the last (largest) pass
  // Physical reference from the camera method (camera_paths.h: the true radiance per pixel)
  // instead of the light method's photons; its budget in camera paths per pixel, all passes.
  void setCameraMethod(bool camera);
  void setPathBudget(uint64_t paths);
  bool cameraMethod() const { return camera_; }
  uint64_t pathBudget() const { return path_budget_; }
  // Display only.
  void setQuantity(Quantity quantity);
  analysis::ReferenceKind referenceKind() const { return kind_; }
  Quantity quantity() const { return quantity_; }
  int imageWidth() const { return width_; }
  int imageHeight() const;
  uint64_t photonBudget() const { return photon_budget_; }
  // Where the physical reference is traced: "auto", "cpu" or "gpu" (CompareRunConfig::device).
  void setTracerDevice(const std::string& device);
  const std::string& tracerDevice() const { return tracer_device_; }
  uint64_t sampleBudget() const { return sample_budget_; }

  struct Status {
    int generation = 0;     // reference runs started (a restart increments it)
    int passes = 0;         // complete passes of the current run shown
    uint64_t count = 0;     // photons per channel / samples of the reference shown
    uint64_t computed = 0;  // all of them computed by the current run so far
    uint64_t budget = 0;
    double seconds = 0.0;   // current run: time to the reference shown
    bool running = false;
    bool technique = false;  // a technique frame of the current scene is there
  };
  Status status() const;

  // The pair compared and its metrics, as shown; nullopt until a technique frame and a reference
  // pass of the same scene are both there.
  const std::optional<analysis::Metrics>& metrics() const { return metrics_; }
  const analysis::CompareImage& comparedTest() const { return test_; }
  const analysis::CompareImage& comparedReference() const { return reference_; }
  const std::vector<uint8_t>& comparedMask() const { return mask_; }
  // The display options the metrics were taken with (exposure, gamma; the mask is comparedMask).
  analysis::MetricOptions displayOptions() const;
  QString metricsText() const;
  // The technique's frame shown (nullptr before the first).
  std::shared_ptr<const RenderedFrame> techniqueFrame() const { return frame_; }
  QImage techniqueImage() const { return technique_image_; }
  QImage referenceImage() const { return reference_image_; }
  QImage differenceImage() const { return difference_image_; }

  // ± this relative difference saturates the colour map.
  static constexpr float kDifferenceRange = 0.5f;
  static constexpr int kRestartDelayMs = 40;

 signals:
  void passCompleted(int pass);
  void runStarted();
  void runFinished();
  void techniqueFrameReceived();
  void comparisonChanged();  // metrics and difference recomputed (or cleared)

 private:
  void buildUi();
  void restart(bool force);
  scene::Scene compareScene() const;
  void startRun(const scene::Scene& scene, std::string key);
  void stopRun();
  void requestFrame(const scene::Scene& scene, std::string frameKey, std::string sceneKey);
  void onPass(int generation, std::shared_ptr<const CompareSnapshot> snapshot);
  void onProgress(int generation, double fraction);
  void onFinished(int generation, bool stopped, const QString& error);
  void onFrame(std::shared_ptr<const RenderedFrame> frame);
  void onPrepareFailed(quint64 id, const QString& message);
  void updateComparison();
  void redraw();
  void updateStatus();

  ExplorerState& state_;
  bool visible_ = false;  // last visibilityChanged
  bool started_ = false;  // first shown: the render thread runs and the reference follows
  analysis::ReferenceKind kind_ = analysis::ReferenceKind::Physical;
  Quantity quantity_ = Quantity::Radiance;
  int width_ = 64;
  uint64_t photon_budget_ = uint64_t{1} << 22;
  std::string tracer_device_ = "auto";
  uint64_t sample_budget_ = 160000;
  bool camera_ = false;          // the physical reference from the camera method
  uint64_t path_budget_ = 64;    // its camera paths per pixel and channel, all passes

  // Reference.
  std::unique_ptr<CompareRun> run_;
  int generation_ = 0;
  std::string run_key_;        // the run's inputs
  std::string run_scene_key_;  // the scene of the run (technique and display aside)
  bool stale_ = false;         // the last restart failed: the reference is of a previous scene
  QString last_error_;         // of the last failed restart (not repeated while it persists)
  std::shared_ptr<const CompareSnapshot> snapshot_;
  int snapshot_generation_ = 0;
  std::string snapshot_scene_key_;
  double fraction_ = 0.0;
  struct Retiring {
    int generation;
    std::unique_ptr<CompareRun> run;
  };
  std::vector<Retiring> retiring_;

  // Technique.
  std::unique_ptr<RenderWorker> worker_;
  uint64_t frame_request_ = 0;
  std::string frame_key_;            // inputs of the requested frame
  std::string frame_request_scene_;  // scene key of the requested frame
  std::set<uint64_t> failed_requests_;
  std::shared_ptr<const RenderedFrame> frame_;
  std::string frame_scene_key_;      // scene key of frame_
  std::string shown_frame_key_;      // frame key of frame_ (!= frame_key_: a newer one is coming)
  QString technique_error_;
  QString last_technique_error_;  // reported once while it persists

  // What is shown.
  std::optional<analysis::Metrics> metrics_;
  analysis::CompareImage test_, reference_;
  std::vector<uint8_t> mask_;
  QImage technique_image_, reference_image_, difference_image_;

  QTimer* restart_timer_ = nullptr;
  QComboBox* kind_box_ = nullptr;
  QComboBox* quantity_box_ = nullptr;
  QSpinBox* width_box_ = nullptr;
  QSpinBox* photons_box_ = nullptr;
  QSpinBox* samples_box_ = nullptr;
  QSpinBox* paths_box_ = nullptr;  // the camera method's paths per pixel
  QComboBox* device_box_ = nullptr;
  void updateBudgetBoxes();  // which budget box the reference kind and method show
  void dropReference();      // after a change of kind or method: restart without the old images
  PixelImageView* technique_view_ = nullptr;
  PixelImageView* reference_view_ = nullptr;
  PixelImageView* difference_view_ = nullptr;
  QLabel* technique_label_ = nullptr;
  QLabel* reference_label_ = nullptr;
  QLabel* difference_label_ = nullptr;
  QLabel* metrics_label_ = nullptr;
  QProgressBar* progress_ = nullptr;
};

}  // namespace translucent::explorer
