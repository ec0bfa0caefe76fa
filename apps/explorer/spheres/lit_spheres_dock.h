// SPDX-License-Identifier: GPL-3.0-or-later
// The lit spheres dock (seed 3.6.2, figure 3.9): the sphere of the current material under a
// directional light, path traced (the volumetric reference, seed 3.2) and as the current BSSRDF
// model predicts it (the model integrated over the sphere's surface, seed 3.5), in tabs or side by
// side, with the per-pixel relative difference of the two and its RMSE split into Monte Carlo
// noise and a systematic part (analysis/mc_compare.h): the point of the widget is to see where
// and by how much the model departs from the reference.
//
// The scene is the CLI's `translucent pathtrace sphere` / `integrate sphere` default (radius 1
// scene unit, light from (1,1,1) with irradiance 1, orthographic view along -z, seed 1) at a small
// resolution, the light's direction adjustable as θL (from the view axis) and φL (about it,
// from +x; the default 54.7°, 45° is (1,1,1)), with the explorer's material: the model's medium (ExplorerState::mediumFor, which is
// the shared medium unless the model has its own), scale included. Both images are computed on
// background threads by doubling passes (reference/progressive.h) and refreshed after each pass;
// a material change cancels the runs whose inputs changed and starts them again. Exposure, gamma
// and the displayed quantity (radiant exitance B or the diffusion radiance Ft B / π) only change
// the display. The budgets (photons per channel for the path tracer, samples per pixel for the
// integration; the seed notes the latter needs far more, 3.6.2) and the resolution restart.
//
// The integration takes every model: registered ones, tabulated profiles (.csv) and .bssrdf files
// (a radial file tabulated on the GPU for the medium and integrated on the CPU; a directional one
// integrated on the GPU with the light's direction, uniform sampling). A material the runs cannot
// use (an invalid medium, an unknown model, a broken file) goes to the console as an error and
// the last images stay.
#pragma once

#include <QtGui/QImage>
#include <QtWidgets/QDockWidget>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "translucent/analysis/mc_compare.h"
#include "spheres/sphere_run.h"

class QCheckBox;
class QComboBox;
class QDoubleSpinBox;
class QLabel;
class QProgressBar;
class QSlider;
class QSpinBox;
class QStackedWidget;
class QTabWidget;
class QTimer;

namespace translucent::explorer {

class ExplorerState;
class PixelImageView;

class LitSpheresDock : public QDockWidget {
  Q_OBJECT

 public:
  enum class Pane { PathTraced = 0, Integrated = 1 };
  Q_ENUM(Pane)
  enum class Quantity { Exitance, Radiance };

  explicit LitSpheresDock(ExplorerState& state, QWidget* parent = nullptr);
  ~LitSpheresDock() override;  // stops both runs and joins their threads

  // Display (no recomputation). Exposure in stops, gamma > 0.
  void setExposure(double stops);
  void setGamma(double gamma);
  void setQuantity(Quantity quantity);
  void setSideBySide(bool sideBySide);
  double exposure() const { return exposure_; }
  double gamma() const { return gamma_; }
  bool sideBySide() const;

  // Computation (each restarts what it affects at once; material changes restart after
  // kRestartDelayMs, so that a burst of them, a slider being dragged, starts one run).
  void setResolution(int pixels);             // square images, 8..1024
  // The light's direction: polar angle θL from the view axis (+z) in [0, 180] and azimuth φL
  // about it from +x, in degrees; l = (sin θL cos φL, sin θL sin φL, cos θL).
  void setLightAngles(double thetaDeg, double phiDeg);
  double lightTheta() const { return light_theta_; }
  double lightPhi() const { return light_phi_; }
  void setPhotonBudget(uint64_t photons);     // path tracer: photons per channel, all passes
  void setSampleBudget(uint64_t samples);     // integration: samples per pixel, all passes
  // Where the path tracer runs: "cpu", "gpu" or "auto" (sphere_run.h). A device that cannot
  // be opened is an error on the console; the previous image stays.
  void setTracerDevice(const std::string& device);
  const std::string& tracerDevice() const { return tracer_device_; }
  // Which of the path tracer's light it shows (the seed's "multi + single scattering"
  // selector): "all", "single" or "multiple" scattering (seed Eq. 2.13). The diffusion models
  // describe multiple scattering only, so "multiple" compares them with what they model.
  void setTracerLight(const std::string& light);
  const std::string& tracerLight() const { return tracer_light_; }
  int resolution() const { return resolution_; }
  uint64_t photonBudget() const { return photon_budget_; }
  uint64_t sampleBudget() const { return sample_budget_; }

