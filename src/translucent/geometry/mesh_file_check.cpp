// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/geometry/mesh_file_check.h"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <optional>
#include <vector>

#include "translucent/geometry/mesh.h"

namespace translucent::geometry::detail {
namespace {

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw MeshError(fmt::format("mesh file '{}': {}", path, what));
}

// A token as it can be shown in a message: at most 40 characters, control bytes escaped (a
// fuzzed file's token can be any bytes).
std::string shown(std::string_view s) {
  std::string out;
  for (const char c : s.substr(0, 40)) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u >= 0x7f)
      out += fmt::format("\\x{:02x}", u);
    else
      out += c;
  }
  if (s.size() > 40) out += "...";
  return "'" + out + "'";
}

bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v'; }

std::vector<std::string_view> tokens(std::string_view line) {
  std::vector<std::string_view> out;
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && isSpace(line[i])) ++i;
    const size_t start = i;
    while (i < line.size() && !isSpace(line[i])) ++i;
    if (i > start) out.push_back(line.substr(start, i - start));
  }
  return out;
}

std::optional<int64_t> parseInteger(std::string_view s) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  int64_t v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size() || s.empty()) return std::nullopt;
  return v;
}

std::optional<double> parseReal(std::string_view s) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  double v = 0.0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  // result_out_of_range: a literal beyond double's range, which is not finite either.
  if (ec == std::errc::result_out_of_range) return std::numeric_limits<double>::infinity();
  if (ec != std::errc() || end != s.data() + s.size() || s.empty()) return std::nullopt;
  return v;
}

// Text formats: assimp's line readers stop at a NUL byte and treat form feeds and lone carriage
// returns as line ends, so a file with them splits into different lines for assimp than for any
// check; such files are rejected.
void checkText(const std::string& path, std::string_view data, size_t offset) {
  for (size_t i = offset; i < data.size(); ++i) {
    const char c = data[i];
    if (c == '\0' || c == '\f' || (c == '\r' && (i + 1 == data.size() || data[i + 1] != '\n')))
      fail(path, fmt::format("byte {} is 0x{:02x}: expected a text file (no NUL, form feed or "
                             "lone carriage return)", i, static_cast<unsigned char>(c)));
  }
}

// Lines with their 1-based numbers; a trailing '\r' is dropped.
struct Line {
  std::string_view text;
  size_t number = 0;
};
std::vector<Line> splitLines(std::string_view data, size_t offset = 0, size_t firstNumber = 1) {
  std::vector<Line> lines;
  size_t number = firstNumber;
  for (size_t pos = offset; pos < data.size(); ++number) {
    size_t end = data.find('\n', pos);
    if (end == std::string_view::npos) end = data.size();
    std::string_view text = data.substr(pos, end - pos);
    if (!text.empty() && text.back() == '\r') text.remove_suffix(1);
    lines.push_back({text, number});
    pos = end + 1;
  }
  return lines;
}

// ---- PLY ------------------------------------------------------------------------------------

enum class PlyType { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

std::optional<PlyType> plyType(std::string_view s) {
  if (s == "char" || s == "int8") return PlyType::Int8;
  if (s == "uchar" || s == "uint8") return PlyType::UInt8;
  if (s == "short" || s == "int16") return PlyType::Int16;
  if (s == "ushort" || s == "uint16") return PlyType::UInt16;
  if (s == "int" || s == "int32") return PlyType::Int32;
  if (s == "uint" || s == "uint32") return PlyType::UInt32;
  if (s == "float" || s == "float32") return PlyType::Float32;
  if (s == "double" || s == "float64") return PlyType::Float64;
  return std::nullopt;
}
size_t plySize(PlyType t) {
  switch (t) {
    case PlyType::Int8: case PlyType::UInt8: return 1;
    case PlyType::Int16: case PlyType::UInt16: return 2;
    case PlyType::Int32: case PlyType::UInt32: case PlyType::Float32: return 4;
    case PlyType::Float64: return 8;
  }
  return 8;
}
bool plyIsReal(PlyType t) { return t == PlyType::Float32 || t == PlyType::Float64; }

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::Float32;  // the item type for a list
  bool list = false;
  PlyType countType = PlyType::UInt8;
};
struct PlyElement {
  std::string name;
  uint64_t count = 0;
  size_t line = 0;
  std::vector<PlyProperty> properties;
};

