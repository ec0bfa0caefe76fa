// SPDX-License-Identifier: GPL-3.0-or-later
// The viewport's renderer: one thread that owns a headless OpenGL 4.5 core context (gpu::Context,
// EGL, the same path as `translucent render`) and the technique, and turns render requests into
// linear frames (techniques::Frame) for the viewport to show.
//
// Why a thread with its own context, and not the QOpenGLWidget's context on the GUI thread:
// under `xvfb-run` on llvmpipe Qt does give a 4.5 core context (GLX by default, EGL with
// QT_XCB_GL_INTEGRATION=xcb_egl) and libepoxy calls work in it; we checked both. But a technique's
// prepare() samples the point cloud or casts ambient-occlusion rays for seconds, and llvmpipe
// renders a full-resolution frame in tens to hundreds of milliseconds, so on the GUI thread the
// window would freeze. Here the GUI thread never waits: it posts the newest request (older
// pending ones are dropped) and shows whichever frame arrives; the widget's own 4.5 context only
// uploads and tone maps the frame (gpu::FrameDisplay). Frames are exactly those the CLI renders
// for the same scene (same context type, same calls), which the round-trip test relies on.
//
// Last good state: a request whose prepare() fails (a broken mesh, a failing shader, a missing
// environment map) is reported through prepareFailed() and the previous technique and scene are
// restored and kept rendering.
#pragma once

#include <QtCore/QMetaType>
#include <QtCore/QObject>
#include <QtCore/QString>

#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>

#include "translucent/scene/scene.h"
#include "translucent/techniques/technique.h"

namespace translucent::explorer {

struct RenderRequest {
  scene::Scene scene;         // technique, settings, camera, lights, material: everything
  int width = 0, height = 0;  // image size [pixels] (the scene camera's size is not used)
  bool continuous = false;    // keep rendering frames (random lighting, benchmarks)
  bool converge = false;      // finish progressive work in one frame (FrameRequest::converge)
  bool views = false;         // also the technique's inspection views (FrameRequest::views)
  // A fresh technique instance prepared for this request: its shaders are read from disk and
  // compiled again (the explorer's "Reload shaders"; empirical seed appendix A). A GLSL error is
  // a prepareFailed with its message, and the last good state goes on rendering.
  bool reload = false;
  std::uint64_t id = 0;       // assigned by RenderWorker::request
};

struct RenderedFrame {
  techniques::Frame frame;
  std::uint64_t request_id = 0;
  std::string technique;
  // Of frame.rgb (techniques::radianceConvention), for comparisons with a reference.
  bssrdf::ExitConvention convention = bssrdf::ExitConvention::Jensen;
  double render_ms = 0.0;   // wall time of render() (GPU work and read-back)
  double prepare_ms = 0.0;  // wall time of prepare() before it, 0 when none was needed
  std::size_t faces = 0, vertices = 0;
  bool continuous = false;
  // The placed mesh's bounding box and the camera of the frame (the viewport's overlay).
  glm::dvec3 bounds_lo{0.0}, bounds_hi{0.0};
  reference::Camera camera;
};

class RenderWorker : public QObject {
  Q_OBJECT

 public:
  explicit RenderWorker(QObject* parent = nullptr);
  ~RenderWorker() override;  // stops the thread (after the frame in progress)

  // Starts the thread (creates the context); connect the signals first.
  void start();

  // Ends the thread after the frame in hand (the destructor then only joins).
  void requestStop();

  // Replaces any request not started yet; returns its id.
  std::uint64_t request(RenderRequest request);
  // The scene the technique was last prepared with successfully (empty before the first).
  std::optional<scene::Scene> lastGoodScene() const;

 signals:
  // Queued to the GUI thread.
  void contextReady(const QString& description);  // "llvmpipe ... (4.5 (Core Profile) Mesa ...)"
  void contextFailed(const QString& message);     // no 4.5 core context: nothing will render
  void frameReady(std::shared_ptr<const translucent::explorer::RenderedFrame> frame);
  // prepare() of request `id` threw: `message` says why; `restored` is the scene now rendering.
  void prepareFailed(quint64 id, const QString& message,
                     std::shared_ptr<const translucent::scene::Scene> restored);

 private:
  void run(std::stop_token stop);

  mutable std::mutex mutex_;
  std::condition_variable_any wake_;
  std::optional<RenderRequest> pending_;
  std::optional<scene::Scene> good_scene_;
  std::uint64_t next_id_ = 1;
  std::jthread thread_;
};

// Lets a worker go without waiting for it: it is disconnected and asked to stop, and its thread
// ends after the frame or prepare() in hand (a point cloud takes seconds on llvmpipe, a minute on
// a loaded machine), releasing its context and technique; the object itself stays, a child of
// the application, joined when the application is destroyed. For a dock that must close
// promptly (docks are destroyed with the window, so few ever retire).
void retireInBackground(std::unique_ptr<RenderWorker> worker);

}  // namespace translucent::explorer

Q_DECLARE_METATYPE(std::shared_ptr<const translucent::explorer::RenderedFrame>)
Q_DECLARE_METATYPE(std::shared_ptr<const translucent::scene::Scene>)
