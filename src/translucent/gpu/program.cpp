// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/gpu/program.h"

#include <fmt/format.h>

#include <glm/gtc/type_ptr.hpp>

namespace translucent::gpu {
namespace {

const char* stageName(GLenum stage) {
  switch (stage) {
    case GL_VERTEX_SHADER: return "vertex";
    case GL_FRAGMENT_SHADER: return "fragment";
    case GL_GEOMETRY_SHADER: return "geometry";
    case GL_TESS_CONTROL_SHADER: return "tessellation control";
    case GL_TESS_EVALUATION_SHADER: return "tessellation evaluation";
    case GL_COMPUTE_SHADER: return "compute";
    default: return "unknown";
  }
}

std::string shaderLog(GLuint shader) {
  GLint length = 0;
  glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
  std::string log(static_cast<size_t>(std::max(length, 1)), '\0');
  glGetShaderInfoLog(shader, length, nullptr, log.data());
  log.resize(std::char_traits<char>::length(log.c_str()));
  return log;
}

std::string programLog(GLuint program) {
  GLint length = 0;
  glGetProgramiv(program, GL_INFO_LOG_LENGTH, &length);
  std::string log(static_cast<size_t>(std::max(length, 1)), '\0');
  glGetProgramInfoLog(program, length, nullptr, log.data());
  log.resize(std::char_traits<char>::length(log.c_str()));
  return log;
}

StageRecipe fileRecipe(GLenum stage, const std::filesystem::path& file, const Defines& defines) {
  return {stage, [file, defines] {
            ShaderPreprocessor pp;
            for (const auto& [name, value] : defines) pp.define(name, value);
            return pp.load(file);
          }};
}

}  // namespace

ShaderProgram::ShaderProgram(std::string name, std::vector<StageRecipe> stages)
    : name_(std::move(name)), stages_(std::move(stages)) {
  build();
}

ShaderProgram ShaderProgram::compute(const std::filesystem::path& file, const Defines& defines) {
  return ShaderProgram(file.string(), {fileRecipe(GL_COMPUTE_SHADER, file, defines)});
}

ShaderProgram ShaderProgram::graphics(const std::filesystem::path& vertex,
                                      const std::filesystem::path& fragment,
                                      const Defines& defines) {
  return ShaderProgram(fmt::format("{} + {}", vertex.string(), fragment.string()),
                       {fileRecipe(GL_VERTEX_SHADER, vertex, defines),
                        fileRecipe(GL_FRAGMENT_SHADER, fragment, defines)});
}

void ShaderProgram::build() {
  if (stages_.empty()) throw GlError(fmt::format("program '{}' has no shader stages", name_));

  // Compile every stage; the log is rewritten to original files and lines.
  std::vector<Shader> shaders;
  std::vector<ShaderSource> sources;
  std::vector<std::filesystem::path> dependencies;
  for (const StageRecipe& recipe : stages_) {
    ShaderSource src = recipe.source();
    Shader shader = Shader::create(recipe.stage);
    const char* text = src.text.c_str();
    glShaderSource(shader.id(), 1, &text, nullptr);
    glCompileShader(shader.id());
    GLint ok = GL_FALSE;
    glGetShaderiv(shader.id(), GL_COMPILE_STATUS, &ok);
    if (ok != GL_TRUE)
      throw GlError(fmt::format("program '{}': the {} shader does not compile:\n{}", name_,
                                stageName(recipe.stage), src.rewriteLog(shaderLog(shader.id()))));
    dependencies.insert(dependencies.end(), src.dependencies.begin(), src.dependencies.end());
    shaders.push_back(std::move(shader));
    sources.push_back(std::move(src));
  }

  // Link. Link logs rarely carry positions; a single-stage program's table still maps them.
  Program program = Program::create();
  for (const Shader& s : shaders) glAttachShader(program.id(), s.id());
  glLinkProgram(program.id());
  for (const Shader& s : shaders) glDetachShader(program.id(), s.id());
  GLint ok = GL_FALSE;
  glGetProgramiv(program.id(), GL_LINK_STATUS, &ok);
  if (ok != GL_TRUE) {
    const std::string log = programLog(program.id());
    throw GlError(fmt::format("program '{}' does not link:\n{}", name_,
                              sources.size() == 1 ? sources.front().rewriteLog(log) : log));
  }

  program_ = std::move(program);
  dependencies_ = std::move(dependencies);
  locations_.clear();
  ++generation_;
}

bool ShaderProgram::reload() {
  try {
    build();
    last_error_.clear();
    return true;
  } catch (const std::exception& e) {
    // The previous program_ is untouched: build() only replaces it after a successful link.
    last_error_ = e.what();
    return false;
  }
}

GLint ShaderProgram::uniformLocation(std::string_view name) const {
  if (const auto it = locations_.find(name); it != locations_.end()) return it->second;
  const std::string key(name);
  const GLint loc = glGetUniformLocation(program_.id(), key.c_str());
  locations_.emplace(key, loc);
  return loc;
}

void ShaderProgram::set(std::string_view name, float v) const {
  glProgramUniform1f(program_.id(), uniformLocation(name), v);
}
void ShaderProgram::set(std::string_view name, int v) const {
  glProgramUniform1i(program_.id(), uniformLocation(name), v);
}
void ShaderProgram::set(std::string_view name, unsigned v) const {
  glProgramUniform1ui(program_.id(), uniformLocation(name), v);
}
void ShaderProgram::set(std::string_view name, bool v) const {
  glProgramUniform1i(program_.id(), uniformLocation(name), v ? 1 : 0);
}
void ShaderProgram::set(std::string_view name, const glm::vec2& v) const {
  glProgramUniform2fv(program_.id(), uniformLocation(name), 1, glm::value_ptr(v));
}
void ShaderProgram::set(std::string_view name, const glm::vec3& v) const {
  glProgramUniform3fv(program_.id(), uniformLocation(name), 1, glm::value_ptr(v));
}
void ShaderProgram::set(std::string_view name, const glm::ivec3& v) const {
  glProgramUniform3iv(program_.id(), uniformLocation(name), 1, glm::value_ptr(v));
}
void ShaderProgram::set(std::string_view name, const glm::vec4& v) const {
  glProgramUniform4fv(program_.id(), uniformLocation(name), 1, glm::value_ptr(v));
}
void ShaderProgram::set(std::string_view name, const glm::mat3& v) const {
  glProgramUniformMatrix3fv(program_.id(), uniformLocation(name), 1, GL_FALSE, glm::value_ptr(v));
}
void ShaderProgram::set(std::string_view name, const glm::mat4& v) const {
  glProgramUniformMatrix4fv(program_.id(), uniformLocation(name), 1, GL_FALSE, glm::value_ptr(v));
}

std::array<GLuint, 3> ShaderProgram::workGroupSize() const {
  GLint size[3] = {0, 0, 0};
  glGetProgramiv(program_.id(), GL_COMPUTE_WORK_GROUP_SIZE, size);
  checkGlError("glGetProgramiv(GL_COMPUTE_WORK_GROUP_SIZE) (is this a compute program?)");
  return {static_cast<GLuint>(size[0]), static_cast<GLuint>(size[1]), static_cast<GLuint>(size[2])};
}

}  // namespace translucent::gpu
