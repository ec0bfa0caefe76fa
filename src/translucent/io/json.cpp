// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/io/json.h"

#include "translucent/io/input_file.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <nlohmann/json.hpp>
#include <string>
#include <system_error>
#include <vector>

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

// The key path of the value at `offset` ("camera.width", "lights[0].irradiance"; "" at the top),
// by one pass over the text before it: a stack of the objects and arrays open there, with each
// object's current key and each array's index. Keys are quoted as written (escapes kept).
std::string jsonPathAt(std::string_view text, size_t offset) {
  struct Frame {
    bool object = false;
    bool expect_key = true;
    std::string key;
    size_t index = 0;
  };
  std::vector<Frame> stack;
  for (size_t i = 0; i < offset && i < text.size(); ++i) {
    const char ch = text[i];
    if (ch == '"') {
      size_t end = i + 1;
      while (end < text.size() && text[end] != '"') end += text[end] == '\\' ? 2 : 1;
      if (!stack.empty() && stack.back().object && stack.back().expect_key) {
        stack.back().key = std::string(text.substr(i + 1, std::min(end, text.size()) - i - 1));
        stack.back().expect_key = false;
      }
      i = end;
    } else if (ch == '{' || ch == '[') {
      stack.emplace_back();
      stack.back().object = ch == '{';
    } else if ((ch == '}' || ch == ']') && !stack.empty()) {
      stack.pop_back();
    } else if (ch == ',' && !stack.empty()) {
      if (stack.back().object)
        stack.back().expect_key = true;
      else
        ++stack.back().index;
    }
  }
  std::string path;
  for (const Frame& f : stack) {
    if (f.object && !f.expect_key)
      path += (path.empty() ? "" : ".") + f.key;
    else if (!f.object)
      path += fmt::format("[{}]", f.index);
  }
  return path;
}

// nlohmann reports a number beyond a double's range ("number overflow parsing '1000…'") without
// its place: find the number in the text and name its line, column and key.
std::string numberOverflowText(std::string_view text, const std::string& message) {
  const size_t open = message.find('\''), close = message.rfind('\'');
  if (open == std::string::npos || close <= open + 1) return message;
  const std::string token = message.substr(open + 1, close - open - 1);
  const auto isNumberChar = [](char c) {
    return std::isdigit(static_cast<unsigned char>(c)) || c == '.' || c == '-' || c == '+' ||
           c == 'e' || c == 'E';
  };
  size_t at = text.find(token);
  while (at != std::string_view::npos &&
         ((at > 0 && isNumberChar(text[at - 1])) ||
          (at + token.size() < text.size() && isNumberChar(text[at + token.size()]))))
    at = text.find(token, at + 1);
  const std::string shown =
      token.size() > 24 ? fmt::format("{}… ({} characters)", token.substr(0, 12), token.size())
                        : token;
  if (at == std::string_view::npos)
    return fmt::format("the number {} is beyond the range of a double", shown);
  const std::string path = jsonPathAt(text, at);
  return fmt::format("the number {} at {}{} is beyond the range of a double", shown,
                     textPosition(text, at), path.empty() ? "" : " (" + path + ")");
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
  } catch (const nlohmann::json::out_of_range& e) {  // 406: a number beyond a double's range
    const std::string message = jsonErrorText(e);
    throw JsonError(fmt::format("{}: not valid JSON: {}", what,
                                e.id == 406 ? numberOverflowText(text, message) : message));
  } catch (const nlohmann::json::exception& e) {  // syntax errors (with line and column)
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