constexpr const char* kPlyTypes =
    "char, uchar, short, ushort, int, uint, float, double (or int8 ... float64)";

// One binary value as a double (every PLY type is exact in a double).
double readBinary(const unsigned char* p, PlyType t, bool bigEndian) {
  unsigned char b[8];
  const size_t n = plySize(t);
  std::memcpy(b, p, n);
  if (bigEndian != (std::endian::native == std::endian::big)) std::reverse(b, b + n);
  switch (t) {
    case PlyType::Int8: { int8_t v; std::memcpy(&v, b, 1); return v; }
    case PlyType::UInt8: return b[0];
    case PlyType::Int16: { int16_t v; std::memcpy(&v, b, 2); return v; }
    case PlyType::UInt16: { uint16_t v; std::memcpy(&v, b, 2); return v; }
    case PlyType::Int32: { int32_t v; std::memcpy(&v, b, 4); return v; }
    case PlyType::UInt32: { uint32_t v; std::memcpy(&v, b, 4); return v; }
    case PlyType::Float32: { float v; std::memcpy(&v, b, 4); return static_cast<double>(v); }
    case PlyType::Float64: { double v; std::memcpy(&v, b, 8); return v; }
  }
  return 0.0;
}

bool isFaceIndexList(const PlyElement& e, const PlyProperty& p) {
  return e.name == "face" && p.list && (p.name == "vertex_indices" || p.name == "vertex_index");
}

