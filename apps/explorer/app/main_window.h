// SPDX-License-Identifier: GPL-3.0-or-later
// The explorer's main window: every view is a dock widget (pop out, move, resize), the layout and
// window geometry are remembered across runs (QSettings), File and View menus, and the status bar
// with the viewport's frame rate and the mesh's faces, vertices and points.
#pragma once

#include <QtCore/QString>
#include <QtWidgets/QMainWindow>

#include <filesystem>

#include "translucent/scene/scene.h"

class QDockWidget;
class QLabel;

namespace translucent::explorer {

class ConsoleDock;
class ExplorerState;
class ViewportDock;

struct MainWindowOptions {
  bool restore_layout = true;  // restore the saved dock layout and geometry (--reset-layout: no)
  bool save_layout = true;     // save them when the window closes
};

class MainWindow : public QMainWindow {
  Q_OBJECT

 public:
  explicit MainWindow(ExplorerState& state, MainWindowOptions options = {},
                      QWidget* parent = nullptr);
  ~MainWindow() override;

  ViewportDock* viewport() const { return viewport_; }
  ConsoleDock* console() const { return console_; }

  // Opens a scene file (errors to the console; the current scene stays).
  bool openScene(const QString& path);
  // Writes the current scene as JSON (paths made absolute, the camera at the viewport's
  // full-resolution size); errors to the console.
  bool saveScene(const QString& path);
  // Saves the view to a scene file in the temporary folder and returns the `translucent render`
  // command line that reproduces it (also put on the clipboard by the menu item).
  QString commandLineForView();
  // The scene as the CLI should render it: absolute paths, the camera at `width` x `height`.
  static scene::Scene sceneForCli(const scene::Scene& scene, int width, int height);

  // The default dock layout at the window's present size (View > Reset layout); the saved
  // layout is replaced when the window closes.
  void resetLayout();

 signals:
  // The default dock sizes are in place (after the first show without a saved layout, or a
  // reset); tests measure the layout after it.
  void defaultLayoutApplied();

 public:
  // "Print current data" (empirical seed, appendix A: "print all current data"): the scene as
  // JSON, then every parameter of the current technique with the value it renders with (the
  // scene's setting, else the default, marked so), as one text; the menu item sends it to the
  // console. Throws nothing: an unknown technique name is said in the text.
  QString currentDataText() const;

 protected:
  void closeEvent(QCloseEvent* e) override;
  void showEvent(QShowEvent* e) override;

 private:
  void updateStatus();

  ExplorerState& state_;
  MainWindowOptions options_;
  ViewportDock* viewport_ = nullptr;
  ConsoleDock* console_ = nullptr;
  QDockWidget* top_right_ = nullptr;     // the settings tabs
  QDockWidget* bottom_right_ = nullptr;  // the plot and comparison tabs
  QByteArray default_state_;
  bool sized_ = false;  // the default dock sizes were applied (or a saved layout restored)
  void applyDefaultSizes();
  QLabel* fps_ = nullptr;
  QLabel* counts_ = nullptr;
  int view_saves_ = 0;
};

// The `translucent` CLI next to this program when it is there, else "translucent" (PATH).
QString cliProgram();

}  // namespace translucent::explorer
