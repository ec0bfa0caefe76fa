// SPDX-License-Identifier: GPL-3.0-or-later
// The Compare dock (apps/explorer/compare): the technique frame and the reference appear, the
// reference refines pass by pass (its photon count grows, the numbers shown change), the metrics
// shown are analysis::computeMetrics of the images shown (bit for bit), the physical reference
// after N photons is the one-shot reference of the CLI (bit for bit), a material change restarts
// the reference, an environment map that cannot be read is reported on the console, the model reference refines
// with doubling sample counts, and destroying the dock mid-run returns within a second.
//
// Small images (32 pixels wide, the default scene's square camera: 32²) and budgets keep each
// case to a few seconds on two cores. The scene is the explorer's default (the bunny in Marble,
// the point-cloud technique).
#include <QtCore/QElapsedTimer>
#include <QtTest/QSignalSpy>
#include <QtTest/QTest>
#include <QtWidgets/QComboBox>
#include <QtWidgets/QSpinBox>
#include <QtWidgets/QLabel>

#include <bit>
#include <cmath>
#include <memory>
#include <vector>

#include "translucent/compare/compare.h"
#include "translucent/analysis/metrics.h"
#include "compare/compare_dock.h"
#include "core/explorer_state.h"
#include "translucent/optics/presets.h"

using namespace translucent;
using namespace translucent::explorer;

namespace {

constexpr int kWidth = 32;
// Passes of 16, 32 and 64 blocks of 1024 photons per channel.
constexpr uint64_t kPhotons = 112 * 1024;
constexpr int kWaitMs = 60000;

std::unique_ptr<CompareDock> smallDock(ExplorerState& state, uint64_t photons = kPhotons) {
  auto dock = std::make_unique<CompareDock>(state);
  dock->setImageWidth(kWidth);
  dock->setPhotonBudget(photons);
  dock->show();  // nothing runs before the dock is shown
  return dock;
}

Medium presetMedium(const char* name, double scale) {
  const auto& p = preset(name);
  return Medium::fromReduced(p.sigma_a, p.sigma_s_prime, p.g, p.eta, scale);
}

// Equal as stored (NaN equals NaN): the dock must show exactly what the library computes.
bool same(double a, double b) { return std::bit_cast<uint64_t>(a) == std::bit_cast<uint64_t>(b); }

bool sameMetrics(const analysis::Metrics& a, const analysis::Metrics& b) {
  return a.pixels == b.pixels && same(a.mean_reference, b.mean_reference) &&
         same(a.mean_test, b.mean_test) && same(a.rel_rmse, b.rel_rmse) &&
         same(a.rel_rmse_raw, b.rel_rmse_raw) && same(a.noise_mse, b.noise_mse) &&
         same(a.noise_mse_stderr, b.noise_mse_stderr) && same(a.noise_variance, b.noise_variance) &&
         same(a.bias, b.bias) && same(a.bias_stderr, b.bias_stderr) && same(a.ssim, b.ssim) &&
         same(a.flip, b.flip) && same(a.mean_abs_z, b.mean_abs_z) &&
         same(a.fraction_abs_z_above_3, b.fraction_abs_z_above_3) && a.z_pixels == b.z_pixels;
}

double mean(const std::vector<float>& v) {
  double s = 0.0;
  for (float x : v) s += static_cast<double>(x);
  return v.empty() ? 0.0 : s / static_cast<double>(v.size());
}

}  // namespace

class TestCompareDock : public QObject {
  Q_OBJECT

