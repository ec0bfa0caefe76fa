// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/gpu/shader_source.h"

#include "translucent/bssrdf/bssrdf_file.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdlib>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include "translucent/gpu/gl.h"
#include "translucent/io/resources.h"


namespace translucent::gpu {
namespace {

using bssrdf::splitLines;

std::string_view trimLeft(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  return s;
}

// "#  include ..." -> ("include", rest); empty name for non-directives.
std::pair<std::string_view, std::string_view> directive(std::string_view line) {
  std::string_view s = trimLeft(line);
  if (s.empty() || s.front() != '#') return {};
  s = trimLeft(s.substr(1));
  size_t n = 0;
  while (n < s.size() && (std::isalpha(static_cast<unsigned char>(s[n])) != 0)) ++n;
  return {s.substr(0, n), trimLeft(s.substr(n))};
}

// A decimal number from a driver log (saturating: logs are not trusted to be sane).
int toInt(const std::string& digits) {
  int v = 0;
  const auto [ptr, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), v);
  return ec == std::errc{} ? v : -1;
}

std::string readFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return {};
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

class Expander {
 public:
  Expander(const std::vector<std::filesystem::path>& dirs,
           const std::map<std::string, SourceFile>& virtuals,
           const std::vector<std::pair<std::string, std::string>>& defines)
      : dirs_(dirs), virtuals_(virtuals), defines_(defines) {}

  ShaderSource run(const SourceFile& top, const std::filesystem::path& topDir) {
    // #line may not precede #version: if the top file has one, directives start after it.
    hasVersion_ = false;
    for (std::string_view l : splitLines(top.text))
      if (directive(l).first == "version") hasVersion_ = true;
    if (!hasVersion_) emitDefines();
    expand(top, topDir, "top:" + top.path, true);
    return std::move(out_);
  }

  void addDependency(const std::filesystem::path& p) { out_.dependencies.push_back(p); }

 private:
  int indexOf(const std::string& path) {
    const auto it = std::find(out_.files.begin(), out_.files.end(), path);
    if (it != out_.files.end()) return static_cast<int>(it - out_.files.begin());
    out_.files.push_back(path);
    return static_cast<int>(out_.files.size()) - 1;
  }

  void emit(std::string_view text, int source, int line) {
    const int want = source * kLineStride + line;
    const bool allowed = !hasVersion_ || versionEmitted_;
    if (allowed && (driverSource_ != source || driverLine_ != want)) {
      out_.text += fmt::format("#line {} {}\n", want, source);
      driverSource_ = source;
      driverLine_ = want;
    }
    out_.text += text;
    out_.text += '\n';
    ++driverLine_;
  }

  void emitDefines() {
    if (defines_.empty()) return;
    const int k = indexOf("<defines>");
    int line = 1;
    for (const auto& [name, value] : defines_)
      emit(value.empty() ? fmt::format("#define {}", name)
                         : fmt::format("#define {} {}", name, value),
           k, line++);
  }

  [[noreturn]] void fail(const std::string& path, int line, const std::string& message) const {
    throw GlError(fmt::format("{}:{}: error: {}", path, line, message));
  }

  // Resolves an include name: virtual files, then the including file's folder, then the dirs.
  struct Resolved {
    SourceFile file;
    std::filesystem::path dir;
    std::string id;
  };
  Resolved resolve(const std::string& name, const std::filesystem::path& fromDir,
                   const std::string& path, int line) {
    if (const auto it = virtuals_.find(name); it != virtuals_.end())
      return {it->second, {}, "virtual:" + name};
    std::vector<std::filesystem::path> tried;
    std::vector<std::filesystem::path> dirs;
    if (!fromDir.empty()) dirs.push_back(fromDir);
    dirs.insert(dirs.end(), dirs_.begin(), dirs_.end());
    for (const auto& d : dirs) {
      const std::filesystem::path candidate = (d / name).lexically_normal();
      tried.push_back(candidate);
      std::error_code ec;
      if (!std::filesystem::is_regular_file(candidate, ec)) continue;
      SourceFile f;
      f.path = candidate.string();
      f.text = readFile(candidate);
      addDependency(candidate);
      const auto canonical = std::filesystem::weakly_canonical(candidate, ec);
      return {std::move(f), candidate.parent_path(), "file:" + (ec ? candidate : canonical).string()};
    }
    std::string searched;
    for (const auto& t : tried) searched += (searched.empty() ? "" : ", ") + t.string();
    fail(path, line, fmt::format("cannot find #include \"{}\" (searched: {})", name,
                                 searched.empty() ? "nowhere" : searched));
  }