void checkPly(const std::string& path, std::string_view data) {
  // Header: text lines up to end_header; the data starts after that line's '\n'.
  size_t pos = 0, number = 0, dataStart = std::string_view::npos;
  std::optional<std::string> format;
  std::vector<PlyElement> elements;
  while (pos < data.size()) {
    ++number;
    size_t end = data.find('\n', pos);
    if (end == std::string_view::npos) end = data.size();
    const std::string_view raw = data.substr(pos, end - pos);
    pos = end + 1;
    const auto t = tokens(raw);
    if (number == 1) {
      if (t.size() != 1 || t[0] != "ply")
        fail(path, fmt::format("line 1 is {}: expected 'ply'", shown(raw)));
      continue;
    }
    if (t.empty() || t[0] == "comment" || t[0] == "obj_info") continue;
    if (t[0] == "end_header") {
      dataStart = std::min(pos, data.size());
      break;
    }
    if (t[0] == "format") {
      if (t.size() < 2 || (t[1] != "ascii" && t[1] != "binary_little_endian" &&
                           t[1] != "binary_big_endian"))
        fail(path, fmt::format("line {}: format {}: expected ascii, binary_little_endian or "
                               "binary_big_endian", number, shown(t.size() < 2 ? "" : t[1])));
      format = std::string(t[1]);
    } else if (t[0] == "element") {
      if (t.size() != 3)
        fail(path, fmt::format("line {} is {}: expected 'element NAME COUNT'", number, shown(raw)));
      const auto count = parseInteger(t[2]);
      if (!count || *count < 0 || *count > std::numeric_limits<uint32_t>::max())
        fail(path, fmt::format("line {}: element '{}' count {}: expected an integer from 0 to {}",
                               number, t[1], shown(t[2]), std::numeric_limits<uint32_t>::max()));
      // assimp mixes up repeated elements or properties (a second vertex element or a second x
      // loads a different mesh, silently), so names must be unique.
      for (const auto& e : elements)
        if (e.name == t[1])
          fail(path, fmt::format("line {}: a second element '{}' (the first on line {}): expected "
                                 "each element once", number, e.name, e.line));
      elements.push_back({std::string(t[1]), static_cast<uint64_t>(*count), number, {}});
    } else if (t[0] == "property") {
      if (elements.empty())
        fail(path, fmt::format("line {}: a property before any element: expected 'element NAME "
                               "COUNT' first", number));
      PlyProperty p;
      if (t.size() == 5 && t[1] == "list") {
        const auto ct = plyType(t[2]), it = plyType(t[3]);
        if (!ct || plyIsReal(*ct))
          fail(path, fmt::format("line {}: list count type {}: expected an integer type", number,
                                 shown(t[2])));
        if (!it)
          fail(path, fmt::format("line {}: list item type {}: expected one of {}", number,
                                 shown(t[3]), kPlyTypes));
        p = {std::string(t[4]), *it, true, *ct};
      } else if (t.size() == 3) {
        const auto ty = plyType(t[1]);
        if (!ty)
          fail(path, fmt::format("line {}: property type {}: expected one of {}", number,
                                 shown(t[1]), kPlyTypes));
        p = {std::string(t[2]), *ty, false, PlyType::UInt8};
      } else {
        fail(path, fmt::format("line {} is {}: expected 'property TYPE NAME' or 'property list "
                               "COUNT_TYPE ITEM_TYPE NAME'", number, shown(raw)));
      }
      for (const auto& q : elements.back().properties)
        if (q.name == p.name)
          fail(path, fmt::format("line {}: a second property '{}' in element '{}': expected each "
                                 "property once", number, p.name, elements.back().name));
      elements.back().properties.push_back(p);
    } else {
      fail(path, fmt::format("line {} is {}: expected format, element, property, comment, obj_info "
                             "or end_header in the PLY header", number, shown(raw)));
    }
  }
  if (dataStart == std::string_view::npos)
    fail(path, "the header has no end_header line: expected a PLY header ending in end_header");
  if (!format) fail(path, "the header has no format line: expected 'format ascii 1.0' or binary");

  const PlyElement* vertex = nullptr;
  const PlyElement* face = nullptr;
  for (const auto& e : elements) {
    if (e.count > 0 && e.properties.empty())
      fail(path, fmt::format("line {}: element '{}' has {} instances but no properties: expected "
                             "properties after it", e.line, e.name, e.count));
    if (e.name == "vertex" && !vertex) vertex = &e;
    if (e.name == "face" && !face) face = &e;
  }
  if (!vertex || vertex->count == 0)
    fail(path, "the header declares no vertices: expected 'element vertex N' with N > 0");
  for (const char* axis : {"x", "y", "z"})
    if (std::none_of(vertex->properties.begin(), vertex->properties.end(),
                     [&](const PlyProperty& p) { return p.name == axis && !p.list; }))
      fail(path, fmt::format("line {}: element vertex has no scalar property '{}': expected x, y "
                             "and z", vertex->line, axis));
  const bool hasIndices = face && std::any_of(face->properties.begin(), face->properties.end(),
                                              [&](const PlyProperty& p) {
                                                return isFaceIndexList(*face, p);
                                              });
  if (!face || face->count == 0 || !hasIndices)
    fail(path, "the header declares no faces: expected 'element face N' (N > 0) with a "
               "'property list ... vertex_indices'; a point cloud is not a triangle mesh");

  // Before walking: the least each element needs (lists empty; in ASCII one character and one
  // separator per value) must fit the data, so that a lying count fails at once, not after a
  // loop over 4e9 instances.
  const bool ascii = *format == "ascii";
  const uint64_t available = data.size() - dataStart;
  uint64_t needed = 0;
  for (const auto& e : elements) {
    uint64_t least = 0;
    for (const auto& p : e.properties) least += ascii ? 2 : plySize(p.list ? p.countType : p.type);
    needed += e.count * least;
    if (needed > available + 1)
      fail(path, fmt::format("line {}: element '{}' count {}: the {} bytes after the header hold "
                             "fewer (each needs at least {} bytes): expected counts that match the "
                             "data", e.line, e.name, e.count, available, least));
  }

  const uint64_t nv = vertex->count;
  // `where` gives the message's prefix (the line, or the byte offset), made only on failure.
  auto checkIndex = [&](double v, uint64_t instance, const auto& where) {
    if (!(v >= 0.0 && v < static_cast<double>(nv)))
      fail(path, fmt::format("{}face {} has vertex index {}, out of range: expected 0 to {}", where(), instance,
                             v, nv - 1));
  };
  auto checkValue = [&](double v, const PlyElement& e, const PlyProperty& p, uint64_t instance,
                        const auto& where) {
    if (plyIsReal(p.type) && !std::isfinite(v))
      fail(path, fmt::format("{}{} {} property '{}' is {}: expected a finite number", where(),
                             e.name, instance, p.name, v));
  };

  if (!ascii) {
    const bool big = *format == "binary_big_endian";
    const auto* bytes = reinterpret_cast<const unsigned char*>(data.data());
    uint64_t at = dataStart;
    auto byte = [&] { return fmt::format("byte {}: ", at); };
    auto need = [&](uint64_t n, const PlyElement& e, uint64_t instance) {
      if (n > data.size() - at)
        fail(path, fmt::format("{} {} (declared {} on line {}) ends past the end of the file at "
                               "byte {}: expected the data the header promises", e.name, instance,
                               e.count, e.line, data.size()));
    };
    for (const auto& e : elements)
      for (uint64_t i = 0; i < e.count; ++i)
        for (const auto& p : e.properties) {
          if (!p.list) {
            need(plySize(p.type), e, i);
            checkValue(readBinary(bytes + at, p.type, big), e, p, i, byte);
            at += plySize(p.type);
            continue;
          }
          need(plySize(p.countType), e, i);
          const double n = readBinary(bytes + at, p.countType, big);
          at += plySize(p.countType);
          if (n < 0)
            fail(path, fmt::format("{} {} property '{}' has a list of {} items: expected a "
                                   "non-negative count", e.name, i, p.name, n));
          const auto items = static_cast<uint64_t>(n);
          // A face of no index fails an assertion in assimp's triangulation; one or two indices
          // are no triangle either.
          if (isFaceIndexList(e, p) && items < 3)
            fail(path, fmt::format("byte {}: face {} has {} vertex indices: expected at least 3",
                                   at - plySize(p.countType), i, items));
          if (items > (data.size() - at) / plySize(p.type)) need(data.size() - at + 1, e, i);
          for (uint64_t k = 0; k < items; ++k, at += plySize(p.type)) {
            const double v = readBinary(bytes + at, p.type, big);
            if (isFaceIndexList(e, p))
              checkIndex(v, i, byte);
            else
              checkValue(v, e, p, i, byte);
          }
        }
    return;
  }

  // ASCII: one instance per line, exactly the values the header declares. assimp reads an empty
  // line as an instance and misreads a line with extra values (it then fails an assertion), so
  // both are errors; empty lines after the last instance are not.
  checkText(path, data, dataStart);
  const auto lines = splitLines(data, dataStart, number + 1);
  size_t li = 0;
  for (const auto& e : elements)
    for (uint64_t i = 0; i < e.count; ++i) {
      if (li == lines.size() || (li + 1 == lines.size() && lines[li].text.empty()))
        fail(path, fmt::format("the data ends before {} {}: line {} declares {}: expected one line "
                               "per instance", e.name, i, e.line, e.count));
      const Line& line = lines[li++];
      const auto t = tokens(line.text);
      auto where = [&] { return fmt::format("line {}: ", line.number); };
      if (t.empty())
        fail(path, fmt::format("{}blank where {} {} should be: expected one line per instance",
                               where(), e.name, i));
      size_t k = 0;
      auto next = [&](const PlyProperty& p) {
        if (k == t.size())
          fail(path, fmt::format("{}{} {} ends before property '{}': expected all of its values "
                                 "on one line", where(), e.name, i, p.name));
        return t[k++];
      };
      auto value = [&](std::string_view s, PlyType type, const PlyProperty& p) {
        if (plyIsReal(type)) {
          const auto v = parseReal(s);
          if (!v)
            fail(path, fmt::format("{}{} {} property '{}' is {}: expected a number", where(), e.name,
                                   i, p.name, shown(s)));
          return *v;
        }
        const auto v = parseInteger(s);
        if (!v)
          fail(path, fmt::format("{}{} {} property '{}' is {}: expected an integer", where(), e.name,
                                 i, p.name, shown(s)));
        return static_cast<double>(*v);
      };
      for (const auto& p : e.properties) {
        if (!p.list) {
          checkValue(value(next(p), p.type, p), e, p, i, where);
          continue;
        }
        const double n = value(next(p), p.countType, p);
        if (isFaceIndexList(e, p) && n < 3)
          fail(path, fmt::format("{}face {} has {} vertex indices: expected at least 3", where(), i,
                                 n));
        if (n < 0 || n > static_cast<double>(t.size()))
          fail(path, fmt::format("{}{} {} property '{}' has a list of {} items but the line holds "
                                 "{} values: expected the count to match", where(), e.name, i,
                                 p.name, n, t.size() - k));
        for (uint64_t j = 0; j < static_cast<uint64_t>(n); ++j) {
          const double v = value(next(p), p.type, p);
          if (isFaceIndexList(e, p))
            checkIndex(v, i, where);
          else
            checkValue(v, e, p, i, where);
        }
      }
      if (k != t.size())
        fail(path, fmt::format("{}{} {} has {} values more than its properties: expected {}",
                               where(), e.name, i, t.size() - k, k));
    }
}