 private slots:
  void nothingRunsWhileHidden() {
    ExplorerState state;
    CompareDock dock(state);
    QCOMPARE(dock.objectName(), QString("compare"));
    QTest::qWait(200);
    QCOMPARE(dock.status().generation, 0);
    QVERIFY(!dock.status().running);
    dock.setImageWidth(kWidth);
    dock.setPhotonBudget(4096 * 1024);
    dock.show();
    QTRY_VERIFY_WITH_TIMEOUT(dock.status().running, 5000);
    QCOMPARE(dock.status().generation, 1);
    // Hidden: the run stops and scene changes start nothing.
    dock.hide();
    QTRY_VERIFY(!dock.status().running);
    state.setMedium(presetMedium("Skin1", 25.0), "Skin1");
    QTest::qWait(4 * CompareDock::kRestartDelayMs);
    QCOMPARE(dock.status().generation, 1);
    // Shown again: one run for the current scene.
    dock.show();
    QTRY_VERIFY(dock.status().running);
    QCOMPARE(dock.status().generation, 2);
  }

  void refinesAndShowsTheLibrarysMetrics() {
    ExplorerState state;
    // The technique's first frame (its prepare: the point cloud) takes longer than a small
    // reference: one pass first, then the refinement is watched with the frame there.
    auto dock = smallDock(state, 16 * 1024);
    QSignalSpy frames(dock.get(), &CompareDock::techniqueFrameReceived);
    QTRY_VERIFY_WITH_TIMEOUT(!dock->status().running && dock->metrics().has_value(), kWaitMs);
    QCOMPARE(frames.count(), 1);
    qInfo("technique frame: prepare %.0f ms, render %.1f ms; first reference pass %.2f s",
          dock->techniqueFrame()->prepare_ms, dock->techniqueFrame()->render_ms,
          dock->status().seconds);
    dock->setPhotonBudget(kPhotons);
    QCOMPARE(dock->status().generation, 2);
    struct Seen {
      CompareDock::Status status;
      analysis::Metrics metrics;
      QString text;
    };
    std::vector<Seen> seen;
    int checked = 0;
    connect(dock.get(), &CompareDock::comparisonChanged, this, [&] {
      if (!dock->metrics()) return;
      seen.push_back({dock->status(), *dock->metrics(), dock->metricsText()});
      // Shown = computed by the library from the images shown, over the mask shown.
      analysis::MetricOptions o = dock->displayOptions();
      o.mask = dock->comparedMask();
      const analysis::Metrics again =
          analysis::computeMetrics(dock->comparedTest().ref(), dock->comparedReference().ref(), o);
      QVERIFY(sameMetrics(again, *dock->metrics()));
      ++checked;
    });
    QTRY_VERIFY_WITH_TIMEOUT(!dock->status().running && dock->status().passes == 3, kWaitMs);
    QVERIFY(dock->metrics().has_value());
    QCOMPARE(checked, 3);  // a comparison after every pass
    QCOMPARE(frames.count(), 1);  // a new budget needs no new technique frame

    // One run, refined: the photon count grows pass by pass (16, 48, 112 blocks) and the
    // numbers shown change with it.
    const CompareDock::Status s = dock->status();
    QCOMPARE(s.generation, 2);
    QCOMPARE(s.count, kPhotons);
    QVERIFY(s.technique);
    QVERIFY2(seen.size() >= 2, qPrintable(QString("%1 comparisons").arg(seen.size())));
    for (size_t k = 1; k < seen.size(); ++k) {
      QVERIFY(seen[k].status.count >= seen[k - 1].status.count);
      if (seen[k].status.count > seen[k - 1].status.count) {
        QVERIFY(seen[k].text != seen[k - 1].text);
        QVERIFY(!same(seen[k].metrics.rel_rmse_raw, seen[k - 1].metrics.rel_rmse_raw));
        // More photons: less reference noise in the compared pixels (the variance per value
        // falls as 1 / photons: at least halved from one pass to the next, within 10%).
        QVERIFY(seen[k].metrics.noise_variance < 0.55 * seen[k - 1].metrics.noise_variance);
      }
    }
    QCOMPARE(seen.front().status.count, uint64_t{16 * 1024});

    // The label shows the numbers: relative RMSE and bias in percent, two decimals.
    const analysis::Metrics& m = *dock->metrics();
    const QString label = dock->findChild<QLabel*>("metrics")->text();
    QCOMPARE(label, dock->metricsText());
    QVERIFY(label.contains(QString::number(100.0 * m.rel_rmse, 'f', 2) + "%"));
    QVERIFY(label.contains(QString::number(100.0 * m.bias, 'f', 2) + "%"));
    // Sizes: the technique frame at the reference's camera, nothing resampled.
    QCOMPARE(dock->comparedTest().width, kWidth);
    QCOMPARE(dock->comparedTest().height, dock->imageHeight());
    QCOMPARE(dock->comparedReference().width, kWidth);
    QCOMPARE(dock->differenceImage().size(), QSize(kWidth, dock->imageHeight()));
    // The interior of the bunny: a good part of the frame, and the point-cloud technique within
    // a factor of two of the path tracer there.
    qInfo("after %llu photons per channel (%.2f s): %s", static_cast<unsigned long long>(s.count),
          s.seconds, qPrintable(dock->metricsText()));
    QVERIFY(m.pixels > 100);
    QVERIFY(m.mean_test > 0.5 * m.mean_reference && m.mean_test < 2.0 * m.mean_reference);
  }

