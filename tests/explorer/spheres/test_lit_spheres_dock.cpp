// SPDX-License-Identifier: GPL-3.0-or-later
// The lit spheres dock (issue 6 section 1, seed 3.6.2): both images appear and refine pass by
// pass (the photon and sample counts grow), a material change cancels and restarts both runs and
// the new images differ from the old by far more than their noise, exposure changes the display
// without recomputing, a model the integration cannot use is reported and changes nothing, and
// destroying the dock while both runs work returns promptly.
//
// Small images (32²) and budgets keep the whole test within a few seconds of computing on two
// cores; the default material is the explorer's: Marble, 25 mm per scene unit.
#include <QtCore/QElapsedTimer>
#include <QtTest/QSignalSpy>
#include <QtTest/QTest>
#include <QtWidgets/QDoubleSpinBox>
#include <QtWidgets/QComboBox>
#include <QtWidgets/QSlider>

#include <cmath>
#include <map>
#include <memory>
#include <numeric>
#include <vector>

#include "core/explorer_state.h"
#include "translucent/optics/presets.h"
#include "spheres/lit_spheres_dock.h"

using namespace translucent;
using namespace translucent::explorer;
using Pane = LitSpheresDock::Pane;

namespace {

constexpr int kSize = 32;
constexpr uint64_t kPhotons = 60 * 1024;  // passes of 8, 16, 32 and 4 blocks
constexpr uint64_t kSamples = 12;         // passes of 1, 2, 4 and 5 samples per pixel
constexpr int kWaitMs = 30000;

std::unique_ptr<LitSpheresDock> smallDock(ExplorerState& state) {
  auto dock = std::make_unique<LitSpheresDock>(state);
  dock->setResolution(kSize);
  dock->setPhotonBudget(kPhotons);
  dock->setSampleBudget(kSamples);
  return dock;
}

bool finished(const LitSpheresDock& d) {
  return !d.status(Pane::PathTraced).running && !d.status(Pane::Integrated).running;
}

// Mean of one channel of a linear RGB image.
double channelMean(const std::vector<float>& rgb, int c) {
  double s = 0.0;
  for (size_t i = static_cast<size_t>(c); i < rgb.size(); i += 3) s += static_cast<double>(rgb[i]);
  return s / static_cast<double>(rgb.size() / 3);
}

Medium presetMedium(const char* name, double scale) {
  const auto& p = preset(name);
  return Medium::fromReduced(p.sigma_a, p.sigma_s_prime, p.g, p.eta, scale);
}

}  // namespace

class TestLitSpheresDock : public QObject {
  Q_OBJECT

 private slots:
  void hasStableObjectName() {
    ExplorerState state;
    LitSpheresDock dock(state);
    QCOMPARE(dock.objectName(), QString("lit_spheres"));
  }

