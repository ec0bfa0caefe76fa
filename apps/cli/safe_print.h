// SPDX-License-Identifier: GPL-3.0-or-later
// Messages to stderr that never throw: fmt::print throws when the stream cannot be written (a
// closed or full stderr, `2>&-`), which would end a run over a progress bar, or abort one that is
// already reporting an error (an exception escaping main's handler). A lost diagnostic is not worth
// either, so failures to write are ignored here; outputs (stdout, files) still check every write.
#pragma once

#include <fmt/format.h>

#include <cstdio>
#include <string>
#include <utility>

namespace translucent::cli {

template <class... T>
void printStderr(fmt::format_string<T...> format, T&&... args) {
  const std::string text = fmt::format(format, std::forward<T>(args)...);
  (void)std::fwrite(text.data(), 1, text.size(), stderr);
  (void)std::fflush(stderr);
}

}  // namespace translucent::cli
