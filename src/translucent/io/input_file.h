// SPDX-License-Identifier: GPL-3.0-or-later
// What is wrong with a path given as an input file, before it is opened: a FIFO blocks its
// reader until someone writes to it (for ever, in a batch job), and a device such as /dev/zero or
// /dev/urandom never ends; readers refuse both, and a folder, with the file named.
#pragma once

#include <filesystem>
#include <string>

namespace translucent::io {

// "" for a regular file (symbolic links followed) or a path that does not exist (the reader's
// own "cannot be opened" says so); else "is a folder", "is a FIFO (named pipe)", "is a device",
// "is a socket" or "is not a regular file", for "<what> '<file>' <reason>: expected a file".
inline std::string irregularInput(const std::filesystem::path& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status s = fs::status(path, ec);
  if (ec || !fs::exists(s) || fs::is_regular_file(s)) return "";
  if (fs::is_directory(s)) return "is a folder";
  if (fs::is_fifo(s)) return "is a FIFO (named pipe)";
  if (fs::is_character_file(s) || fs::is_block_file(s)) return "is a device";
  if (fs::is_socket(s)) return "is a socket";
  return "is not a regular file";
}

}  // namespace translucent::io
