// The Material dock with the viewport under Xvfb (issue 12, §5): switching the type to veins and
// back, a number edited in the generated form changes the scene's material (toJson) and renders a
// new frame, an invalid value names its key in the console and the last good material keeps
// rendering, the Parameters dock's coefficients are disabled for a spatially varying material,
// and a technique that refuses such a material says so in the console while the explorer goes on.
#include <QtTest/QtTest>
#include <QtWidgets/QComboBox>
#include <QtWidgets/QDoubleSpinBox>
#include <QtWidgets/QLabel>
#include <QtWidgets/QMainWindow>
#include <QtWidgets/QStackedWidget>

#include <nlohmann/json.hpp>

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
};

QTEST_MAIN(MaterialDockTest)
#include "test_material_dock.moc"
