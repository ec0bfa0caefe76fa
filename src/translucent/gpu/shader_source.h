// SPDX-License-Identifier: GPL-3.0-or-later
// GLSL source assembly: `#include "file"`, injected #defines, and line mapping so that driver
// messages name the original file and line.
//
// Every file (or generated piece) that ends up in a shader gets a source-string number k, the
// index into ShaderSource::files. The assembled text carries `#line L k` directives (GLSL 4.50:
// the line after the directive is line L of source string k), so drivers report positions as
// `k:L(col)` (Mesa) or `k(L)` (NVIDIA). Mesa 22 drops the source-string number from errors inside
// expressions (it reports 0), so the line numbers carry the file as well: line ℓ of file k is
// emitted as L = k·kLineStride + ℓ, and rewriteLog() decodes L when the reported number is 0.
// The result: `shaders/foo.glsl:12: error: ...`, or `data/bssrdf/dipole.bssrdf:33: error: ...`
// for code that came from a .bssrdf section.
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace translucent::gpu {

// Line numbers of file k are offset by k·kLineStride (see above); files must be shorter.
inline constexpr int kLineStride = 100000;

// GLSL text and where it came from.
struct SourceFile {
  std::string path;     // shown in messages (a file path, or "<generated ...>")
  std::string text;
  int first_line = 1;   // original line number of the text's first line
  // Optional: the original line of each line of `text` (overrides first_line); for generated code
  // whose lines come from scattered places (parameter declarations of a .bssrdf file).
  std::vector<int> line_numbers;
};

// One assembled shader stage, ready for glShaderSource.
struct ShaderSource {
  std::string text;
  std::vector<std::string> files;  // source-string number -> path
  // Files read from disk (for hot reloading: what to watch).
  std::vector<std::filesystem::path> dependencies;

  // Rewrites positions in a driver info log from source-string numbers to paths:
  //   Mesa    "0:12(3): error: x"       -> "path:12: error: x"
  //   NVIDIA  "0(12) : error C1008: x"  -> "path:12: error C1008: x"
  //   others  "ERROR: 0:12: x"          -> "path:12: error: x"
  // Lines in other formats are kept as they are.
  std::string rewriteLog(std::string_view log) const;
  // (path, line) for an emitted (source-string, line) pair, decoding the line stride.
  std::pair<std::string, int> locate(int source, int line) const;
};

// The shaders/ folder: $TRANSLUCENT_SHADER_DIR if set, else io::shareDirectory()'s (installed
// share/translucent/shaders beside the binary, or the source tree's for a build-tree run).
std::filesystem::path shaderDirectory();

class ShaderPreprocessor {
 public:
  // Includes are searched relative to the including file, then in `include_dirs` (default: the
  // shader directory).
  explicit ShaderPreprocessor(std::vector<std::filesystem::path> include_dirs = {shaderDirectory()});

  // A file that `#include "name"` resolves to before anything on disk (generated code).
  void addVirtualFile(const std::string& name, SourceFile file);
  // `#define name value`, inserted after the #version line of the top-level file.
  void define(const std::string& name, const std::string& value = "");

  // Reads `file` (relative paths: relative to the first include dir) and expands it.
  ShaderSource load(const std::filesystem::path& file) const;
  // Expands in-memory top-level source.
  ShaderSource assemble(const SourceFile& top) const;

 private:
  std::vector<std::filesystem::path> include_dirs_;
  std::map<std::string, SourceFile> virtual_files_;
  std::vector<std::pair<std::string, std::string>> defines_;
};

}  // namespace translucent::gpu
