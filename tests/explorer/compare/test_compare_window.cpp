// SPDX-License-Identifier: GPL-3.0-or-later
// The Compare dock in the explorer's main window: present, tabbed behind another dock and idle
// (no render thread, no photons) until raised; raised, it renders the viewport's technique and
// refines a reference of the scene while the viewport and the lit spheres run beside it, and is
// destroyed promptly with everything running.
#include <QtCore/QElapsedTimer>
#include <QtTest/QTest>
#include <QtWidgets/QDockWidget>

#include <memory>

#include "app/main_window.h"
#include "compare/compare_dock.h"
#include "core/explorer_state.h"

using namespace translucent;
using namespace translucent::explorer;

class TestCompareWindow : public QObject {
  Q_OBJECT

 private slots:
  void idleUntilRaisedThenCompares() {
    QElapsedTimer clock;
    clock.start();
    ExplorerState state;
    auto window = std::make_unique<MainWindow>(state, MainWindowOptions{false, false});
    window->show();
    QVERIFY(QTest::qWaitForWindowExposed(window.get()));
    qInfo("window shown after %lld ms", static_cast<long long>(clock.elapsed()));
    auto* dock = window->findChild<CompareDock*>("compare");
    QVERIFY(dock != nullptr);
    QVERIFY(!window->tabifiedDockWidgets(dock).isEmpty());
    QTest::qWait(500);
    QCOMPARE(dock->status().generation, 0);  // a hidden tab: nothing started

    dock->setImageWidth(16);
    dock->setPhotonBudget(32 * 1024);  // passes of 16 and 16 blocks
    dock->raise();
    QTRY_VERIFY_WITH_TIMEOUT(dock->status().generation == 1 && dock->status().running, 5000);
    // The comparison itself is the dock test's; here the first pass of the reference, computed
    // beside the viewport and the lit spheres.
    QTRY_VERIFY_WITH_TIMEOUT(dock->status().passes >= 1, 60000);
    qInfo("first reference pass after %lld ms", static_cast<long long>(clock.elapsed()));

    // The dock first, alone, with everything else still running.
    QElapsedTimer timer;
    timer.start();
    delete dock;
    qInfo("Compare dock destroyed in the running window in %lld ms",
          static_cast<long long>(timer.elapsed()));
    QVERIFY2(timer.elapsed() < 1000, qPrintable(QString("%1 ms").arg(timer.elapsed())));
    // The rest of the window, dock by dock, for the record (no bound here: not this dock's).
    for (QDockWidget* d : window->findChildren<QDockWidget*>()) {
      timer.restart();
      const QString name = d->objectName();
      delete d;
      qInfo("%s dock destroyed in %lld ms", qPrintable(name), static_cast<long long>(timer.elapsed()));
    }
    window.reset();
  }
};

QTEST_MAIN(TestCompareWindow)
#include "test_compare_window.moc"