  void physicalReferenceIsTheClisOneShotReference() {
    ExplorerState state;
    auto dock = smallDock(state, 48 * 1024);  // passes of 16 and 32 blocks
    QTRY_VERIFY_WITH_TIMEOUT(!dock->status().running && dock->status().passes == 2, kWaitMs);
    QTRY_VERIFY_WITH_TIMEOUT(dock->metrics().has_value(), kWaitMs);
    dock->setQuantity(CompareDock::Quantity::Exitance);
    QVERIFY(dock->metrics().has_value());  // the point-cloud technique has an exitance layer
    scene::Scene s = state.scene();
    s.camera.width = kWidth;
    s.camera.height = dock->imageHeight();
    const analysis::Reference once = analysis::computeReference(
        s, scene::loadSceneMesh(s), {analysis::ReferenceKind::Physical, 48 * 1024, 1, 0});
    QVERIFY(once.exitance.rgb == dock->comparedReference().rgb);
    QVERIFY(once.exitance.se == dock->comparedReference().se);
  }

  void physicalReferenceOnTheGpuIsTheLibrarysGpuReference() {
    // The dock's device box (auto: the CPU on llvmpipe) set to GPU: the physical reference is
    // traced by the GPU walk, the status says so, and the image is, bit for bit, the one-shot
    // GPU reference of the library (the walk's streams are per photon: passes do not matter).
    ExplorerState state;
    auto dock = smallDock(state, 48 * 1024);
    auto* box = dock->findChild<QComboBox*>("tracer_device");
    QVERIFY(box);
    QCOMPARE(dock->tracerDevice(), std::string("auto"));
    box->setCurrentIndex(box->findData(QStringLiteral("gpu")));
    QCOMPARE(dock->tracerDevice(), std::string("gpu"));
    QTRY_VERIFY_WITH_TIMEOUT(!dock->status().running && dock->status().passes == 2, kWaitMs);
    QTRY_VERIFY_WITH_TIMEOUT(dock->metrics().has_value(), kWaitMs);
    QVERIFY(dock->findChild<QWidget*>("reference_pane")->findChildren<QLabel*>().size() >= 2);
    bool said = false;
    for (const QLabel* l : dock->findChild<QWidget*>("reference_pane")->findChildren<QLabel*>())
      said |= l->text().contains("on the GPU");
    QVERIFY(said);
    dock->setQuantity(CompareDock::Quantity::Exitance);
    scene::Scene s = state.scene();
    s.camera.width = kWidth;
    s.camera.height = dock->imageHeight();
    analysis::ReferenceRequest gpu{analysis::ReferenceKind::Physical, 48 * 1024, 1, 0};
    gpu.device = "gpu";
    const analysis::Reference once = analysis::computeReference(s, scene::loadSceneMesh(s), gpu);
    QVERIFY(once.exitance.rgb == dock->comparedReference().rgb);
    QVERIFY(once.exitance.se == dock->comparedReference().se);
    const analysis::Reference cpu = analysis::computeReference(
        s, scene::loadSceneMesh(s), {analysis::ReferenceKind::Physical, 48 * 1024, 1, 0});
    QVERIFY(cpu.exitance.rgb != once.exitance.rgb);
  }

