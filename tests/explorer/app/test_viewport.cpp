// SPDX-License-Identifier: GPL-3.0-or-later
// The viewport under Xvfb on whatever OpenGL 4.5 the machine has (Mesa llvmpipe here): the first
// image of the default scene, a technique switch, a broken mesh, the round trip through the CLI
// and the tone map on screen. Settings are cut down (few points, coarse traversal, a 128x96
// picture) so that llvmpipe renders a frame in about a second.
#include <QtCore/QProcess>
#include <QtCore/QTemporaryDir>
#include <QtTest/QtTest>
#include <QtWidgets/QCheckBox>
#include <QtWidgets/QComboBox>
#include <QtWidgets/QDoubleSpinBox>
#include <QtWidgets/QMainWindow>
#include <QtWidgets/QSlider>
#include <QtWidgets/QPushButton>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "translucent/io/image_io.h"
#include "translucent/lights/environment_map.h"
#include "app/console_dock.h"
#include "app/technique_views_dock.h"
#include "app/main_window.h"
#include "app/view_math.h"
#include "app/viewport_dock.h"
#include "app/viewport_widget.h"
#include "core/explorer_state.h"
#include "translucent/geometry/icosphere.h"

using namespace translucent;
using namespace translucent::explorer;

namespace {

constexpr int kFrameTimeoutMs = 60000;

// Mean luminance-like average of |a - b| over the mean of a (linear RGB, same size).
double relativeMeanDifference(const std::vector<float>& a, const std::vector<float>& b) {
  double diff = 0.0, ref = 0.0;
  for (size_t i = 0; i < a.size(); ++i) {
    diff += std::abs(double(a[i]) - double(b[i]));
    ref += std::abs(double(a[i]));
  }
  return ref > 0.0 ? diff / ref : 0.0;
}

}  // namespace

class Viewport : public QObject {
  Q_OBJECT

 private:
  ExplorerState* state_ = nullptr;
  QMainWindow* window_ = nullptr;
  ViewportDock* dock_ = nullptr;
  ConsoleDock* console_ = nullptr;
  int full_frames_ = 0;
  std::shared_ptr<const RenderedFrame> full_;
  QTemporaryDir dir_;

  // Pixels of the screen image that differ by more than one 8-bit level from the frame tone
  // mapped on the CPU (analysis::toneMap, as the CLI's PNG).
  static int pixelsOffTheToneMap(const QImage& img, const techniques::Frame& f, const analysis::ToneMap& tm) {
    int bad = 0;
    for (int y = 0; y < f.height; ++y)
      for (int x = 0; x < f.width; ++x) {
        const QRgb p = img.pixel(x, y);
        const float* v = &f.rgb[(size_t(y) * f.width + x) * 3];
        const int ref[3] = {analysis::toneMap(v[0], tm), analysis::toneMap(v[1], tm),
                            analysis::toneMap(v[2], tm)};
        bad += std::abs(qRed(p) - ref[0]) > 1 || std::abs(qGreen(p) - ref[1]) > 1 ||
               std::abs(qBlue(p) - ref[2]) > 1;
      }
    return bad;
  }

  // Waits for the next full-resolution frame of technique `technique` after the call.
  std::shared_ptr<const RenderedFrame> nextFull(const std::string& technique) {
    const int before = full_frames_;
    const bool ok = QTest::qWaitFor(
        [&] { return full_frames_ > before && full_ != nullptr && full_->technique == technique; },
        kFrameTimeoutMs);
    return ok ? full_ : nullptr;
  }

 private slots:
  void initTestCase() {
    QVERIFY(dir_.isValid());
    state_ = new ExplorerState;
    window_ = new QMainWindow;
    console_ = new ConsoleDock(*state_, window_);
    dock_ = new ViewportDock(*state_, window_);
    window_->addDockWidget(Qt::TopDockWidgetArea, dock_);
    window_->addDockWidget(Qt::BottomDockWidgetArea, console_);
    dock_->view()->setFixedSize(128, 96);
    dock_->fixRenderScale(1.0);
    connect(dock_, &ViewportDock::frameShown, this,
            [this](std::shared_ptr<const RenderedFrame> f, bool full) {
              if (!full) return;
              full_ = std::move(f);
              ++full_frames_;
            });
    // Cheap point-cloud settings for llvmpipe.
    state_->setTechniqueSetting("points", 4000.0);
    state_->setTechniqueSetting("epsilon", 1.0);
    state_->setTechniqueSetting("shadow_map_size", 512.0);
    window_->show();
    QVERIFY(QTest::qWaitForWindowExposed(window_));
  }

