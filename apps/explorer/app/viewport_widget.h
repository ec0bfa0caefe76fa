// SPDX-License-Identifier: GPL-3.0-or-later
// The viewport's picture: a QOpenGLWidget with a 4.5 core context that shows the render thread's
// latest frame (RenderWorker), tone mapped with the scene's exposure and gamma
// (gpu::FrameDisplay), and turns mouse input into camera and light edits of the ExplorerState:
//   left drag: orbit about the look-at point     middle drag: pan      wheel: zoom
//   right drag: turn the light (directional lights about the view axes; environment: rotate)
// No GL header here or in the .cpp (libepoxy and Qt's GL headers clash): GL work is in src/gpu.
#pragma once

#include <QtCore/QPoint>
#include <QtCore/QString>
#include <QtOpenGLWidgets/QOpenGLWidget>

#include <memory>

#include "app/render_worker.h"

namespace translucent::gpu {
class FrameDisplay;
}

namespace translucent::explorer {

class ExplorerState;

class ViewportWidget : public QOpenGLWidget {
  Q_OBJECT

 public:
  explicit ViewportWidget(ExplorerState& state, QWidget* parent = nullptr);
  ~ViewportWidget() override;

  // Shows this frame (the next paint uploads it).
  void showFrame(std::shared_ptr<const RenderedFrame> frame);
  std::shared_ptr<const RenderedFrame> frame() const { return frame_; }
  // A message drawn over the picture (empty: none), e.g. "no OpenGL 4.5 core context".
  void setMessage(const QString& message);
  // The overlay (issue 14 §7): the mesh's bounding box and the x, y, z axes (red, green, blue,
  // one scene unit long from the origin), drawn over the frame with its own camera.
  void setOverlay(bool boundingBox, bool axes);
  bool boundingBoxShown() const { return show_box_; }
  bool axesShown() const { return show_axes_; }
  QString message() const { return message_; }
  // Whether the widget's own context is a 4.5 core one (known after the first show).
  bool displayReady() const { return display_ != nullptr; }

  QSize sizeHint() const override { return {640, 480}; }

 signals:
  void interactionStarted();  // a mouse drag or wheel step began changing the view
  void glInfo(const QString& text, bool ok);
  void resized();

 protected:
  void initializeGL() override;
  void paintGL() override;
  void resizeGL(int, int) override { emit resized(); }
  void mousePressEvent(QMouseEvent* e) override;
  void mouseMoveEvent(QMouseEvent* e) override;
  void mouseReleaseEvent(QMouseEvent* e) override;
  void wheelEvent(QWheelEvent* e) override;

 private:
  void releaseGl();

  ExplorerState& state_;
  std::unique_ptr<gpu::FrameDisplay> display_;
  std::shared_ptr<const RenderedFrame> frame_;
  bool show_box_ = false, show_axes_ = false;
  bool upload_ = false;
  QString message_;
  const void* connected_context_ = nullptr;  // whose aboutToBeDestroyed we listen to
  QMetaObject::Connection context_connection_;
  QPoint last_;
  Qt::MouseButton button_ = Qt::NoButton;
};

}  // namespace translucent::explorer