  void techniqueSettingRendersAgainWithoutANewReference() {
    ExplorerState state;
    auto dock = smallDock(state, 16 * 1024);
    QSignalSpy frames(dock.get(), &CompareDock::techniqueFrameReceived);
    QTRY_VERIFY_WITH_TIMEOUT(!dock->status().running && dock->metrics().has_value(), kWaitMs);
    const std::vector<float> before = dock->comparedReference().rgb;
    // QVERIFY, not QCOMPARE: QTest would free the static string of bssrdf::toString.
    const bssrdf::ExitConvention from = dock->techniqueFrame()->convention;
    const bssrdf::ExitConvention to = from == bssrdf::ExitConvention::Jensen
                                          ? bssrdf::ExitConvention::Normalized
                                          : bssrdf::ExitConvention::Jensen;

    // The other convention (Eq. 2.16): the technique's L changes, the reference does not, and
    // L's reference is the same image times the ratio of the conventions' scales
    // (Reference::radianceFor).
    state.setTechniqueSetting("radiance_convention", std::string(bssrdf::toString(to)));
    QTRY_VERIFY_WITH_TIMEOUT(frames.count() == 2 && dock->metrics().has_value(), kWaitMs);
    QVERIFY(!dock->metricsText().contains("previous settings"));
    QCOMPARE(dock->status().generation, 1);  // no new reference
    QVERIFY(dock->techniqueFrame()->convention == to);
    const double eta = state.scene().medium.eta;
    const double jensenToNormalized =
        bssrdf::exitConventionScale(bssrdf::ExitConvention::Normalized, eta);
    QVERIFY(jensenToNormalized > 1.0);  // 1 / 4C_φ(1/η), 4C_φ < 1
    const std::vector<float>& after = dock->comparedReference().rgb;
    QCOMPARE(after.size(), before.size());
    // radianceFor scales the stored Jensen image once (in double, rounded to float): compare
    // the ratio to the conventions' ratio within float rounding (2 ulp of each value).
    const double ratio = to == bssrdf::ExitConvention::Normalized ? jensenToNormalized
                                                                  : 1.0 / jensenToNormalized;
    for (size_t i = 0; i < before.size(); ++i) {
      const double expected = static_cast<double>(before[i]) * ratio;
      QVERIFY2(std::abs(static_cast<double>(after[i]) - expected) <= 2.5e-7 * std::abs(expected),
               qPrintable(QString("value %1: %2 vs %3").arg(i).arg(after[i]).arg(expected)));
    }
  }

