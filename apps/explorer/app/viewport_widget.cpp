// SPDX-License-Identifier: GPL-3.0-or-later
#include "app/viewport_widget.h"

#include <QtGui/QMouseEvent>
#include <QtGui/QOpenGLContext>
#include <QtGui/QPainter>
#include <QtGui/QWheelEvent>

#include <cmath>
#include <exception>

#include "app/view_math.h"
#include "core/explorer_state.h"
#include "translucent/gpu/frame_display.h"

namespace translucent::explorer {

ViewportWidget::ViewportWidget(ExplorerState& state, QWidget* parent)
    : QOpenGLWidget(parent), state_(state) {
  // The display needs OpenGL 4.5 core like the rest of src/gpu; the rendering itself happens in
  // the RenderWorker's own context.
  QSurfaceFormat format;
  format.setVersion(4, 5);
  format.setProfile(QSurfaceFormat::CoreProfile);
  format.setRenderableType(QSurfaceFormat::OpenGL);
  setFormat(format);
  setMinimumSize(64, 64);
  setFocusPolicy(Qt::StrongFocus);
}

ViewportWidget::~ViewportWidget() {
  // ~QOpenGLWidget destroys the context and emits aboutToBeDestroyed when this object is no
  // longer a ViewportWidget: the slot must not run then (UBSan: member call on a destroyed type).
  disconnect(context_connection_);
  if (display_ != nullptr) {
    makeCurrent();
    releaseGl();
    doneCurrent();
  }
}

void ViewportWidget::releaseGl() { display_.reset(); }

void ViewportWidget::initializeGL() {
  // The context is recreated when the widget moves to another top-level window (a dock popping
  // out): release the old objects while the old context is still current.
  if (connected_context_ != context()) {
    connected_context_ = context();
    disconnect(context_connection_);
    context_connection_ = connect(context(), &QOpenGLContext::aboutToBeDestroyed, this, [this] {
      makeCurrent();
      releaseGl();
      doneCurrent();
    });
  }
  const gpu::CurrentContextInfo info = gpu::currentContextInfo();
  const QString text = QStringLiteral("display context: OpenGL %1 on %2")
                           .arg(QString::fromStdString(info.version),
                                QString::fromStdString(info.renderer));
  if (!info.atLeast45Core()) {
    setMessage(QStringLiteral("No OpenGL 4.5 core context for the viewport (got OpenGL %1 on %2).\n"
                              "The explorer needs OpenGL 4.5; on machines without a GPU, Mesa's "
                              "llvmpipe provides it.")
                   .arg(QString::fromStdString(info.version), QString::fromStdString(info.renderer)));
    emit glInfo(message_, false);
    return;
  }
  try {
    display_ = std::make_unique<gpu::FrameDisplay>();
    upload_ = frame_ != nullptr;
    emit glInfo(text, true);
  } catch (const std::exception& e) {
    setMessage(QStringLiteral("The viewport cannot display frames: %1").arg(e.what()));
    emit glInfo(message_, false);
  }
}

void ViewportWidget::showFrame(std::shared_ptr<const RenderedFrame> frame) {
  frame_ = std::move(frame);
  upload_ = true;
  update();
}

void ViewportWidget::setOverlay(bool boundingBox, bool axes) {
  show_box_ = boundingBox;
  show_axes_ = axes;
  update();
}

void ViewportWidget::setMessage(const QString& message) {
  message_ = message;
  update();
}

void ViewportWidget::paintGL() {
  const double dpr = devicePixelRatioF();
  const int w = int(std::lround(width() * dpr)), h = int(std::lround(height() * dpr));
  if (display_ != nullptr) {
    try {
      if (upload_ && frame_ != nullptr && frame_->frame.width > 0) {
        const auto& f = frame_->frame;
        display_->upload(f.rgb, f.width, f.height);
      }
      upload_ = false;
      const auto& s = state_.scene();
      display_->draw(defaultFramebufferObject(), w, h, scene::displayToneMap(s));
    } catch (const std::exception& e) {
      message_ = QString::fromUtf8(e.what());
    }
  }
  if ((show_box_ || show_axes_) && frame_ != nullptr && frame_->frame.width > 0) {
    // The frame fills the widget (FrameDisplay stretches it): frame pixels scale to widget ones.
    const auto& f = frame_->frame;
    const double sx = double(width()) / f.width, sy = double(height()) / f.height;
    QPainter painter(this);
    painter.setRenderHint(QPainter::Antialiasing);
    const QColor colours[4] = {QColor(255, 220, 0), QColor(230, 40, 40), QColor(40, 200, 40),
                               QColor(60, 90, 255)};
    for (const OverlaySegment& seg :
         overlaySegments(frame_->camera, frame_->bounds_lo, frame_->bounds_hi, f.width, f.height)) {
      if (!seg.visible || (seg.kind == 0 ? !show_box_ : !show_axes_)) continue;
      painter.setPen(QPen(colours[seg.kind], seg.kind == 0 ? 1.0 : 2.0));
      painter.drawLine(QPointF(seg.x0 * sx, seg.y0 * sy), QPointF(seg.x1 * sx, seg.y1 * sy));
    }
  }
  if (!message_.isEmpty()) {
    QPainter painter(this);
    if (display_ == nullptr) painter.fillRect(rect(), QColor(40, 40, 40));
    painter.setPen(Qt::white);
    painter.drawText(rect().adjusted(12, 12, -12, -12), Qt::AlignCenter | Qt::TextWordWrap,
                     message_);
  }
}

void ViewportWidget::mousePressEvent(QMouseEvent* e) {
  last_ = e->position().toPoint();
  button_ = e->button();
  e->accept();
}

void ViewportWidget::mouseReleaseEvent(QMouseEvent* e) {
  if (e->button() == button_) button_ = Qt::NoButton;
  e->accept();
}

void ViewportWidget::mouseMoveEvent(QMouseEvent* e) {
  if (button_ == Qt::NoButton) return;
  const QPoint p = e->position().toPoint();
  const double dx = double(p.x() - last_.x()) / std::max(1, height());
  const double dy = double(p.y() - last_.y()) / std::max(1, height());
  last_ = p;
  if (dx == 0.0 && dy == 0.0) return;
  emit interactionStarted();
  const reference::Camera& camera = state_.scene().camera;
  constexpr double kTurn = 3.0;  // radians per view height of mouse travel
  if (button_ == Qt::LeftButton) {
    state_.setCamera(orbit(camera, kTurn * dx, kTurn * dy));
  } else if (button_ == Qt::MiddleButton) {
    state_.setCamera(pan(camera, dx, -dy));
  } else if (button_ == Qt::RightButton) {
    // Turn every light that has a direction; an environment turns about +y.
    std::vector<scene::Light> lights = state_.scene().lights;
    for (auto& light : lights) {
      std::visit(
          [&](auto& emitter) {
            using T = std::decay_t<decltype(emitter)>;
            if constexpr (std::is_same_v<T, reference::DirectionalLight> ||
                          std::is_same_v<T, scene::FilteredDirectionalLight>) {
              emitter.direction = turnDirection(camera, emitter.direction, kTurn * dx, kTurn * dy);
            } else if constexpr (std::is_same_v<T, scene::EnvironmentLight>) {
              emitter.rotate = std::fmod(emitter.rotate + 180.0 / M_PI * kTurn * dx + 360.0, 360.0);
            }
          },
          light.emitter);
    }
    state_.setLights(std::move(lights));
  }
  e->accept();
}

void ViewportWidget::wheelEvent(QWheelEvent* e) {
  const double steps = e->angleDelta().y() / 120.0;
  if (steps == 0.0) return;
  emit interactionStarted();
  state_.setCamera(zoom(state_.scene().camera, std::pow(0.9, steps)));
  e->accept();
}

}  // namespace translucent::explorer
