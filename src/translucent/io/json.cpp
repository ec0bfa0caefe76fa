// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/io/json.h"

#include "translucent/io/input_file.h"

#include <fmt/format.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <nlohmann/json.hpp>
#include <string>
#include <system_error>

namespace translucent::io {

std::string textPosition(std::string_view text, size_t offset) {
  size_t line = 1, column = 1;
  for (size_t i = 0; i < offset && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  return fmt::format("line {}, column {}", line, column);
}

std::string jsonErrorText(const std::exception& e) {
  const std::string_view text = e.what();
  if (text.starts_with("[json.exception.")) {
    if (const size_t end = text.find("] "); end != std::string_view::npos)
      return std::string(text.substr(end + 2));
  }
  return std::string(text);
}

namespace {

// The offset of the first bracket that opens level max_depth + 1, or npos. Strings (with their
// escapes) are skipped; whatever else is malformed is left to the parser.
size_t tooDeepAt(std::string_view text, int max_depth) {
  int depth = 0;
  bool inString = false, escaped = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char ch = text[i];
    if (inString) {
      if (escaped)
        escaped = false;
      else if (ch == '\\')
        escaped = true;
      else if (ch == '"')
        inString = false;
      continue;
    }
    if (ch == '"') {
      inString = true;
    } else if (ch == '[' || ch == '{') {
      if (++depth > max_depth) return i;
    } else if ((ch == ']' || ch == '}') && depth > 0) {
      --depth;
    }
  }
  return std::string_view::npos;
}

}  // namespace

nlohmann::json parseJson(std::string_view text, const std::string& what, int max_depth) {
  if (const size_t at = tooDeepAt(text, max_depth); at != std::string_view::npos)
    throw JsonError(fmt::format("{}: not valid JSON: arrays and objects nest deeper than {} "
                                "levels (at {}): expected a flatter document",
                                what, max_depth, textPosition(text, at)));
  // nlohmann's parser ends a document at a NUL byte and ignores what follows (a layers file
  // with NULs after it was accepted); JSON text never holds one, escaped strings aside.
  if (const size_t nul = text.find('\0'); nul != std::string_view::npos)
    throw JsonError(fmt::format("{}: not valid JSON: a NUL byte at {}", what, textPosition(text, nul)));
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {  // syntax errors (with line and column), ranges
    throw JsonError(fmt::format("{}: not valid JSON: {}", what, jsonErrorText(e)));
  }
}

nlohmann::json readJsonFile(const std::filesystem::path& file, const std::string& what) {
  const std::string name = what.empty() ? fmt::format("'{}'", file.string()) : what;
  if (const std::string why = irregularInput(file); !why.empty())
    throw JsonError(fmt::format("{}: {}: expected a JSON file", name, why));
  std::FILE* f = std::fopen(file.c_str(), "rb");
  if (!f)
    throw JsonError(fmt::format("{}: cannot be opened: {}", name, std::strerror(errno)));
  std::string bytes;
  char buffer[1 << 16];
  size_t n = 0;
  while ((n = std::fread(buffer, 1, sizeof buffer, f)) > 0) bytes.append(buffer, n);
  const bool failed = std::ferror(f) != 0;
  std::fclose(f);
  if (failed) throw JsonError(fmt::format("{}: cannot be read", name));
  return parseJson(bytes, name);
}

}  // namespace translucent::io