  void cleanupTestCase() {
    delete window_;
    delete state_;
  }

  void drawsANonEmptyImageOfTheDefaultScene() {
    const auto f = nextFull("pointcloud");
    QVERIFY2(f != nullptr, qPrintable(console_->text()));
    QVERIFY(dock_->view()->displayReady());
    QCOMPARE(f->frame.width, 128);
    QCOMPARE(f->frame.height, 96);
    QCOMPARE(f->faces, size_t(69666));  // the glmark2 bunny
    // On screen: the bunny covers a good part of the picture (> 15% of the pixels brighter than
    // the black background) and the picture is not flat (grey-level standard deviation > 10).
    QApplication::processEvents();
    const QImage img = dock_->view()->grabFramebuffer();
    QCOMPARE(img.width(), 128);
    int lit = 0;
    double sum = 0.0, sum2 = 0.0;
    for (int y = 0; y < img.height(); ++y)
      for (int x = 0; x < img.width(); ++x) {
        const int g = qGray(img.pixel(x, y));
        lit += g > 8;
        sum += g;
        sum2 += double(g) * g;
      }
    const double n = double(img.width()) * img.height();
    const double sd = std::sqrt(std::max(0.0, sum2 / n - (sum / n) * (sum / n)));
    qInfo("lit pixels %d of %g, grey standard deviation %g", lit, n, sd);
    QVERIFY2(lit > 0.15 * n, qPrintable(QStringLiteral("lit pixels %1 of %2").arg(lit).arg(n)));
    QVERIFY2(sd > 10.0, qPrintable(QStringLiteral("grey standard deviation %1").arg(sd)));
  }

  void screenShowsTheFrameToneMapped() {
    // The display shader's tone map against analysis::toneMap (the CLI's PNG) on the same linear
    // frame, pixel by pixel (the picture is the frame's size): within one 8-bit level.
    QVERIFY(full_ != nullptr);
    const QImage img = dock_->view()->grabFramebuffer();
    const auto& f = full_->frame;
    const analysis::ToneMap tm{state_->scene().exposure, state_->scene().gamma};
    const int bad = pixelsOffTheToneMap(img, f, tm);
    QVERIFY2(bad == 0, qPrintable(QStringLiteral("%1 pixels differ by more than one level").arg(bad)));
  }

  void reinhardToneMapMatchesThePngWriters() {
    // The dock's tone map set to Reinhard (key 0.5): the display shader against analysis::toneMap
    // with the frame's own average (what writePng uses), pixel by pixel within one 8-bit level;
    // then back to clamp.
    QVERIFY(full_ != nullptr);
    auto* op = dock_->controlsDock()->findChild<QComboBox*>(QStringLiteral("tonemap"));
    auto* key = dock_->controlsDock()->findChild<QDoubleSpinBox*>(QStringLiteral("tonemap_key"));
    QVERIFY(op != nullptr && key != nullptr);
    const std::string technique = full_->technique;
    key->setValue(0.5);
    op->setCurrentIndex(1);
    QCOMPARE(state_->scene().tonemap, analysis::ToneOperator::Reinhard);
    QCOMPARE(state_->scene().tonemap_key, 0.5);
    const auto shown = nextFull(technique);  // a display change renders the view again
    QVERIFY(shown != nullptr);
    const QImage img = dock_->view()->grabFramebuffer();
    const auto& f = shown->frame;
    const analysis::ToneMap tm = analysis::withImageAverage(scene::displayToneMap(state_->scene()), f.rgb);
    QVERIFY(tm.average > 0.0);
    const int bad = pixelsOffTheToneMap(img, f, tm);
    int bright = 0;
    for (size_t i = 1; i < f.rgb.size(); i += 3) bright += analysis::toneMap(f.rgb[i], tm) > 64;
    op->setCurrentIndex(0);
    key->setValue(1.0);
    QVERIFY(nextFull(technique) != nullptr);
    QVERIFY2(bad == 0, qPrintable(QStringLiteral("%1 pixels differ by more than one level").arg(bad)));
    QVERIFY2(bright > 0, "no pixel brighter than a quarter of white: the test would pass on black");
  }

