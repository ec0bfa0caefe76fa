// SPDX-License-Identifier: GPL-3.0-or-later
// A chart's legend as a widget of its own that wraps into as many columns as its width holds
// (entries read down each column, as in the plot files). Qt Charts' legend stays in one column
// beside the plot or one row under it: with the nine models of the pencil plot it was taller
// than the plot in a dock of 300 px, or cut the names short.
#pragma once

#include <QtGui/QBrush>
#include <QtGui/QPen>
#include <QtWidgets/QWidget>

#include <vector>

QT_BEGIN_NAMESPACE
class QChart;
QT_END_NAMESPACE

namespace translucent::plot {

// The property that marks a series left out of the legend (a standard-error band, a curve's
// second channel): set by the chart builders of profile_chart.h.
inline constexpr char kHiddenFromLegend[] = "translucent_hidden_from_legend";

class ChartLegend : public QWidget {
 public:
  explicit ChartLegend(QWidget* parent = nullptr);

  // One entry per series of `chart` not marked kHiddenFromLegend, with its pen (lines) or
  // colour (scatter dots); nullptr: no entries. Hides the chart's own legend: call it before
  // the chart is shown, so that its layout never reserves the legend's room.
  void setChart(QChart* chart);

  int entries() const { return static_cast<int>(entries_.size()); }
  int columnsFor(int width) const;
  // Whether a name is cut short at the present width (only when one column is too narrow).
  bool elides() const;

  bool hasHeightForWidth() const override { return true; }
  int heightForWidth(int width) const override;
  QSize sizeHint() const override;
  QSize minimumSizeHint() const override;

 protected:
  void paintEvent(QPaintEvent* e) override;

 private:
  struct Entry {
    QString name;
    QPen pen;
    QBrush dot;  // a scatter series: drawn as a dot, not a line
    bool is_dot = false;
  };
  int columnWidth() const;
  int rowHeight() const;
  std::vector<Entry> entries_;
};

}  // namespace translucent::plot
