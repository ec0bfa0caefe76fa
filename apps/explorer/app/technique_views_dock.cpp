// SPDX-License-Identifier: GPL-3.0-or-later
#include "app/technique_views_dock.h"

#include <QtCharts/QChart>
#include <QtCharts/QChartView>
#include <QtWidgets/QComboBox>
#include <QtWidgets/QLabel>
#include <QtWidgets/QVBoxLayout>

#include <algorithm>

#include "app/render_worker.h"
#include "app/viewport_dock.h"
#include "core/pixel_image_view.h"
#include "plot/frame_plot.h"

namespace translucent::explorer {

TechniqueViewsDock::TechniqueViewsDock(ViewportDock& viewport, QWidget* parent)
    : QDockWidget(tr("Technique views"), parent), viewport_(viewport) {
  setObjectName(QStringLiteral("techniqueViewsDock"));
  auto* panel = new QWidget(this);
  auto* layout = new QVBoxLayout(panel);
  choice_ = new QComboBox(panel);
  caption_ = new QLabel(tr("The technique's own views appear here (tsis: the irradiance atlas)."), panel);
  caption_->setWordWrap(true);
  view_ = new PixelImageView(panel);
  chart_ = new QChartView(panel);
  chart_->setRenderHint(QPainter::Antialiasing);
  chart_->hide();
  layout->addWidget(choice_);
  layout->addWidget(view_, 1);
  layout->addWidget(chart_, 1);
  layout->addWidget(caption_);
  setWidget(panel);
  connect(choice_, &QComboBox::currentTextChanged, this, [this] { showCurrent(); });
  connect(&viewport_, &ViewportDock::frameShown, this, &TechniqueViewsDock::onFrame);
  // Views only while someone can see them: they cost a read-back per frame.
  connect(this, &QDockWidget::visibilityChanged, this, [this](bool visible) {
    viewport_.setViewsWanted(visible);
  });
}

QStringList TechniqueViewsDock::viewNames() const {
  QStringList out;
  for (int i = 0; i < choice_->count(); ++i) out << choice_->itemText(i);
  return out;
}

QString TechniqueViewsDock::currentView() const { return choice_->currentText(); }

int TechniqueViewsDock::chartSeries() const {
  return chart_->isHidden() ? 0 : int(chart_->chart()->series().size());
}

namespace {
const QString kPlotPrefix = QStringLiteral("plot: ");
}

void TechniqueViewsDock::onFrame(std::shared_ptr<const RenderedFrame> frame, bool full) {
  if (!full || !isVisible()) return;
  frame_ = std::move(frame);
  const QString keep = choice_->currentText();
  QStringList names;
  for (const auto& [name, v] : frame_->frame.views) names << QString::fromStdString(name);
  for (const auto& [name, p] : frame_->frame.plots) names << kPlotPrefix + QString::fromStdString(name);
  if (names != viewNames()) {
    const QSignalBlocker block(choice_);
    choice_->clear();
    choice_->addItems(names);
    if (names.contains(keep)) choice_->setCurrentText(keep);
  }
  showCurrent();
}

void TechniqueViewsDock::showCurrent() {
  if (!frame_) return;
  if (const QString current = choice_->currentText(); current.startsWith(kPlotPrefix)) {
    const auto p = frame_->frame.plots.find(current.mid(kPlotPrefix.size()).toStdString());
    if (p != frame_->frame.plots.end()) {
      const techniques::FramePlot& fp = p->second;
      const plot::FrameXyPlot xy = plot::xyPlotOf(fp);
      QChart* old = chart_->chart();
      chart_->setChart(plot::makeXyChart(xy.series, xy.options).release());
      delete old;
      view_->hide();
      chart_->show();
      caption_->setText(QString::fromStdString(fp.title));
      return;
    }
  }
  chart_->hide();
  view_->show();
  const auto it = frame_->frame.views.find(choice_->currentText().toStdString());
  if (it == frame_->frame.views.end()) {
    image_ = QImage();
    view_->setImage(image_);
    caption_->setText(tr("%1 has no views.").arg(QString::fromStdString(frame_->technique)));
    return;
  }
  const techniques::FrameView& v = it->second;
  image_ = toneMappedImage(v.rgb, v.width, v.height, 0.0, 1.0);  // display-ready [0, 1]
  view_->setImage(image_);
  caption_->setText(QString::fromStdString(v.description));
}

}  // namespace translucent::explorer