  void savedSceneRendersTheSameThroughTheCli() {
    QVERIFY(full_ != nullptr);
    const auto f = full_;
    const QString json = dir_.filePath(QStringLiteral("view.json"));
    const QString exr = dir_.filePath(QStringLiteral("view.exr"));
    scene::saveScene(MainWindow::sceneForCli(state_->scene(), f->frame.width, f->frame.height),
                     json.toStdString());
    QProcess cli;
    cli.start(QStringLiteral(TRANSLUCENT_CLI), {QStringLiteral("render"), json, QStringLiteral("--exr"), exr});
    QVERIFY(cli.waitForFinished(120000));
    QVERIFY2(cli.exitCode() == 0, cli.readAllStandardError().constData());
    const analysis::RgbImage img = analysis::readRgb(exr.toStdString());
    QCOMPARE(img.width, f->frame.width);
    QCOMPARE(img.height, f->frame.height);
    // Same scene, same code, same kind of context: the linear frames agree to 0.1% (mean
    // absolute difference over mean value; float summation order is the only freedom).
    const double d = relativeMeanDifference(f->frame.rgb, img.rgb);
    qInfo("viewport vs CLI: relative mean difference %g", d);
    QVERIFY2(d < 1e-3, qPrintable(QStringLiteral("relative mean difference %1").arg(d)));
  }

  // Orbiting (issue 14 §6): a camera move reaches the point cloud through setCamera, not
  // prepare(): the frames after it render no shadow maps and no irradiance pass and take no
  // preparation time, and the image changes (the bunny turned).
  void cameraOrbitKeepsTheLighting() {
    QVERIFY(full_ != nullptr);
    const auto before = full_;
    state_->setCamera(orbit(state_->scene().camera, 0.4, 0.0));
    const auto after = nextFull("pointcloud");
    QVERIFY2(after != nullptr, qPrintable(console_->text()));
    QCOMPARE(after->prepare_ms, 0.0);
    for (const auto& pass : after->frame.passes)
      QVERIFY2(pass.name != "shadow maps" && pass.name != "irradiance", pass.name.c_str());
    const double d = relativeMeanDifference(before->frame.rgb, after->frame.rgb);
    qInfo("orbit by 0.4 rad: relative mean difference %g", d);
    QVERIFY(d > 0.01);
  }

  // The overlay's switches (issue 14 §7): the axes change what is on screen, and red (the x
  // axis) appears; off again, the picture is the frame's.
  void overlayShowsTheAxes() {
    QVERIFY(full_ != nullptr);
    QApplication::processEvents();
    const QImage plain = dock_->view()->grabFramebuffer();
    auto* axes = dock_->controlsDock()->findChild<QCheckBox*>(QStringLiteral("show_axes"));
    QVERIFY(axes != nullptr);
    axes->setChecked(true);
    QVERIFY(dock_->view()->axesShown());
    QApplication::processEvents();
    const QImage shown = dock_->view()->grabFramebuffer();
    int changed = 0, red = 0;
    for (int y = 0; y < shown.height(); ++y)
      for (int x = 0; x < shown.width(); ++x) {
        const QRgb a = plain.pixel(x, y), b = shown.pixel(x, y);
        if (a != b) ++changed;
        if (qRed(b) > 180 && qGreen(b) < 120 && qBlue(b) < 120) ++red;
      }
    qInfo("axes overlay: %d pixels changed, %d red", changed, red);
    QVERIFY(changed > 20);
    QVERIFY(red > 5);
    axes->setChecked(false);
    QApplication::processEvents();
    QVERIFY(dock_->view()->grabFramebuffer() == plain);
  }

