// SPDX-License-Identifier: GPL-3.0-or-later
// The Material dock with the viewport under Xvfb (issue 12, §5): switching the type to veins and
// back, a number edited in the generated form changes the scene's material (toJson) and renders a
// new frame, an invalid value names its key in the console and the last good material keeps
// rendering, the Parameters dock's coefficients are disabled for a spatially varying material,
// and a technique that refuses such a material says so in the console while the explorer goes on;
// the debug view shows the two media of a checker as two values (σa), Rd and the 95% radius.
#include <QtTest/QSignalSpy>
#include <QtTest/QtTest>
#include <QtWidgets/QComboBox>
#include <QtWidgets/QDoubleSpinBox>
#include <QtWidgets/QLabel>
#include <QtWidgets/QMainWindow>
#include <QtWidgets/QScrollArea>
#include <QtWidgets/QSpinBox>
#include <QtWidgets/QStackedWidget>

#include <nlohmann/json.hpp>

#include <cmath>

#include "app/console_dock.h"
#include "app/viewport_dock.h"
#include "app/viewport_widget.h"
#include "core/explorer_state.h"
#include "material/material_dock.h"
#include "material/parameters_dock.h"

using namespace translucent;
using namespace translucent::explorer;

namespace {
constexpr int kFrameTimeoutMs = 60000;
}

class MaterialDockTest : public QObject {
  Q_OBJECT

 private:
  ExplorerState* state_ = nullptr;
  QMainWindow* window_ = nullptr;
  ViewportDock* dock_ = nullptr;
  ConsoleDock* console_ = nullptr;
  MaterialDock* material_ = nullptr;
  ParametersDock* parameters_ = nullptr;
  int full_frames_ = 0;
  std::shared_ptr<const RenderedFrame> full_;

  std::shared_ptr<const RenderedFrame> nextFull(const std::string& technique) {
    const int before = full_frames_;
    const bool ok = QTest::qWaitFor(
        [&] { return full_frames_ > before && full_ != nullptr && full_->technique == technique; },
        kFrameTimeoutMs);
    return ok ? full_ : nullptr;
  }
  nlohmann::json sceneMaterial() const { return nlohmann::json::parse(state_->materialJson()); }
  QComboBox* typeCombo() const { return material_->findChild<QComboBox*>("material_type"); }

 private slots:
  void initTestCase() {
    state_ = new ExplorerState;
    window_ = new QMainWindow;
    console_ = new ConsoleDock(*state_, window_);
    dock_ = new ViewportDock(*state_, window_);
    material_ = new MaterialDock(*state_, window_);
    parameters_ = new ParametersDock(*state_, window_);
    window_->addDockWidget(Qt::TopDockWidgetArea, dock_);
    window_->addDockWidget(Qt::RightDockWidgetArea, material_);
    window_->addDockWidget(Qt::RightDockWidgetArea, parameters_);
    window_->addDockWidget(Qt::BottomDockWidgetArea, console_);
    dock_->view()->setFixedSize(128, 96);
    dock_->fixRenderScale(1.0);
    connect(dock_, &ViewportDock::frameShown, this,
            [this](std::shared_ptr<const RenderedFrame> f, bool full) {
              if (!full) return;
              full_ = std::move(f);
              ++full_frames_;
            });
    state_->setTechniqueSetting("points", 4000.0);
    state_->setTechniqueSetting("epsilon", 1.0);
    state_->setTechniqueSetting("shadow_map_size", 512.0);
    window_->show();
    QVERIFY(QTest::qWaitForWindowExposed(window_));
    QVERIFY2(nextFull("pointcloud") != nullptr, qPrintable(console_->text()));
  }

  void cleanupTestCase() {
    delete window_;
    delete state_;
  }

  void typeComboListsEveryType() {
    QComboBox* type = typeCombo();
    QVERIFY(type != nullptr);
    QCOMPARE(type->currentText(), QStringLiteral("homogeneous"));
    for (const char* t : {"layers", "veins", "checker", "gradient", "voxels", "map", "rd_map",
                          "surface_checker"})
      QVERIFY2(type->findText(t) >= 0, t);
  }

