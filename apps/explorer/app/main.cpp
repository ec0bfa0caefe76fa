// SPDX-License-Identifier: GPL-3.0-or-later
// translucent-explorer: the interactive desktop app (issue 6). `translucent-explorer [scene.json]`
// opens the scene (default: the built-in bunny, scene::defaultScene()).
//
//   --reset-layout          start with the default dock layout (the saved one is replaced on exit)
//   --screenshot FILE       wait for the first full-resolution frame and the docks' first pass,
//                           write the whole window to FILE (PNG) and exit (scripts/screenshot)
//   --benchmark-frames N    render N full-resolution frames continuously, then 2N steps, a
//                           camera orbit step and a turn of the first light in turn (each timed
//                           to its full-resolution frame); print the three rates, then the time
//                           from a material change (ExplorerState::setMedium) to the updated
//                           full-resolution image, and exit
//   --render-scale S        full-resolution size relative to the picture (1, 0.5, 0.25; software
//                           renderers default to 0.25)
//   --size WxH              window size (default 1600x1000, or the saved geometry)
#include <QtCore/QCommandLineParser>
#include <QtCore/QElapsedTimer>
#include <QtCore/QTimer>
#include <QtGui/QImage>
#include <QtGui/QSurfaceFormat>
#include <QtWidgets/QApplication>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <variant>
#include <memory>
#include <vector>

#include "app/main_window.h"
#include "app/view_math.h"
#include "app/viewport_dock.h"
#include "core/explorer_state.h"
#include "core/message_repeats.h"
#include "translucent/io/image_io.h"
#include "translucent/io/output_guard.h"
#include "translucent/scene/scene.h"

using namespace translucent;
using namespace translucent::explorer;

namespace {

void runBenchmark(QApplication& app, ExplorerState& state, ViewportDock* viewport, int frames) {
  // Phases: 0 waiting for the first full frame; 1 N frames of a still scene; 2 2N steps, camera
  // orbit steps (the technique keeps its lighting, Technique::setCamera) and changes of the first
  // light's direction (everything light-dependent recomputed) in turn, so that both kinds of step
  // share whatever else runs meanwhile (the docks' first computations, which are heavy at the
  // start, and other processes); 3 the material change.
  struct Tally {
    std::vector<double> ms;  // per step: prepare and render of its half- and full-resolution frames
    // Its light-side passes, all frames: "shadow maps" and "irradiance" (the point cloud, tsis,
    // lss; splatting's light-view irradiance buffers), "irradiance hierarchy" (splatting), "light
    // maps" (tsm).
    double lighting_ms = 0.0;
    double prepare_ms = 0.0;  // its Technique::prepare() calls, all frames
    double wall_ms = 0.0;     // from each step to its full-resolution frame on screen
  };
  struct Bench {
    int phase = 0;
    Tally still, orbit, light;
    bool lightStep = false;  // phase 2: the step in flight turned the light (else the camera)
    double step_ms = 0.0;    // frames since the last step (half and full resolution)
    QElapsedTimer wall, change;
    double first_change_ms = -1.0;
  };
  auto b = std::make_shared<Bench>();
  auto report = [](const char* what, const RenderedFrame& f, const Tally& t) {
    double sum = 0.0, lo = 1e300, hi = 0.0;
    for (double m : t.ms) sum += m, lo = std::min(lo, m), hi = std::max(hi, m);
    const double n = double(t.ms.size());
    std::printf("viewport (%s): %s, %dx%d, %d steps: %.2f per second (time per step, the half- and "
                "full-resolution frames, mean %.1f ms, min %.1f, max %.1f, of which prepare %.1f and light "
                "passes (shadow maps, light maps, irradiance) %.1f; %.2f steps/s wall clock including "
                "display)\n",
                what, f.technique.c_str(), f.frame.width, f.frame.height, int(t.ms.size()),
                1000.0 * n / sum, sum / n, lo, hi, t.prepare_ms / n, t.lighting_ms / n,
                1000.0 * n / t.wall_ms);
    std::fflush(stdout);
  };
  auto step = [&state](bool turnLight) {
    if (!turnLight) {
      state.setCamera(orbit(state.scene().camera, 0.05, 0.0));
      return;
    }
    std::vector<scene::Light> lights = state.scene().lights;
    for (auto& light : lights) {
      auto turn = [](glm::dvec3& d) {
        const double c = std::cos(0.05), sn = std::sin(0.05);
        d = glm::dvec3(c * d.x + sn * d.z, d.y, -sn * d.x + c * d.z);
      };
      if (auto* d = std::get_if<reference::DirectionalLight>(&light.emitter)) {
        turn(d->direction);
        break;
      }
      if (auto* p = std::get_if<reference::PointLight>(&light.emitter)) {
        turn(p->position);
        break;
      }
    }
    // As the viewport's right drag turns it: setScene would also announce a material change,
    // whose handlers in the docks run beside the frames timed (the pencil plot, for one, stops
    // its reference and samples its curves again).
    state.setLights(std::move(lights));
  };
  QObject::connect(viewport, &ViewportDock::frameShown, viewport,
                   [&app, &state, viewport, frames, b, report, step](std::shared_ptr<const RenderedFrame> f, bool full) {
    if (b->phase == 0 && full) {
      b->phase = 1;
      b->wall.start();
      viewport->setContinuous(true);
      return;
    }
    if (b->phase == 1 || b->phase == 2) {
      // A change shows at half resolution first, then in full: a step's cost is both frames'
      // (prepare and render), counted when the full one arrives.
      // A still scene: each full frame on its own.
      if (b->phase == 1 && !full) return;
      Tally& t = b->phase == 1 ? b->still : b->lightStep ? b->light : b->orbit;
      b->step_ms += f->prepare_ms + f->render_ms;
      t.prepare_ms += f->prepare_ms;
      for (const auto& pass : f->frame.passes)
        if (pass.name == "shadow maps" || pass.name == "irradiance" || pass.name == "light maps" ||
            pass.name == "irradiance hierarchy")
          t.lighting_ms += pass.ms;
      if (!full) return;
      t.ms.push_back(b->step_ms);
      b->step_ms = 0.0;
      t.wall_ms += double(b->wall.restart());
      if (b->phase == 1) {
        if (int(t.ms.size()) < frames) {
          viewport->requestFullFrame();
          return;
        }
        report("still", *f, t);
        viewport->setContinuous(false);
        b->phase = 2;
        b->lightStep = false;
        b->wall.restart();
        step(b->lightStep);
        return;
      }
      if (int(b->orbit.ms.size() + b->light.ms.size()) < 2 * frames) {
        b->lightStep = !b->lightStep;
        step(b->lightStep);
        return;
      }
      report("camera orbit", *f, b->orbit);
      report("light moving", *f, b->light);
      b->phase = 3;
      b->change.start();
      Medium m = state.medium();
      for (double& v : m.sigma_a) v *= 1.25;
      state.setMedium(m);  // request ids after this one show the new material
      return;
    }
    if (b->phase == 3) {
      if (b->first_change_ms < 0.0) b->first_change_ms = b->change.elapsed();
      if (!full) return;
      std::printf("material change (setMedium) -> first image %.0f ms (half resolution), "
                  "-> full-resolution image %lld ms\n",
                  b->first_change_ms, static_cast<long long>(b->change.elapsed()));
      std::fflush(stdout);
      b->phase = 4;
      app.quit();
    }
  });
}

}  // namespace

