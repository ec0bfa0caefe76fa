// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/techniques/common/profile_atlas_gpu.h"

#include <fmt/format.h>

#include <span>

#include <glm/vec2.hpp>

#include "translucent/gpu/compute.h"
#include "translucent/gpu/gl.h"

namespace translucent::techniques {

std::vector<ParameterInfo> profileStorageParameters() {
  return {ParameterInfo::enumeration(
              "profile_storage", "vertex", {"vertex", "texture"},
              "where a heterogeneous material's per-point profiles (Eqs. 8-9) are kept for the "
              "surface points a frame evaluates: at the mesh's vertices, interpolated across each "
              "triangle, or in a texture over the surface atlas, as the splatting paper stores "
              "them (detail finer than the triangles)"),
          ParameterInfo::integer("profile_texels", 256, 16, 4096,
                                 "side of the profile texture (profile_storage texture)", "texels")};
}

void GpuProfileAtlas::bind() const {
  gpu::bindStorage(kTriangleUvBinding, triangle_uvs);
  glBindTextureUnit(kProfileAtlasUnit, texture.id());
}

GpuProfileAtlas uploadProfileAtlas(const material::ProfileAtlas& pa, const std::string& what) {
  GpuProfileAtlas out;
  const GLsizei n = GLsizei(pa.size), layers = GLsizei(pa.segments + 1);
  out.texture = gpu::Texture::create(GL_TEXTURE_2D_ARRAY);
  gpu::allocateTexture2DArray(out.texture, GL_RGBA32F, n, n, layers, what);
  glTextureSubImage3D(out.texture.id(), 0, 0, 0, 0, n, n, layers, GL_RGBA, GL_FLOAT, pa.nodes.data());
  glTextureParameteri(out.texture.id(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTextureParameteri(out.texture.id(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTextureParameteri(out.texture.id(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(out.texture.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  out.triangle_uvs = gpu::makeStorageBuffer(std::span<const glm::vec2>(pa.triangle_uvs));
  gpu::checkGlError(what.c_str());
  return out;
}

std::string describeProfileAtlas(const char* technique, const material::ProfileAtlas& pa) {
  return fmt::format("{}: per-point profiles in a {}² texture over the surface atlas ({} texels "
                     "on the surface, {} segments on [0, r_s = {:.4g}])",
                     technique, pa.size, pa.owned, pa.segments, pa.radius);
}

}  // namespace translucent::techniques