// ---- OFF ------------------------------------------------------------------------------------

void checkOff(const std::string& path, std::string_view data) {
  checkText(path, data, 0);
  // assimp's OFF reader copies lines into a 4096-byte buffer and skips empty lines (runs of line
  // ends), but not comments or blank ones.
  std::vector<Line> lines;
  for (const Line& l : splitLines(data)) {
    if (l.text.size() > 4000)
      fail(path, fmt::format("line {} has {} characters: expected at most 4000", l.number,
                             l.text.size()));
    if (!l.text.empty()) lines.push_back(l);
  }
  size_t li = 0;
  if (lines.empty()) fail(path, "no lines: expected an OFF header");
  auto head = tokens(lines[0].text);
  if (head.empty())
    fail(path, fmt::format("line {} is blank: expected 'OFF'", lines[0].number));
  // The header keyword: [ST][C][N]OFF (assimp's variants; 4OFF and nOFF it rejects), or none.
  std::string_view kw = head[0];
  size_t countsAt = 0;
  if (kw.ends_with("OFF")) {
    std::string_view prefix = kw.substr(0, kw.size() - 3);
    if (prefix.starts_with("ST")) prefix.remove_prefix(2);
    if (prefix.starts_with("C")) prefix.remove_prefix(1);
    if (prefix.starts_with("N")) prefix.remove_prefix(1);
    if (!prefix.empty())
      fail(path, fmt::format("line {}: header {}: expected OFF, COFF, NOFF or STOFF (3D "
                             "vertices)", lines[0].number, shown(kw)));
    countsAt = 1;
  } else if (!parseInteger(kw)) {
    fail(path, fmt::format("line {}: header {}: expected 'OFF'", lines[0].number, shown(kw)));
  }
  if (countsAt == head.size()) {  // the counts on the next line
    li = 1;
    if (li == lines.size())
      fail(path, "the file ends after the header: expected 'VERTICES FACES EDGES'");
    head = tokens(lines[li].text);
    countsAt = 0;
  }
  const size_t countsLine = lines[li].number;
  ++li;
  if (head.size() - countsAt != 3)
    fail(path, fmt::format("line {}: counts '{}': expected 'VERTICES FACES EDGES' (three "
                           "non-negative integers)", countsLine,
                           fmt::join(head.begin() + static_cast<ptrdiff_t>(countsAt), head.end(),
                                     " ")));
  uint64_t counts[3];
  const char* names[3] = {"vertex", "face", "edge"};
  for (int c = 0; c < 3; ++c) {
    const auto v = parseInteger(head[countsAt + static_cast<size_t>(c)]);
    if (!v || *v < 0 || *v > std::numeric_limits<uint32_t>::max())
      fail(path, fmt::format("line {}: {} count {}: expected an integer from 0 to {}", countsLine,
                             names[c], shown(head[countsAt + static_cast<size_t>(c)]),
                             std::numeric_limits<uint32_t>::max()));
    counts[c] = static_cast<uint64_t>(*v);
  }
  const uint64_t nv = counts[0], nf = counts[1];
  if (nv == 0) fail(path, fmt::format("line {}: 0 vertices: expected a mesh", countsLine));
  if (nf == 0) fail(path, fmt::format("line {}: 0 faces: expected a triangle mesh", countsLine));
  if (nv + nf > lines.size() - li)
    fail(path, fmt::format("line {} declares {} vertices and {} faces but {} lines follow: "
                           "expected one line per vertex and per face", countsLine, nv, nf,
                           lines.size() - li));
  for (uint64_t i = 0; i < nv; ++i, ++li) {
    const auto t = tokens(lines[li].text);
    if (t.size() < 3)
      fail(path, fmt::format("line {}: vertex {} has {} values: expected x y z", lines[li].number,
                             i, t.size()));
    for (size_t k = 0; k < t.size(); ++k) {
      const auto v = parseReal(t[k]);
      if (!v)
        fail(path, fmt::format("line {}: vertex {} value {}: expected a number", lines[li].number,
                               i, shown(t[k])));
      if (k < 3 && !std::isfinite(*v))
        fail(path, fmt::format("line {}: vertex {} coordinate {} is {}: expected a finite number",
                               lines[li].number, i, "xyz"[k], *v));
    }
  }
  for (uint64_t i = 0; i < nf; ++i, ++li) {
    const auto t = tokens(lines[li].text);
    int64_t parsed = -1;  // not a count
    if (!t.empty()) parsed = parseInteger(t[0]).value_or(-1);
    // assimp drops faces of 0 or more than 9 vertices; both are errors here, not lost faces.
    if (parsed < 1 || parsed > 9)
      fail(path, fmt::format("line {}: face {} vertex count {}: expected 1 to 9", lines[li].number,
                             i, shown(t.empty() ? "" : t[0])));
    const auto n = static_cast<size_t>(parsed);
    if (t.size() < 1 + n)
      fail(path, fmt::format("line {}: face {} lists {} of its {} vertex indices: expected all on "
                             "one line", lines[li].number, i, t.size() - 1, n));
    for (size_t k = 1; k <= n; ++k) {
      const auto v = parseInteger(t[k]);
      if (!v || *v < 0 || static_cast<uint64_t>(*v) >= nv)
        fail(path, fmt::format("line {}: face {} has vertex index {}, out of range: expected 0 to {}",
                               lines[li].number, i, shown(t[k]), nv - 1));
    }
  }
}

