// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/bssrdf/tabulated.h"

#include "translucent/io/input_file.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

namespace translucent::bssrdf {
namespace {

std::string lower(std::string_view s) {
  std::string out(s);
  for (auto& ch : out) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return out;
}

std::string trim(std::string_view s) {
  size_t a = 0, b = s.size();
  while (a < b && std::isspace(static_cast<unsigned char>(s[a]))) ++a;
  while (b > a && std::isspace(static_cast<unsigned char>(s[b - 1]))) --b;
  return std::string(s.substr(a, b - a));
}

// The ranges a table's samples must lie in (readProfileSamples).
constexpr double kMaxRadiusMm = 1e6;  // 1 km
constexpr double kMinValuePerMm2 = 1e-30, kMaxValuePerMm2 = 1e30;

std::vector<std::string> splitCsv(const std::string& line) {
  std::vector<std::string> out;
  std::string cell;
  std::istringstream in(line);
  while (std::getline(in, cell, ',')) out.push_back(trim(cell));
  if (!line.empty() && line.back() == ',') out.emplace_back();
  return out;
}

// Text of the file as shown in a message: control bytes (a NUL would end the message where it is
// printed as a C string) as \xHH, and at most 60 bytes of it.
std::string shown(std::string_view text) {
  std::string out;
  for (size_t i = 0; i < text.size() && i < 60; ++i) {
    const auto ch = static_cast<unsigned char>(text[i]);
    out += ch < 0x20 || ch == 0x7f ? fmt::format("\\x{:02x}", ch) : std::string(1, text[i]);
  }
  if (text.size() > 60) out += "...";
  return out;
}

// Millimetres per unit of r.
double unitFactor(const std::string& unit, const std::string& where) {
  if (unit == "mm") return 1.0;
  if (unit == "cm") return 10.0;
  if (unit == "m") return 1000.0;
  if (unit == "um" || unit == "µm" || unit == "micron") return 0.001;
  throw ParameterError(fmt::format("{}: units '{}': expected mm, cm, m or um", where, shown(unit)));
}

double number(const std::string& cell, const std::string& where, const char* what) {
  double v = 0.0;
  const char* end = cell.data() + cell.size();
  const auto [p, ec] = std::from_chars(cell.data(), end, v);
  if (cell.empty() || ec != std::errc() || p != end || !std::isfinite(v))
    throw ParameterError(fmt::format("{}: {} '{}': expected a finite number", where, what,
                                     shown(cell)));
  return v;
}

}  // namespace

bool isTabulatedFile(std::string_view name) {
  return name.size() > 4 && lower(name.substr(name.size() - 4)) == ".csv";
}

ProfileSamples readProfileSamples(const std::string& path) {
  if (const std::string why = io::irregularInput(path); !why.empty())
    throw ParameterError(fmt::format("{}: {}: expected a tabulated profile (CSV)", path, why));
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw ParameterError(fmt::format("{}: cannot read the tabulated profile (no such file, or "
                                     "not readable)", path));
  ProfileSamples t;
  t.source = path;
  std::string unit;
  enum class Format { None, Rgb, Curves } format = Format::None;
  // Curves format: rows per (model, channel), then one model chosen.
  std::map<std::string, std::array<std::vector<std::pair<double, double>>, 3>> curves;
  std::string line;
  int lineNo = 0, firstData = 0;
  while (std::getline(in, line)) {
    ++lineNo;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::string where = fmt::format("{}:{}", path, lineNo);
    const std::string s = trim(line);
    if (s.empty()) continue;
    if (s[0] == '#') {
      const std::string body = trim(std::string_view(s).substr(1));
      const auto colon = body.find(':');
      if (colon == std::string::npos) continue;
      const std::string key = lower(trim(std::string_view(body).substr(0, colon)));
      const std::string value = trim(std::string_view(body).substr(colon + 1));
      if (key == "units" || key == "unit") {
        (void)unitFactor(lower(value), where);
        unit = lower(value);
      } else if (key == "eta") {
        t.eta = number(value, where, "eta");
        if (!(t.eta > 0.0))
          throw ParameterError(fmt::format("{}: eta {}: expected > 0", where, shown(value)));
      }
      continue;
    }
    const auto cells = splitCsv(s);
    if (format == Format::None) {
      std::vector<std::string> names;
      for (const auto& c : cells) names.push_back(lower(c));
      if (names == std::vector<std::string>{"r", "r_r", "r_g", "r_b"}) {
        format = Format::Rgb;
      } else if (names.size() >= 4 && names[0] == "model" && names[1] == "channel" &&
                 names[2] == "r" && names[3] == "value") {
        format = Format::Curves;
      } else {
        throw ParameterError(fmt::format(
            "{}: header '{}': expected 'r,R_r,R_g,R_b' (with a '# units: mm' line above it) or "
            "the 'model,channel,r,value' CSV of translucent profile",
            where, shown(s)));
      }
      continue;
    }
    if (firstData == 0) firstData = lineNo;
    if (format == Format::Rgb) {
      if (cells.size() != 4)
        throw ParameterError(
            fmt::format("{}: {} values: expected 4 (r,R_r,R_g,R_b)", where, cells.size()));
      t.r_mm.push_back(number(cells[0], where, "r"));
      for (int c = 0; c < 3; ++c)
        t.R_mm[size_t(c)].push_back(number(cells[size_t(c) + 1], where, "R"));
    } else {
      if (cells.size() < 4)
        throw ParameterError(fmt::format(
            "{}: {} values: expected at least 4 (model,channel,r,value)", where, cells.size()));
      const std::string ch = lower(cells[1]);
      const int c = ch == "r" ? 0 : ch == "g" ? 1 : ch == "b" ? 2 : -1;
      if (c < 0) continue;  // luminance curves: not a channel of the table
      curves[cells[0]][size_t(c)].emplace_back(number(cells[2], where, "r"),
                                               number(cells[3], where, "value"));
    }
  }
  if (format == Format::None)
    throw ParameterError(fmt::format("{}: no header: expected 'r,R_r,R_g,R_b' or "
                                     "'model,channel,r,value'", path));
  if (format == Format::Rgb && unit.empty())
    throw ParameterError(fmt::format(
        "{}: no '# units: mm' line (mm, cm, m or um): the unit of r must be stated", path));
  if (format == Format::Curves) {
    std::string chosen;
    if (curves.contains("reference")) {
      chosen = "reference";
    } else if (curves.size() == 1) {
      chosen = curves.begin()->first;
    } else {
      std::vector<std::string> names;
      for (const auto& [n, _] : curves) names.push_back(n);
      throw ParameterError(fmt::format(
          "{}: curves of {} models and none named 'reference': expected one model's r, g and b "
          "curves (found {})",
          path, names.size(), fmt::format("{}", fmt::join(names, ", "))));
    }
    const auto& rgb = curves[chosen];
    for (int c = 0; c < 3; ++c)
      if (rgb[size_t(c)].empty())
        throw ParameterError(fmt::format(
            "{}: model '{}' has no '{}' channel rows: expected r, g and b curves (translucent "
            "profile --channel all)",
            path, chosen, "rgb"[c]));
    for (int c = 1; c < 3; ++c) {
      bool same = rgb[size_t(c)].size() == rgb[0].size();
      for (size_t i = 0; same && i < rgb[0].size(); ++i)
        same = rgb[size_t(c)][i].first == rgb[0][i].first;
      if (!same)
        throw ParameterError(fmt::format(
            "{}: the '{}' curve of '{}' has other radii than the 'r' curve: expected one radius "
            "grid for all channels", path, "rgb"[c], chosen));
    }
    for (size_t i = 0; i < rgb[0].size(); ++i) {
      t.r_mm.push_back(rgb[0][i].first);
      for (int c = 0; c < 3; ++c) t.R_mm[size_t(c)].push_back(rgb[size_t(c)][i].second);
    }
    if (unit.empty()) unit = "mm";
  }
  const double f = unitFactor(unit, path);
  if (t.r_mm.size() < 2)
    throw ParameterError(fmt::format("{}: {} samples: expected at least 2 radii", path,
                                     t.r_mm.size()));
  for (size_t i = 0; i < t.r_mm.size(); ++i) {
    const std::string where =
        format == Format::Rgb ? fmt::format("{}:{}", path, firstData + static_cast<int>(i))
                              : fmt::format("{} (sample {})", path, i + 1);
    if (t.r_mm[i] < 0.0) throw ParameterError(fmt::format("{}: r {}: expected >= 0", where, t.r_mm[i]));
    if (i > 0 && !(t.r_mm[i] > t.r_mm[i - 1]))
      throw ParameterError(fmt::format("{}: r {} after {}: expected increasing radii", where,
                                       t.r_mm[i], t.r_mm[i - 1]));
    // Radii and values a renderer can use: beyond these the quadrature of Rd overflows to
    // non-finite pixels, or the profile lands at ~0 everywhere a pixel looks (an all-black image).
    if (!(t.r_mm[i] * f <= kMaxRadiusMm))
      throw ParameterError(fmt::format("{}: r {} ({} mm): expected at most {} mm", where, t.r_mm[i],
                                       t.r_mm[i] * f, kMaxRadiusMm));
    for (int c = 0; c < 3; ++c) {
      const double v = t.R_mm[size_t(c)][i];
      if (v < 0.0)
        throw ParameterError(fmt::format("{}: R ({} channel) {}: expected >= 0", where,
                                         kChannelNames[c], v));
      const double perMm2 = v / (f * f);
      if (!(perMm2 <= kMaxValuePerMm2))
        throw ParameterError(fmt::format("{}: R ({} channel) {} ({} per mm²): expected at most {} "
                                         "per mm²", where, kChannelNames[c], v, perMm2,
                                         kMaxValuePerMm2));
    }
  }
  // A tail may fall as far below kMinValuePerMm2 as it likes (a profile decays exponentially);
  // what a renderer cannot use is a channel whose largest value is that small: its pixels come
  // out as 0 (or subnormal) everywhere.
  for (int c = 0; c < 3; ++c) {
    const auto& ch = t.R_mm[size_t(c)];
    const double peak = *std::max_element(ch.begin(), ch.end());
    if (!(peak > 0.0))
      throw ParameterError(fmt::format("{}: the {} channel is 0 everywhere: expected some "
                                       "reflectance", path, kChannelNames[c]));
    if (!(peak / (f * f) >= kMinValuePerMm2))
      throw ParameterError(fmt::format("{}: the {} channel's largest R is {} ({} per mm²): "
                                       "expected a peak of at least {} per mm²",
                                       path, kChannelNames[c], peak, peak / (f * f),
                                       kMinValuePerMm2));
  }
  for (auto& r : t.r_mm) r *= f;
  for (auto& ch : t.R_mm)
    for (auto& v : ch) v /= f * f;
  // What a renderer divides by: Rd, the quadrature of R(r) (RadialProfile::cumulative, panels of
  // 1/48 decade). A channel that is 0 except near one far sample ("0" at 1001.2 mm, "4" at
  // 1002 mm) passed the checks above and integrated to Rd = 0, where sampling divides by Rd
  // (fuzz_tabulated): refused here, with the radii where it is not 0.
  const TabulatedModel model(t);
  for (int c = 0; c < 3; ++c) {
    ScalarMedium m;
    m.channel = c;
    const double rd = model.profile(m)->Rd();
    if (std::isfinite(rd) && rd > 0.0) continue;
    const auto& ch = t.R_mm[size_t(c)];
    size_t first = 0, last = ch.size() - 1;
    while (ch[first] == 0.0) ++first;
    while (ch[last] == 0.0) --last;
    throw ParameterError(fmt::format(
        "{}: the {} channel integrates to Rd = {}: it is 0 except between r = {} and {} mm, too "
        "narrow a range for the quadrature of Rd; expected a profile that is not 0 over a range "
        "of radii, or more samples there",
        path, kChannelNames[c], rd, first > 0 ? t.r_mm[first - 1] : t.r_mm[first],
        last + 1 < ch.size() ? t.r_mm[last + 1] : t.r_mm[last]));
  }
  return t;
}

void writeProfileSamples(const std::string& path, const ProfileSamples& table,
                       const std::vector<std::string>& comment) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) throw std::runtime_error(fmt::format("cannot write '{}'", path));
  for (const auto& c : comment) fmt::print(f, "# {}\n", c);
  fmt::print(f, "# units: mm\n");
  if (table.eta > 0.0) fmt::print(f, "# eta: {:.9g}\n", table.eta);
  fmt::print(f, "r,R_r,R_g,R_b\n");
  for (size_t i = 0; i < table.r_mm.size(); ++i)
    fmt::print(f, "{:.9g},{:.9g},{:.9g},{:.9g}\n", table.r_mm[i], table.R_mm[0][i],
               table.R_mm[1][i], table.R_mm[2][i]);
  const bool ok = std::ferror(f) == 0;
  if (std::fclose(f) != 0 || !ok) throw std::runtime_error(fmt::format("cannot write '{}'", path));
}