  void imagesAppearAndRefinePassByPass() {
    ExplorerState state;
    auto dock = smallDock(state);
    std::map<Pane, std::vector<LitSpheresDock::PaneStatus>> seen;
    connect(dock.get(), &LitSpheresDock::passCompleted, this,
            [&](Pane p, int) { seen[p].push_back(dock->status(p)); });
    QTRY_VERIFY_WITH_TIMEOUT(finished(*dock), kWaitMs);

    // Path tracer: 8 + 16 + 32 + 4 blocks; integration 1 + 2 + 4 + 5 samples per pixel.
    const std::map<Pane, std::vector<uint64_t>> expected = {
        {Pane::PathTraced, {8 * 1024, 24 * 1024, 56 * 1024, 60 * 1024}},
        {Pane::Integrated, {1, 3, 7, 12}}};
    for (Pane p : {Pane::PathTraced, Pane::Integrated}) {
      const auto& s = seen[p];
      QCOMPARE(s.size(), expected.at(p).size());
      for (size_t k = 0; k < s.size(); ++k) {
        QCOMPARE(s[k].passes, static_cast<int>(k) + 1);
        QCOMPARE(s[k].done, expected.at(p)[k]);
        QCOMPARE(s[k].generation, s.front().generation);  // one run, refined
      }
      const QImage img = dock->image(p);
      QCOMPARE(img.size(), QSize(kSize, kSize));
      // Non-empty: a lit sphere fills most of the frame, so many pixels are far from black.
      int lit = 0;
      for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) lit += qGray(img.pixel(x, y)) > 40 ? 1 : 0;
      QVERIFY2(lit > kSize * kSize / 4, qPrintable(QString("only %1 lit pixels").arg(lit)));
    }
    // Both images exist: the comparison covers the sphere's disc (π/4 of the frame at margin
    // 1.05, about 0.71 kSize²) and the dipole is within a factor of two of the reference.
    QVERIFY(dock->comparison().has_value());
    const auto& c = *dock->comparison();
    QVERIFY(c.metrics.pixels > static_cast<uint64_t>(0.6 * kSize * kSize));
    QVERIFY(c.metrics.mean_test > 0.5 * c.metrics.mean_reference &&
            c.metrics.mean_test < 2.0 * c.metrics.mean_reference);
    QVERIFY(!dock->differenceImage().isNull());
  }

  void tracerOnTheGpuRestartsThePathTracerOnlyAndAgreesWithTheCpu() {
    // The "Tracer on" combo: GPU restarts the path tracer alone (the integration's run is kept),
    // the status names the renderer, and the GPU image's mean is the CPU image's within a few
    // of its standard errors (the means of 60k-photon images differ by ~1% at most here).
    ExplorerState state;
    auto dock = smallDock(state);
    QTRY_VERIFY_WITH_TIMEOUT(finished(*dock), kWaitMs);
    QCOMPARE(dock->tracerDevice(), std::string("auto"));
    QCOMPARE(dock->status(Pane::PathTraced).device, std::string("cpu"));  // llvmpipe: auto = cpu
    const std::vector<float> cpu = dock->linearImage(Pane::PathTraced);
    const int integration = dock->status(Pane::Integrated).generation;
    auto* box = dock->findChild<QComboBox*>("tracer_device");
    QVERIFY(box);
    box->setCurrentIndex(box->findData(QStringLiteral("gpu")));
    QCOMPARE(dock->tracerDevice(), std::string("gpu"));
    QTRY_VERIFY_WITH_TIMEOUT(finished(*dock) && dock->status(Pane::PathTraced).passes == 4, kWaitMs);
    QCOMPARE(dock->status(Pane::Integrated).generation, integration);
    const std::string device = dock->status(Pane::PathTraced).device;
    QVERIFY2(device.rfind("gpu (", 0) == 0, device.c_str());
    const std::vector<float> gpu = dock->linearImage(Pane::PathTraced);
    QCOMPARE(gpu.size(), cpu.size());
    for (int c = 0; c < 3; ++c) {
      const double a = channelMean(cpu, c), b = channelMean(gpu, c);
      QVERIFY2(std::abs(a - b) < 0.03 * a, qPrintable(QString("channel %1: cpu %2, gpu %3").arg(c).arg(a).arg(b)));
    }
    QVERIFY(gpu != cpu);  // other streams
  }

  void tracedLightSelectsTheScatteringOrder() {
    // "Traced light" (issue 14 §4, the seed's multi + single selector): multiple or single
    // scattering restarts the path tracer alone; with the same seed the same photons are traced,
    // so the two parts' images add up to the whole one (Marble at 25 mm per unit: nothing
    // crosses the sphere unscattered), and single scattering is a small, nonzero share.
    ExplorerState state;
    auto dock = smallDock(state);
    QTRY_VERIFY_WITH_TIMEOUT(finished(*dock), kWaitMs);
    const std::vector<float> all = dock->linearImage(Pane::PathTraced);
    const int integration = dock->status(Pane::Integrated).generation;
    auto* box = dock->findChild<QComboBox*>("tracer_light");
    QVERIFY(box);
    std::map<std::string, std::vector<float>> parts;
    for (const char* light : {"multiple", "single"}) {
      const int generation = dock->status(Pane::PathTraced).generation;
      box->setCurrentIndex(box->findData(QString(light)));
      QCOMPARE(dock->tracerLight(), std::string(light));
      QVERIFY(dock->status(Pane::PathTraced).generation > generation);
      QTRY_VERIFY_WITH_TIMEOUT(finished(*dock) && dock->status(Pane::PathTraced).passes == 4, kWaitMs);
      parts[light] = dock->linearImage(Pane::PathTraced);
    }
    QCOMPARE(dock->status(Pane::Integrated).generation, integration);
    for (int c = 0; c < 3; ++c) {
      const double total = channelMean(all, c), single = channelMean(parts["single"], c),
                   multiple = channelMean(parts["multiple"], c);
      QVERIFY2(std::abs(single + multiple - total) <= 1e-5 * total,
               qPrintable(QString("channel %1: %2 + %3 vs %4").arg(c).arg(single).arg(multiple).arg(total)));
      QVERIFY2(single > 0.001 * total && single < 0.2 * total,
               qPrintable(QString("channel %1: single share %2").arg(c).arg(single / total)));
    }
  }

  void materialChangeCancelsAndRestarts() {
    ExplorerState state;
    auto dock = smallDock(state);
    QTRY_VERIFY_WITH_TIMEOUT(finished(*dock), kWaitMs);
    const std::vector<float> marble[2] = {dock->linearImage(Pane::PathTraced),
                                          dock->linearImage(Pane::Integrated)};

    // A larger path-tracing budget restarts the path tracer at once; the material changes while
    // that run is between its passes.
    dock->setPhotonBudget(2 * kPhotons);
    QTRY_VERIFY_WITH_TIMEOUT(dock->status(Pane::PathTraced).passes >= 1, kWaitMs);
    QVERIFY(dock->status(Pane::PathTraced).running);
    const int gen[2] = {dock->status(Pane::PathTraced).generation,
                        dock->status(Pane::Integrated).generation};

    // Two changes in a row (a slider being dragged) make one restart per pane, shortly after.
    // The status is read when each run starts (a 32² integration pass takes a millisecond).
    std::map<Pane, LitSpheresDock::PaneStatus> atStart;
    connect(dock.get(), &LitSpheresDock::runStarted, this,
            [&](Pane p) { atStart[p] = dock->status(p); });
    QSignalSpy started(dock.get(), &LitSpheresDock::runStarted);
    state.setMedium(presetMedium("Skin1", 25.0), "Skin1");
    state.setMedium(presetMedium("Ketchup", 25.0), "Ketchup");
    QTRY_COMPARE(started.count(), 2);
    for (Pane p : {Pane::PathTraced, Pane::Integrated}) {
      const auto s = atStart.at(p);
      QCOMPARE(s.generation, gen[static_cast<int>(p)] + 1);
      QCOMPARE(s.passes, 0);  // the pass counter starts again
      QVERIFY(s.running);
    }
    QTRY_VERIFY_WITH_TIMEOUT(finished(*dock), kWaitMs);
    // Ketchup absorbs green strongly (σa 0.97 /mm against marble's 0.0041, and σs' 0.07 against
    // 2.62): its green exitance is a small fraction of marble's, its red a larger one. Measured
    // (both panes): green about 0.01, red about 0.2 of marble's; the bounds below (green < 0.5,
    // red > 2 green) are far outside the noise of these budgets.
    for (Pane p : {Pane::PathTraced, Pane::Integrated}) {
      const auto& before = marble[static_cast<int>(p)];
      const auto after = dock->linearImage(p);
      QCOMPARE(after.size(), before.size());
      const double green = channelMean(after, 1) / channelMean(before, 1);
      qInfo("%s: Ketchup / Marble mean exitance: red %.3f, green %.3f",
            p == Pane::PathTraced ? "path traced" : "integrated",
            channelMean(after, 0) / channelMean(before, 0), green);
      QVERIFY2(green < 0.5, qPrintable(QString("green ratio %1").arg(green)));
      QVERIFY(channelMean(after, 0) > 2.0 * channelMean(after, 1));  // ketchup is red
      QCOMPARE(dock->status(p).done, p == Pane::PathTraced ? 2 * kPhotons : kSamples);
    }
  }

  // θL/φL (issue 14 §4): a change restarts both runs with the light there. With the light from
  // behind the sphere (θL = 150°) the camera sees the unlit side: its images are far darker than
  // with the light from the camera (θL = 0), in both panes, and the spin boxes show the angles.
  void lightAnglesMoveTheLight() {
    ExplorerState state;
    auto dock = smallDock(state);
    dock->setLightAngles(0.0, 0.0);
    QTRY_VERIFY_WITH_TIMEOUT(finished(*dock), kWaitMs);
    const std::vector<float> front[2] = {dock->linearImage(Pane::PathTraced),
                                         dock->linearImage(Pane::Integrated)};
    const int gen[2] = {dock->status(Pane::PathTraced).generation,
                        dock->status(Pane::Integrated).generation};
    dock->findChild<QDoubleSpinBox*>("light_theta")->setValue(150.0);
    QCOMPARE(dock->lightTheta(), 150.0);
    QTRY_VERIFY_WITH_TIMEOUT(finished(*dock), kWaitMs);
    for (Pane p : {Pane::PathTraced, Pane::Integrated}) {
      QCOMPARE(dock->status(p).generation, gen[static_cast<int>(p)] + 1);
      const double ratio = channelMean(dock->linearImage(p), 1) /
                           channelMean(front[static_cast<int>(p)], 1);
      qInfo("%s: light from behind / from the camera, mean green exitance %.3f",
            p == Pane::PathTraced ? "path traced" : "integrated", ratio);
      QVERIFY2(ratio < 0.5, qPrintable(QString("ratio %1").arg(ratio)));
    }
  }

  void exposureChangesTheDisplayOnly() {
    ExplorerState state;
    auto dock = smallDock(state);
    QTRY_VERIFY_WITH_TIMEOUT(finished(*dock), kWaitMs);
    const QImage before = dock->image(Pane::PathTraced);
    const std::vector<float> linear = dock->linearImage(Pane::PathTraced);
    const int generation = dock->status(Pane::PathTraced).generation;
    QSignalSpy started(dock.get(), &LitSpheresDock::runStarted);
    QSignalSpy redrawn(dock.get(), &LitSpheresDock::displayChanged);

    auto* slider = dock->findChild<QSlider*>("exposure");
    QVERIFY(slider != nullptr);
    slider->setValue(-20);  // -2 stops: a quarter of the linear values
    QCOMPARE(dock->exposure(), -2.0);
    QVERIFY(redrawn.count() >= 1);
    const QImage after = dock->image(Pane::PathTraced);
    QCOMPARE(after.size(), before.size());
    int darker = 0, brighter = 0;
    for (int y = 0; y < kSize; ++y)
      for (int x = 0; x < kSize; ++x) {
        darker += qGray(after.pixel(x, y)) < qGray(before.pixel(x, y)) ? 1 : 0;
        brighter += qGray(after.pixel(x, y)) > qGray(before.pixel(x, y)) ? 1 : 0;
      }
    QVERIFY2(darker > kSize * kSize / 4, qPrintable(QString("%1 darker pixels").arg(darker)));
    QCOMPARE(brighter, 0);
    // Nothing recomputed: same run, same data, no run started.
    QCOMPARE(started.count(), 0);
    QCOMPARE(dock->status(Pane::PathTraced).generation, generation);
    QVERIFY(dock->linearImage(Pane::PathTraced) == linear);

    auto* gamma = dock->findChild<QSlider*>("gamma");
    QVERIFY(gamma != nullptr);
    gamma->setValue(10);
    QCOMPARE(dock->gamma(), 1.0);
    QCOMPARE(started.count(), 0);
  }

  void modelTheIntegrationCannotUseIsReportedAndChangesNothing() {
    ExplorerState state;
    auto dock = smallDock(state);
    QTRY_VERIFY_WITH_TIMEOUT(finished(*dock), kWaitMs);
    const auto integrated = dock->linearImage(Pane::Integrated);
    const int gen[2] = {dock->status(Pane::PathTraced).generation,
                        dock->status(Pane::Integrated).generation};
    QStringList errors;
    connect(&state, &ExplorerState::message, this, [&](MessageLevel level, const QString& t) {
      if (level == MessageLevel::Error) errors << t;
    });
    QSignalSpy started(dock.get(), &LitSpheresDock::runStarted);
    state.setModel("/nonexistent/model.bssrdf");
    QTRY_COMPARE(errors.size(), 1);  // after the restart delay
    QVERIFY2(errors[0].contains("Lit spheres") && errors[0].contains("/nonexistent/model.bssrdf"),
             qPrintable(errors[0]));
    QCOMPARE(started.count(), 0);  // the medium did not change: the path tracer goes on as well
    QCOMPARE(dock->status(Pane::PathTraced).generation, gen[0]);
    QCOMPARE(dock->status(Pane::Integrated).generation, gen[1]);
    QVERIFY(dock->linearImage(Pane::Integrated) == integrated);
    // Back to the model of the images shown: they are current again, nothing is recomputed.
    state.setModel("dipole");
    QTest::qWait(3 * LitSpheresDock::kRestartDelayMs);
    QCOMPARE(started.count(), 0);
    QCOMPARE(errors.size(), 1);
    QVERIFY(dock->linearImage(Pane::Integrated) == integrated);
  }

  // .bssrdf models (issue 14 §3): a radial file is integrated through its GPU values tabulated for
  // the medium, so its image is the registered twin's to the table's precision (the CLI's
  // `integrate sphere` path: 1.4e-6); a directional file is integrated on the GPU with the light's
  // direction, and its mean agrees with the C++ directional dipole's within the noise.
  void bssrdfModelsAreIntegrated() {
    const std::string dir = TRANSLUCENT_TEST_BSSRDF_DIR;
    ExplorerState state;
    state.setModel("better-dipole");
    auto dock = smallDock(state);
    QTRY_VERIFY_WITH_TIMEOUT(finished(*dock), kWaitMs);
    const auto cpp = dock->linearImage(Pane::Integrated);
    QStringList errors;
    connect(&state, &ExplorerState::message, this, [&](MessageLevel level, const QString& t) {
      if (level == MessageLevel::Error) errors << t;
    });
    QSignalSpy started(dock.get(), &LitSpheresDock::runStarted);
    state.setModel(dir + "/better-dipole.bssrdf");
    QTRY_VERIFY_WITH_TIMEOUT(started.count() == 1, kWaitMs);
    QTRY_VERIFY_WITH_TIMEOUT(finished(*dock), kWaitMs);
    QVERIFY2(errors.isEmpty(), qPrintable(errors.join("; ")));
    const auto file = dock->linearImage(Pane::Integrated);
    QCOMPARE(file.size(), cpp.size());
    double worst = 0.0, peak = 0.0;
    for (float v : cpp) peak = std::max(peak, static_cast<double>(v));
    for (size_t i = 0; i < cpp.size(); ++i)
      worst = std::max(worst, std::abs(static_cast<double>(file[i]) - static_cast<double>(cpp[i])) / peak);
    qInfo("better-dipole.bssrdf vs better-dipole: largest difference %.2g of the peak", worst);
    QVERIFY(worst < 1e-4);

    // Directional: the C++ model on the CPU, then its file on the GPU.
    dock->setSampleBudget(256);
    state.setModel("directional-dipole");
    QTRY_VERIFY_WITH_TIMEOUT(finished(*dock) && dock->status(Pane::Integrated).done == 256, kWaitMs);
    const double cppMean = channelMean(dock->linearImage(Pane::Integrated), 1);
    started.clear();
    state.setModel(dir + "/directional-dipole.bssrdf");
    QTRY_VERIFY_WITH_TIMEOUT(started.count() == 1, kWaitMs);
    QTRY_VERIFY_WITH_TIMEOUT(finished(*dock), 3 * kWaitMs);
    QVERIFY2(errors.isEmpty(), qPrintable(errors.join("; ")));
    QCOMPARE(dock->status(Pane::Integrated).done, uint64_t{256});
    const double gpuMean = channelMean(dock->linearImage(Pane::Integrated), 1);
    qInfo("directional dipole, mean green exitance: C++ on the CPU %.5g, .bssrdf on the GPU %.5g",
          cppMean, gpuMean);
    // Image means of two independent 256-sample integrations of the same kernel (uniform
    // sampling on the GPU, of a kernel ~1/60 of the sphere radius wide: its noise dominates):
    // measured 2.5% apart; 5% allowed.
    QVERIFY(std::abs(gpuMean - cppMean) < 0.05 * cppMean);
  }

  void sideBySideShowsAllPanes() {
    ExplorerState state;
    LitSpheresDock dock(state);
    dock.resize(900, 500);
    dock.show();
    QVERIFY(!dock.sideBySide());  // seed 3.6.2: tabs first
    dock.setSideBySide(true);
    QVERIFY(dock.sideBySide());
    for (const char* name : {"path_traced_pane", "integration_pane", "difference_pane"}) {
      auto* w = dock.findChild<QWidget*>(name);
      QVERIFY(w != nullptr);
      QVERIFY2(w->isVisible(), name);
    }
    dock.setSideBySide(false);
    QVERIFY(!dock.sideBySide());
    // Tabs again: one page shown at a time (the first), the others hidden under it.
    QVERIFY(dock.findChild<QWidget*>("path_traced_pane")->isVisible());
    QVERIFY(!dock.findChild<QWidget*>("integration_pane")->isVisible());
    QVERIFY(!dock.findChild<QWidget*>("difference_pane")->isVisible());
  }

  void destroyingTheDockMidComputationReturnsPromptly() {
    ExplorerState state;
    // Default budgets (about 10^6 photons per channel): far more than the test waits for.
    auto dock = std::make_unique<LitSpheresDock>(state);
    QSignalSpy passes(dock.get(), &LitSpheresDock::passCompleted);
    QTRY_VERIFY_WITH_TIMEOUT(passes.count() >= 1, kWaitMs);
    QVERIFY(dock->status(Pane::PathTraced).running);
    // A restart just before (the previous runs may still be winding down).
    state.setMedium(presetMedium("Skin1", 25.0), "Skin1");
    QTRY_VERIFY(dock->status(Pane::PathTraced).generation == 2);
    QElapsedTimer timer;
    timer.start();
    dock.reset();
    qInfo("dock destroyed mid-computation in %lld ms", static_cast<long long>(timer.elapsed()));
    // The stop is polled ten times a second and a block is short: well under a second. The
    // bound leaves room for a loaded machine.
    QVERIFY2(timer.elapsed() < 3000, qPrintable(QString("%1 ms").arg(timer.elapsed())));
    // Queued calls from the runs must not reach the destroyed dock.
    QTest::qWait(50);

    // And right after construction, before any pass.
    auto fresh = std::make_unique<LitSpheresDock>(state);
    fresh.reset();
  }
};

QTEST_MAIN(TestLitSpheresDock)
#include "test_lit_spheres_dock.moc"