int main(int argc, char** argv) {
  // Every QOpenGLWidget asks for 4.5 core (src/gpu's baseline); set before the application so
  // that shared contexts match.
  QSurfaceFormat format;
  format.setVersion(4, 5);
  format.setProfile(QSurfaceFormat::CoreProfile);
  QSurfaceFormat::setDefaultFormat(format);

  QApplication app(argc, argv);
  QApplication::setApplicationName(QStringLiteral("translucent-explorer"));
  QApplication::setOrganizationName(QStringLiteral("translucent"));

  QCommandLineParser parser;
  parser.setApplicationDescription(
      QStringLiteral("Translucent Explorer: BSSRDFs, reference transport and real-time techniques"));
  parser.addHelpOption();
  parser.addPositionalArgument(QStringLiteral("scene"),
                               QStringLiteral("Scene file (JSON); default: the built-in bunny"));
  QCommandLineOption reset(QStringLiteral("reset-layout"), QStringLiteral("Start with the default dock layout"));
  QCommandLineOption shot(QStringLiteral("screenshot"), QStringLiteral("Write the window to FILE (PNG) and exit"),
                          QStringLiteral("FILE"));
  QCommandLineOption delay(QStringLiteral("screenshot-delay"),
                           QStringLiteral("Milliseconds to wait after the first full frame (default 4000)"),
                           QStringLiteral("MS"), QStringLiteral("4000"));
  QCommandLineOption bench(QStringLiteral("benchmark-frames"),
                           QStringLiteral("Render N full frames, print the frame rate and the material-change latency, exit"),
                           QStringLiteral("N"));
  QCommandLineOption scale(QStringLiteral("render-scale"),
                           QStringLiteral("Full-resolution size relative to the picture (0.05 to 1)"),
                           QStringLiteral("S"));
  QCommandLineOption size(QStringLiteral("size"), QStringLiteral("Window size WxH"), QStringLiteral("WxH"));
  parser.addOptions({reset, shot, delay, bench, scale, size});
  parser.process(app);

  const bool scripted = parser.isSet(shot) || parser.isSet(bench);
  ExplorerState state;
  MainWindowOptions options;
  options.restore_layout = !parser.isSet(reset) && !scripted;
  options.save_layout = !scripted;
  MainWindow window(state, options);
  if (scripted) {
    // No one watches the console of a scripted run: its warnings and errors go to stderr too,
    // a repeat of the previous message once (core/message_repeats.h).
    auto repeats = std::make_shared<MessageRepeats>();
    QObject::connect(&state, &ExplorerState::message, &state,
                     [repeats](MessageLevel level, const QString& text) {
                       if (level == MessageLevel::Info || repeats->see(level, text) > 1) return;
                       std::fprintf(stderr, "translucent-explorer: %s: %s\n",
                                    level == MessageLevel::Error ? "error" : "warning",
                                    qPrintable(text));
                     });
  }
  if (parser.isSet(size)) {
    const QStringList wh = parser.value(size).split(QLatin1Char('x'));
    if (wh.size() != 2 || wh[0].toInt() <= 0 || wh[1].toInt() <= 0) {
      std::fprintf(stderr, "--size '%s': expected WIDTHxHEIGHT, e.g. 1600x1000\n",
                   qPrintable(parser.value(size)));
      return 2;
    }
    window.resize(wh[0].toInt(), wh[1].toInt());
  }
  if (parser.isSet(scale)) {
    bool ok = false;
    const double s = parser.value(scale).toDouble(&ok);
    if (!ok || !(s >= 0.05 && s <= 1.0)) {
      std::fprintf(stderr, "--render-scale '%s': expected a number in [0.05, 1]\n",
                   qPrintable(parser.value(scale)));
      return 2;
    }
    window.viewport()->fixRenderScale(s);
  }
  if (!parser.positionalArguments().isEmpty()) {
    const QString file = parser.positionalArguments().first();
    if (!window.openScene(file) && scripted) {
      std::fprintf(stderr, "cannot open the scene '%s' (the reason is above)\n", qPrintable(file));
      return 1;
    }
  }
  window.show();

  if (parser.isSet(bench)) {
    bool ok = false;
    const int n = parser.value(bench).toInt(&ok);
    if (!ok || n < 1) {
      std::fprintf(stderr, "--benchmark-frames '%s': expected a positive integer\n",
                   qPrintable(parser.value(bench)));
      return 2;
    }
    runBenchmark(app, state, window.viewport(), n);
  }
  if (parser.isSet(shot)) {
    const QString path = parser.value(shot);
    // The screenshot must not replace what the run reads (the scene, its mesh, maps, grids; a
    // hard or symbolic link to one too), and is checked before any rendering.
    translucent::io::OutputSet outputs;
    outputs.output("--screenshot", path.toStdString());
    if (!parser.positionalArguments().isEmpty())
      outputs.input("the scene", parser.positionalArguments().first().toStdString());
    for (const auto& [what, file] : translucent::scene::inputFiles(state.scene()))
      outputs.input(what, file);
    try {
      outputs.check();
    } catch (const std::exception& e) {
      std::fprintf(stderr, "translucent-explorer: error: %s\n", e.what());
      return 1;
    }
    const int wait = parser.value(delay).toInt();
    auto taken = std::make_shared<bool>(false);
    auto take = [&app, &window, path, taken] {
      if (*taken) return;
      *taken = true;
      // Written to a temporary file renamed over the target (io/image_io.h): a failed write
      // leaves an existing file as it was instead of truncating it (QImage::save opens the
      // target first), and a symbolic link is replaced, never written through.
      const QImage image = window.grab().toImage().convertToFormat(QImage::Format_RGB888);
      std::vector<uint8_t> rgb(static_cast<size_t>(image.width()) * image.height() * 3);
      for (int y = 0; y < image.height(); ++y)
        std::memcpy(rgb.data() + static_cast<size_t>(y) * image.width() * 3, image.constScanLine(y),
                    static_cast<size_t>(image.width()) * 3);
      bool ok = !image.isNull();
      std::string why = "the window could not be captured";
      if (ok) {
        try {
          translucent::analysis::writePng8(path.toStdString(), image.width(), image.height(), rgb);
        } catch (const std::exception& e) {
          ok = false;
          why = e.what();
        }
      }
      if (ok)
        std::printf("wrote %s\n", qPrintable(path));
      else
        std::fprintf(stderr, "translucent-explorer: error: cannot write %s: %s\n",
                     qPrintable(path), why.c_str());
      app.exit(ok ? 0 : 1);
    };
    QObject::connect(window.viewport(), &ViewportDock::frameShown, &window,
                     [take, wait](std::shared_ptr<const RenderedFrame>, bool full) {
                       if (full) QTimer::singleShot(wait, take);
                     });
    QTimer::singleShot(180000, take);  // a renderer that never delivers: shoot what is there
  }
  return app.exec();
}
