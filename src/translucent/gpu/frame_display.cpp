// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/gpu/frame_display.h"

#include <fmt/format.h>

#include <cmath>

#include "translucent/gpu/gl.h"
#include "translucent/gpu/objects.h"
#include "translucent/gpu/program.h"

namespace translucent::gpu {
namespace {

// One triangle covering the viewport; uv (0,0) at the bottom left.
constexpr const char* kVertex = R"(#version 450 core
out vec2 uv;
void main() {
  vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
  uv = p;
  gl_Position = vec4(2.0 * p - 1.0, 0.0, 1.0);
}
)";

// The tone map of analysis::toneMap: scale by 2^exposure, clamp to [0, 1] (or Reinhard's
// s/(1 + s), s = key v / average), then ^(1/gamma).
// Image rows are stored from the top, so v is flipped.
constexpr const char* kFragment = R"(#version 450 core
in vec2 uv;
out vec4 color;
layout(binding = 0) uniform sampler2D image;
uniform float scale;     // 2^exposure
uniform float invGamma;  // 1/gamma
uniform bool reinhard;
uniform float reinhardScale;  // key / average
void main() {
  vec3 v = texture(image, vec2(uv.x, 1.0 - uv.y)).rgb * scale;
  if (reinhard) {
    v *= reinhardScale;
    v = v / (1.0 + v);
  }
  // NaN and negative values fail v > 0 and map to 0, as on the CPU.
  v = mix(vec3(0.0), min(v, vec3(1.0)), greaterThan(v, vec3(0.0)));
  color = vec4(pow(v, vec3(invGamma)), 1.0);
}
)";

StageRecipe inlineStage(GLenum stage, const char* text, const char* file) {
  return {stage, [text, file] {
            ShaderSource s;
            s.text = text;
            s.files = {file};
            return s;
          }};
}

}  // namespace

CurrentContextInfo currentContextInfo() {
  CurrentContextInfo info;
  const auto* v = reinterpret_cast<const char*>(glGetString(GL_VERSION));
  const auto* r = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  info.version = v != nullptr ? v : "";
  info.renderer = r != nullptr ? r : "";
  // GL_MAJOR_VERSION exists from 3.0; older contexts leave the zeros (and an error, drained).
  glGetIntegerv(GL_MAJOR_VERSION, &info.major);
  glGetIntegerv(GL_MINOR_VERSION, &info.minor);
  if (info.major >= 3) {
    GLint profile = 0;
    glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
    info.core_profile = (profile & GL_CONTEXT_CORE_PROFILE_BIT) != 0;
  }
  while (glGetError() != GL_NO_ERROR) {
  }
  return info;
}

struct FrameDisplay::Impl {
  ShaderProgram program{"frame_display",
                        {inlineStage(GL_VERTEX_SHADER, kVertex, "frame_display.vert"),
                         inlineStage(GL_FRAGMENT_SHADER, kFragment, "frame_display.frag")}};
  VertexArray vao = VertexArray::create();
  Texture texture;
  int width = 0, height = 0;
  double average = 0.0;  // of the uploaded image (analysis::withImageAverage)
};

FrameDisplay::FrameDisplay() : impl_(std::make_unique<Impl>()) {}
FrameDisplay::~FrameDisplay() = default;

bool FrameDisplay::hasImage() const { return impl_->width > 0; }

void FrameDisplay::upload(std::span<const float> rgb, int width, int height) {
  if (width <= 0 || height <= 0 || rgb.size() != size_t(width) * size_t(height) * 3)
    throw GlError(fmt::format("FrameDisplay::upload: {}x{} image with {} values; expected "
                              "width*height*3 = {}",
                              width, height, rgb.size(),
                              width > 0 && height > 0 ? size_t(width) * size_t(height) * 3 : 0));
  Impl& m = *impl_;
  if (width != m.width || height != m.height || !m.texture) {
    m.texture = Texture::create(GL_TEXTURE_2D);
    allocateTexture2D(m.texture, 1, GL_RGB32F, width, height, "frame display");
    glTextureParameteri(m.texture.id(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTextureParameteri(m.texture.id(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(m.texture.id(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(m.texture.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    m.width = width;
    m.height = height;
  }
  // Rows of 3 floats are 4-byte aligned whatever the width; the context's unpack state may not
  // be the default (Qt leaves it alone, but be explicit).
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
  glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
  glTextureSubImage2D(m.texture.id(), 0, 0, 0, width, height, GL_RGB, GL_FLOAT, rgb.data());
  m.average = analysis::withImageAverage({}, rgb).average;
  checkGlError("FrameDisplay::upload");
}

void FrameDisplay::draw(unsigned framebuffer, int width, int height, double exposure,
                        double gamma) const {
  draw(framebuffer, width, height, analysis::ToneMap{exposure, gamma});
}

void FrameDisplay::draw(unsigned framebuffer, int width, int height,
                        const analysis::ToneMap& tm) const {
  const double exposure = tm.exposure, gamma = tm.gamma;
  const Impl& m = *impl_;
  glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
  glViewport(0, 0, width, height);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  glDisable(GL_SCISSOR_TEST);
  glDisable(GL_CULL_FACE);
  glDisable(GL_FRAMEBUFFER_SRGB);  // the tone map already applies the display gamma
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  if (m.width == 0) {
    glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    checkGlError("FrameDisplay::draw (clear)");
    return;
  }
  const double g = gamma > 0.0 && std::isfinite(gamma) ? gamma : 2.2;
  const double e = std::isfinite(exposure) ? exposure : 0.0;
  m.program.use();
  m.program.set("scale", static_cast<float>(std::exp2(e)));
  m.program.set("invGamma", static_cast<float>(1.0 / g));
  const bool reinhard = tm.op == analysis::ToneOperator::Reinhard;
  const double average = tm.average > 0.0 ? tm.average : (m.average > 0.0 ? m.average : 1.0);
  m.program.set("reinhard", reinhard);
  m.program.set("reinhardScale", static_cast<float>(reinhard ? tm.key / average : 1.0));
  glBindTextureUnit(0, m.texture.id());
  glBindVertexArray(m.vao.id());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
  glUseProgram(0);
  glBindTextureUnit(0, 0);
  checkGlError("FrameDisplay::draw");
}

}  // namespace translucent::gpu
