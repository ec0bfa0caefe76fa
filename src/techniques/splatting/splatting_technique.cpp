#include "techniques/splatting/splatting_technique.h"

#include <fmt/format.h>

#include <optional>
#include <string>

#include <glm/geometric.hpp>

#include "bssrdf/exit_radiance.h"
#include "gpu/compute.h"
#include "gpu/pass_timer.h"
#include "material/material.h"
#include "material/material_desc.h"
#include <fmt/ranges.h>
#include "scene/scene.h"
#include "techniques/common/profile_kernel.h"

namespace translucent::splatting {
namespace {

using techniques::ParameterInfo;

// SSBO bindings: pointcloud/hetero.glsl's 11 (vertex profiles) and 13 (triangles), 14 the
// GpuMesh's interleaved vertex buffer (splatting/profile.glsl), 7 and 8 the outputs.
enum Binding : GLuint {
  kRadianceOut = 7,
  kExitanceOut = 8,
  kVertexProfiles = 11,
  kTriangles = 13,
  kMeshFloats = 14
};

std::vector<ParameterInfo> parameterInfos(bool shah) {
  std::vector<ParameterInfo> out = {
      ParameterInfo::integer("irradiance_size", 512, 16, 8192,
                             "resolution of each light's irradiance buffer (light-view map)", "texels")
          .withSweep({128, 256, 512, 1024}),
  };
  if (!shah) {
    out.push_back(ParameterInfo::integer("levels", 3, 1, 6,
                                         "splatting levels of the multiresolution hierarchy "
                                         "(used with multires)", "levels"));
    out.push_back(ParameterInfo::boolean("adaptive", false,
                                         "adaptive sample selection (Eqs. 10-11, Algorithm 1); "
                                         "not implemented on this branch yet"));
    out.push_back(ParameterInfo::boolean("multires", false,
                                         "multiresolution splatting (Eqs. 12-17); not implemented "
                                         "on this branch yet"));
    out.push_back(ParameterInfo::floating("z0", 0.03, 0.0, 1.0,
                                          "depth threshold of Eq. 10 as a fraction of the bounding "
                                          "sphere's radius", "radius"));
    out.push_back(ParameterInfo::floating("alpha", 15.0, 0.0, 1000.0,
                                          "α of the material sampling rate (Eq. 11)", ""));
    out.push_back(ParameterInfo::floating("epsilon", 0.001, 1e-6, 0.5,
                                          "ε of the minimal effective rendering radius (Eq. 14)", ""));
    out.push_back(ParameterInfo::floating("lambda_z", 8.0, 0.0, 100.0,
                                          "λz of the bilateral upsampling (Eq. 17)", ""));
    out.push_back(ParameterInfo::floating("lambda_m", 8.0, 0.0, 100.0,
                                          "λm of the bilateral upsampling (Eq. 17)", ""));
  }
  out.push_back(techniques::radianceConventionParameter());
  return out;
}

glm::vec3 toVec3(const glm::dvec3& v) { return glm::vec3(v); }
glm::vec3 toVec3(const Rgb& c) {
  return {static_cast<float>(c[0]), static_cast<float>(c[1]), static_cast<float>(c[2])};
}

}  // namespace

struct SplattingTechnique::Impl : techniques::ClosedMeshState {
  explicit Impl(bool shahBaseline) : shah(shahBaseline), params(parameterInfos(shahBaseline)) {}
  bool shah;
  techniques::ParameterSet params;
  const char* techniqueName() const { return shah ? "shah" : "splatting"; }

  std::optional<scene::Scene> scene;
  std::string profileKey;  // mesh, model and medium of the vertex profiles
  std::optional<material::MaterialDesc> profileDesc;  // and their material
  material::PointProfiles profiles;
  gpu::Buffer vertexProfileBuffer, triangleBuffer;
  int programNodes = 0;

  std::optional<gpu::ShaderProgram> mapProgram, gbufferProgram, splatProgram, radianceProgram;

  struct LightState {
    scene::Light light;
    std::unique_ptr<techniques::LightViewMap> map;
  };
  std::vector<LightState> lights;

  techniques::GBuffer gbuffer;
  gpu::Texture accum;
  gpu::Framebuffer accumFbo;
  gpu::VertexArray emptyVao;
  int accumW = 0, accumH = 0;
  gpu::Buffer radianceOut, exitanceOut;
  size_t outPixels = 0;
  std::optional<gpu::PassTimer> timer;

