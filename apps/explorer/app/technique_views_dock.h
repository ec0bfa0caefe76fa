// SPDX-License-Identifier: GPL-3.0-or-later
// The technique's inspection views (techniques::Frame::views), e.g. tsis's irradiance atlas with
// the frame's samples drawn over it (seed Fig. 3.1), and its plots (techniques::Frame::plots,
// listed as "plot: NAME", drawn as charts; e.g. splatting's effective rendering radius): a
// choice of view, the picture or chart and what it shows. The views cost a read-back of their own, so the viewport asks for them only while this
// dock is visible, and only in its full-resolution frames.
#pragma once

#include <QtWidgets/QDockWidget>

#include <memory>
#include <string>

class QComboBox;
class QLabel;
QT_BEGIN_NAMESPACE
class QChartView;
QT_END_NAMESPACE

namespace translucent::explorer {

class PixelImageView;
class ViewportDock;
struct RenderedFrame;

class TechniqueViewsDock : public QDockWidget {
  Q_OBJECT

 public:
  TechniqueViewsDock(ViewportDock& viewport, QWidget* parent = nullptr);

  // Names of the views of the last full frame shown, and the one on screen ("" for none).
  QStringList viewNames() const;
  QString currentView() const;
  // The picture on screen (null before the first view).
  const QImage& image() const { return image_; }
  // Qt series of the chart on screen (a line and its markers per curve; 0 when a picture or
  // nothing is shown).
  int chartSeries() const;

 private:
  void onFrame(std::shared_ptr<const RenderedFrame> frame, bool full);
  void showCurrent();

  ViewportDock& viewport_;
  QComboBox* choice_ = nullptr;
  QLabel* caption_ = nullptr;
  PixelImageView* view_ = nullptr;
  QChartView* chart_ = nullptr;
  std::shared_ptr<const RenderedFrame> frame_;
  QImage image_;
};

}  // namespace translucent::explorer
