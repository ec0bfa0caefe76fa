// SPDX-License-Identifier: GPL-3.0-or-later
// The console (issue 6): every ExplorerState message (info, warning, error: shader compile errors
// with file and line, broken meshes, bad .bssrdf files) and Qt's own warnings, colour coded.
#pragma once

#include <QtWidgets/QDockWidget>

#include "core/explorer_state.h"
#include "core/message_repeats.h"

class QPlainTextEdit;

namespace translucent::explorer {

class ConsoleDock : public QDockWidget {
  Q_OBJECT

 public:
  explicit ConsoleDock(ExplorerState& state, QWidget* parent = nullptr);
  ~ConsoleDock() override;

  QString text() const;  // plain text of the log, one message a line
  int errorCount() const { return errors_; }  // errors received (repeats included)

  void append(MessageLevel level, const QString& text);

 private:
  QPlainTextEdit* log_ = nullptr;
  int errors_ = 0;
  MessageRepeats repeats_;  // a repeat of the last message rewrites its line with a count
};

}  // namespace translucent::explorer
