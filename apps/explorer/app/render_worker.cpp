// SPDX-License-Identifier: GPL-3.0-or-later
#include "app/render_worker.h"

#include <QtCore/QCoreApplication>

#include <chrono>

#include <exception>
#include <string>
#include <utility>

#include "translucent/gpu/context.h"
#include "translucent/techniques/registry.h"

namespace translucent::explorer {
namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// What prepare() depends on: the whole scene except the display settings and the image size
// (the size goes with each FrameRequest, so half/full resolution switches need no prepare).
std::string preparedKey(scene::Scene s) {
  s.exposure = 0.0;
  s.gamma = 2.2;
  s.camera.width = 1;
  s.camera.height = 1;
  return scene::toJson(s);
}

// The same without the camera: two scenes with equal keys differ at most in the camera, which a
// technique may take without prepare() (Technique::setCamera: orbiting keeps the lighting).
std::string preparedKeyWithoutCamera(scene::Scene s) {
  s.camera = reference::Camera{};
  return preparedKey(std::move(s));
}

}  // namespace

void retireInBackground(std::unique_ptr<RenderWorker> worker) {
  if (!worker) return;
  worker->disconnect();  // its last signals reach nobody
  worker->requestStop();
  // Joined with the application's children, on the GUI thread while Qt is alive (not on another
  // thread: a QObject is destroyed on its own); without an application, here.
  if (QCoreApplication* app = QCoreApplication::instance()) worker.release()->setParent(app);
}

void RenderWorker::requestStop() {
  thread_.request_stop();
  wake_.notify_all();
}

RenderWorker::RenderWorker(QObject* parent) : QObject(parent) {
  qRegisterMetaType<std::shared_ptr<const RenderedFrame>>();
  qRegisterMetaType<std::shared_ptr<const scene::Scene>>();
}

void RenderWorker::start() {
  if (!thread_.joinable()) thread_ = std::jthread([this](std::stop_token stop) { run(stop); });
}

