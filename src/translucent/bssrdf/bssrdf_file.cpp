// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/bssrdf/bssrdf_file.h"

#include "translucent/io/input_file.h"
#include "translucent/bssrdf/tabulated.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

namespace translucent::bssrdf {
namespace {

std::string formatError(const std::string& path, int line, const std::string& message) {
  if (line > 0) return fmt::format("{}:{}: error: {}", path, line, message);
  return fmt::format("{}: error: {}", path, message);
}

bool isSpace(char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; }

std::string_view trim(std::string_view s) {
  while (!s.empty() && isSpace(s.front())) s.remove_prefix(1);
  while (!s.empty() && isSpace(s.back())) s.remove_suffix(1);
  return s;
}

std::vector<std::string_view> splitWords(std::string_view s) {
  std::vector<std::string_view> words;
  size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && isSpace(s[i])) ++i;
    const size_t start = i;
    while (i < s.size() && !isSpace(s[i])) ++i;
    if (i > start) words.push_back(s.substr(start, i - start));
  }
  return words;
}


bool isComment(std::string_view trimmed) {
  return trimmed.starts_with("//") || trimmed.starts_with("#");
}

bool isIdentifier(std::string_view s) {
  if (s.empty()) return false;
  if (!(std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_')) return false;
  return std::all_of(s.begin(), s.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
  });
}

std::optional<double> parseNumber(std::string_view s) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  double v = 0.0;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc{} || ptr != s.data() + s.size() || !std::isfinite(v)) return std::nullopt;
  // Parameters become GLSL float uniforms: a larger double would be inf on the GPU.
  if (std::abs(v) > double(std::numeric_limits<float>::max())) return std::nullopt;
  return v;
}

std::optional<bool> parseBool(std::string_view s) {
  if (s == "true" || s == "1") return true;
  if (s == "false" || s == "0") return false;
  return std::nullopt;
}

// A `::begin NAME` / `::end NAME` marker line.
struct Marker {
  enum Kind { Begin, End } kind;
  std::string name;  // may be empty for ::end
};

class Parser {
 public:
  Parser(std::string_view text, std::string path) : text_(text) { file_.path = std::move(path); }

  BssrdfFile parse() {
    checkText();
    const auto lines = splitLines(text_);
    if (lines.empty()) fail(0, "empty file: expected the attribute list (e.g. 'analytic radial no_wi no_wo') on line 1");
    parseAttributes(lines[0]);

    // State: outside any section, or inside `open_` begun at `openLine_`.
    for (size_t i = 1; i < lines.size(); ++i) {
      const int line = static_cast<int>(i) + 1;
      const std::string_view trimmed = trim(lines[i]);
      const std::optional<Marker> marker = parseMarker(trimmed, line);

      if (!open_) {
        if (marker) {
          if (marker->kind == Marker::End)
            fail(line, fmt::format("'{}' without a matching '::begin'", trimmed));
          begin(marker->name, line);
        } else if (!trimmed.empty() && !isComment(trimmed)) {
          fail(line, fmt::format("text outside a section: expected '::begin NAME', a comment or a "
                                 "blank line, found '{}'",
                                 trimmed));
        }
        continue;
      }

      if (marker) {
        if (marker->kind == Marker::Begin)
          fail(openLine_, fmt::format("unterminated section '{}': expected '::end {}' before "
                                      "'::begin {}' at line {}",
                                      *open_, *open_, marker->name, line));
        if (!marker->name.empty() && marker->name != *open_)
          fail(line, fmt::format("'::end {}' does not close the open section: expected '::end {}' "
                                 "(section begun at line {})",
                                 marker->name, *open_, openLine_));
        end(line);
        continue;
      }
      body_.push_back(lines[i]);
    }

    if (open_)
      fail(openLine_, fmt::format("unterminated section '{}': expected '::end {}' before the end "
                                  "of the file",
                                  *open_, *open_));
    if (!sawShader_)
      fail(0, "missing section 'shader': expected '::begin shader' ... '::end shader' defining "
              "vec3 Bssrdf(vec3 Xi, vec3 Wi, vec3 Xo, vec3 Wo)");
    return std::move(file_);
  }

 private:
  [[noreturn]] void fail(int line, const std::string& message) const {
    throw BssrdfFileError(file_.path, line, message);
  }

