// SPDX-License-Identifier: GPL-3.0-or-later
// Shader programs built from the repository's shaders/ folder (or generated sources), with
// compile and link errors reported at the original file and line, and hot reloading.
//
//   auto p = ShaderProgram::compute("tests/fill.comp");         // throws GlError on failure
//   p.set("Count", 128u);
//   ... edit the file ...
//   if (!p.reload()) std::cerr << p.lastError();                // old program still usable
//
// A program is made of stages, each with a *recipe*: a function that produces the stage's
// ShaderSource (reading files, assembling generated code). reload() runs the recipes again, so
// it picks up edited files; when anything fails (a missing file, a compile or a link error) the
// previous program stays in place and lastError() says why.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "translucent/gpu/objects.h"
#include "translucent/gpu/shader_source.h"

namespace translucent::gpu {

struct StageRecipe {
  GLenum stage = GL_COMPUTE_SHADER;  // GL_VERTEX_SHADER, GL_FRAGMENT_SHADER, GL_COMPUTE_SHADER...
  std::function<ShaderSource()> source;
};

using Defines = std::vector<std::pair<std::string, std::string>>;

class ShaderProgram {
 public:
  // Builds the program now; throws GlError with the mapped driver log if it fails.
  ShaderProgram(std::string name, std::vector<StageRecipe> stages);
  ShaderProgram(ShaderProgram&&) noexcept = default;
  ShaderProgram& operator=(ShaderProgram&&) noexcept = default;

  // A compute program from one file (relative to shaderDirectory() unless absolute).
  static ShaderProgram compute(const std::filesystem::path& file, const Defines& defines = {});
  // A vertex + fragment program from two files.
  static ShaderProgram graphics(const std::filesystem::path& vertex,
                                const std::filesystem::path& fragment,
                                const Defines& defines = {});

  // Rebuilds from the recipes. On success the new program replaces the old one (uniform values
  // are not carried over) and true is returned; on failure the old program is kept, false is
  // returned and lastError() holds the message.
  bool reload();
  const std::string& lastError() const { return last_error_; }
  // Number of successful builds (1 after construction); lets users notice a reload.
  std::uint64_t generation() const { return generation_; }

  const std::string& name() const { return name_; }
  GLuint id() const { return program_.id(); }
  void use() const { glUseProgram(program_.id()); }
  // Files read by the last successful build (to watch for changes).
  const std::vector<std::filesystem::path>& dependencies() const { return dependencies_; }

  // Location of an active uniform, -1 if the program has none of that name (optimised away).
  GLint uniformLocation(std::string_view name) const;
  bool hasUniform(std::string_view name) const { return uniformLocation(name) >= 0; }
  // Setters (glProgramUniform*: no need to bind). Unknown or inactive names are ignored, as GL
  // does for location -1.
  void set(std::string_view name, float v) const;
  void set(std::string_view name, int v) const;
  void set(std::string_view name, unsigned v) const;
  void set(std::string_view name, bool v) const;
  void set(std::string_view name, const glm::vec2& v) const;
  void set(std::string_view name, const glm::vec3& v) const;
  void set(std::string_view name, const glm::ivec3& v) const;
  void set(std::string_view name, const glm::vec4& v) const;
  void set(std::string_view name, const glm::mat3& v) const;
  void set(std::string_view name, const glm::mat4& v) const;

  // Compute programs: local work-group size declared by the shader.
  std::array<GLuint, 3> workGroupSize() const;

 private:
  // Compiles and links everything; throws GlError (mapped log) on failure.
  void build();

  std::string name_;
  std::vector<StageRecipe> stages_;
  Program program_;
  std::vector<std::filesystem::path> dependencies_;
  std::string last_error_;
  std::uint64_t generation_ = 0;
  mutable std::map<std::string, GLint, std::less<>> locations_;
};

}  // namespace translucent::gpu