  void everyTypeStartsFromDefaultsOrNamesWhatIsMissing() {
    // Types whose defaults parse switch the scene; voxels and map need files: the console names
    // the key and the scene keeps its material. Either way the form shows the type's keys.
    for (const char* t : {"layers", "checker", "gradient", "rd_map", "surface_checker", "voxels",
                          "map"}) {
      const std::string before = state_->materialJson();
      const int lines = console_->text().count('\n');
      typeCombo()->setCurrentIndex(typeCombo()->findText(t));
      const bool needsFile = std::string(t) == "voxels" || std::string(t) == "map";
      if (needsFile) {
        QCOMPARE(state_->materialJson(), before);
        QVERIFY2(console_->text().count('\n') > lines, t);
        QVERIFY2(console_->text().contains("material."), qPrintable(console_->text()));
        QVERIFY2(material_->findChild<QWidget*>(std::string(t) == "voxels" ? "file.browse"
                                                                           : "sigma_a.browse"),
                 t);
      } else {
        QVERIFY2(std::string(state_->scene().material.type()) == t, qPrintable(console_->text()));
      }
      QCOMPARE(material_->edited().at("type").get<std::string>(), std::string(t));
    }
    typeCombo()->setCurrentIndex(typeCombo()->findText("homogeneous"));
    QVERIFY2(state_->scene().material.homogeneous(), qPrintable(console_->text()));
    QVERIFY2(nextFull("pointcloud") != nullptr, qPrintable(console_->text()));
  }

  void switchToVeinsRendersIt() {
    typeCombo()->setCurrentIndex(typeCombo()->findText("veins"));
    QVERIFY2(!state_->scene().material.homogeneous(), qPrintable(console_->text()));
    QCOMPARE(std::string(state_->scene().material.type()), std::string("veins"));
    const auto m = sceneMaterial();
    QCOMPARE(m.at("type").get<std::string>(), std::string("veins"));
    QCOMPARE(m.at("media").size(), size_t(2));
    QVERIFY2(nextFull("pointcloud") != nullptr, qPrintable(console_->text()));
    // The Parameters dock no longer edits the (unused) representative medium's coefficients.
    auto* note = parameters_->findChild<QLabel*>("hetero_note");
    QVERIFY(note != nullptr);
    QVERIFY(note->isVisibleTo(parameters_));
    QVERIFY(note->text().contains("veins"));
    QVERIFY(!parameters_->findChild<QComboBox*>("preset")->isEnabled());
    QVERIFY(!parameters_->findChild<QStackedWidget*>()->isEnabled());
  }

  void editingANumberChangesTheSceneAndRenders() {
    auto* period = material_->findChild<QDoubleSpinBox*>("period");
    QVERIFY(period != nullptr);
    const double before = sceneMaterial().at("period").get<double>();
    const double next = before * 0.5;
    period->setValue(next);
    QCOMPARE(sceneMaterial().at("period").get<double>(), next);
    QVERIFY2(nextFull("pointcloud") != nullptr, qPrintable(console_->text()));
    // A medium coefficient in the nested form.
    auto* sa = material_->findChild<QDoubleSpinBox*>("media[1].sigma_a[0]");
    QVERIFY(sa != nullptr);
    sa->setValue(0.75);
    QCOMPARE(sceneMaterial().at("media").at(1).at("sigma_a").at(0).get<double>(), 0.75);
  }

  void invalidValueNamesTheKeyAndKeepsRendering() {
    const std::string good = state_->materialJson();
    auto* period = material_->findChild<QDoubleSpinBox*>("period");
    QVERIFY(period != nullptr);
    const int lines = console_->text().count('\n');
    period->setValue(-1.0);
    const QString text = console_->text();
    QVERIFY2(text.count('\n') > lines, qPrintable(text));
    QVERIFY2(text.contains("material.period"), qPrintable(text));
    QCOMPARE(state_->materialJson(), good);
    // Still rendering: a camera change gives a new frame.
    reference::Camera c = state_->scene().camera;
    c.fov *= 1.05;
    state_->setCamera(c);
    QVERIFY2(nextFull("pointcloud") != nullptr, qPrintable(console_->text()));
    period->setValue(0.05);  // corrected: valid again
    QCOMPARE(sceneMaterial().at("period").get<double>(), 0.05);
  }

  void techniqueThatRefusesItSaysSoAndTheExplorerGoesOn() {
    state_->setTechnique("tsis");
    QVERIFY2(QTest::qWaitFor([&] { return console_->text().contains("tsis") &&
                                          console_->text().contains("veins"); },
                             kFrameTimeoutMs),
             qPrintable(console_->text()));
    state_->setTechnique("pointcloud");
    state_->setTechniqueSetting("points", 4000.0);
    state_->setTechniqueSetting("epsilon", 1.0);
    state_->setTechniqueSetting("shadow_map_size", 512.0);
    QVERIFY2(nextFull("pointcloud") != nullptr, qPrintable(console_->text()));
  }

