// SPDX-License-Identifier: GPL-3.0-or-later
#include "plot/chart_legend.h"

#include <QtCharts/QChart>
#include <QtCharts/QLegend>
#include <QtCharts/QScatterSeries>
#include <QtCharts/QXYSeries>
#include <QtGui/QFontMetrics>
#include <QtGui/QPainter>

#include <algorithm>

namespace translucent::plot {
namespace {
constexpr int kSample = 28, kGap = 6, kColumnGap = 14, kMargin = 2;
}

ChartLegend::ChartLegend(QWidget* parent) : QWidget(parent) {
  setObjectName(QStringLiteral("chart_legend"));
  QFont f = font();  // the size of Qt Charts' legend text (9 pt beside the widgets' 10 pt)
  f.setPointSizeF(f.pointSizeF() * 0.9);
  setFont(f);
  QSizePolicy p(QSizePolicy::Preferred, QSizePolicy::Preferred);
  p.setHeightForWidth(true);
  setSizePolicy(p);
}

void ChartLegend::setChart(QChart* chart) {
  entries_.clear();
  if (chart != nullptr) {
    for (QAbstractSeries* s : chart->series()) {
      if (s->property(kHiddenFromLegend).toBool()) continue;
      Entry e;
      e.name = s->name();
      if (const auto* dots = qobject_cast<const QScatterSeries*>(s)) {
        e.is_dot = true;
        e.dot = dots->brush();
        e.pen = dots->pen();
      } else if (const auto* xy = qobject_cast<const QXYSeries*>(s)) {
        e.pen = xy->pen();
      }
      entries_.push_back(std::move(e));
    }
    chart->legend()->hide();
  }
  updateGeometry();
  update();
}

int ChartLegend::rowHeight() const { return fontMetrics().height() + 1; }

int ChartLegend::columnWidth() const {
  int text = 0;
  for (const Entry& e : entries_) text = std::max(text, fontMetrics().horizontalAdvance(e.name));
  return kSample + kGap + text + kColumnGap;
}

int ChartLegend::columnsFor(int width) const {
  if (entries_.empty()) return 0;
  return std::clamp((width - 2 * kMargin + kColumnGap) / std::max(1, columnWidth()), 1, entries());
}

bool ChartLegend::elides() const {
  return !entries_.empty() && columnsFor(width()) == 1 && columnWidth() - kColumnGap > width() - 2 * kMargin;
}

int ChartLegend::heightForWidth(int width) const {
  if (entries_.empty()) return 0;
  const int columns = columnsFor(width);
  const int rows = (entries() + columns - 1) / columns;
  return rows * rowHeight() + 2 * kMargin;
}

QSize ChartLegend::sizeHint() const {
  const int w = std::max(columnWidth() * 2, 200);
  return {w, heightForWidth(w)};
}

QSize ChartLegend::minimumSizeHint() const { return {60, heightForWidth(width() > 0 ? width() : 200)}; }

void ChartLegend::paintEvent(QPaintEvent*) {
  if (entries_.empty()) return;
  QPainter p(this);
  p.setRenderHint(QPainter::Antialiasing);
  const int columns = columnsFor(width());
  const int rows = (entries() + columns - 1) / columns;
  const int column_width = (width() - 2 * kMargin) / columns;
  const int row_height = rowHeight();
  const QFontMetrics fm = fontMetrics();
  for (int i = 0; i < entries(); ++i) {
    const Entry& e = entries_[static_cast<size_t>(i)];
    const int x = kMargin + (i / rows) * column_width;
    const int y = kMargin + (i % rows) * row_height;
    const int yc = y + row_height / 2;
    if (e.is_dot) {
      p.setPen(e.pen);
      p.setBrush(e.dot);
      p.drawEllipse(QPointF(x + kSample / 2.0, yc), 3.5, 3.5);
    } else {
      QPen pen = e.pen;
      pen.setWidthF(std::max(1.5, pen.widthF()));
      p.setPen(pen);
      p.drawLine(QPointF(x + 1, yc), QPointF(x + kSample - 1, yc));
    }
    p.setPen(palette().color(QPalette::WindowText));
    const int text_width = column_width - kSample - kGap;
    p.drawText(QRect(x + kSample + kGap, y, text_width, row_height), Qt::AlignVCenter | Qt::AlignLeft,
               fm.elidedText(e.name, Qt::ElideRight, text_width));
  }
}

}  // namespace translucent::plot
