// SPDX-License-Identifier: GPL-3.0-or-later
// Pure parts of the explorer's shell: the mouse-driven camera and light mathematics, the command
// line builder, the generated sliders' value mapping, the frame-rate statistics.
#include <QtTest/QtTest>

#include <glm/geometric.hpp>

#include <cmath>

#include "app/command_line.h"
#include "app/current_data.h"
#include "translucent/techniques/registry.h"
#include "app/main_window.h"
#include "app/parameter_form.h"
#include "app/view_math.h"
#include "translucent/reference/camera.h"
#include "app/viewport_dock.h"

using namespace translucent;
using namespace translucent::explorer;

class AppUnits : public QObject {
  Q_OBJECT

 private slots:
  void orbitKeepsDistanceAndTurnsByTheAngle() {
    reference::Camera c;
    c.position = {0.0, 0.0, 3.0};
    c.look_at = {0.0, 0.0, 0.0};
    const reference::Camera o = orbit(c, 0.5, 0.0);
    QVERIFY(std::abs(glm::length(o.position - o.look_at) - 3.0) < 1e-12);
    // A yaw of 0.5 rad about +y: the angle between old and new offsets is 0.5.
    const double angle = std::acos(glm::dot(glm::normalize(o.position), glm::normalize(c.position)));
    QVERIFY(std::abs(angle - 0.5) < 1e-12);
    QVERIFY(std::abs(o.position.y) < 1e-12);
    // Pitching far past the pole stops 1 degree short of it.
    const reference::Camera p = orbit(c, 0.0, 10.0);
    const double elevation = std::asin(glm::normalize(p.position - p.look_at).y);
    QVERIFY(std::abs(elevation - (M_PI / 2 - M_PI / 180)) < 1e-9);
  }

  void panMovesEyeAndTargetTogether() {
    reference::Camera c;
    c.position = {0.0, 0.0, 2.0};
    c.fov = 90.0;  // view height at distance 2: 2 * 2 * tan(45°) = 4
    const reference::Camera p = pan(c, 0.25, 0.0);
    QVERIFY(std::abs((p.position - c.position).x + 1.0) < 1e-12);  // scene moves right: eye left
    QVERIFY(glm::length((p.position - p.look_at) - (c.position - c.look_at)) < 1e-12);
  }

  void zoomScalesTheDistance() {
    reference::Camera c;
    c.position = {1.0, 2.0, 2.0};  // distance 3
    const reference::Camera z = zoom(c, 0.5);
    QVERIFY(std::abs(glm::length(z.position - z.look_at) - 1.5) < 1e-12);
    QCOMPARE(zoom(c, -1.0).position.x, c.position.x);  // invalid factors change nothing
  }

  void lightTurnsAboutTheViewAxes() {
    reference::Camera c;
    c.position = {0.0, 0.0, 3.0};
    const glm::dvec3 d = turnDirection(c, {0.0, 0.0, 1.0}, M_PI / 2, 0.0);
    QVERIFY(std::abs(glm::length(d) - 1.0) < 1e-12);
    QVERIFY(std::abs(d.x - 1.0) < 1e-12);  // +z turned by 90° about +y
  }

  void commandLineQuotesWordsAShellWouldSplit() {
    const QString cmd = renderCommandLine(QStringLiteral("/opt/bin/translucent"),
                                          "/tmp/my scenes/view's.json", QStringLiteral("empirical"),
                                          320, 240, QStringLiteral("view.exr"));
    QCOMPARE(cmd, QStringLiteral("/opt/bin/translucent render '/tmp/my scenes/view'\\''s.json' "
                                 "--technique empirical --width 320 --height 240 --exr view.exr"));
    QCOMPARE(shellQuote(QString()), QStringLiteral("''"));
  }

  // "Print current data" (issue 14 §7): the scene's JSON, then every technique parameter with
  // the value it renders with, the scene's settings unmarked and the rest "(default)".
  void currentDataListsTheSceneAndEveryParameter() {
    scene::Scene s = scene::defaultScene();
    s.settings["epsilon"] = 0.5;
    const QString text = currentDataText(s);
    QVERIFY(text.contains(QString::fromStdString(scene::toJson(s))));
    QVERIFY(text.contains("technique pointcloud"));
    QVERIFY2(text.contains("\n  epsilon = 0.5\n"), qPrintable(text));
    QVERIFY2(text.contains("\n  points = 100000 (default)\n"), qPrintable(text));
    const auto t = techniques::make("pointcloud");
    for (const auto& p : t->parameters())
      QVERIFY2(text.contains(QString::fromStdString("\n  " + p.name + " = ")), p.name.c_str());
    s.technique = "no-such-technique";
    QVERIFY(currentDataText(s).contains("technique no-such-technique:"));
  }