  void switchingTechniqueChangesTheImage() {
    QVERIFY(full_ != nullptr);
    const auto before = full_;
    state_->setTechnique("empirical");
    state_->setTechniqueSetting("ao_rays", 16.0);
    const auto after = nextFull("empirical");
    QVERIFY2(after != nullptr, qPrintable(console_->text()));
    QCOMPARE(after->frame.rgb.size(), before->frame.rgb.size());
    // Different shading models of the same bunny: they differ by more than 20% of the mean.
    const double d = relativeMeanDifference(before->frame.rgb, after->frame.rgb);
    qInfo("pointcloud vs empirical: relative mean difference %g", d);
    QVERIFY2(d > 0.2, qPrintable(QStringLiteral("relative mean difference %1").arg(d)));
  }

  // "Reload shaders" (issue 14 §7): the technique's shaders are read from disk again. With the
  // shader folder copied (TRANSLUCENT_SHADER_DIR) and the empirical shading pass edited to halve
  // its colour, a reload halves the image; a GLSL error is reported on the console with the file
  // and the previous shaders go on rendering; the original folder back, a reload restores it.
  void reloadShadersRebuildsFromDisk() {
    QVERIFY(full_ != nullptr && full_->technique == "empirical");
    const auto before = full_;
    const QString copy = dir_.filePath(QStringLiteral("shaders"));
    std::filesystem::copy(TRANSLUCENT_SHADER_DIR, copy.toStdString(),
                          std::filesystem::copy_options::recursive);
    const std::string shade = copy.toStdString() + "/empirical/shade.comp";
    std::string text;
    {
      std::ifstream in(shade);
      std::stringstream ss;
      ss << in.rdbuf();
      text = ss.str();
    }
    const std::string store = "imageStore(OutColor, p, vec4(color, 1.0));";
    QVERIFY(text.find(store) != std::string::npos);
    auto write = [&](const std::string& replacement) {
      std::string t = text;
      t.replace(t.find(store), store.size(), replacement);
      std::ofstream(shade) << t;
    };
    qputenv("TRANSLUCENT_SHADER_DIR", copy.toUtf8());
    write("imageStore(OutColor, p, vec4(0.5 * color, 1.0));");
    auto* reload = dock_->controlsDock()->findChild<QPushButton*>(QStringLiteral("reload_shaders"));
    QVERIFY(reload != nullptr);
    reload->click();
    const auto halved = nextFull("empirical");
    QVERIFY2(halved != nullptr, qPrintable(console_->text()));
    double a = 0.0, b = 0.0;
    for (float v : before->frame.rgb) a += double(v);
    for (float v : halved->frame.rgb) b += double(v);
    QVERIFY2(std::abs(b / a - 0.5) < 1e-3, qPrintable(QString::number(b / a)));

    const int errors = console_->errorCount();
    write("imageStore(OutColor, p, vec4(color, 1.0)) +;");  // a syntax error
    reload->click();
    QVERIFY(QTest::qWaitFor([&] { return console_->errorCount() > errors; }, kFrameTimeoutMs));
    QVERIFY2(console_->text().contains(QStringLiteral("shade.comp")), qPrintable(console_->text()));
    const auto kept = nextFull("empirical");
    QVERIFY(kept != nullptr);
    double c = 0.0;
    for (float v : kept->frame.rgb) c += double(v);
    QVERIFY2(std::abs(c / a - 0.5) < 1e-3, qPrintable(QString::number(c / a)));  // the halving shaders

    qunsetenv("TRANSLUCENT_SHADER_DIR");
    reload->click();
    const auto restored = nextFull("empirical");
    QVERIFY(restored != nullptr);
    double d = 0.0;
    for (float v : restored->frame.rgb) d += double(v);
    QVERIFY2(std::abs(d / a - 1.0) < 1e-3, qPrintable(QString::number(d / a)));
  }