namespace {

class TabulatedProfile final : public RadialProfile {
 public:
  TabulatedProfile(const ScalarMedium& m, const TabulatedModel& model)
      : RadialProfile(m), model_(model), c_(m.channel), scale_(m.scale) {}
  // r_scene = r_mm / scale and R_scene = R_mm · scale² (the table is in mm).
  double evaluate(double r) const override { return model_.Rmm(c_, r * scale_) * scale_ * scale_; }

 protected:
  // The table's panels start below its first positive radius.
  double innerScale() const override {
    const auto& r = model_.table().r_mm;
    return (r[0] > 0.0 ? r[0] : r[1]) / scale_;
  }

 private:
  const TabulatedModel& model_;
  int c_;
  double scale_;
};

}  // namespace

TabulatedModel::TabulatedModel(ProfileSamples table) : table_(std::move(table)) {
  name_ = table_.source;
  description_ = fmt::format("tabulated profile from {} ({} radii, {:.4g} to {:.4g} mm{})",
                             std::filesystem::path(table_.source).filename().string(),
                             table_.r_mm.size(), table_.r_mm.front(), table_.r_mm.back(),
                             table_.eta > 0.0 ? fmt::format(", eta {:g}", table_.eta) : "");
  // Tail: least-squares slope of ln R against r over the last tenth of the positive samples.
  for (int c = 0; c < 3; ++c) {
    std::vector<std::pair<double, double>> pts;
    for (size_t i = 0; i < table_.r_mm.size(); ++i)
      if (table_.R_mm[size_t(c)][i] > 0.0)
        pts.emplace_back(table_.r_mm[i], std::log(table_.R_mm[size_t(c)][i]));
    const size_t n = std::max<size_t>(2, pts.size() / 10);
    double slope = 0.0;
    if (pts.size() >= 2) {
      double sx = 0, sy = 0, sxx = 0, sxy = 0;
      for (size_t i = pts.size() - n; i < pts.size(); ++i) {
        sx += pts[i].first;
        sy += pts[i].second;
        sxx += pts[i].first * pts[i].first;
        sxy += pts[i].first * pts[i].second;
      }
      const double k = static_cast<double>(n);
      const double den = k * sxx - sx * sx;
      if (den > 0.0) slope = (k * sxy - sx * sy) / den;
    }
    tailSlope_[size_t(c)] = slope < 0.0 ? slope : 0.0;
  }
}

