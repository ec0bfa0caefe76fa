// SPDX-License-Identifier: GPL-3.0-or-later
// GPU evaluation of `.bssrdf` plug-in models (seed appendix A.2, parsed by bssrdf/bssrdf_file.h).
//
// The GLSL sections of a parsed file are pieced together with the kernels in shaders/bssrdf/:
//   profile.comp              R(r) = Bssrdf(Xi = 0, Wi = N, Xo = (r, 0, 0), Wo = N) per radius
//   diffuse_reflectance.comp  Rdr(α') = DiffuseReflectance(vec3(α')) per albedo (seed 3.4)
//   directional.comp          Bssrdf(Xi, Wi, Xo, Wo) at given points, normals and directions
//                             (directional models: the globals Ni, No carry the normals)
// The standard inputs (shaders/bssrdf/interface.glsl) are SigmaA, SigmaS (vec3, per scene unit),
// G, IOR and the constant PI; every declared parameter becomes a uniform of its own name
// (float -> float, bool -> bool, color -> vec3). A file without an initializer gets an empty
// init(). Code from the .bssrdf file keeps its line numbers, so a GLSL error in a section is
// reported as `path/to/model.bssrdf:LINE: error: ...`.
#pragma once

#include <array>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include <glm/vec3.hpp>

#include "translucent/bssrdf/bssrdf_file.h"
#include "translucent/gpu/program.h"
#include "translucent/optics/medium.h"

namespace translucent::gpu {

// data/bssrdf/ (the built-in models): $TRANSLUCENT_BSSRDF_DIR if set, else io::shareDirectory()'s.
std::filesystem::path bssrdfDirectory();

// A preprocessor whose virtual include files are the file's sections: "bssrdf:parameters" (one
// uniform per declared parameter), "bssrdf:initializer" (an empty init() when absent),
// "bssrdf:diffuseReflectance" and "bssrdf:shader", each keeping the .bssrdf file's line numbers.
// Shaders that call Bssrdf() include them after "bssrdf/interface.glsl", as profile.comp does.
ShaderPreprocessor bssrdfPreprocessor(const bssrdf::BssrdfFile& file);

enum class BssrdfKernel { Profile, DiffuseReflectance, Directional };

// One evaluation of Bssrdf() at arbitrary geometry (BssrdfEvaluator::evaluate): points, outward
// unit normals, and unit directions pointing away from the surface (w_i towards the light, w_o
// towards the viewer), in scene units.
struct BssrdfQuery {
  glm::vec3 x_i{0.0f}, n_i{0.0f, 0.0f, 1.0f}, w_i{0.0f, 0.0f, 1.0f};
  glm::vec3 x_o{0.0f}, n_o{0.0f, 0.0f, 1.0f}, w_o{0.0f, 0.0f, 1.0f};
};

// The assembled compute shader for one kernel (the file must have a diffuseReflectance section
// for BssrdfKernel::DiffuseReflectance; GlError otherwise).
ShaderSource assembleBssrdfKernel(const bssrdf::BssrdfFile& file, BssrdfKernel kernel);
// A compiled kernel program; throws GlError with .bssrdf lines on compile errors.
ShaderProgram buildBssrdfKernel(const bssrdf::BssrdfFile& file, BssrdfKernel kernel);

using ParameterValue = std::variant<double, bool, Rgb>;

class BssrdfEvaluator {
 public:
  // Parses `file` and compiles its kernels (needs a current 4.5 context). Throws
  // bssrdf::BssrdfFileError for a malformed file, GlError for GLSL errors.
  explicit BssrdfEvaluator(std::filesystem::path file);
  // A built-in model: bssrdfDirectory() / (name + ".bssrdf").
  static BssrdfEvaluator builtin(std::string_view name);

  const bssrdf::BssrdfFile& file() const { return *file_; }
  bool hasDiffuseReflectance() const { return rd_.has_value(); }

  // Standard inputs from a medium: SigmaA/SigmaS = coefficients · scale (Medium::channel), G, IOR.
  // Throws ParameterError if the medium is invalid.
  void setMedium(const Medium& medium);
  // Sets a declared parameter; the value's type must match the declaration (float: a double
  // within [min, max]; bool; color: Rgb). Throws ParameterError naming the parameter otherwise.
  void setParameter(std::string_view name, const ParameterValue& value);
  // Current value of a parameter (its default from the file until set).
  ParameterValue parameter(std::string_view name) const;

  // R(r) for every radius, RGB; one compute dispatch.
  std::vector<std::array<float, 3>> profile(std::span<const float> radii);
  // Bssrdf() for every query, RGB; one dispatch (the directional kernel is compiled on first use).
  // For a directional file this is the kernel R(x_i, n_i, w_i; x_o, n_o) of bssrdf/profile.h's
  // DirectionalProfile; a radial file gives R(|x_o - x_i|) whatever the directions.
  std::vector<std::array<float, 3>> evaluate(std::span<const BssrdfQuery> queries);
  // Rdr(α') for every reduced albedo, RGB (depends on IOR and parameters through init()).
  // Throws GlError if the file has no diffuseReflectance section.
  std::vector<std::array<float, 3>> diffuseReflectance(std::span<const float> alpha_prime);

  // Re-reads the .bssrdf file and the shaders and rebuilds both kernels. On failure (parse or
  // GLSL error) everything stays as it was, false is returned and lastError() says why.
  // Values set with setParameter() are kept for parameters that still exist with the same type
  // and range; the others take the (possibly edited) defaults of the file.
  bool reload();
  const std::string& lastError() const { return last_error_; }

  const ShaderProgram& profileProgram() const { return *profile_; }

  // Sets the standard inputs and the parameters on another program built from this file's
  // sections (bssrdfPreprocessor), e.g. the sphere integration kernel.
  void applyUniforms(const ShaderProgram& program) const;

 private:
  std::vector<std::array<float, 3>> run(ShaderProgram& program, std::span<const float> input,
                                        size_t count);

  std::filesystem::path path_;
  std::shared_ptr<const bssrdf::BssrdfFile> file_;
  std::optional<ShaderProgram> profile_;
  std::optional<ShaderProgram> rd_;
  std::optional<ShaderProgram> directional_;  // built by the first evaluate()
  std::map<std::string, ParameterValue, std::less<>> overrides_;  // set by setParameter()
  Medium medium_;
  std::string last_error_;
};

// Loads and compiles a .bssrdf file for a user (a context must be current): parse and GLSL
// errors become a ParameterError whose message is the first `file.bssrdf:LINE` line of the
// diagnostic (a driver log can span many lines). The command line and the explorer use it.
std::unique_ptr<BssrdfEvaluator> openBssrdf(const std::filesystem::path& path);

}  // namespace translucent::gpu