  void materialChangeRestartsTheReference() {
    ExplorerState state;
    auto dock = smallDock(state, 4096 * 1024);  // far more than the test waits for
    QSignalSpy frames(dock.get(), &CompareDock::techniqueFrameReceived);
    QTRY_VERIFY_WITH_TIMEOUT(dock->status().passes >= 1 && dock->metrics(), kWaitMs);
    QVERIFY(dock->status().running);
    QCOMPARE(dock->status().generation, 1);
    QCOMPARE(frames.count(), 1);
    const double marble = mean(dock->comparedReference().rgb);

    QSignalSpy started(dock.get(), &CompareDock::runStarted);
    // Two changes in a row (a slider drag) make one restart.
    state.setMedium(presetMedium("Skin1", 25.0), "Skin1");
    state.setMedium(presetMedium("Ketchup", 25.0), "Ketchup");
    QTRY_COMPARE_WITH_TIMEOUT(started.count(), 1, 5000);
    QCOMPARE(dock->status().generation, 2);
    QCOMPARE(dock->status().passes, 0);  // the pass counter starts again
    QVERIFY(!dock->metrics().has_value() || dock->status().passes > 0);
    QTRY_VERIFY_WITH_TIMEOUT(dock->status().passes >= 1 && dock->status().technique &&
                                 dock->metrics().has_value(),
                             kWaitMs);
    // Ketchup absorbs green and blue strongly (σa 0.97 and 1.45 /mm against marble's 0.004 and
    // 0.005): its reference is far darker than marble's, far beyond the noise of 16 blocks.
    const double ketchup = mean(dock->comparedReference().rgb);
    QVERIFY2(ketchup < 0.7 * marble, qPrintable(QString("%1 vs %2").arg(ketchup).arg(marble)));
    QCOMPARE(frames.count(), 2);  // and the technique was rendered again, once
    QTest::qWait(300);
    QCOMPARE(started.count(), 1);
  }

  void missingEnvironmentMapGoesToTheConsole() {
    ExplorerState state;
    auto dock = smallDock(state);
    QTRY_VERIFY_WITH_TIMEOUT(dock->status().passes >= 1, kWaitMs);
    const int generation = dock->status().generation;
    QStringList errors;
    connect(&state, &ExplorerState::message, this, [&](MessageLevel level, const QString& text) {
      if (level == MessageLevel::Error) errors << text;
    });
    scene::Light env;
    env.emitter = scene::EnvironmentLight{"/nonexistent/sky.exr", 1.0, 0.0, false};
    state.setLights({env});
    QTRY_VERIFY_WITH_TIMEOUT(!errors.isEmpty(), 5000);
    // The dock's own message (its render thread reports the missing map separately).
    QVERIFY2(errors.join("\n").contains("Compare: no physical reference for this scene"),
             qPrintable(errors.join("\n")));
    QCOMPARE(dock->status().generation, generation);  // nothing started
    // Turning the environment (a right drag) reports the same reason once, not per step.
    const qsizetype reported = errors.filter("Compare: no physical reference").size();
    QCOMPARE(reported, 1);
    env.emitter = scene::EnvironmentLight{"/nonexistent/sky.exr", 1.0, 30.0, false};
    state.setLights({env});
    QTest::qWait(4 * CompareDock::kRestartDelayMs);
    QCOMPARE(errors.filter("Compare: no physical reference").size(), reported);
    QVERIFY(!dock->status().running);
    QVERIFY(dock->findChild<QLabel*>("metrics")->text().contains("previous scene") ||
            !dock->metrics().has_value());
  }

  void modelReferenceRefinesWithDoublingSamples() {
    ExplorerState state;
    auto dock = std::make_unique<CompareDock>(state);
    dock->setImageWidth(kWidth);
    dock->setReferenceKind(analysis::ReferenceKind::Model);
    dock->setSampleBudget(40000);  // passes of 10 k, 20 k and 40 k samples
    dock->show();
    std::vector<CompareDock::Status> seen;
    connect(dock.get(), &CompareDock::passCompleted, this,
            [&](int) { seen.push_back(dock->status()); });
    QTRY_VERIFY_WITH_TIMEOUT(!dock->status().running && dock->status().passes == 3, kWaitMs);
    QCOMPARE(seen.size(), size_t{3});
    const uint64_t counts[] = {10000, 20000, 40000}, computed[] = {10000, 30000, 70000};
    for (size_t k = 0; k < 3; ++k) {
      QCOMPARE(seen[k].count, counts[k]);
      QCOMPARE(seen[k].computed, computed[k]);
    }
    QTRY_VERIFY_WITH_TIMEOUT(dock->metrics().has_value(), kWaitMs);
    QVERIFY(dock->metricsText().contains("model reference"));
    qInfo("after 40000 samples (%.2f s): %s", dock->status().seconds,
          qPrintable(dock->metricsText()));
    QVERIFY(dock->metrics()->pixels > 100);
  }