  void backToHomogeneous() {
    typeCombo()->setCurrentIndex(typeCombo()->findText("homogeneous"));
    QVERIFY2(state_->scene().material.homogeneous(), qPrintable(console_->text()));
    QVERIFY(!sceneMaterial().contains("type") ||
            sceneMaterial().at("type").get<std::string>() == "homogeneous");
    QVERIFY(parameters_->findChild<QComboBox*>("preset")->isEnabled());
    QVERIFY2(nextFull("pointcloud") != nullptr, qPrintable(console_->text()));
  }

 private:
  // Waits for the debug view's next update after `change` and returns its image.
  template <typename F>
  const DebugImage& debugAfter(F change) {
    QSignalSpy spy(material_, &MaterialDock::debugViewUpdated);
    change();
    [&] { QVERIFY2(spy.wait(kFrameTimeoutMs), qPrintable(console_->text())); }();
    return material_->debugImage();
  }

 private slots:
  void debugViewShowsTheTwoMediaOfAChecker() {
    auto* quantity = material_->findChild<QComboBox*>("debug_quantity");
    auto* channel = material_->findChild<QComboBox*>("debug_channel");
    QVERIFY(quantity != nullptr && channel != nullptr);
    // Homogeneous: one value over the mesh.
    channel->setCurrentIndex(channel->findText("red"));
    const DebugImage& flat = debugAfter([&] { quantity->setCurrentIndex(quantity->findText("σa")); });
    QVERIFY(flat.width > 0 && flat.height > 0);
    QCOMPARE(flat.values.size(), size_t(flat.width) * size_t(flat.height));
    const double sa0 = state_->scene().medium.sigma_a[0];
    QVERIFY2(std::abs(flat.lo - sa0) <= 1e-6 * sa0 && flat.hi - flat.lo <= 1e-5 * sa0,
             qPrintable(QStringLiteral("%1 .. %2, medium %3").arg(flat.lo).arg(flat.hi).arg(sa0)));
    // A checker of two media (σa 0.2 and 2 per medium unit in red; absorbing enough that the
    // diffusion length the surface medium averages over is small beside the cells).
    nlohmann::json m = material_->defaults("checker");
    constexpr double a0 = 0.2, a1 = 2.0;
    m["media"][0]["sigma_a"] = {a0, 0.3, 0.4};
    m["media"][1]["sigma_a"] = {a1, a1, a1};
    const int framesBefore = full_frames_;
    const DebugImage& two = debugAfter([&] { state_->setMaterialJson(m.dump()); });
    size_t covered = 0, near0 = 0, near1 = 0;
    for (const float f : two.values) {
      const double v = f;
      if (!std::isfinite(v)) continue;
      ++covered;
      // Within 5% of the contrast of either medium (a 3D field's surface medium averages over
      // a diffusion length below the surface: near a cell face it is a blend).
      near0 += std::abs(v - a0) <= 0.05 * (a1 - a0);
      near1 += std::abs(v - a1) <= 0.05 * (a1 - a0);
    }
    qInfo("debug view %dx%d: %zu covered, %zu at a0, %zu at a1, range %g .. %g", two.width,
          two.height, covered, near0, near1, two.lo, two.hi);
    QVERIFY(covered > 0.1 * two.values.size());
    QVERIFY(near0 > 0.1 * covered);
    QVERIFY(near1 > 0.1 * covered);
    QVERIFY(near0 + near1 > 0.5 * covered);
    QVERIFY(std::abs(two.lo - a0) < 1e-3 * a0 && std::abs(two.hi - a1) < 1e-3 * a1);
    // Colours follow: the two media are drawn in different colours.
    QVERIFY(two.rgb.size() == 3 * two.values.size());
    // Rd and the radius differ between the media too; the luminance channel works.
    const DebugImage& rd = debugAfter([&] { quantity->setCurrentIndex(quantity->findText("Rd")); });
    QVERIFY2(rd.hi > 1.5 * rd.lo, qPrintable(QStringLiteral("Rd %1 .. %2").arg(rd.lo).arg(rd.hi)));
    const DebugImage& r95 = debugAfter([&] {
      quantity->setCurrentIndex(quantity->findText("95% radius"));
    });
    QVERIFY2(r95.hi > 1.5 * r95.lo, qPrintable(QStringLiteral("r95 %1 .. %2").arg(r95.lo).arg(r95.hi)));
    const DebugImage& lum = debugAfter([&] { channel->setCurrentIndex(0); });
    QVERIFY(lum.hi > lum.lo);
    // A surface map: the UV checker of the same two media, read at the vertices' atlas UVs.
    nlohmann::json sc = material_->defaults("surface_checker");
    sc["media"] = m["media"];
    channel->setCurrentIndex(channel->findText("red"));
    quantity->setCurrentIndex(quantity->findText("σa"));
    const DebugImage& uv = debugAfter([&] { state_->setMaterialJson(sc.dump()); });
    size_t uvCovered = 0, uv0 = 0, uv1 = 0;
    for (const float f : uv.values) {
      const double v = f;
      if (!std::isfinite(v)) continue;
      ++uvCovered;
      uv0 += std::abs(v - a0) <= 0.05 * (a1 - a0);
      uv1 += std::abs(v - a1) <= 0.05 * (a1 - a0);
    }
    qInfo("surface checker: %zu covered, %zu at a0, %zu at a1", uvCovered, uv0, uv1);
    QVERIFY(uv0 > 0.1 * uvCovered && uv1 > 0.1 * uvCovered);
    auto* label = material_->findChild<QLabel*>("debug_image");
    QVERIFY(label != nullptr && !label->pixmap().isNull());
    // For a look at the dock: TRANSLUCENT_TEST_SNAPSHOT_DIR=dir saves it as material-dock.png.
    if (const QString dir = qEnvironmentVariable("TRANSLUCENT_TEST_SNAPSHOT_DIR"); !dir.isEmpty())
      QVERIFY(material_->findChild<QScrollArea*>()->widget()->grab().save(dir + "/material-dock.png"));
    // The viewport rendered the checker.
    QVERIFY2(QTest::qWaitFor([&] { return full_frames_ > framesBefore; }, kFrameTimeoutMs),
             qPrintable(console_->text()));
  }

