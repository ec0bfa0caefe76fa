// SPDX-License-Identifier: GPL-3.0-or-later
#include "material/material_worker.h"

#include <fmt/format.h>

#include <QtCore/QMetaObject>

#include <algorithm>

#include "translucent/bssrdf/bssrdf_file.h"
#include "core/explorer_state.h"
#include "translucent/gpu/context.h"
#include "translucent/gpu/program.h"

namespace translucent::explorer {

bool isBssrdfPath(const std::string& entry) { return bssrdf::hasBssrdfExtension(entry); }

MaterialGl::MaterialGl() = default;

MaterialGl::~MaterialGl() {
  models_.clear();  // GL objects go before their context
  context_.reset();
}

void MaterialGl::ensureContext() {
  if (context_) return;
  try {
    context_ = std::make_unique<gpu::Context>();
  } catch (const gpu::ContextError& e) {
    throw ParameterError(fmt::format(
        ".bssrdf models need an OpenGL 4.5 core context (their shaders run on the GPU), and "
        "none could be created: {}",
        e.what()));
  }
}

gpu::BssrdfEvaluator* MaterialGl::find(const std::string& path) {
  auto it = models_.find(path);
  return it == models_.end() ? nullptr : it->second.get();
}

gpu::BssrdfEvaluator& MaterialGl::load(const std::string& path) {
  if (auto* e = find(path)) return *e;
  // Parse first (no GL needed): a malformed file is reported by file:line even where no context
  // can be made.
  try {
    (void)bssrdf::loadBssrdf(path);
  } catch (const bssrdf::BssrdfFileError& err) {
    throw ParameterError(err.what());
  }
  ensureContext();
  // A directional file (no `radial`) is taken too: the pencil plot and the techniques that take a
  // radial profile use its normal-incidence restriction (gpu/bssrdf_profiles.h), the lit spheres
  // and the point cloud's shader kernel its directions.
  std::unique_ptr<gpu::BssrdfEvaluator> e = gpu::openBssrdf(path);
  auto& ref = *e;
  models_[path] = std::move(e);
  return ref;
}

void MaterialGl::reload(const std::string& path) {
  auto* e = find(path);
  if (e == nullptr) {
    load(path);
    return;
  }
  if (!e->reload()) throw ParameterError(bssrdf::firstBssrdfLine(e->lastError()));
}

void MaterialGl::unload(const std::string& path) { models_.erase(path); }

MaterialWorker& MaterialWorker::of(ExplorerState& state) {
  if (auto* w = state.findChild<MaterialWorker*>(QStringLiteral("material_worker"),
                                                 Qt::FindDirectChildrenOnly))
    return *w;
  return *new MaterialWorker(&state);
}

MaterialWorker::MaterialWorker(QObject* parent) : QObject(parent) {
  setObjectName(QStringLiteral("material_worker"));
  thread_ = std::thread([this] { loop(); });
}

MaterialWorker::~MaterialWorker() {
  {
    std::lock_guard lock(mutex_);
    quit_ = true;
    jobs_.clear();
  }
  wake_.notify_all();
  thread_.join();
}

void MaterialWorker::loop() {
  MaterialGl gl;
  for (;;) {
    std::function<void(MaterialGl&)> job;
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [&] { return quit_ || !jobs_.empty(); });
      if (quit_) return;
      job = std::move(jobs_.front());
      jobs_.pop_front();
    }
    job(gl);
  }
}

void MaterialWorker::post(QObject* owner, Job job, std::function<void(const QString&)> on_error) {
  QPointer<QObject> guard(owner);
  auto run = [this, guard, job = std::move(job), on_error = std::move(on_error)](MaterialGl& gl) {
    Continuation next;
    QString error;
    try {
      next = job(gl);
    } catch (const std::exception& e) {
      error = QString::fromStdString(e.what());
      if (error.isEmpty()) error = QStringLiteral("unknown error");
    }
    // Back on the GUI thread through the worker (which outlives its thread), then only if the
    // owner is still alive (QPointer is read on the GUI thread, where owners are deleted).
    QMetaObject::invokeMethod(
        this,
        [guard, next = std::move(next), error, on_error] {
          if (!guard) return;
          if (!error.isEmpty()) {
            if (on_error) on_error(error);
          } else if (next) {
            next();
          }
        },
        Qt::QueuedConnection);
  };
  {
    std::lock_guard lock(mutex_);
    jobs_.push_back(std::move(run));
  }
  wake_.notify_one();
}

}  // namespace translucent::explorer