  // What is shown, for the status lines and for tests.
  struct PaneStatus {
    int generation = 0;    // runs started for this pane (a restart increments it)
    int passes = 0;        // complete passes of the current run shown
    uint64_t done = 0;     // photons per channel or samples per pixel in the image shown
    uint64_t budget = 0;
    double seconds = 0.0;  // current run: time to the image shown
    std::string device;    // what traced the image shown (the path tracer's pane)
    bool running = false;
  };
  PaneStatus status(Pane pane) const;
  QImage image(Pane pane) const;  // the tone-mapped image shown; null before the first pass
  QImage differenceImage() const;  // per-pixel relative difference, null until both exist
  // Linear RGB of the displayed quantity (row by row from the top); empty before the first pass.
  std::vector<float> linearImage(Pane pane) const;
  // Integration against path tracing, displayed quantity; nullopt until both images exist.
  const std::optional<analysis::McComparison>& comparison() const { return comparison_; }
  // Range of the difference colour map: ± this relative difference saturates.
  static constexpr float kDifferenceRange = 0.5f;
  static constexpr int kRestartDelayMs = 40;

 signals:
  void passCompleted(translucent::explorer::LitSpheresDock::Pane pane, int pass);
  void runStarted(translucent::explorer::LitSpheresDock::Pane pane);
  void runFinished(translucent::explorer::LitSpheresDock::Pane pane);
  void displayChanged();  // any shown image was redrawn

 private:
  struct PaneData;
  void buildUi();
  void restartForMaterial();  // restarts the runs whose inputs changed
  // Starts (or restarts) a pane's run from the current state if its inputs changed (or `force`).
  void restart(Pane pane, bool force);
  void startRun(Pane pane, SphereRunConfig config, std::string key);
  void restartPlugin(SphereRunConfig config, const std::string& model, bool force);
  // Starts a run for `key` unless it is the key of the images shown (and not `force`d).
  void startIfChanged(Pane pane, SphereRunConfig config, std::string key, const std::string& model,
                      bool force);
  void stopRun(Pane pane);
  void onPass(Pane pane, int generation, std::shared_ptr<const SphereSnapshot> snapshot);
  void onProgress(Pane pane, int generation, double fraction);
  void onFinished(Pane pane, int generation, bool stopped, const QString& error);
  void redraw();
  void updateStatus(Pane pane);
  void updateComparison();
  reference::SphereScene sphereScene() const;
  PaneData& pane(Pane p);
  const PaneData& pane(Pane p) const;

  ExplorerState& state_;
  double exposure_ = 0.0, gamma_ = 2.2;
  Quantity quantity_ = Quantity::Exitance;
  int resolution_ = 128;
  double light_theta_ = 54.735610317245346;  // acos(1/√3): the CLI's (1,1,1)
  double light_phi_ = 45.0;
  uint64_t plugin_ticket_ = 0;  // latest .bssrdf preparation posted to the material worker
  // From the angles; exactly the CLI's (1,1,1) until they are changed.
  glm::dvec3 light_direction_{1.0, 1.0, 1.0};
  uint64_t photon_budget_ = uint64_t{1} << 20;
  uint64_t sample_budget_ = 64;
  std::string tracer_device_ = "auto";
  std::string tracer_light_ = "all";  // setTracerLight
  std::unique_ptr<PaneData> panes_[2];
  // Runs asked to stop, kept until their thread says it has finished (then joined at once).
  struct Retiring {
    Pane pane;
    int generation;
    std::unique_ptr<SphereRun> run;
  };
  std::vector<Retiring> retiring_;
  std::optional<analysis::McComparison> comparison_;
  QTimer* restart_timer_ = nullptr;  // coalesces bursts of material changes (a slider drag)
  QImage difference_image_;

  // Widgets.
  QStackedWidget* views_ = nullptr;
  QTabWidget* tabs_ = nullptr;
  QWidget* side_ = nullptr;
  QWidget* difference_pane_ = nullptr;
  PixelImageView* difference_view_ = nullptr;
  QLabel* difference_label_ = nullptr;
  QLabel* summary_label_ = nullptr;
  QCheckBox* side_by_side_ = nullptr;
  QComboBox* quantity_box_ = nullptr;
  QSlider* exposure_slider_ = nullptr;
  QSlider* gamma_slider_ = nullptr;
  QLabel* exposure_value_ = nullptr;
  QLabel* gamma_value_ = nullptr;
  QSpinBox* resolution_box_ = nullptr;
  QDoubleSpinBox* light_theta_box_ = nullptr;
  QDoubleSpinBox* light_phi_box_ = nullptr;
  QSpinBox* photons_box_ = nullptr;
  QSpinBox* samples_box_ = nullptr;
  QComboBox* device_box_ = nullptr;
  QComboBox* light_box_ = nullptr;  // "tracer_light": all, single, multiple
};

}  // namespace translucent::explorer