  // The explorer seed's file choices and the zoom slider (issue 14 §7): the filtered light's
  // texture and the environment map from files (each switches to its lighting mode and renders),
  // a map that cannot be read is an error on the console naming it, and the zoom slider sets the
  // camera's distance to its look-at point.
  void lightingFilesAndZoom() {
    state_->setTechnique("pointcloud");
    QVERIFY2(nextFull("pointcloud") != nullptr, qPrintable(console_->text()));
    auto* zoom = dock_->controlsDock()->findChild<QSlider*>(QStringLiteral("zoom"));
    QVERIFY(zoom != nullptr);
    zoom->setValue(600);
    const reference::Camera& c = state_->scene().camera;
    QVERIFY(std::abs(glm::length(c.position - c.look_at) - 0.05 * std::pow(1000.0, 0.6)) < 1e-9);
    QVERIFY(nextFull("pointcloud") != nullptr);

    const QString png = dir_.filePath(QStringLiteral("stripes.png"));
    QImage stripes(8, 8, QImage::Format_RGB32);
    for (int y = 0; y < 8; ++y)
      for (int x = 0; x < 8; ++x) stripes.setPixel(x, y, x % 2 ? qRgb(255, 255, 255) : qRgb(20, 20, 20));
    QVERIFY(stripes.save(png));
    const int errors = console_->errorCount();
    dock_->setFilterTexture(png);
    const auto* f = std::get_if<scene::FilteredDirectionalLight>(&state_->scene().lights.at(0).emitter);
    QVERIFY(f != nullptr);
    QCOMPARE(QString::fromStdString(f->texture.string()), png);
    QVERIFY2(nextFull("pointcloud") != nullptr, qPrintable(console_->text()));
    QCOMPARE(console_->errorCount(), errors);

    const QString exr = dir_.filePath(QStringLiteral("sky.exr"));
    const auto map = lights::EnvironmentMap::constant(glm::vec3(0.5f, 0.7f, 1.0f), 16, 8);
    analysis::writeExr(exr.toStdString(), map.width, map.height, map.rgb);
    dock_->setEnvironmentMap(exr);
    const auto* e = std::get_if<scene::EnvironmentLight>(&state_->scene().lights.at(0).emitter);
    QVERIFY(e != nullptr);
    QCOMPARE(QString::fromStdString(e->file.string()), exr);
    QVERIFY2(nextFull("pointcloud") != nullptr, qPrintable(console_->text()));
    QCOMPARE(console_->errorCount(), errors);

    dock_->setEnvironmentMap(dir_.filePath(QStringLiteral("missing.exr")));
    QVERIFY(QTest::qWaitFor([&] { return console_->errorCount() > errors; }, kFrameTimeoutMs));
    QVERIFY2(console_->text().contains(QStringLiteral("missing.exr")), qPrintable(console_->text()));
    state_->setLights(scene::defaultScene().lights);
    QVERIFY(nextFull("pointcloud") != nullptr);
    state_->setTechnique("empirical");  // what the next tests expect
    QVERIFY(nextFull("empirical") != nullptr);
  }

  void brokenMeshIsReportedAndTheLastGoodStateKeepsRendering() {
    const std::string good = state_->scene().mesh_file.string();
    const QString broken = dir_.filePath(QStringLiteral("broken.obj"));
    {
      std::ofstream out(broken.toStdString());
      out << "v 0 0 0\nv 1 0 0\nf 1 2 7\n";  // index out of range
    }
    const int errors = console_->errorCount();
    dock_->loadMesh(broken);
    QVERIFY(QTest::qWaitFor([&] { return console_->errorCount() > errors; }, kFrameTimeoutMs));
    QVERIFY2(console_->text().contains(QStringLiteral("broken.obj")), qPrintable(console_->text()));
    // The scene went back to the good mesh, and the viewport still renders it.
    QVERIFY(QTest::qWaitFor([&] { return state_->scene().mesh_file.string() == good; }, 5000));
    dock_->requestFullFrame();
    const auto f = nextFull("empirical");
    QVERIFY(f != nullptr);
    QCOMPARE(f->faces, size_t(69666));
    double sum = 0.0;
    for (float v : f->frame.rgb) sum += double(v);
    QVERIFY(sum > 0.0);
  }