double TabulatedModel::Rmm(int c, double r) const {
  const auto& rs = table_.r_mm;
  const auto& v = table_.R_mm[size_t(c)];
  if (r <= rs.front()) return v.front();
  if (r >= rs.back()) {
    // A zero slope means the fit found no decay: nothing is extrapolated.
    return tailSlope_[size_t(c)] < 0.0 ? v.back() * std::exp(tailSlope_[size_t(c)] * (r - rs.back()))
                                       : 0.0;
  }
  const size_t i = static_cast<size_t>(std::upper_bound(rs.begin(), rs.end(), r) - rs.begin());
  const double r0 = rs[i - 1], r1 = rs[i], v0 = v[i - 1], v1 = v[i];
  if (r0 > 0.0 && v0 > 0.0 && v1 > 0.0) {
    // In logarithms: v0 · (v1 / v0)^t overflowed to inf where the ratio does (a subnormal v0
    // next to an ordinary v1, "1e-320" then "0.13": fuzz_tabulated), and inf · 0 made NaN
    // pixels. ln v lies in [-745, 710], so this stays between v0 and v1.
    const double t = std::log(r / r0) / std::log(r1 / r0);
    return std::exp(std::log(v0) + t * (std::log(v1) - std::log(v0)));
  }
  return v0 + (v1 - v0) * (r - r0) / (r1 - r0);
}

std::unique_ptr<RadialProfile> TabulatedModel::profile(const ScalarMedium& medium) const {
  if (medium.channel < 0 || medium.channel > 2)
    throw ParameterError(fmt::format(
        "model '{}' is a tabulated profile, one R(r) per RGB channel: it has no profile for a "
        "scalar medium (a channel of a Medium is needed)", name_));
  if (!(medium.scale > 0.0) || !std::isfinite(medium.scale))
    throw ParameterError(fmt::format("model '{}': scale {}: expected > 0", name_, medium.scale));
  return std::make_unique<TabulatedProfile>(medium, *this);
}

double TabulatedModel::totalReflectance(double, double) const {
  throw ParameterError(fmt::format(
      "model '{}' is a tabulated profile: its Rd is fixed per channel, not a function of the "
      "albedo (it cannot be inverted or used for heterogeneous materials)", name_));
}

}  // namespace translucent::bssrdf