  // A .bssrdf file is text: a NUL or another control byte (other than tab, CR, LF, form feed)
  // means binary data (a file picked by mistake, or corrupted). It is refused up front with its
  // line and byte, so that no message quotes raw bytes and the GLSL compiler never sees them.
  void checkText() const {
    int line = 1;
    for (size_t i = 0; i < text_.size(); ++i) {
      const auto c = static_cast<unsigned char>(text_[i]);
      if (c == '\n') ++line;
      if (c < 0x20 && c != '\n' && c != '\r' && c != '\t' && c != '\f')
        fail(line, fmt::format("byte {} is 0x{:02x}, a control character: expected a text file "
                               "(binary data?)", i, c));
    }
  }

  void parseAttributes(std::string_view line) {
    const auto words = splitWords(line);
    if (words.empty())
      fail(1, "expected the attribute list (e.g. 'analytic radial no_wi no_wo') on line 1, found "
              "an empty line");
    for (std::string_view w : words) {
      auto& a = file_.attributes;
      if (w == "analytic") a.analytic = true;
      else if (w == "radial") a.radial = true;
      else if (w == "no_wi") a.no_wi = true;
      else if (w == "no_wo") a.no_wo = true;
      else if (w.starts_with("::"))
        fail(1, "expected the attribute list (e.g. 'analytic radial no_wi no_wo') on line 1 "
                "before the first section");
      else
        fail(1, fmt::format("unknown attribute '{}': expected analytic, radial, no_wi or no_wo", w));
    }
    if (!file_.attributes.analytic)
      fail(1, "missing attribute 'analytic': it is mandatory for every .bssrdf file");
  }

  std::optional<Marker> parseMarker(std::string_view trimmed, int line) const {
    if (!trimmed.starts_with("::")) return std::nullopt;
    const auto words = splitWords(trimmed.substr(2));
    if (words.empty() || (words[0] != "begin" && words[0] != "end"))
      fail(line, fmt::format("malformed section marker '{}': expected '::begin NAME' or '::end NAME'",
                             trimmed));
    const bool isBegin = words[0] == "begin";
    if (words.size() > 2)
      fail(line, fmt::format("malformed section marker '{}': expected '::{} NAME' with a single "
                             "name",
                             trimmed, words[0]));
    if (isBegin && words.size() < 2)
      fail(line, "section without a name: expected '::begin NAME'");
    return Marker{isBegin ? Marker::Begin : Marker::End,
                  words.size() > 1 ? std::string(words[1]) : std::string()};
  }

  void begin(const std::string& name, int line) {
    for (const auto& [seen, seenLine] : seen_)
      if (seen == name)
        fail(line, fmt::format("duplicate section '{}' (first begun at line {})", name, seenLine));
    seen_.emplace_back(name, line);
    open_ = name;
    openLine_ = line;
    body_.clear();
  }

  void end(int /*line*/) {
    const std::string& name = *open_;
    GlslSection section;
    section.first_line = openLine_ + 1;
    for (std::string_view l : body_) {
      section.code += l;
      section.code += '\n';
    }
    if (name == "parameters") {
      file_.parameters_line = openLine_;
      for (size_t k = 0; k < body_.size(); ++k)
        parseParameter(body_[k], openLine_ + 1 + static_cast<int>(k));
    } else if (name == "initializer") {
      file_.initializer = std::move(section);
    } else if (name == "diffuseReflectance") {
      file_.diffuse_reflectance = std::move(section);
    } else if (name == "shader") {
      file_.shader = std::move(section);
      sawShader_ = true;
    } else {
      file_.ignored_sections.push_back(name);
    }
    open_.reset();
    body_.clear();
  }

