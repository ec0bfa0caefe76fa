// SPDX-License-Identifier: GPL-3.0-or-later
// `.bssrdf` plug-in files: analytic BSSRDFs described in a small text format (seed appendix A.2).
//
//   analytic radial no_wi no_wo          <- line 1: attributes (`analytic` is mandatory)
//   ::begin parameters                    <- named sections, in any order
//   float Multiplier 0.0 10.0 1.0         <- float NAME MIN MAX DEFAULT
//   bool  Clamp true                      <- bool NAME DEFAULT (true/false/1/0)
//   color Tint 1.0 0.5 0.25               <- color NAME R G B
//   ::end parameters
//   ::begin initializer  ... GLSL defining void init() ...              ::end initializer
//   ::begin diffuseReflectance  ... vec3 DiffuseReflectance(vec3) ...    ::end diffuseReflectance
//   ::begin shader  ... vec3 Bssrdf(vec3 Xi, vec3 Wi, vec3 Xo, vec3 Wo) ... ::end shader
//
// Sections with other names are skipped (seed: "If the name of a section is not recognized by the
// application, it is ignored"). `shader` is required; `initializer`, `diffuseReflectance` and
// `parameters` are optional (without `diffuseReflectance` the Rdr/ℓd parametrisation is off).
// Outside sections only blank lines and comment lines (`//` or `#`) may appear. Whitespace
// between `::` and `begin`/`end` is accepted (the seed's own listing has `:: begin`). The name
// after `::end` may be omitted; when given it must match the open section.
//
// The parser keeps, for every GLSL section, the .bssrdf line of its first code line so that the
// GPU layer can emit `#line` directives and report GLSL compile errors as `file.bssrdf:LINE`.
// No GL dependency: the GLSL text is not checked here (the driver does that, with mapped lines).
#pragma once

#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "translucent/optics/medium.h"

namespace translucent::bssrdf {

// A malformed .bssrdf file. what() is "PATH:LINE: error: MESSAGE" (line 0: the whole file, then
// "PATH: error: MESSAGE").
class BssrdfFileError : public std::runtime_error {
 public:
  BssrdfFileError(std::string path, int line, const std::string& message);
  const std::string& path() const { return path_; }
  int line() const { return line_; }
  const std::string& message() const { return message_; }

 private:
  std::string path_;
  int line_;
  std::string message_;
};

struct BssrdfAttributes {
  bool analytic = false;  // mandatory: the BSSRDF is in analytic form
  bool radial = false;    // depends only on ||xo - xi||
  bool no_wi = false;     // independent of the incident direction
  bool no_wo = false;     // independent of the exitant direction
};

struct FloatParameter {
  double min = 0.0, max = 1.0, value = 0.0;  // value = the default
};
struct BoolParameter {
  bool value = false;
};
struct ColorParameter {
  Rgb value{0.0, 0.0, 0.0};
};

// One user parameter; the GPU layer declares it as a uniform of the same name
// (float -> float, bool -> bool, color -> vec3).
struct BssrdfParameter {
  std::string name;
  std::variant<FloatParameter, BoolParameter, ColorParameter> spec;
  int line = 0;  // its line in the .bssrdf file
};

// A GLSL section: its code and the .bssrdf line number of the code's first line (the line after
// `::begin NAME`).
struct GlslSection {
  std::string code;
  int first_line = 0;
};

struct BssrdfFile {
  std::string path;  // as given to the parser; used in every error message
  BssrdfAttributes attributes;
  int parameters_line = 0;  // line of `::begin parameters` (0: no such section)
  std::vector<BssrdfParameter> parameters;
  std::optional<GlslSection> initializer;         // defines void init()
  std::optional<GlslSection> diffuse_reflectance; // defines vec3 DiffuseReflectance(vec3)
  GlslSection shader;                             // defines vec3 Bssrdf(vec3, vec3, vec3, vec3)
  std::vector<std::string> ignored_sections;      // names of unrecognised sections, in file order

  const BssrdfParameter* findParameter(std::string_view name) const;
  // The file name without directories and extension ("dipole" for data/bssrdf/dipole.bssrdf).
  std::string stem() const;
};

// Names the GPU layer declares for every model (seed listing A.2 uses them); a parameter may not
// reuse them.
inline constexpr const char* kBssrdfStandardNames[] = {"SigmaA", "SigmaS", "G", "IOR", "PI", "Ni", "No"};

// Parses the text of a .bssrdf file; `path` is used in error messages only.
BssrdfFile parseBssrdf(std::string_view text, const std::string& path);
// Reads and parses a file; a missing or unreadable file is a BssrdfFileError (line 0).
BssrdfFile loadBssrdf(const std::filesystem::path& path);

// Lines of a text without their terminators ("\n" or "\r\n"); a final line without "\n"
// counts. The views point into `text`. (Shared with the GLSL include expander in src/gpu.)
std::vector<std::string_view> splitLines(std::string_view text);

// True when `path` names a .bssrdf file by its extension (any case, e.g. "Skin.BSSRDF"): how the
// command line, scenes and the explorer tell a plug-in file from a registered model name.
bool hasBssrdfExtension(std::string_view path);
// Whether a model entry (--model, a scene's model) names a .bssrdf plug-in: it ends in .bssrdf,
// or it is an existing file that is not a tabulated profile (.csv, bssrdf/tabulated.h).
bool isPluginFile(const std::string& entry);

// The first line of `message` that names a .bssrdf line ("file.bssrdf:12: ..."), else the whole
// message: a GLSL driver log can span many lines, and this is the one to show a user.
std::string firstBssrdfLine(const std::string& message);

}  // namespace translucent::bssrdf
