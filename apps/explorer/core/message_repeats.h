// SPDX-License-Identifier: GPL-3.0-or-later
// Repeated identical messages are shown once (issue 15 §6): a renderer that fails on every frame
// (a broken shader, a mesh that cannot be loaded) would otherwise fill the console, or a
// scripted run's stderr, with the same line 60 times a second. A message equal to the previous
// one (same level and text) is counted instead of shown; the console then rewrites its last
// line as "… (repeated N times)".
#pragma once

#include <QtCore/QString>

#include "core/explorer_state.h"

namespace translucent::explorer {

class MessageRepeats {
 public:
  // How many times this message has now been seen in a row: 1 for a new message (show it), more
  // for a repeat of the previous one.
  int see(MessageLevel level, const QString& text) {
    if (count_ > 0 && level == level_ && text == text_) return ++count_;
    level_ = level;
    text_ = text;
    return count_ = 1;
  }

 private:
  MessageLevel level_ = MessageLevel::Info;
  QString text_;
  int count_ = 0;
};

}  // namespace translucent::explorer