  void buildPrograms(int nodes) {
    if (splatProgram && programNodes == nodes) return;
    const gpu::Defines d{{"PC_HETERO", "1"}, {"PC_PROFILE_NODES", std::to_string(nodes)},
                         {"LVM_PRIMITIVE_ID", "1"}};
    mapProgram.emplace(
        gpu::ShaderProgram::graphics("common/light_view_map.vert", "common/light_view_map.frag", d));
    gbufferProgram.emplace(
        gpu::ShaderProgram::graphics("pointcloud/gbuffer.vert", "pointcloud/gbuffer.frag", d));
    splatProgram.emplace(gpu::ShaderProgram::graphics("splatting/splat.vert", "splatting/splat.frag", d));
    radianceProgram.emplace(gpu::ShaderProgram::compute("splatting/radiance.comp"));
    programNodes = nodes;
    gpu::checkGlError("building the splatting programs");
  }

  void prepareLights(const scene::Scene& s) {
    lights.clear();
    const int size = params.getInt("irradiance_size");
    for (size_t i = 0; i < s.lights.size(); ++i) {
      LightState st;
      st.light = s.lights[i];
      const auto& e = st.light.emitter;
      const char* kind = nullptr;
      if (std::holds_alternative<scene::FilteredDirectionalLight>(e)) kind = "a filtered directional light";
      else if (std::holds_alternative<reference::BeamLight>(e)) kind = "a beam light";
      else if (std::holds_alternative<scene::EnvironmentLight>(e)) kind = "an environment light";
      else if (!std::holds_alternative<reference::DirectionalLight>(e) &&
               !std::holds_alternative<reference::PointLight>(e))
        kind = "this light type";
      if (kind)
        throw ParameterError(fmt::format("lights[{}]: {}: the {} technique supports directional and "
                                         "point lights only (one irradiance buffer each)",
                                         i, kind, techniqueName()));
      if (const auto* p = std::get_if<reference::PointLight>(&e);
          p && !(glm::length(p->position - center) > 1.02 * radius))
        throw ParameterError(fmt::format("lights[{}]: the point light lies inside the mesh's bounding "
                                         "sphere: the {} technique's irradiance buffer needs it outside",
                                         i, techniqueName()));
      st.map = std::make_unique<techniques::LightViewMap>(size);
      lights.push_back(std::move(st));
    }
  }

  // Per-vertex profiles at the rest pose (once per mesh and material).
  void buildProfiles(const scene::Scene& s) {
    const geometry::TriangleMesh& restMesh = rest.positions.empty() ? mesh : rest;
    const std::string key = fmt::format("{}|{}|{}|{}|{}|{}|{}", meshKey, s.model, s.medium.sigma_a,
                                        s.medium.sigma_s, s.medium.g, s.medium.eta, s.medium.scale);
    if (key == profileKey && profileDesc && *profileDesc == s.material) return;
    profileKey.clear();
    const material::Material mat = scene::sceneMaterial(s, restMesh);
    if (mat.kind == material::Material::Kind::Surface)
      throw ParameterError(fmt::format("material.type '{}': the {} technique renders homogeneous and "
                                       "volume materials only (a surface map needs an atlas)",
                                       s.material.type(), techniqueName()));
    const std::vector<glm::dvec3> normals = techniques::vertexNormals(restMesh);
    std::vector<glm::vec3> vp(restMesh.vertexCount()), vn(restMesh.vertexCount());
    for (size_t i = 0; i < vp.size(); ++i) {
      vp[i] = glm::vec3(restMesh.positions[i]);
      vn[i] = glm::vec3(normals[i]);
    }
    profiles = material::PointProfiles::build(mat, material::PointProfiles::surfaceMedia(mat, vp, vn));
    const int m = profiles.segments() + 1;
    std::vector<glm::vec4> nodes;
    nodes.reserve(profiles.size() * size_t(m));
    for (size_t v = 0; v < profiles.size(); ++v)
      for (int k = 0; k < m; ++k)
        nodes.emplace_back(float(profiles.node(v, 0, k)), float(profiles.node(v, 1, k)),
                           float(profiles.node(v, 2, k)), 0.0f);
    vertexProfileBuffer = gpu::makeStorageBuffer(std::span<const glm::vec4>(nodes));
    std::vector<glm::uvec4> tris(restMesh.triangleCount());
    for (size_t i = 0; i < tris.size(); ++i) tris[i] = glm::uvec4(restMesh.triangles[i], 0u);
    triangleBuffer = gpu::makeStorageBuffer(std::span<const glm::uvec4>(tris));
    buildPrograms(m);
    profileKey = key;
    profileDesc = s.material;
  }