  void expand(const SourceFile& file, const std::filesystem::path& dir, const std::string& id,
              bool top) {
    if (std::find(stack_.begin(), stack_.end(), id) != stack_.end()) {
      std::string chain;
      for (const auto& s : stack_) chain += s.substr(s.find(':') + 1) + " -> ";
      throw GlError(fmt::format("{}: error: #include cycle: {}{}", file.path, chain, file.path));
    }
    stack_.push_back(id);
    const int k = indexOf(file.path);
    const auto lines = splitLines(file.text);
    if (!file.line_numbers.empty() && file.line_numbers.size() < lines.size())
      throw GlError(fmt::format("{}: error: {} line numbers for {} lines", file.path,
                                file.line_numbers.size(), lines.size()));
    for (size_t i = 0; i < lines.size(); ++i) {
      const int line = file.line_numbers.empty() ? file.first_line + static_cast<int>(i)
                                                 : file.line_numbers[i];
      if (line >= kLineStride)
        fail(file.path, line, fmt::format("shader files are limited to {} lines", kLineStride - 1));
      const auto [name, rest] = directive(lines[i]);
      if (name == "include") {
        const char open = rest.empty() ? '\0' : rest.front();
        const char close = open == '"' ? '"' : open == '<' ? '>' : '\0';
        const size_t end = close ? rest.find(close, 1) : std::string_view::npos;
        if (end == std::string_view::npos || end == 1)
          fail(file.path, line, "malformed #include: expected #include \"file\"");
        const std::string target(rest.substr(1, end - 1));
        Resolved r = resolve(target, dir, file.path, line);
        if (!once_.contains(r.id)) expand(r.file, r.dir, r.id, false);
        continue;
      }
      if (name == "pragma" && rest.starts_with("once")) {
        once_.insert(id);
        emit("", k, line);
        continue;
      }
      if (name == "version") {
        if (!top) fail(file.path, line, "#version may only appear in the top-level shader file");
        emit(lines[i], k, line);
        versionEmitted_ = true;
        emitDefines();
        continue;
      }
      emit(lines[i], k, line);
    }
    stack_.pop_back();
  }

  const std::vector<std::filesystem::path>& dirs_;
  const std::map<std::string, SourceFile>& virtuals_;
  const std::vector<std::pair<std::string, std::string>>& defines_;
  ShaderSource out_;
  std::vector<std::string> stack_;
  std::set<std::string> once_;
  bool hasVersion_ = false, versionEmitted_ = false;
  int driverSource_ = 0, driverLine_ = 1;
};

}  // namespace

std::filesystem::path shaderDirectory() {
  if (const char* env = std::getenv("TRANSLUCENT_SHADER_DIR"); env != nullptr && *env != '\0')
    return std::filesystem::path(env);
  return io::shareDirectory() / "shaders";
}

ShaderPreprocessor::ShaderPreprocessor(std::vector<std::filesystem::path> include_dirs)
    : include_dirs_(std::move(include_dirs)) {}

void ShaderPreprocessor::addVirtualFile(const std::string& name, SourceFile file) {
  virtual_files_[name] = std::move(file);
}

void ShaderPreprocessor::define(const std::string& name, const std::string& value) {
  defines_.emplace_back(name, value);
}

ShaderSource ShaderPreprocessor::load(const std::filesystem::path& file) const {
  std::filesystem::path path = file;
  if (path.is_relative() && !include_dirs_.empty()) path = include_dirs_.front() / path;
  path = path.lexically_normal();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw GlError(fmt::format(
        "cannot open shader file '{}' (shader directory: {}; set TRANSLUCENT_SHADER_DIR to use "
        "another)",
        path.string(), shaderDirectory().string()));
  SourceFile top;
  top.path = path.string();
  top.text = readFile(path);
  Expander e(include_dirs_, virtual_files_, defines_);
  e.addDependency(path);
  return e.run(top, path.parent_path());
}

ShaderSource ShaderPreprocessor::assemble(const SourceFile& top) const {
  return Expander(include_dirs_, virtual_files_, defines_).run(top, {});
}

std::pair<std::string, int> ShaderSource::locate(int source, int line) const {
  if (line >= kLineStride) {
    source = line / kLineStride;
    line = line % kLineStride;
  }
  if (source >= 0 && static_cast<size_t>(source) < files.size())
    return {files[static_cast<size_t>(source)], line};
  return {fmt::format("<source {}>", source), line};
}

std::string ShaderSource::rewriteLog(std::string_view log) const {
  static const std::regex mesa(R"(^\s*(\d+):(\d+)\((\d+)\):\s*(.*)$)");
  static const std::regex nvidia(R"(^\s*(\d+)\((\d+)\)\s*:\s*(.*)$)");
  static const std::regex generic(R"(^\s*(ERROR|WARNING):\s*(\d+):(\d+):\s*(.*)$)");
  std::string out;
  for (std::string_view l : splitLines(log)) {
    const std::string line(l);
    std::smatch m;
    if (std::regex_match(line, m, mesa)) {
      const auto [path, n] = locate(toInt(m[1]), toInt(m[2]));
      out += fmt::format("{}:{}: {}", path, n, m[4].str());
    } else if (std::regex_match(line, m, nvidia)) {
      const auto [path, n] = locate(toInt(m[1]), toInt(m[2]));
      out += fmt::format("{}:{}: {}", path, n, m[3].str());
    } else if (std::regex_match(line, m, generic)) {
      const auto [path, n] = locate(toInt(m[2]), toInt(m[3]));
      out += fmt::format("{}:{}: {}: {}", path, n, m[1].str() == "ERROR" ? "error" : "warning",
                         m[4].str());
    } else {
      out += line;
    }
    out += '\n';
  }
  while (!out.empty() && out.back() == '\n') out.pop_back();
  return out;
}

}  // namespace translucent::gpu
