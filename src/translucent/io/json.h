// SPDX-License-Identifier: GPL-3.0-or-later
// The one way the library and its front ends read JSON written by someone else (scenes, layer
// files, reports, leaderboards, partial-run headers): a depth limit checked before parsing, so
// that a document nested a few hundred thousand levels deep ("[[[[...") is refused with a
// message instead of overflowing the stack in whatever walks the tree afterwards (copies,
// comparisons, dump() and the readers are recursive), and errors that name the source and the
// line and column.
#pragma once

#include <filesystem>
#include <nlohmann/json_fwd.hpp>
#include <stdexcept>
#include <string>
#include <string_view>

namespace translucent::io {

// Deepest nesting of arrays and objects accepted (a scene needs fewer than 10 levels).
inline constexpr int kMaxJsonDepth = 512;

// Thrown for a document that is not valid JSON, nests too deeply, or cannot be read; the message
// starts with the source's name.
class JsonError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

// Parses `text`; `what` names it in messages ("scene 'a.json'", "--layers 'l.json'"). Throws
// JsonError "<what>: not valid JSON: ..." with the line and column of the fault, also when
// arrays and objects nest deeper than `max_depth` (checked by a scan of the text before parsing,
// brackets inside strings ignored).
nlohmann::json parseJson(std::string_view text, const std::string& what,
                         int max_depth = kMaxJsonDepth);

// The text of an exception of nlohmann::json without its "[json.exception.type_error.302] " tag
// (for messages about a document that parsed but holds the wrong types).
std::string jsonErrorText(const std::exception& e);

// The line and column (from 1) of byte `offset` of `text`, as "line L, column C".
std::string textPosition(std::string_view text, size_t offset);

// Reads `file` whole and parses it; `what` names it in messages (empty: "'<file>'"). A folder,
// a missing or unreadable file is a JsonError naming the file too.
nlohmann::json readJsonFile(const std::filesystem::path& file, const std::string& what = "");

}  // namespace translucent::io