  void requireImplemented() const {
    if (shah) return;
    if (params.getBool("adaptive"))
      throw ParameterError("splatting: adaptive = true (Eqs. 10-11) is not implemented on this "
                           "branch yet: expected adaptive = false");
    if (params.getBool("multires"))
      throw ParameterError("splatting: multires = true (Eqs. 12-17) is not implemented on this "
                           "branch yet: expected multires = false");
  }

  void renderMap(LightState& st) {
    const scene::Scene& s = *scene;
    const glm::vec3 color = toVec3(st.light.color);
    const auto& e = st.light.emitter;
    if (const auto* d = std::get_if<reference::DirectionalLight>(&e))
      st.map->renderDirectional(*gpuMesh, *mapProgram, d->direction, color * float(d->irradiance),
                                s.medium.eta, center, radius);
    else if (const auto* p = std::get_if<reference::PointLight>(&e))
      st.map->renderPoint(*gpuMesh, *mapProgram, p->position, color * float(p->intensity),
                          s.medium.eta, center, radius);
  }

  void resizeAccum(int w, int h) {
    if (w == accumW && h == accumH) return;
    accum = gpu::Texture::create(GL_TEXTURE_2D);
    gpu::allocateTexture2D(accum, 1, GL_RGBA32F, w, h, "splatting accumulation");
    glTextureParameteri(accum.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(accum.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    accumFbo = gpu::Framebuffer::create();
    glNamedFramebufferTexture(accumFbo.id(), GL_COLOR_ATTACHMENT0, accum.id(), 0);
    if (glCheckNamedFramebufferStatus(accumFbo.id(), GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      throw gpu::GlError("splatting: the accumulation framebuffer is incomplete");
    accumW = w;
    accumH = h;
  }

  techniques::Frame render(const techniques::FrameRequest& request) {
    if (!scene) throw ParameterError(fmt::format("{}: render() before prepare(): expected a scene", techniqueName()));
    requireImplemented();
    const scene::Scene& s = *scene;
    const auto [width, height] = techniques::frameSize(request, s.camera);
    if (!timer) timer.emplace();
    if (!emptyVao.id()) emptyVao = gpu::VertexArray::create();
    techniques::Frame frame;
    const size_t pixels = size_t(width) * size_t(height);
    if (pixels != outPixels) {
      radianceOut = gpu::makeStorageBuffer(pixels * sizeof(glm::vec4));
      exitanceOut = gpu::makeStorageBuffer(pixels * sizeof(glm::vec4));
      outPixels = pixels;
    }
    const glm::mat4 vp = techniques::cameraViewProjection(s.camera, s.clip_near, s.clip_far, center,
                                                          radius, width, height);
    {
      auto t = timer->scope("g-buffer");
      gbuffer.resize(width, height);
      gbuffer.render(*gpuMesh, *gbufferProgram, vp);
    }
    {
      auto t = timer->scope("irradiance");
      for (auto& st : lights) renderMap(st);
    }
    resizeAccum(width, height);
    {
      auto t = timer->scope("splat");
      const float zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
      glClearNamedFramebufferfv(accumFbo.id(), GL_COLOR, 0, zero);
      glBindFramebuffer(GL_FRAMEBUFFER, accumFbo.id());
      glViewport(0, 0, width, height);
      glDisable(GL_DEPTH_TEST);
      glDisable(GL_CULL_FACE);
      glEnable(GL_BLEND);
      glBlendEquation(GL_FUNC_ADD);
      glBlendFunc(GL_ONE, GL_ONE);
      const gpu::ShaderProgram& p = *splatProgram;
      p.use();
      gpu::bindStorage(kVertexProfiles, vertexProfileBuffer);
      gpu::bindStorage(kTriangles, triangleBuffer);
      gpu::bindStorage(kMeshFloats, gpuMesh->vertexBuffer());
      glBindTextureUnit(0, gbuffer.position().id());
      p.set("ViewProjection", vp);
      p.set("SpFloatsPerVertex", gpuMesh->floatsPerVertex());
      p.set("HeteroRadius", static_cast<float>(profiles.radius()));
      p.set("SplatRadius", static_cast<float>(profiles.cutRadius()));
      p.set("RMin", 0.0f);
      p.set("RMax", static_cast<float>(profiles.cutRadius()));
      p.set("PixelSize", glm::vec2(2.0f / float(width), 2.0f / float(height)));
      glBindVertexArray(emptyVao.id());
      for (auto& st : lights) {
        st.map->bind(p, 1);  // units 1, 2, 3
        p.set("MapSize", st.map->size());
        glDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, st.map->size() * st.map->size());
      }
      glBindVertexArray(0);
      glDisable(GL_BLEND);
      glBindFramebuffer(GL_FRAMEBUFFER, 0);
      gpu::checkGlError("splatting pass");
    }
    {
      auto t = timer->scope("radiance");
      glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
      const gpu::ShaderProgram& p = *radianceProgram;
      gpu::bindStorage(kRadianceOut, radianceOut);
      gpu::bindStorage(kExitanceOut, exitanceOut);
      glBindTextureUnit(0, gbuffer.position().id());
      glBindTextureUnit(1, gbuffer.normal().id());
      glBindTextureUnit(2, accum.id());
      glProgramUniform2ui(p.id(), p.uniformLocation("Size"), unsigned(width), unsigned(height));
      p.set("Eta", static_cast<float>(s.medium.eta));
      p.set("ExitScale", glm::vec3(static_cast<float>(bssrdf::exitConventionScale(
                             bssrdf::parseExitConvention(params.getEnum("radiance_convention")),
                             s.medium.eta))));
      p.set("CameraPosition", toVec3(s.camera.position));
      p.set("CameraForward", toVec3(glm::normalize(s.camera.look_at - s.camera.position)));
      p.set("Orthographic", s.camera.projection == reference::Camera::Projection::Orthographic);
      gpu::dispatch(p, {(unsigned(width) + 7u) / 8u, (unsigned(height) + 7u) / 8u, 1u});
      glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    }
    gpu::checkGlError("splatting frame");
    frame.width = width;
    frame.height = height;
    if (request.readback) techniques::readRadianceAndExitance(frame, radianceOut, exitanceOut, pixels);
    techniques::addPasses(frame, *timer);
    return frame;
  }
};

SplattingTechnique::SplattingTechnique(bool shah) : impl_(std::make_unique<Impl>(shah)) {}
SplattingTechnique::~SplattingTechnique() = default;

std::string_view SplattingTechnique::name() const { return impl_->techniqueName(); }

std::string_view SplattingTechnique::description() const {
  return impl_->shah ? "image-space splatting of every irradiance texel with full-size splats "
                       "(Shah, Kontinen & Pattanaik 2009)"
                     : "multiresolution splatting of light-view irradiance samples (Chen, Peers, "
                       "Zhang & Tong 2012); so far without its accelerations";
}

const std::vector<techniques::ParameterInfo>& SplattingTechnique::parameters() const {
  return impl_->params.infos();
}

void SplattingTechnique::setParameter(std::string_view name, const techniques::ParameterValue& value) {
  const techniques::ParameterValue checked = techniques::checkedValue(impl_->params.info(name), value);
  if (!impl_->params.set(name, checked)) return;
  if (name == "irradiance_size" && impl_->scene) impl_->prepareLights(*impl_->scene);
}

techniques::ParameterValue SplattingTechnique::parameter(std::string_view name) const {
  return impl_->params.get(name);
}

void SplattingTechnique::prepare(const scene::Scene& scene, gpu::Context& gl) {
  gl.makeCurrent();
  scene.camera.validate();
  scene.medium.validate();
  impl_->scene.reset();  // until this preparation succeeds
  impl_->loadClosedMesh(scene, /*gpuDeform=*/true);
  impl_->prepareLights(scene);
  impl_->buildProfiles(scene);
  impl_->scene = scene;
}

techniques::Frame SplattingTechnique::render(const techniques::FrameRequest& request) {
  return impl_->render(request);
}

const material::PointProfiles& SplattingTechnique::vertexProfiles() const { return impl_->profiles; }
const geometry::TriangleMesh& SplattingTechnique::mesh() const { return impl_->mesh; }
size_t SplattingTechnique::lightCount() const { return impl_->lights.size(); }
const techniques::LightViewMap& SplattingTechnique::lightMap(size_t i) const { return *impl_->lights.at(i).map; }
const techniques::GBuffer& SplattingTechnique::gbuffer() const { return impl_->gbuffer; }

std::unique_ptr<techniques::Technique> makeSplattingTechnique() {
  return std::make_unique<SplattingTechnique>(false);
}
std::unique_ptr<techniques::Technique> makeShahTechnique() {
  return std::make_unique<SplattingTechnique>(true);
}

}  // namespace translucent::splatting