// ---- OBJ ------------------------------------------------------------------------------------

void checkObj(const std::string& path, std::string_view data) {
  checkText(path, data, 0);
  const auto lines = splitLines(data);
  // Totals first: a positive index may name any vertex of the file; a negative one counts back
  // from the vertices read so far (as assimp resolves them).
  uint64_t total[3] = {0, 0, 0};
  auto kind = [](std::string_view k) { return k == "v" ? 0 : k == "vt" ? 1 : k == "vn" ? 2 : -1; };
  for (const auto& l : lines) {
    const auto t = tokens(l.text);
    if (!t.empty() && kind(t[0]) >= 0) ++total[kind(t[0])];
  }
  uint64_t sofar[3] = {0, 0, 0};
  bool faces = false;
  const char* what[3] = {"vertex", "texture coordinate", "normal"};
  const char* whats[3] = {"vertices", "texture coordinates", "normals"};
  for (const auto& l : lines) {
    const auto t = tokens(l.text);
    if (t.empty()) continue;
    if (t[0] == "v") {
      if (t.size() < 4)
        fail(path, fmt::format("line {}: vertex {} has {} coordinates: expected x y z", l.number,
                               sofar[0] + 1, t.size() - 1));
      for (size_t k = 1; k <= 3; ++k) {
        const auto v = parseReal(t[k]);
        if (!v)
          fail(path, fmt::format("line {}: vertex {} coordinate {}: expected a number", l.number,
                                 sofar[0] + 1, shown(t[k])));
        if (!std::isfinite(*v))
          fail(path, fmt::format("line {}: vertex {} coordinate {} is {}: expected a finite "
                                 "number", l.number, sofar[0] + 1, "xyz"[k - 1], *v));
      }
    }
    if (kind(t[0]) >= 0) {
      ++sofar[kind(t[0])];
      continue;
    }
    if (t[0] != "f" && t[0] != "l" && t[0] != "p") continue;
    faces = faces || t[0] == "f";
    // With assimp's validation, a face of one or two vertices among triangles makes the whole
    // file fail with a message about primitive type flags; say what is wrong instead.
    if (t[0] == "f" && t.size() < 4)
      fail(path, fmt::format("line {}: a face of {} vertices: expected at least 3 ('l' and 'p' "
                             "lines are for lines and points)", l.number, t.size() - 1));
    for (size_t k = 1; k < t.size(); ++k) {
      // v, v/vt, v//vn or v/vt/vn.
      std::string_view rest = t[k];
      for (int part = 0; part < 3 && !rest.empty(); ++part) {
        const size_t slash = rest.find('/');
        const std::string_view s = rest.substr(0, slash);
        rest = slash == std::string_view::npos ? std::string_view() : rest.substr(slash + 1);
        if (s.empty() && part > 0) continue;
        const auto v = parseInteger(s);
        if (!v)
          fail(path, fmt::format("line {}: '{}' index {}: expected an integer", l.number, t[0],
                                 shown(s)));
        const bool ok = *v > 0 ? static_cast<uint64_t>(*v) <= total[part]
                               : *v < 0 && static_cast<uint64_t>(-(*v + 1)) < sofar[part];
        if (!ok && total[part] == 0)
          fail(path, fmt::format("line {}: {} index {}, but the file has no {} ('{}' lines)",
                                 l.number, what[part], *v, whats[part],
                                 part == 0 ? "v" : part == 1 ? "vt" : "vn"));
        if (!ok)
          fail(path, fmt::format("line {}: {} index {} is out of range: expected 1 to {} (or -1 to "
                                 "-{} counting back){}", l.number, what[part], *v, total[part], sofar[part],
                                 *v == 0 ? "; OBJ indices start at 1" : ""));
      }
    }
  }
  if (total[0] == 0) fail(path, "no vertices ('v' lines): expected a triangle mesh");
  if (!faces) fail(path, "no faces ('f' lines): expected a triangle mesh");
}

}  // namespace

void checkMeshFile(const std::string& path, std::string_view data, const std::string& extension) {
  if (extension == ".ply")
    checkPly(path, data);
  else if (extension == ".off")
    checkOff(path, data);
  else if (extension == ".obj")
    checkObj(path, data);
}

}  // namespace translucent::geometry::detail
