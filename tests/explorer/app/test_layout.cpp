// SPDX-License-Identifier: GPL-3.0-or-later
// The explorer's first look under Xvfb: the default dock layout at 1400×900 and 1280×720 gives
// the picture at least half the window's width at the scene camera's aspect ratio, shows the
// Parameters dock's first rows without scrolling, wraps the pencil plot's legend in columns under
// the chart (no name cut, no taller than the chart),
// and is written as a screenshot beside the test (for a person to look at; the checks read the
// widgets' geometry). A layout the user changed is remembered (QSettings) and "Reset layout"
// brings the default back.
#include <QtCharts/QChart>
#include <QtCharts/QChartView>
#include <QtCharts/QLegend>
#include <QtCharts/QLogValueAxis>
#include <QtCore/QSettings>
#include <QtCore/QStandardPaths>
#include <QtCore/QTemporaryDir>
#include <QtGui/QFontMetricsF>
#include <QtTest/QSignalSpy>
#include <QtTest/QtTest>
#include <QtWidgets/QDoubleSpinBox>
#include <QtWidgets/QScrollArea>
#include <QtWidgets/QScrollBar>

#include <cmath>
#include <memory>

#include "app/main_window.h"
#include "app/viewport_dock.h"
#include "core/explorer_state.h"
#include "material/parameters_dock.h"
#include "material/pencil_plot_dock.h"
#include "plot/chart_legend.h"

using namespace translucent;
using namespace translucent::explorer;

namespace {

struct Layout {
  double picture_share = 0.0;  // picture width / window width
  double aspect_error = 0.0;   // |picture aspect / camera aspect - 1|
  int parameter_rows_hidden = 0;
  bool legend_fits = false;
  bool plot_scrolls = true;
  bool y_labels_fit = false;
};

// How far a widget inside a scroll area is from being fully visible without scrolling (pixels
// below the visible part; 0 when it is visible).
int hiddenBelow(const QScrollArea& area, const QWidget& w) {
  const QPoint top = w.mapTo(area.widget(), QPoint(0, 0));
  return std::max(0, top.y() + w.height() - area.viewport()->height());
}

}  // namespace

class LayoutTest : public QObject {
  Q_OBJECT

 private:
  QTemporaryDir settings_dir_;

  static std::unique_ptr<MainWindow> open(ExplorerState& state, MainWindowOptions options, QSize size) {
    auto w = std::make_unique<MainWindow>(state, options);
    w->resize(size);
    QSignalSpy applied(w.get(), &MainWindow::defaultLayoutApplied);
    w->show();
    if (!options.restore_layout) {
      if (!applied.wait(20000)) return nullptr;
    }
    QTest::qWait(300);  // the docks' geometry settles after the last resize
    return w;
  }

  static Layout measure(MainWindow& w, const ExplorerState& state) {
    Layout m;
    const QSize pic = w.viewport()->pictureSize();
    m.picture_share = double(pic.width()) / w.width();
    const auto& cam = state.scene().camera;
    m.aspect_error = std::abs((double(pic.width()) / pic.height()) / (double(cam.width) / cam.height) - 1.0);
    auto* params = w.findChild<ParametersDock*>();
    auto* area = params->findChild<QScrollArea*>();
    // The material's rows through η: what a user edits first.
    for (const char* name : {"preset", "model", "sigma_a_r", "sigma_a_g", "sigma_a_b", "sigma_s_r",
                             "sigma_s_g", "sigma_s_b", "g", "eta"}) {
      auto* row = params->findChild<QWidget*>(QString::fromLatin1(name));
      if (row == nullptr) {
        qWarning("no parameter row %s", name);
        m.parameter_rows_hidden += 100;
        continue;
      }
      if (hiddenBelow(*area, *row) > 0) ++m.parameter_rows_hidden;
    }
    auto* plot = w.findChild<PencilPlotDock*>();
    // The model curves are computed in the background: wait for them.
    if (!QTest::qWaitFor([&] { return plot->chart()->series().size() >= 9; }, 30000))
      qWarning("the pencil plot has %d series", int(plot->chart()->series().size()));
    QTest::qWait(200);
    const QChart* chart = plot->chart();
    // (ChartLegend has no meta-object of its own: found by name.)
    auto* legend = dynamic_cast<plot::ChartLegend*>(plot->findChild<QWidget*>(QStringLiteral("pencil_plot_legend")));
    auto* view = plot->findChild<QChartView*>();
    // Every curve named in full, the legend no taller than the chart above it.
    m.legend_fits = legend != nullptr && legend->isVisible() && legend->entries() >= 9 &&
                    !legend->elides() && legend->height() <= view->height() &&
                    !chart->legend()->isVisible();
    // The plot dock's controls, chart and legend fit without a scroll bar.
    auto* plot_area = plot->findChild<QScrollArea*>();
    m.plot_scrolls = plot_area != nullptr && plot_area->verticalScrollBar()->isVisible();
    // Each y label has its text's height (Qt Charts elides a label taller than its share).
    for (QAbstractAxis* a : chart->axes(Qt::Vertical))
      if (auto* l = qobject_cast<QLogValueAxis*>(a)) {
        const double labels = std::floor(std::log(l->max() / l->min()) / std::log(l->base())) + 1.0;
        const double share = chart->plotArea().height() / labels;
        m.y_labels_fit = share >= QFontMetricsF(l->labelsFont()).height() + 4.0;
        qInfo("log axis: base %g, %g..%g, %.0f labels in %.0f px", l->base(), l->min(), l->max(),
              labels, chart->plotArea().height());
      }
    qInfo("%dx%d: picture %dx%d (%.1f%% of the width, aspect off by %.1f%%), parameter rows "
          "hidden %d, plot scrolls %d, legend %dx%d (%d entries in %d columns) under a %dx%d chart",
          w.width(), w.height(), pic.width(), pic.height(), 100.0 * m.picture_share,
          100.0 * m.aspect_error, m.parameter_rows_hidden, int(m.plot_scrolls), legend ? legend->width() : 0,
          legend ? legend->height() : 0, legend ? legend->entries() : 0,
          legend ? legend->columnsFor(legend->width()) : 0, view->width(), view->height());
    return m;
  }

