// SPDX-License-Identifier: GPL-3.0-or-later
// A machine without OpenGL 4.5: Mesa is told to offer at most OpenGL 3.3
// (MESA_GL_VERSION_OVERRIDE, set before anything starts). The viewport must say so clearly in
// the picture and on the console, and the application must keep running (no crash, no throw).
#include <QtTest/QtTest>
#include <QtWidgets/QApplication>
#include <QtWidgets/QMainWindow>

#include "app/console_dock.h"
#include "app/viewport_dock.h"
#include "app/viewport_widget.h"
#include "core/explorer_state.h"

using namespace translucent::explorer;

class NoGl45 : public QObject {
  Q_OBJECT

 private slots:
  void saysSoAndKeepsRunning() {
    ExplorerState state;
    QMainWindow window;
    auto* console = new ConsoleDock(state, &window);
    auto* dock = new ViewportDock(state, &window);
    window.addDockWidget(Qt::TopDockWidgetArea, dock);
    window.addDockWidget(Qt::BottomDockWidgetArea, console);
    dock->view()->setFixedSize(96, 64);
    window.show();
    QVERIFY(QTest::qWaitForWindowExposed(&window));
    QVERIFY(QTest::qWaitFor([&] { return !dock->view()->message().isEmpty(); }, 20000));
    QVERIFY2(dock->view()->message().contains(QStringLiteral("4.5")),
             qPrintable(dock->view()->message()));
    QVERIFY(QTest::qWaitFor([&] { return console->errorCount() > 0; }, 20000));
    QVERIFY2(console->text().contains(QStringLiteral("4.5")), qPrintable(console->text()));
    qInfo("viewport message: %s", qPrintable(dock->view()->message()));
    QVERIFY(!dock->rendererReady() || !dock->view()->displayReady());
    // Still responsive: an edit goes through and the window still repaints.
    state.setTechnique("empirical");
    QTest::qWait(200);
    QCOMPARE(state.scene().technique, std::string("empirical"));
    QVERIFY(!window.grab().isNull());
  }
};

int main(int argc, char** argv) {
  qputenv("MESA_GL_VERSION_OVERRIDE", "3.3");
  QApplication app(argc, argv);
  NoGl45 test;
  return QTest::qExec(&test, argc, argv);
}
#include "test_no_gl45.moc"