  void cameraMethodReferenceRefinesWithDoublingPaths() {
    // The physical reference from the camera method (the kind box's third entry): passes of 4,
    // 8 and 16 camera paths per pixel, its images the camera method's, its true radiance compared.
    ExplorerState state;
    auto dock = std::make_unique<CompareDock>(state);
    dock->setImageWidth(kWidth);
    dock->setPathBudget(28);
    auto* kind = dock->findChild<QComboBox*>("reference_kind");
    QVERIFY(kind);
    kind->setCurrentIndex(2);
    QVERIFY(dock->cameraMethod());
    QCOMPARE(dock->referenceKind(), analysis::ReferenceKind::Physical);
    QVERIFY(!dock->findChild<QSpinBox*>("photons")->isVisibleTo(dock.get()));
    QVERIFY(dock->findChild<QSpinBox*>("paths")->isVisibleTo(dock.get()));
    dock->setQuantity(CompareDock::Quantity::ConeRadiance);
    dock->show();
    std::vector<CompareDock::Status> seen;
    connect(dock.get(), &CompareDock::passCompleted, this,
            [&](int) { seen.push_back(dock->status()); });
    QTRY_VERIFY_WITH_TIMEOUT(!dock->status().running && dock->status().passes == 3, kWaitMs);
    QCOMPARE(seen.size(), size_t{3});
    const uint64_t counts[] = {4, 12, 28};
    for (size_t k = 0; k < 3; ++k) QCOMPARE(seen[k].count, counts[k]);
    QTRY_VERIFY_WITH_TIMEOUT(dock->metrics().has_value(), kWaitMs);
    QVERIFY(dock->metrics()->pixels > 100);
    qInfo("camera method, 28 paths (%.2f s): %s", dock->status().seconds,
          qPrintable(dock->metricsText()));
    // Back to the photons: the other method's images are not kept.
    kind->setCurrentIndex(0);
    QVERIFY(!dock->cameraMethod());
    QVERIFY(dock->findChild<QSpinBox*>("photons")->isVisibleTo(dock.get()));
  }

  void destroyingTheDockMidRunReturnsPromptly() {
    ExplorerState state;
    auto dock = smallDock(state, 4096 * 1024);
    QTRY_VERIFY_WITH_TIMEOUT(dock->status().passes >= 1 && dock->status().technique, kWaitMs);
    QVERIFY(dock->status().running);
    QElapsedTimer timer;
    timer.start();
    dock.reset();
    qInfo("dock destroyed mid-run in %lld ms", static_cast<long long>(timer.elapsed()));
    // The tracer polls the stop flag ten times a second and drops its block; the render thread
    // is idle (its frame is there). Well under a second; the bound allows a loaded machine.
    QVERIFY2(timer.elapsed() < 1000, qPrintable(QString("%1 ms").arg(timer.elapsed())));
    QTest::qWait(50);  // queued calls from the threads must not reach the destroyed dock

    // Right after being shown, before the first frame or pass: the render thread is creating its
    // context or preparing the technique (seconds), which the dock does not wait for.
    auto fresh = smallDock(state);
    QTRY_VERIFY(fresh->status().running);
    QTest::qWait(200);
    const bool preparing = !fresh->techniqueFrame();
    timer.restart();
    fresh.reset();
    qInfo("dock destroyed %s in %lld ms", preparing ? "during the technique's prepare" : "",
          static_cast<long long>(timer.elapsed()));
    // The reference run is in its setup (mesh load, masks, BVH: read the stop flag between
    // steps only), the render thread in its prepare (not waited for): the slowest setup step
    // bounds it, about a second on a loaded machine.
    QVERIFY2(timer.elapsed() < 3000, qPrintable(QString("%1 ms").arg(timer.elapsed())));
  }
};

QTEST_MAIN(TestCompareDock)
#include "test_compare_dock.moc"