  // A message repeated back to back is shown once, its line rewritten with the count (a renderer
  // failing on every frame must not flood the console); a different message in between starts
  // a new line; every error still counts.
  void repeatedMessagesAreShownOnceWithACount() {
    const int errors = console_->errorCount();
    const QString text = QStringLiteral("shader 'x.glsl' line 3: a test error");
    for (int i = 0; i < 3; ++i) console_->append(MessageLevel::Error, text);
    console_->append(MessageLevel::Info, QStringLiteral("something else"));
    console_->append(MessageLevel::Error, text);
    QCOMPARE(console_->errorCount(), errors + 4);
    const QStringList lines = console_->text().split(QLatin1Char('\n'));
    QVERIFY(lines.size() >= 3);
    const QStringList last = lines.mid(lines.size() - 3);
    QVERIFY2(last[0].endsWith(text + QStringLiteral(" (repeated 3 times)")), qPrintable(last[0]));
    QVERIFY2(last[1].endsWith(QStringLiteral("info: something else")), qPrintable(last[1]));
    QVERIFY2(last[2].endsWith(QStringLiteral("error: ") + text), qPrintable(last[2]));
    QCOMPARE(console_->text().count(text), 2);
  }

  // The technique views dock (seed Fig. 3.1 for tsis): visible, it asks the viewport for the
  // views; it then shows tsis's atlas, in which the frame's samples are drawn in red over the
  // grey irradiance.
  void techniqueViewsDockShowsTheTsisAtlasWithItsSamples() {
    auto* views = new TechniqueViewsDock(*dock_, window_);
    window_->addDockWidget(Qt::RightDockWidgetArea, views);
    views->show();
    const QString sphere = dir_.filePath(QStringLiteral("sphere.obj"));
    {
      const geometry::TriangleMesh m = geometry::makeIcosphere(2, 1.0);
      std::ofstream out(sphere.toStdString());
      for (const auto& p : m.positions) out << "v " << p.x << ' ' << p.y << ' ' << p.z << '\n';
      for (const auto& t : m.triangles) out << "f " << t.x + 1 << ' ' << t.y + 1 << ' ' << t.z + 1 << '\n';
    }
    dock_->loadMesh(sphere);
    state_->setTechnique("tsis");
    state_->setTechniqueSetting("atlas_size", 64.0);
    state_->setTechniqueSetting("samples", 64.0);
    state_->setTechniqueSetting("accumulate", false);
    state_->setTechniqueSetting("shadow_map_size", 256.0);
    QVERIFY2(nextFull("tsis") != nullptr, qPrintable(console_->text()));
    QVERIFY2(QTest::qWaitFor([&] { return !views->image().isNull(); }, kFrameTimeoutMs),
             qPrintable(console_->text()));
    QCOMPARE(views->viewNames(), QStringList{QStringLiteral("atlas")});
    QCOMPARE(views->image().width(), 64);
    int red = 0, grey = 0;
    for (int y = 0; y < 64; ++y)
      for (int x = 0; x < 64; ++x) {
        const QRgb p = views->image().pixel(x, y);
        red += qRed(p) > 200 && qGreen(p) < 80;
        grey += qRed(p) > 40 && std::abs(qRed(p) - qGreen(p)) < 4 && std::abs(qRed(p) - qBlue(p)) < 4;
      }
    qInfo("atlas view: %d red (sample) pixels, %d lit grey pixels", red, grey);
    QVERIFY(red >= 20);    // 64 samples, crosses of 5 pixels, some on the same texels
    QVERIFY(grey >= 200);  // the lit half of the sphere's charts
    delete views;
  }

  // Plots appear in the same dock as charts: splatting's minimal effective rendering radius
  // (Chen et al. 2012, Fig. 3b), two curves (the mean profile and one vertex's).
  void techniqueViewsDockShowsTheSplattingRadiusPlot() {
    auto* views = new TechniqueViewsDock(*dock_, window_);
    window_->addDockWidget(Qt::RightDockWidgetArea, views);
    views->show();
    state_->setTechnique("splatting");
    state_->setTechniqueSetting("irradiance_size", 64.0);
    QVERIFY2(nextFull("splatting") != nullptr, qPrintable(console_->text()));
    const QString name = QStringLiteral("plot: effective_radius");
    QVERIFY2(QTest::qWaitFor([&] { return views->viewNames().contains(name); }, kFrameTimeoutMs),
             qPrintable(views->viewNames().join(QStringLiteral(", "))));
    auto* choice = views->findChild<QComboBox*>();
    QVERIFY(choice != nullptr);
    choice->setCurrentText(name);
    QCOMPARE(views->currentView(), name);
    QCOMPARE(views->chartSeries(), 4);  // each curve is a line and its markers (plot::makeXyChart)
    delete views;
  }

