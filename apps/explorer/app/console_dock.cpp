// SPDX-License-Identifier: GPL-3.0-or-later
#include "app/console_dock.h"

#include <QtCore/QDateTime>
#include <QtCore/QPointer>
#include <QtGui/QFontDatabase>
#include <QtGui/QTextCursor>
#include <QtWidgets/QPlainTextEdit>

namespace translucent::explorer {
namespace {

// Qt's messages (qWarning from any thread) go to the console of the newest ConsoleDock, and on
// to the previous handler (stderr).
QPointer<ExplorerState> g_state;
QtMessageHandler g_previous = nullptr;

void forwardQtMessage(QtMsgType type, const QMessageLogContext& context, const QString& message) {
  if (g_previous != nullptr) g_previous(type, context, message);
  if (type == QtDebugMsg || type == QtInfoMsg) return;
  const MessageLevel level = type == QtWarningMsg ? MessageLevel::Warning : MessageLevel::Error;
  if (ExplorerState* state = g_state.data()) {
    const QString text = QStringLiteral("Qt: ") + message;
    QMetaObject::invokeMethod(state, [state, level, text] { state->log(level, text); },
                              Qt::QueuedConnection);
  }
}

}  // namespace

ConsoleDock::ConsoleDock(ExplorerState& state, QWidget* parent)
    : QDockWidget(QStringLiteral("Console"), parent) {
  setObjectName(QStringLiteral("console_dock"));
  log_ = new QPlainTextEdit;
  log_->setObjectName(QStringLiteral("console"));
  log_->setReadOnly(true);
  log_->setMaximumBlockCount(5000);
  log_->setFont(QFontDatabase::systemFont(QFontDatabase::FixedFont));
  setWidget(log_);
  connect(&state, &ExplorerState::message, this, &ConsoleDock::append);
  g_state = &state;
  QtMessageHandler previous = qInstallMessageHandler(forwardQtMessage);
  if (previous != forwardQtMessage) g_previous = previous;
}

ConsoleDock::~ConsoleDock() {
  qInstallMessageHandler(g_previous);
  g_previous = nullptr;
}

void ConsoleDock::append(MessageLevel level, const QString& text) {
  const char* colour = level == MessageLevel::Error     ? "#d03030"
                       : level == MessageLevel::Warning ? "#c08000"
                                                        : "#404040";
  const char* tag = level == MessageLevel::Error ? "error" : level == MessageLevel::Warning ? "warning" : "info";
  if (level == MessageLevel::Error) ++errors_;
  const int seen = repeats_.see(level, text);
  const QString time = QDateTime::currentDateTime().toString(QStringLiteral("HH:mm:ss"));
  QString html = text.toHtmlEscaped();
  if (seen > 1) html += QStringLiteral(" (repeated %1 times)").arg(seen);
  html.replace(QLatin1Char('\n'), QStringLiteral("<br>&nbsp;&nbsp;"));
  const QString line = QStringLiteral("<span style=\"color:%1\">%2 %3: %4</span>")
                           .arg(QLatin1String(colour), time, QLatin1String(tag), html);
  if (seen == 1) {
    log_->appendHtml(line);
    return;
  }
  // The same message again: its line (the last one) is rewritten in place with the count.
  QTextCursor cursor(log_->document());
  cursor.movePosition(QTextCursor::End);
  cursor.movePosition(QTextCursor::StartOfBlock, QTextCursor::KeepAnchor);
  cursor.removeSelectedText();
  cursor.insertHtml(line);
}

QString ConsoleDock::text() const { return log_->toPlainText(); }

}  // namespace translucent::explorer