  // The viewport overlay (issue 14 §7): 12 box edges then the x, y, z axes, their ends where the
  // camera model projects them; behind a pinhole camera nothing is drawn.
  void overlaySegmentsProjectTheBoxAndTheAxes() {
    reference::Camera c;
    c.projection = reference::Camera::Projection::Pinhole;
    c.position = {0.5, 0.8, 3.0};
    c.look_at = {0.0, 0.0, 0.0};
    c.up = {0.0, 1.0, 0.0};
    c.fov = 40.0;
    const glm::dvec3 lo(-0.5, -0.4, -0.3), hi(0.6, 0.5, 0.2);
    const auto segs = overlaySegments(c, lo, hi, 200, 100);
    QCOMPARE(segs.size(), size_t(15));
    reference::Camera sized = c;
    sized.width = 200;
    sized.height = 100;
    const reference::CameraModel model(sized);
    int corners = 0;
    for (int i = 0; i < 12; ++i) {
      QCOMPARE(segs[size_t(i)].kind, 0);
      QVERIFY(segs[size_t(i)].visible);
      for (int end = 0; end < 2; ++end) {
        const double x = end ? segs[size_t(i)].x1 : segs[size_t(i)].x0;
        const double y = end ? segs[size_t(i)].y1 : segs[size_t(i)].y0;
        // Each end is one of the eight corners, projected.
        for (int k = 0; k < 8; ++k) {
          const glm::dvec3 p(k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z);
          double px = 0, py = 0;
          (void)model.project(p, px, py);
          if (std::abs(px - x) < 1e-9 && std::abs(py - y) < 1e-9) {
            ++corners;
            break;
          }
        }
      }
    }
    QCOMPARE(corners, 24);
    for (int a = 0; a < 3; ++a) {
      const auto& s = segs[size_t(12 + a)];
      QCOMPARE(s.kind, a + 1);
      glm::dvec3 e(0.0);
      e[a] = 1.0;
      double px = 0, py = 0;
      (void)model.project(e, px, py);
      QVERIFY(std::abs(s.x1 - px) < 1e-9 && std::abs(s.y1 - py) < 1e-9);
    }
    // Looking away from the box: nothing is drawn.
    c.look_at = {1.0, 1.6, 6.0};
    for (const auto& s : overlaySegments(c, lo, hi, 200, 100)) QVERIFY(!s.visible);
  }

  void sceneForCliMakesPathsAbsoluteAndSetsTheSize() {
    scene::Scene s = scene::defaultScene();
    s.mesh_file = "relative/mesh.obj";
    const scene::Scene out = MainWindow::sceneForCli(s, 123, 45);
    QVERIFY(out.mesh_file.is_absolute());
    QCOMPARE(out.camera.width, 123);
    QCOMPARE(out.camera.height, 45);
  }

  void slidersMapEndpointsAndLogMidpoint() {
    QCOMPARE(sliderToValue(0, 1e-4, 100.0, true), 1e-4);
    QVERIFY(std::abs(sliderToValue(kSliderSteps, 1e-4, 100.0, true) - 100.0) < 1e-9);
    // Logarithmic: the middle is the geometric mean; linear: the arithmetic mean.
    QVERIFY(std::abs(sliderToValue(kSliderSteps / 2, 1e-4, 100.0, true) - 0.1) < 1e-9);
    QVERIFY(std::abs(sliderToValue(kSliderSteps / 2, 0.0, 10.0, false) - 5.0) < 1e-12);
    for (int pos : {0, 1, 250, 777, kSliderSteps}) {
      QCOMPARE(valueToSlider(sliderToValue(pos, 1e-4, 100.0, true), 1e-4, 100.0, true), pos);
      QCOMPARE(valueToSlider(sliderToValue(pos, -2.0, 3.0, false), -2.0, 3.0, false), pos);
    }
  }

  void frameStatsTrackCurrentMinMaxAverage() {
    FrameStats s;
    for (double ms : {100.0, 50.0, 200.0}) s.add(ms);
    QCOMPARE(s.frames, 3);
    QCOMPARE(s.current, 5.0);
    QCOMPARE(s.min, 5.0);
    QCOMPARE(s.max, 20.0);
    QVERIFY(std::abs(s.average() - 3000.0 / 350.0) < 1e-12);  // frames over total time
  }
};

QTEST_MAIN(AppUnits)
#include "test_app_units.moc"
