// SPDX-License-Identifier: GPL-3.0-or-later
// The material docks' worker thread: one thread that runs jobs in order, owns the headless GL
// context (gpu::Context, EGL) and the loaded `.bssrdf` models (gpu::BssrdfEvaluator), and computes
// the pencil plot's model curves. `.bssrdf` models run on the GPU, so everything that touches them
// happens here: the GUI thread's GL context belongs to the viewport (Qt), and an EGL context made
// current there would take its place.
//
// One worker per ExplorerState (MaterialWorker::of creates it as the state's child on first use),
// shared by the parameters dock (loading, reloading, parameter values, (Rd, ℓd) inversion) and the
// pencil-plot dock (curves). A job returns a continuation that runs on the GUI thread, and only
// while the object that asked for it (`owner`) still exists.
#pragma once

#include <QtCore/QObject>
#include <QtCore/QPointer>

#include <condition_variable>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "translucent/gpu/bssrdf_kernels.h"

namespace translucent::gpu {
class Context;
}

namespace translucent::explorer {

class ExplorerState;

// What jobs see on the worker thread: the GL context (made when first needed) and the models.
class MaterialGl {
 public:
  MaterialGl();
  ~MaterialGl();
  // The loaded model for `path`, nullptr when it is not loaded.
  gpu::BssrdfEvaluator* find(const std::string& path);
  // Loads (or returns the loaded) model; throws ParameterError with a `file.bssrdf:LINE` message
  // (or saying that no 4.5 context could be made).
  gpu::BssrdfEvaluator& load(const std::string& path);
  // Re-reads a loaded model; on failure the previous version stays and ParameterError says why.
  void reload(const std::string& path);
  void unload(const std::string& path);

 private:
  void ensureContext();
  std::unique_ptr<gpu::Context> context_;
  std::map<std::string, std::unique_ptr<gpu::BssrdfEvaluator>> models_;
};

class MaterialWorker : public QObject {
  Q_OBJECT

 public:
  // The state's worker (created as its child on first use).
  static MaterialWorker& of(ExplorerState& state);
  ~MaterialWorker() override;

  using Continuation = std::function<void()>;
  using Job = std::function<Continuation(MaterialGl&)>;
  // Queues `job`; its continuation (may be empty) runs on the GUI thread if `owner` still exists.
  // Exceptions from the job are caught: `on_error(message)` runs on the GUI thread instead.
  void post(QObject* owner, Job job, std::function<void(const QString&)> on_error = {});

 signals:
  // A .bssrdf model changed on the worker (parameter value, reload): curves must be redrawn.
  void bssrdfChanged();

 private:
  explicit MaterialWorker(QObject* parent);
  void loop();

  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<std::function<void(MaterialGl&)>> jobs_;
  bool quit_ = false;
  std::thread thread_;
};

// Path of a .bssrdf model as a model entry: a name ending in ".bssrdf" (any case).
bool isBssrdfPath(const std::string& entry);

}  // namespace translucent::explorer