 private slots:
  void initTestCase() {
    QVERIFY(settings_dir_.isValid());
    QSettings::setPath(QSettings::NativeFormat, QSettings::UserScope, settings_dir_.path());
  }

  void defaultLayoutAtTwoSizes_data() {
    QTest::addColumn<QSize>("size");
    QTest::newRow("1400x900") << QSize(1400, 900);
    QTest::newRow("1280x720") << QSize(1280, 720);
  }

  void defaultLayoutAtTwoSizes() {
    QFETCH(QSize, size);
    ExplorerState state;
    auto w = open(state, {.restore_layout = false, .save_layout = false}, size);
    QVERIFY2(w != nullptr, "the default layout was never applied");
    QCOMPARE(w->size(), size);
    const Layout m = measure(*w, state);
    const QString shot = QStringLiteral("layout-%1x%2.png").arg(size.width()).arg(size.height());
    QVERIFY(w->grab().save(shot));
    QVERIFY2(m.picture_share >= 0.5, "the picture has less than half the window's width");
    QVERIFY2(m.aspect_error <= 0.05, "the picture is not at the camera's aspect ratio (5%)");
    // At 1280×720 the Parameters dock shares the right column with the plots: the preset, the
    // model and the absorption rows are visible without scrolling; at 1400×900 every row to η.
    const int allowed = size.height() >= 900 ? 0 : 5;
    QVERIFY2(m.parameter_rows_hidden <= allowed, "parameter rows hidden behind the scroll bar");
    QVERIFY2(m.legend_fits, "the pencil plot's legend is taller than the plot or outside the chart");
    QVERIFY2(!m.plot_scrolls, "the pencil plot needs a scroll bar");
    QVERIFY2(m.y_labels_fit, "the pencil plot's y labels have less than their height each");
  }

  void rememberedLayoutAndReset() {
    const QSize size(1280, 720);
    ExplorerState state;
    Layout before;
    int viewport_width = 0;
    {
      auto w = open(state, {.restore_layout = false, .save_layout = true}, size);
      QVERIFY(w != nullptr);
      before = measure(*w, state);
      // The user narrows the picture to 40% and hides the console.
      w->resizeDocks({w->viewport()}, {size.width() * 2 / 5}, Qt::Horizontal);
      w->findChild<QDockWidget*>(QStringLiteral("console_dock"))->hide();
      QTest::qWait(200);
      viewport_width = w->viewport()->width();
      QVERIFY(viewport_width < size.width() / 2);
      w->close();
    }
    {
      auto w = open(state, {.restore_layout = true, .save_layout = false}, size);
      QVERIFY(w != nullptr);
      QVERIFY2(std::abs(w->viewport()->width() - viewport_width) <= 8, "the layout was not remembered");
      QVERIFY(!w->findChild<QDockWidget*>(QStringLiteral("console_dock"))->isVisible());
      QSignalSpy applied(w.get(), &MainWindow::defaultLayoutApplied);
      w->resetLayout();
      QVERIFY(applied.wait(20000));
      QTest::qWait(300);
      const Layout after = measure(*w, state);
      QVERIFY(w->findChild<QDockWidget*>(QStringLiteral("console_dock"))->isVisible());
      QVERIFY(std::abs(after.picture_share - before.picture_share) < 0.02);
      QVERIFY(after.aspect_error <= 0.05);
    }
  }
};

QTEST_MAIN(LayoutTest)
#include "test_layout.moc"