  // Orbiting keeps tsm's light maps too (issue 14 §6), on the sphere of the previous test: the
  // move reaches tsm through setCamera (no preparation time), its frames render no light maps,
  // and the image changes (the sphere's lit side turned). The camera goes back after (the next
  // test's twist is measured from it).
  void cameraOrbitKeepsTheTsmLightMaps() {
    scene::Scene s = state_->scene();
    const reference::Camera camera = s.camera;
    s.technique = "tsm";
    s.settings.clear();  // tsis's settings are not tsm's
    state_->setScene(std::move(s));
    const auto before = nextFull("tsm");
    QVERIFY2(before != nullptr, qPrintable(console_->text()));
    state_->setCamera(orbit(state_->scene().camera, 0.6, 0.0));
    const auto after = nextFull("tsm");
    QVERIFY2(after != nullptr, qPrintable(console_->text()));
    QCOMPARE(after->prepare_ms, 0.0);
    for (const auto& pass : after->frame.passes) QVERIFY2(pass.name != "light maps", pass.name.c_str());
    const double d = relativeMeanDifference(before->frame.rgb, after->frame.rgb);
    qInfo("tsm, orbit by 0.6 rad: relative mean difference %g", d);
    QVERIFY(d > 0.01);
    state_->setCamera(camera);
    QVERIFY2(nextFull("tsm") != nullptr, qPrintable(console_->text()));
  }

  // Last: it leaves the render thread on a different technique and scene history. (Run before
  // brokenMeshIsReported..., that test's empirical frame did not arrive within 60 s: noted in
  // the closing note of 2026-12-02, not yet understood.)
  // mesh.deform (issue 13 §3: the explorer plays deformations): the time field and play are
  // off without a deformation; with one, a time changes the image, and play advances the time.
  void deformationTimeChangesTheImageAndPlayAdvancesIt() {
    auto* time = dock_->controlsDock()->findChild<QDoubleSpinBox*>(QStringLiteral("deform_time"));
    auto* play = dock_->controlsDock()->findChild<QCheckBox*>(QStringLiteral("deform_play"));
    QVERIFY(time != nullptr && play != nullptr);
    QVERIFY(state_->scene().mesh_deform.empty());
    QVERIFY(!time->isEnabled() && !play->isEnabled());
    const scene::Scene before = state_->scene();  // restored at the end for the next tests
    scene::Scene s = before;
    geometry::Deformation twist;
    twist.type = geometry::Deformation::Type::Twist;
    twist.amount = 120.0;  // degrees per unit length: the ears turn by ~60 degrees
    twist.period = 4.0;
    s.mesh_deform = {twist};
    s.time = 0.0;
    s.technique = "tsm";
    s.settings.clear();  // the previous technique's (empirical's ao_rays) are not tsm's
    state_->setScene(std::move(s));
    const auto rest = nextFull("tsm");
    QVERIFY2(rest != nullptr, qPrintable(console_->text()));
    QVERIFY(time->isEnabled() && play->isEnabled());
    time->setValue(1.0);  // a quarter period: the full twist
    QCOMPARE(state_->scene().time, 1.0);
    const auto twisted = nextFull("tsm");
    QVERIFY2(twisted != nullptr, qPrintable(console_->text()));
    const double d = relativeMeanDifference(rest->frame.rgb, twisted->frame.rgb);
    qInfo("twisted vs rest: relative mean difference %g", d);
    QVERIFY2(d > 0.1, qPrintable(QStringLiteral("relative mean difference %1").arg(d)));
    play->setChecked(true);
    QVERIFY(QTest::qWaitFor([&] { return state_->scene().time > 1.3; }, 5000));
    play->setChecked(false);
    const double stopped = state_->scene().time;
    QTest::qWait(200);
    QCOMPARE(state_->scene().time, stopped);
    QCOMPARE(time->value(), std::round(stopped * 1000.0) / 1000.0);  // the field follows
    // Back to the scene without a deformation: the controls are off again.
    state_->setScene(before);
    QVERIFY(!time->isEnabled() && !play->isEnabled());
  }
};

QTEST_MAIN(Viewport)
#include "test_viewport.moc"
