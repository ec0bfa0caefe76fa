// SPDX-License-Identifier: GPL-3.0-or-later
// The viewport dock (seed 3.6.4, the point cloud widget): the picture (ViewportWidget), and beside
// it the technique selector with the technique's own settings as generated widgets, mesh
// loading (dialog and drag and drop), the lighting mode, camera (field of view, clip planes,
// auto-rotate), the deformation's time (mesh.deform: a time field and play, which advances it in
// real time), render scale, exposure and gamma, and the GPU time of every pass.
//
// Rendering runs on a RenderWorker thread. While the view changes (mouse, material, settings)
// frames are requested at half resolution; 300 ms after the last change one frame is requested at
// full resolution (seed 3.6.4). Progressive techniques (occluded IBL) and the empirical
// technique's random lighting keep rendering frames.
#pragma once

#include <QtCore/QElapsedTimer>
#include <QtCore/QTimer>
#include <QtWidgets/QDockWidget>

#include <functional>
#include <memory>

#include "app/render_worker.h"

class QCheckBox;
class QComboBox;
class QSlider;
class QDoubleSpinBox;
class QLabel;
class QVBoxLayout;

namespace translucent::explorer {

class ExplorerState;
class ParameterForm;
class ViewportWidget;

// Frame-rate statistics over the frames since the last reset (fps = 1000 / frame time, where the
// frame time is the render thread's wall time for the frame, prepare included).
struct FrameStats {
  int frames = 0;
  double current = 0.0, min = 0.0, max = 0.0, sum_ms = 0.0;
  void add(double frame_ms);
  double average() const { return frames > 0 && sum_ms > 0.0 ? 1000.0 * frames / sum_ms : 0.0; }
};

class ViewportDock : public QDockWidget {
  Q_OBJECT

 public:
  explicit ViewportDock(ExplorerState& state, QWidget* parent = nullptr);
  ~ViewportDock() override;

  ViewportWidget* view() const { return view_; }
  // The dock with the technique, scene, camera and display controls (a child of the same parent;
  // the main window places it).
  QDockWidget* controlsDock() const { return controls_; }
  // The picture's size in widget pixels.
  QSize pictureSize() const;
  // The newest frame shown, and the newest full-resolution one (nullptr before the first).
  std::shared_ptr<const RenderedFrame> lastFrame() const { return last_; }
  std::shared_ptr<const RenderedFrame> lastFullFrame() const { return last_full_; }
  // Full-resolution image size: the picture's size in device pixels times the render scale.
  QSize renderSize() const;
  void setRenderScale(double scale);  // 1, 0.5, 0.25
  // The same, and software renderers no longer lower it on start (--render-scale).
  void fixRenderScale(double scale);
  const FrameStats& stats() const { return stats_; }
  // Number of points of the current technique (its "points" setting), -1 when it has none.
  int pointCount() const;
  // Whether the render thread has a 4.5 core context (false while starting or when it failed).
  bool rendererReady() const { return renderer_ok_; }

  // Loads a mesh into the scene (absolute path); a broken file is reported on the console and
  // the last good mesh stays.
  void loadMesh(const QString& path);
  // Renders continuously at full resolution (benchmarks): every frame is a new request.
  void setContinuous(bool on);
  // Asks for a full-resolution frame now (no half-resolution frame first).
  void requestFullFrame();
  // The "Reload shaders" button: a fresh technique instance reads and compiles its shaders from
  // disk (a GLSL error goes to the console and the previous shaders stay).
  void reloadShaders();
  // The explorer seed's file choices (issue 14 §7): the filtered directional light's texture
  // ("checker" or an image file) and the environment map of the IBL modes; each switches the
  // lighting to the mode that uses it. A file the technique cannot read is an error on the
  // console and the last good state goes on rendering.
  void setFilterTexture(const QString& file);
  void setEnvironmentMap(const QString& file);
  // The zoom slider: the camera's distance to its look-at point, in [0.05, 50] scene units.
  void setCameraDistance(double distance);
  // Ask for the technique's inspection views in full-resolution frames (the views dock's
  // visibility); turning it on requests a full frame.
  void setViewsWanted(bool on);

 signals:
  void frameShown(std::shared_ptr<const translucent::explorer::RenderedFrame> frame, bool full);
  void statsChanged();

 protected:
  void dragEnterEvent(QDragEnterEvent* e) override;
  void dropEvent(QDropEvent* e) override;

 private:
  void buildControls(QWidget* panel);
  void rebuildSettings();
  void syncControls();
  void onSceneChanged();
  void request(bool full, bool reload = false);
  void onFrame(std::shared_ptr<const RenderedFrame> frame);
  void onPrepareFailed(quint64 id, const QString& message,
                       std::shared_ptr<const scene::Scene> restored);
  void setLightingMode(int mode);
  int lightingMode() const;

  ExplorerState& state_;
  ViewportWidget* view_ = nullptr;
  QDockWidget* controls_ = nullptr;
  RenderWorker* worker_ = nullptr;
  QTimer rest_timer_, rotate_timer_, play_timer_;
  QElapsedTimer rotate_clock_, play_clock_;
  double render_scale_ = 1.0;
  bool scale_fixed_ = false;
  bool continuous_ = false;
  bool views_ = false;  // the views dock is visible: full frames carry Frame::views
  bool renderer_ok_ = false;
  std::uint64_t last_request_ = 0, last_full_request_ = 0;
  std::shared_ptr<const RenderedFrame> last_, last_full_;
  FrameStats stats_;
  std::string stats_technique_;

  QComboBox* technique_ = nullptr;
  QLabel* technique_help_ = nullptr;
  QVBoxLayout* settings_box_ = nullptr;
  ParameterForm* settings_ = nullptr;
  std::string settings_for_;
  QLabel* mesh_label_ = nullptr;
  QComboBox* lighting_ = nullptr;
  QDoubleSpinBox* fov_ = nullptr;
  QSlider* zoom_ = nullptr;  // camera distance to the look-at point, logarithmic
  QString filter_texture_ = QStringLiteral("checker");  // the filtered light's texture
  QString environment_map_;                             // IBL's map (empty: the default one)
  QDoubleSpinBox* near_ = nullptr;
  QDoubleSpinBox* far_ = nullptr;
  QCheckBox* rotate_ = nullptr;
  QDoubleSpinBox* time_ = nullptr;
  QCheckBox* play_ = nullptr;
  QComboBox* scale_ = nullptr;
  QDoubleSpinBox* exposure_ = nullptr;
  QDoubleSpinBox* gamma_ = nullptr;
  QComboBox* tonemap_ = nullptr;
  QDoubleSpinBox* key_ = nullptr;
  QLabel* passes_ = nullptr;
};

// The environment map for the IBL modes: the first .exr/.hdr of Blender's studio lights
// (/usr/share/blender/datafiles/studiolights/world/) when present, else a built-in sky written
// once to the cache folder. Throws std::runtime_error when neither works.
std::string defaultEnvironmentMap();

}  // namespace translucent::explorer