  void parseParameter(std::string_view raw, int line) {
    const std::string_view trimmed = trim(raw);
    if (trimmed.empty() || isComment(trimmed)) return;
    const auto w = splitWords(trimmed);
    const std::string_view type = w[0];

    const char* form = nullptr;
    size_t fields = 0;
    if (type == "float") form = "float NAME MIN MAX DEFAULT", fields = 5;
    else if (type == "bool") form = "bool NAME DEFAULT", fields = 3;
    else if (type == "color") form = "color NAME R G B", fields = 5;
    else
      fail(line, fmt::format("malformed parameter line '{}': unknown type '{}', expected float, "
                             "bool or color",
                             trimmed, type));
    if (w.size() != fields)
      fail(line, fmt::format("malformed parameter line '{}': expected '{}' ({} fields, found {})",
                             trimmed, form, fields, w.size()));

    BssrdfParameter p;
    p.name = std::string(w[1]);
    p.line = line;
    if (!isIdentifier(p.name) || p.name.starts_with("gl_"))
      fail(line, fmt::format("malformed parameter line '{}': parameter name '{}' is not a valid "
                             "GLSL identifier",
                             trimmed, p.name));
    for (const char* reserved : kBssrdfStandardNames)
      if (p.name == reserved)
        fail(line, fmt::format("parameter name '{}' is reserved: the standard uniforms are SigmaA, "
                               "SigmaS, G, IOR and the constant PI",
                               p.name));
    for (const auto& q : file_.parameters)
      if (q.name == p.name)
        fail(line, fmt::format("duplicate parameter '{}' (first declared at line {})", p.name, q.line));

    auto number = [&](size_t k, const char* what) {
      const auto v = parseNumber(w[k]);
      if (!v)
        fail(line, fmt::format("malformed parameter line '{}': {} '{}' is not a finite number "
                               "that fits a float (expected '{}')",
                               trimmed, what, w[k], form));
      return *v;
    };

    if (type == "float") {
      FloatParameter f{number(2, "minimum"), number(3, "maximum"), number(4, "default")};
      if (f.min > f.max)
        fail(line, fmt::format("parameter '{}': minimum {} is larger than maximum {}", p.name,
                               f.min, f.max));
      if (f.value < f.min || f.value > f.max)
        fail(line, fmt::format("parameter '{}': default {} is outside [{}, {}]", p.name, f.value,
                               f.min, f.max));
      p.spec = f;
    } else if (type == "bool") {
      const auto b = parseBool(w[2]);
      if (!b)
        fail(line, fmt::format("malformed parameter line '{}': default '{}' is not a boolean "
                               "(expected true, false, 1 or 0)",
                               trimmed, w[2]));
      p.spec = BoolParameter{*b};
    } else {
      p.spec = ColorParameter{Rgb{number(2, "red"), number(3, "green"), number(4, "blue")}};
    }
    file_.parameters.push_back(std::move(p));
  }

  std::string_view text_;
  BssrdfFile file_;
  std::optional<std::string> open_;
  int openLine_ = 0;
  std::vector<std::string_view> body_;
  std::vector<std::pair<std::string, int>> seen_;
  bool sawShader_ = false;
};

}  // namespace

BssrdfFileError::BssrdfFileError(std::string path, int line, const std::string& message)
    : std::runtime_error(formatError(path, line, message)),
      path_(std::move(path)),
      line_(line),
      message_(message) {}

const BssrdfParameter* BssrdfFile::findParameter(std::string_view name) const {
  for (const auto& p : parameters)
    if (p.name == name) return &p;
  return nullptr;
}

std::string BssrdfFile::stem() const { return std::filesystem::path(path).stem().string(); }

BssrdfFile parseBssrdf(std::string_view text, const std::string& path) {
  return Parser(text, path).parse();
}

BssrdfFile loadBssrdf(const std::filesystem::path& path) {
  // A directory opens as a stream on Linux and reads as nothing ("empty file"): say what it is.
  if (const std::string why = io::irregularInput(path); !why.empty())
    throw BssrdfFileError(path.string(), 0, why + ": expected a .bssrdf text file");
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw BssrdfFileError(path.string(), 0, "cannot open the file for reading (does it exist?)");
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw BssrdfFileError(path.string(), 0, "read error");
  return parseBssrdf(ss.str(), path.string());
}

std::vector<std::string_view> splitLines(std::string_view text) {
  std::vector<std::string_view> lines;
  size_t start = 0;
  while (start < text.size()) {
    size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(start, end - start);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    lines.push_back(line);
    start = end + 1;
  }
  return lines;
}

bool isPluginFile(const std::string& entry) {
  if (hasBssrdfExtension(entry)) return true;
  if (isTabulatedFile(entry)) return false;
  std::error_code ec;
  return std::filesystem::is_regular_file(entry, ec);
}

bool hasBssrdfExtension(std::string_view path) {
  constexpr std::string_view ext = ".bssrdf";
  if (path.size() <= ext.size()) return false;
  const std::string_view tail = path.substr(path.size() - ext.size());
  return std::equal(tail.begin(), tail.end(), ext.begin(), [](char a, char b) {
    return std::tolower(static_cast<unsigned char>(a)) == b;
  });
}

std::string firstBssrdfLine(const std::string& message) {
  for (std::string_view line : splitLines(message))
    if (line.find(".bssrdf:") != std::string_view::npos) return std::string(line);
  return message;
}

}  // namespace translucent::bssrdf
