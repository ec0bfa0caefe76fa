// SPDX-License-Identifier: GPL-3.0-or-later
#include "app/main_window.h"

#include <QtCore/QCoreApplication>
#include <QtCore/QDir>
#include <QtCore/QFileInfo>
#include <QtCore/QSettings>
#include <QtCore/QTimer>
#include <QtGui/QClipboard>
#include <QtGui/QCloseEvent>
#include <QtGui/QGuiApplication>
#include <QtGui/QKeySequence>
#include <QtWidgets/QFileDialog>
#include <QtWidgets/QLabel>
#include <QtWidgets/QMenuBar>
#include <QtWidgets/QScrollArea>
#include <QtWidgets/QStatusBar>

#include <algorithm>
#include <cmath>
#include <exception>

#include "translucent/bssrdf/tabulated.h"
#include "app/command_line.h"
#include "app/console_dock.h"
#include "app/technique_views_dock.h"
#include "app/current_data.h"
#include "app/viewport_dock.h"
#include "core/explorer_state.h"

#include "material/material_dock.h"
#include "material/parameters_dock.h"
#include "material/pencil_plot_dock.h"
#include "compare/compare_dock.h"
#include "spheres/lit_spheres_dock.h"

namespace translucent::explorer {
namespace {

std::filesystem::path absolutePath(const std::filesystem::path& p) {
  if (p.empty() || p.is_absolute() || p == "checker") return p;
  return std::filesystem::absolute(p);
}

// A dock whose content needs more room than the default layout gives it scrolls, rather than
// forcing its minimum size on the whole column (the comparison's row of pictures wanted 641 px,
// the lit spheres 391 px of height).
void makeScrollable(QDockWidget* d) {
  auto* area = new QScrollArea;
  area->setWidgetResizable(true);
  area->setFrameShape(QFrame::NoFrame);
  area->setWidget(d->widget());
  d->setWidget(area);
}

QSettings layoutSettings() {
  return QSettings(QStringLiteral("translucent"), QStringLiteral("explorer"));
}

}  // namespace

QString cliProgram() {
  const QString local = QCoreApplication::applicationDirPath() + QStringLiteral("/translucent");
  return QFileInfo(local).isExecutable() ? local : QStringLiteral("translucent");
}

MainWindow::MainWindow(ExplorerState& state, MainWindowOptions options, QWidget* parent)
    : QMainWindow(parent), state_(state), options_(options) {
  setObjectName(QStringLiteral("explorer_main_window"));
  setWindowTitle(QStringLiteral("Translucent Explorer"));
  setDockNestingEnabled(true);
  setDockOptions(QMainWindow::AnimatedDocks | QMainWindow::AllowNestedDocks |
                 QMainWindow::AllowTabbedDocks);
  // Every view is a dock; a hidden central widget lets them share the whole window.
  auto* centre = new QWidget;
  centre->hide();
  setCentralWidget(centre);

  console_ = new ConsoleDock(state_, this);  // first: it shows what the others report
  viewport_ = new ViewportDock(state_, this);
  // Default layout: the picture on the left at the scene's aspect ratio with the console under
  // it; on the right, the settings (tabs) above the plots and comparisons (tabs), each column the
  // window's full height.
  addDockWidget(Qt::LeftDockWidgetArea, viewport_);
  splitDockWidget(viewport_, console_, Qt::Vertical);
  auto* parameters = new ParametersDock(state_, this);
  auto* plot = new PencilPlotDock(state_, this);
  auto* material = new MaterialDock(state_, this);
  auto* spheres = new LitSpheresDock(state_, this);
  auto* compare = new CompareDock(state_, this);
  auto* views = new TechniqueViewsDock(*viewport_, this);
  QDockWidget* render_settings = viewport_->controlsDock();
  for (QDockWidget* d : std::initializer_list<QDockWidget*>{plot, spheres, compare, views})
    makeScrollable(d);
  addDockWidget(Qt::RightDockWidgetArea, parameters);
  splitDockWidget(parameters, plot, Qt::Vertical);
  tabifyDockWidget(parameters, render_settings);
  tabifyDockWidget(render_settings, material);
  tabifyDockWidget(plot, spheres);
  tabifyDockWidget(spheres, compare);
  tabifyDockWidget(compare, views);
  plot->raise();
  parameters->raise();
  top_right_ = parameters;
  bottom_right_ = plot;
  const QList<QDockWidget*> docks = {viewport_, console_, parameters, render_settings, material,
                                     plot,      spheres,  compare,    views};
  resize(1600, 1000);
  default_state_ = saveState();  // dock sizes: applyDefaultSizes() once the window is shown

  // File menu.
  QMenu* file = menuBar()->addMenu(QStringLiteral("&File"));
  file->addAction(QStringLiteral("&Open scene…"), QKeySequence::Open, this, [this] {
    const QString f = QFileDialog::getOpenFileName(this, QStringLiteral("Open scene"), QString(),
                                                   QStringLiteral("Scenes (*.json)"));
    if (!f.isEmpty()) openScene(f);
  });
  file->addAction(QStringLiteral("&Save scene…"), QKeySequence::Save, this, [this] {
    const QString f = QFileDialog::getSaveFileName(this, QStringLiteral("Save scene"), QString(),
                                                   QStringLiteral("Scenes (*.json)"));
    if (!f.isEmpty()) saveScene(f);
  });
  file->addAction(QStringLiteral("Load &mesh…"), this, [this] {
    const QString f = QFileDialog::getOpenFileName(this, QStringLiteral("Load mesh"), QString(),
                                                   QStringLiteral("Meshes and point clouds (*.obj *.ply *.off);;All files (*)"));
    if (!f.isEmpty()) viewport_->loadMesh(f);
  });
  file->addAction(QStringLiteral("&Copy command line"), this, [this] {
    const QString cmd = commandLineForView();
    if (cmd.isEmpty()) return;
    QGuiApplication::clipboard()->setText(cmd);
    state_.info(QStringLiteral("copied to the clipboard: %1").arg(cmd));
  });
  QAction* print = file->addAction(QStringLiteral("&Print current data"), this, [this] {
    state_.info(currentDataText());
  });
  print->setObjectName(QStringLiteral("print_current_data"));
  file->addSeparator();
  file->addAction(QStringLiteral("&Quit"), QKeySequence::Quit, this, &QWidget::close);

  // View menu: one toggle per dock.
  QMenu* view = menuBar()->addMenu(QStringLiteral("&View"));
  for (QDockWidget* d : docks) view->addAction(d->toggleViewAction());
  view->addSeparator();
  view->addAction(QStringLiteral("&Reset layout"), this, &MainWindow::resetLayout);

  fps_ = new QLabel;
  fps_->setObjectName(QStringLiteral("status_fps"));
  counts_ = new QLabel;
  counts_->setObjectName(QStringLiteral("status_counts"));
  statusBar()->addWidget(fps_, 1);
  statusBar()->addPermanentWidget(counts_);
  connect(viewport_, &ViewportDock::statsChanged, this, &MainWindow::updateStatus);
  connect(&state_, &ExplorerState::sceneChanged, this, &MainWindow::updateStatus);
  updateStatus();

  if (options_.restore_layout) {
    QSettings settings = layoutSettings();
    restoreGeometry(settings.value(QStringLiteral("geometry")).toByteArray());
    sized_ = restoreState(settings.value(QStringLiteral("windowState")).toByteArray());
  }
}

// resizeDocks() has no effect before the window is laid out, so the default split is applied
// once the first show is done. The right column is shared equally by the settings and the plots
// where it is 700 px tall (at 900 px the Parameters dock then shows every row to η), 40:60 below
// (at 720 px: the material's first five rows above a plot that needs no scroll bar).
void MainWindow::applyDefaultSizes() {
  // The picture at the camera's aspect ratio, as wide as 60% of the window where the left column
  // is tall enough (the right column keeps room for the settings and the plot), at least half the
  // window; the console takes the rest of the left column (at least 90 px).
  const auto& cam = state_.scene().camera;
  const double aspect = cam.height > 0 ? double(cam.width) / cam.height : 4.0 / 3.0;
  const QSize picture = viewport_->pictureSize();
  const int chrome_w = viewport_->width() - picture.width();
  const int chrome_h = viewport_->height() - picture.height();
  const int column_h = viewport_->height() + console_->height();
  const int tallest = int(std::lround(aspect * (column_h - 90 - chrome_h)));
  const int picture_w = std::max(width() / 2, std::min(width() * 3 / 5, tallest));
  const int picture_dock = std::min(column_h - 90, int(std::lround(picture_w / aspect)) + chrome_h);
  resizeDocks({viewport_, console_}, {picture_dock, column_h - picture_dock}, Qt::Vertical);
  // Both columns are given a width: a hidden central widget has no room for the left one to
  // take, so asking for the left one alone only moves it as far as the right one lets it.
  const int left = picture_w + chrome_w;
  const int docks_width = viewport_->width() + top_right_->width();
  resizeDocks({viewport_, top_right_}, {left, std::max(1, docks_width - left)}, Qt::Horizontal);
  const int column = top_right_->height() + bottom_right_->height();
  const int top = column >= 700 ? column / 2 : column * 2 / 5;
  resizeDocks({top_right_, bottom_right_}, {top, column - top}, Qt::Vertical);
  QTimer::singleShot(0, this, &MainWindow::defaultLayoutApplied);
}

void MainWindow::showEvent(QShowEvent* e) {
  QMainWindow::showEvent(e);
  if (sized_) return;
  sized_ = true;
  QTimer::singleShot(0, this, &MainWindow::applyDefaultSizes);
}

MainWindow::~MainWindow() = default;

QString MainWindow::currentDataText() const { return explorer::currentDataText(state_.scene()); }

void MainWindow::resetLayout() {
  restoreState(default_state_);
  for (QDockWidget* d : findChildren<QDockWidget*>()) {
    d->setFloating(false);
    d->show();
  }
  QTimer::singleShot(0, this, &MainWindow::applyDefaultSizes);
}

void MainWindow::closeEvent(QCloseEvent* e) {
  if (options_.save_layout) {
    QSettings settings = layoutSettings();
    settings.setValue(QStringLiteral("geometry"), saveGeometry());
    settings.setValue(QStringLiteral("windowState"), saveState());
  }
  QMainWindow::closeEvent(e);
}

void MainWindow::updateStatus() {
  const FrameStats& s = viewport_->stats();
  if (s.frames == 0) {
    fps_->setText(viewport_->rendererReady() ? QStringLiteral("rendering…")
                                             : QStringLiteral("starting the renderer…"));
  } else {
    fps_->setText(QStringLiteral("%1 fps  (min %2, max %3, average %4 over %5 frames)")
                      .arg(s.current, 0, 'f', 2)
                      .arg(s.min, 0, 'f', 2)
                      .arg(s.max, 0, 'f', 2)
                      .arg(s.average(), 0, 'f', 2)
                      .arg(s.frames));
  }
  QString counts;
  if (const auto f = viewport_->lastFrame(); f != nullptr && f->faces > 0)
    counts = QStringLiteral("%1 faces, %2 vertices").arg(f->faces).arg(f->vertices);
  const int points = viewport_->pointCount();
  if (points >= 0) counts += QStringLiteral("%1%2 points").arg(counts.isEmpty() ? "" : ", ").arg(points);
  counts_->setText(counts);
}

bool MainWindow::openScene(const QString& path) {
  try {
    scene::Scene s = scene::loadScene(path.toStdString());
    state_.setScene(std::move(s));
    state_.info(QStringLiteral("opened %1").arg(path));
    return true;
  } catch (const std::exception& e) {
    state_.error(QStringLiteral("cannot open the scene: %1").arg(e.what()));
    return false;
  }
}

scene::Scene MainWindow::sceneForCli(const scene::Scene& scene, int width, int height) {
  scene::Scene s = scene;
  s.mesh_file = absolutePath(s.mesh_file);
  if (s.model.ends_with(".bssrdf") || bssrdf::isTabulatedFile(s.model))
    s.model = absolutePath(s.model).string();
  for (auto& l : s.lights) {
    if (auto* f = std::get_if<scene::FilteredDirectionalLight>(&l.emitter)) f->texture = absolutePath(f->texture);
    if (auto* e = std::get_if<scene::EnvironmentLight>(&l.emitter)) e->file = absolutePath(e->file);
  }
  s.camera.width = width;
  s.camera.height = height;
  return s;
}

bool MainWindow::saveScene(const QString& path) {
  try {
    const QSize size = viewport_->renderSize();
    scene::saveScene(sceneForCli(state_.scene(), size.width(), size.height()), path.toStdString());
    state_.info(QStringLiteral("saved %1").arg(path));
    return true;
  } catch (const std::exception& e) {
    state_.error(QStringLiteral("cannot save the scene: %1").arg(e.what()));
    return false;
  }
}

QString MainWindow::commandLineForView() {
  // The command needs a file: the view goes to the temporary folder, never over a user's file.
  const QString dir = QDir::tempPath() + QStringLiteral("/translucent-explorer");
  QDir().mkpath(dir);
  const QString file = QStringLiteral("%1/view-%2-%3.json")
                           .arg(dir)
                           .arg(QCoreApplication::applicationPid())
                           .arg(++view_saves_);
  if (!saveScene(file)) return {};
  const QSize size = viewport_->renderSize();
  return renderCommandLine(cliProgram(), file.toStdString(),
                           QString::fromStdString(state_.scene().technique), size.width(),
                           size.height(), QStringLiteral("view.exr"));
}

}  // namespace translucent::explorer