RenderWorker::~RenderWorker() {
  thread_.request_stop();
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

std::uint64_t RenderWorker::request(RenderRequest request) {
  std::uint64_t id = 0;
  {
    std::lock_guard lock(mutex_);
    id = next_id_++;
    request.id = id;
    pending_ = std::move(request);
  }
  wake_.notify_all();
  return id;
}

std::optional<scene::Scene> RenderWorker::lastGoodScene() const {
  std::lock_guard lock(mutex_);
  return good_scene_;
}

void RenderWorker::run(std::stop_token stop) {
  // The context first and last: techniques delete their GL objects while it is current.
  std::unique_ptr<gpu::Context> gl;
  try {
    gl = std::make_unique<gpu::Context>();
    const auto& info = gl->info();
    emit contextReady(QString::fromStdString(info.renderer + " (OpenGL " + info.version + ", " +
                                             info.platform + ")"));
  } catch (const std::exception& e) {
    emit contextFailed(QString::fromStdString(e.what()));
    return;
  }

  std::unique_ptr<techniques::Technique> technique;
  std::string prepared_key;  // preparedKey of the scene the technique holds
  std::string prepared_key_without_camera;  // the same without its camera
  std::string counted_mesh;  // mesh file whose counts are in faces/vertices
  std::size_t faces = 0, vertices = 0;
  glm::dvec3 bounds_lo{0.0}, bounds_hi{0.0};
  std::optional<RenderRequest> current;
  bool more = false;  // the current request wants another frame

  // Prepares `s` (a new technique instance when the name changes); throws on failure, leaving
  // `technique` as it was when the name changed, or possibly half-prepared otherwise.
  auto prepare = [&](const scene::Scene& s) {
    if (!technique || technique->name() != s.technique) {
      auto fresh = techniques::make(s.technique);
      techniques::applySettings(*fresh, s);
      fresh->prepare(s, *gl);
      technique = std::move(fresh);
    } else {
      // Settings removed from the scene go back to their defaults: a fresh set each time.
      for (const auto& p : technique->parameters()) technique->setParameter(p.name, p.value);
      techniques::applySettings(*technique, s);
      technique->prepare(s, *gl);
    }
    prepared_key = preparedKey(s);
    prepared_key_without_camera = preparedKeyWithoutCamera(s);
  };

  while (!stop.stop_requested()) {
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, stop, [&] { return pending_.has_value() || more; });
      if (stop.stop_requested()) break;
      if (pending_) {
        current = std::move(pending_);
        pending_.reset();
      }
    }
    RenderRequest& r = *current;

    double prepare_ms = 0.0;
    const std::string key = preparedKey(r.scene);
    std::unique_ptr<techniques::Technique> before_reload;  // back to it if the reload fails
    std::string before_key, before_key_without_camera;
    if (r.reload && technique) {
      before_reload = std::move(technique);
      before_key = std::exchange(prepared_key, std::string());
      before_key_without_camera = prepared_key_without_camera;
    }
    r.reload = false;  // once (a continuous request repeats)
    // A camera move only: the technique takes the camera and keeps its light-dependent results.
    if (technique && key != prepared_key && technique->name() == r.scene.technique &&
        preparedKeyWithoutCamera(r.scene) == prepared_key_without_camera) {
      try {
        if (technique->setCamera(r.scene.camera)) {
          prepared_key = key;
          std::lock_guard lock(mutex_);
          good_scene_ = r.scene;
        }
      } catch (const std::exception&) {
        // An invalid camera: prepare() below reports it as for any other change.
      }
    }
    if (!technique || key != prepared_key) {
      const auto t0 = Clock::now();
      try {
        // The mesh first: a broken file fails fast with the loader's message, and its counts go
        // to the status bar.
        if (r.scene.mesh_file.string() != counted_mesh) {
          const geometry::TriangleMesh mesh = scene::loadSceneMesh(r.scene);
          faces = mesh.triangleCount();
          vertices = mesh.vertexCount();
          const geometry::Bounds b = mesh.bounds();
          bounds_lo = b.lower;
          bounds_hi = b.upper;
          counted_mesh = r.scene.mesh_file.string();
        }
        prepare(r.scene);
        std::lock_guard lock(mutex_);
        good_scene_ = r.scene;
      } catch (const std::exception& e) {
        const QString message = QString::fromStdString(e.what());
        if (before_reload) {
          // A reload that failed (a GLSL error): the previous instance, with the shaders it was
          // built with, goes on rendering.
          technique = std::move(before_reload);
          prepared_key = before_key;
          prepared_key_without_camera = before_key_without_camera;
        }
        std::optional<scene::Scene> good;
        {
          std::lock_guard lock(mutex_);
          good = good_scene_;
        }
        // Back to the last good state: the instance may be half-prepared, so prepare it again
        // (or a fresh one) with the last good scene.
        bool restored = false;
        if (good) {
          try {
            if (preparedKey(*good) != prepared_key || technique->name() != good->technique)
              prepare(*good);
            restored = true;
          } catch (const std::exception&) {
            technique.reset();
            try {
              prepare(*good);
              restored = true;
            } catch (const std::exception&) {
              technique.reset();
            }
          }
          counted_mesh.clear();
        }
        if (restored) {
          r.scene = *good;
        } else {
          technique.reset();
          prepared_key.clear();
        }
        emit prepareFailed(r.id, message,
                           restored ? std::make_shared<const scene::Scene>(*good) : nullptr);
        if (!restored) {
          more = false;
          continue;
        }
      }
      prepare_ms = msSince(t0);
    }

    auto out = std::make_shared<RenderedFrame>();
    const auto t0 = Clock::now();
    try {
      techniques::FrameRequest fr;
      fr.width = r.width > 0 ? r.width : r.scene.camera.width;
      fr.height = r.height > 0 ? r.height : r.scene.camera.height;
      fr.converge = r.converge;
      fr.views = r.views;
      out->frame = technique->render(fr);
    } catch (const std::exception& e) {
      emit prepareFailed(r.id, QString::fromStdString(e.what()), nullptr);
      technique.reset();
      prepared_key.clear();
      more = false;
      continue;
    }
    out->render_ms = msSince(t0);
    out->prepare_ms = prepare_ms;
    out->request_id = r.id;
    out->technique = r.scene.technique;
    out->convention = techniques::radianceConvention(*technique);
    out->faces = faces;
    out->vertices = vertices;
    out->bounds_lo = bounds_lo;
    out->bounds_hi = bounds_hi;
    out->camera = r.scene.camera;
    out->continuous = r.continuous;
    more = r.continuous || !out->frame.converged;
    emit frameReady(std::move(out));
  }
  technique.reset();  // while the context is current
  gl.reset();
}

}  // namespace translucent::explorer