  void sceneFileMaterialFillsTheForm() {
    // data/scenes/bunny-marble-veins.json: a preset medium as a preset combo, an integer as a
    // spin box; the preset combo edits the scene, "Coefficients" writes the preset out.
    const QString dir = qEnvironmentVariable("TRANSLUCENT_SOURCE_DIR");
    QVERIFY(!dir.isEmpty());
    scene::Scene s = scene::loadScene((dir + "/data/scenes/bunny-marble-veins.json").toStdString());
    s.settings = {{"points", 4000.0}, {"epsilon", 1.0}, {"shadow_map_size", 512.0}};
    s.camera.width = 128;
    s.camera.height = 96;
    const int framesBefore = full_frames_;
    state_->setScene(s);
    QCOMPARE(material_->edited(), sceneMaterial());
    QCOMPARE(typeCombo()->currentText(), QStringLiteral("veins"));
    auto* octaves = material_->findChild<QSpinBox*>("octaves");
    QVERIFY(octaves != nullptr);
    QCOMPARE(octaves->value(), 5);
    auto* preset = material_->findChild<QComboBox*>("media[0].preset");
    QVERIFY(preset != nullptr);
    QCOMPARE(preset->currentText(), QStringLiteral("Marble"));
    preset->setCurrentIndex(preset->findText("Skimmilk"));
    QCOMPARE(sceneMaterial().at("media").at(0).at("preset").get<std::string>(), std::string("Skimmilk"));
    preset->setCurrentIndex(preset->count() - 1);  // Coefficients
    QVERIFY2(sceneMaterial().at("media").at(0).contains("sigma_a"), state_->materialJson().c_str());
    QVERIFY(QTest::qWaitFor([&] {
      return material_->findChild<QDoubleSpinBox*>("media[0].sigma_a[0]") != nullptr;
    }));
    QVERIFY2(QTest::qWaitFor([&] { return full_frames_ > framesBefore; }, kFrameTimeoutMs),
             qPrintable(console_->text()));
    // The debug view of the veins (its cost on the GUI thread, for the log).
    auto* quantity = material_->findChild<QComboBox*>("debug_quantity");
    quantity->setCurrentIndex(0);
    QElapsedTimer t;
    t.start();
    const DebugImage& veins = debugAfter([&] { quantity->setCurrentIndex(quantity->findText("Rd")); });
    qInfo("veins Rd debug view: %lld ms (150 ms of it the debounce), range %g .. %g", t.elapsed(),
          veins.lo, veins.hi);
    QVERIFY(veins.hi > veins.lo);
  }
};

QTEST_MAIN(MaterialDockTest)
#include "test_material_dock.moc"
