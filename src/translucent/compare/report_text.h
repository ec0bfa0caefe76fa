// SPDX-License-Identifier: GPL-3.0-or-later
// Internal to src/analysis: the text helpers that compare's report (report.cpp) and the suite's
// leaderboard (leaderboard.cpp) both write with, so that their HTML, JSON and numbers read alike.
#pragma once

#include <fmt/format.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>

namespace translucent::analysis::text {

// HTML text and attribute values: the four characters that could end or open markup.
inline std::string html(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

// JSON has no NaN or infinity: such values are written as null.
inline nlohmann::json number(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

// Table cells; "–" for a value that does not exist (NaN).
inline std::string num(double v) { return std::isfinite(v) ? fmt::format("{:.4g}", v) : "–"; }
inline std::string pct(double v) { return std::isfinite(v) ? fmt::format("{:.2f}%", 100.0 * v) : "–"; }
inline std::string spct(double v) {
  return std::isfinite(v) ? fmt::format("{:+.2f}%", 100.0 * v) : "–";
}

}  // namespace translucent::analysis::text
