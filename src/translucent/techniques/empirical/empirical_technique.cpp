// SPDX-License-Identifier: GPL-3.0-or-later
// The empirical translucency shader on the GPU (empirical_technique.h).
#include "translucent/techniques/empirical/empirical_technique.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <span>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "translucent/bssrdf/bssrdf_file.h"
#include "translucent/bssrdf/registry.h"
#include "translucent/bssrdf/tabulated.h"
#include "translucent/geometry/ambient_occlusion.h"
#include "translucent/geometry/atlas.h"
#include "translucent/geometry/deform.h"
#include "translucent/gpu/compute.h"
#include "translucent/gpu/objects.h"
#include "translucent/gpu/pass_timer.h"
#include "translucent/gpu/program.h"
#include "translucent/material/material_desc.h"
#include "translucent/techniques/common/gl_resources.h"
#include "translucent/scene/scene.h"
#include "translucent/techniques/empirical/shading.h"

namespace translucent::empirical {
namespace {

using techniques::ParameterInfo;
using techniques::ParameterValue;

constexpr int kMaxLights = 4;  // shade.comp

std::vector<ParameterInfo> parameterInfos() {
  const ShadingParameters d;
  std::vector<std::string> presets = {"none"};
  for (const std::string& n : surveyPresetNames()) presets.push_back(n);
  return {
      ParameterInfo::enumeration("preset", "none", presets,
                                 "survey configuration of Gascons 2011, Table 4.3: sets "
                                 "thickness_exponent, backlight and diffuse_weight"),
      ParameterInfo::floating("ka", d.ka, 0.0, 10.0, "material ambient intensity k_a (Eq. 3.7)"),
      ParameterInfo::floating("kd_red", d.Kd.r, 0.0, 1.0, "material diffuse colour K_d, red"),
      ParameterInfo::floating("kd_green", d.Kd.g, 0.0, 1.0, "material diffuse colour K_d, green"),
      ParameterInfo::floating("kd_blue", d.Kd.b, 0.0, 1.0, "material diffuse colour K_d, blue"),
      ParameterInfo::floating("ambient_light", 1.0, 0.0, 100.0, "ambient light I_a (intensity)"),
      // The seed's interface (appendix A) gives the light ambient, diffuse and specular colours:
      // I_a = ambient_light × ambient colour; the diffuse colour is each light's own (scene
      // lights[i].color); the specular one is the light's value times the specular colour, so
      // that a white highlight on a coloured light (or none) is a setting, not a code change.
      ParameterInfo::floating("ambient_red", 1.0, 0.0, 10.0, "light ambient colour, red (× I_a)"),
      ParameterInfo::floating("ambient_green", 1.0, 0.0, 10.0, "light ambient colour, green (× I_a)"),
      ParameterInfo::floating("ambient_blue", 1.0, 0.0, 10.0, "light ambient colour, blue (× I_a)"),
      ParameterInfo::floating("specular_red", 1.0, 0.0, 10.0,
                              "light specular colour, red (× each light's value; Eq. 3.9)"),
      ParameterInfo::floating("specular_green", 1.0, 0.0, 10.0,
                              "light specular colour, green (× each light's value; Eq. 3.9)"),
      ParameterInfo::floating("specular_blue", 1.0, 0.0, 10.0,
                              "light specular colour, blue (× each light's value; Eq. 3.9)"),
      ParameterInfo::boolean("direct_only", false,
                             "direct light only (appendix A): skip the back layer and the "
                             "translucency term (Eq. 3.10); ambient, diffuse and specular stay"),
      ParameterInfo::floating("diffuse_contribution", d.wd, 0.0, 10.0,
                              "diffuse contribution w_d (Eq. 3.8)"),
      ParameterInfo::floating("specular_contribution", d.ws, 0.0, 10.0,
                              "specular contribution w_s (Eq. 3.9)"),
      ParameterInfo::floating("ks", d.ks, 0.0, 10.0, "material specular intensity k_s (Eq. 3.9)"),
      ParameterInfo::floating("shininess", d.shininess, 1.0, 10000.0,
                              "Blinn-Phong exponent n (Eq. 3.9)", "", true),
      ParameterInfo::floating("backlight", d.wb, 0.0, 10.0,
                              "backlight contribution w_b (Eq. 3.10; Table 4.3 b)"),
      ParameterInfo::floating("thickness_exponent", d.r, 0.0, 1000.0,
                              "thickness exponent r of (1 - t)^r (Eq. 3.10; Table 4.3 t)"),
      ParameterInfo::floating("diffuse_weight", d.Kb, 0.0, 10.0,
                              "diffuse weight K_b added to K_d in the backlight (Eq. 3.10; "
                              "Table 4.3 d)"),
      ParameterInfo::boolean("smoothing", true, "smooth the back depth (appendix C, Eq. C.1)"),
      // The only per-frame cost/quality knob (AO rays are precomputed and cached): the shade
      // pass reads k² back-depth texels per pixel (Eq. C.1).
      ParameterInfo::integer("kernel_size", 5, 1, 15, "smoothing window k × k (odd)", "texels")
          .withSweep({1, 3, 5, 9, 15}),
      ParameterInfo::floating("sigma", 1.0, 0.1, 8.0, "Gaussian σ of the smoothing", "texels"),
      ParameterInfo::floating("smoothing_threshold", 0.1, 1e-4, 10.0,
                              "back-depth deviation at which a neighbour's weight reaches 0 "
                              "(Eq. C.1), in diameters of the scene's bounding sphere", "", true),
      ParameterInfo::floating("peel_epsilon", 1e-4, 0.0, 0.1,
                              "depth peeling margin ε behind the front layer, in diameters", "",
                              false),
      ParameterInfo::boolean("ao", true, "per-vertex ambient occlusion a (Eq. 3.5); off: a = 1"),
      ParameterInfo::integer("ao_rays", 320, 1, 100000, "ambient occlusion rays per vertex"),
      ParameterInfo::boolean("ao_cosine", false,
                             "cosine-weighted ambient occlusion rays (Gascons 2011: uniform)"),
      ParameterInfo::boolean("local_viewer", true,
                             "specular half vector towards the camera from each point (OpenGL's "
                             "local viewer); off: the viewer at infinity along the view axis "
                             "(Gascons 2011, A.1.1)"),
      ParameterInfo::floating("spot_cutoff", 180.0, 0.0, 180.0,
                              "point lights as spotlights aimed at the mesh's centre: no direct "
                              "light beyond this angle from the axis; 180: no spot (OpenGL's "
                              "GL_SPOT_CUTOFF, Gascons 2011, A.1.1)",
                              "degrees"),
      ParameterInfo::floating("spot_exponent", 0.0, 0.0, 128.0,
                              "spotlight falloff: direct light × cos(angle from the axis)^exponent "
                              "inside the cutoff (OpenGL's GL_SPOT_EXPONENT)"),
      ParameterInfo::boolean("random_lighting", false,
                             "move every light along a smooth random path, one step per frame "
                             "(Gascons 2011, A.1.1, Random Lighting)"),
      ParameterInfo::integer("random_seed", 1, 0, 1000000,
                             "seed of the random lighting path (light i uses seed + i)"),
  };
}

gpu::Texture target(GLenum format, int width, int height) {
  gpu::Texture t = gpu::Texture::create(GL_TEXTURE_2D);
  gpu::allocateTexture2D(t, 1, format, width, height, "empirical: frame target");
  glTextureParameteri(t.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(t.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  return t;
}

// GL rows start at the bottom; frames at the top. RGBA -> one RGB layer per selected channel.
std::vector<float> readRows(const gpu::Texture& tex, int w, int h) {
  std::vector<float> rgba(size_t(w) * size_t(h) * 4);
  glGetTextureImage(tex.id(), 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(rgba.size() * sizeof(float)),
                    rgba.data());
  gpu::checkGlError("reading an empirical-technique image");
  std::vector<float> out(rgba.size());
  for (int y = 0; y < h; ++y)
    std::copy_n(rgba.begin() + ptrdiff_t(y) * w * 4, w * 4,
                out.begin() + ptrdiff_t(h - 1 - y) * w * 4);
  return out;
}

}  // namespace

struct EmpiricalTechnique::Impl {
  techniques::ParameterSet params{parameterInfos()};

  std::optional<scene::Scene> scene;
  std::string meshKey, aoKey;
  // The rest pose (scene::loadRestMesh): AO, the per-vertex material factors and the GPU copy are
  // computed on it once; a deformation (scene mesh.deform at scene.time) is applied to the vertex
  // buffer on the GPU per time (GpuMesh::deform), so the material, defined in the rest pose,
  // follows the surface. center and radius bound the deformed surface.
  geometry::TriangleMesh mesh;
  std::string boundsState;  // geometry::deformStateKey of center and radius ("": the rest pose)
  std::string materialKey;  // mesh, model and medium of the per-vertex factors ("": none)
  std::optional<material::MaterialDesc> materialDesc;  // and their material
  glm::dvec3 center{0.0};
  double radius = 1.0;
  std::vector<glm::dvec3> normals;
  std::vector<float> ao;
  bool uploadDirty = true;

  std::optional<techniques::GpuMesh> gpuMesh;  // positions, normals, AO (attribute 2)
  std::optional<gpu::ShaderProgram> frontProgram, backProgram, shadeProgram;

  int width = 0, height = 0;
  gpu::Texture frontDepth, frontNormal, frontPosition, backDepth, color, debug;
  gpu::Framebuffer frontFbo, backFbo;
  std::optional<gpu::PassTimer> timer;
  std::vector<std::string> notes;
  long long randomFrame = 0;  // frames rendered with random lighting on

  // Heterogeneous material: the per-vertex factor of K_d (empirical_technique.h), the
  // EMP_VERTEX_COLOUR variants of the front and shade programs and a front framebuffer with a
  // third attachment for the interpolated factor (built only then).
  std::optional<material::Material> materialOverride;
  material::Material mat;
  bool hetero = false;
  gpu::Buffer vertexColour;
  std::optional<gpu::ShaderProgram> frontHetero, shadeHetero;
  gpu::Texture frontColour;
  gpu::Framebuffer frontFboHetero;

  void prepareMaterial(const scene::Scene& s) {
    // The per-vertex factors are rest-pose quantities: a new time alone keeps them.
    const std::string key = meshKey + "|" + scene::mediumKey(s);
    if (!materialOverride && key == materialKey && materialDesc && *materialDesc == s.material) return;
    materialKey.clear();
    mat = materialOverride ? *materialOverride : scene::restMaterial(s, mesh);
    hetero = mat.heterogeneous();
    const auto done = [&] {
      materialKey = key;
      materialDesc = s.material;
    };
    if (!hetero) return done();
    // Kind::Surface: the map at each vertex's atlas UV, from the first triangle that uses it (a
    // vertex on a chart seam has one UV per chart), in the default atlas (geometry::AtlasOptions{},
    // cached), over which the map must be defined.
    std::vector<glm::dvec2> uvs(mesh.vertexCount(), glm::dvec2(0.0));
    if (mat.kind == material::Material::Kind::Surface) {
      const geometry::CachedAtlas cached = geometry::loadOrBuildAtlas(mesh, geometry::AtlasOptions{});
      std::vector<bool> seen(mesh.vertexCount(), false);
      for (size_t f = 0; f < mesh.triangleCount(); ++f)
        for (int c = 0; c < 3; ++c) {
          const uint32_t v = mesh.triangles[f][c];
          if (seen[v]) continue;
          seen[v] = true;
          uvs[v] = glm::dvec2(cached.atlas.uv(f, c));
        }
    }
    bool file = bssrdf::hasBssrdfExtension(mat.model);
    if (file) notes.push_back("empirical: per-vertex colours from the dipole's Rd (the material's model is a .bssrdf file)");
    // A tabulated profile has no Rd(α'); its material is homogeneous (scene.cpp refuses others),
    // so every vertex's ratio to the reference medium is 1 with any model: the dipole's is used.
    if (bssrdf::isTabulatedFile(mat.model)) file = true;
    const bssrdf::Model& model = bssrdf::model(file ? std::string("dipole") : mat.model);
    const double eta = mat.medium.eta, scale = mat.medium.scale;
    const auto rd = [&](const material::LocalMedium& m) {
      const Medium med = m.medium(eta, scale);
      med.validate();
      glm::dvec3 out;
      for (int c = 0; c < 3; ++c) out[c] = model.totalReflectance(med.channel(c).reducedAlbedo(), eta);
      return out;
    };
    const glm::dvec3 reference = rd(material::LocalMedium::of(mat.medium));
    std::vector<glm::vec4> factor(mesh.vertexCount());
    for (size_t v = 0; v < factor.size(); ++v) {
      const glm::dvec3 local = rd(mat.surfaceMedium(mesh.positions[v], normals[v], uvs[v]));
      for (int c = 0; c < 3; ++c)
        factor[v][c] = reference[c] > 0.0 ? static_cast<float>(local[c] / reference[c]) : 1.0f;
      factor[v].w = 1.0f;
    }
    vertexColour = gpu::makeStorageBuffer(std::span<const glm::vec4>(factor));
    if (!frontHetero) {
      const gpu::Defines d{{"EMP_VERTEX_COLOUR", "1"}};
      frontHetero.emplace(gpu::ShaderProgram::graphics("empirical/layers.vert", "empirical/front.frag", d));
      shadeHetero.emplace(gpu::ShaderProgram::compute("empirical/shade.comp", d));
    }
    width = height = 0;  // the front framebuffer gets its third attachment
    notes.push_back("empirical: heterogeneous material, K_d scaled per vertex by Rd(local) / "
                    "Rd(representative) (an approximation)");
    done();
  }

  void buildPrograms() {
    if (frontProgram) return;
    frontProgram.emplace(gpu::ShaderProgram::graphics("empirical/layers.vert", "empirical/front.frag"));
    backProgram.emplace(gpu::ShaderProgram::graphics("empirical/layers.vert", "empirical/back.frag"));
    shadeProgram.emplace(gpu::ShaderProgram::compute("empirical/shade.comp"));
  }

  void loadMesh(const scene::Scene& s) {
    const std::string key = scene::restMeshKey(s);
    if (key == meshKey) return;
    geometry::TriangleMesh m = scene::loadRestMesh(s);
    if (m.openEdgeCount() == 0) m.orientOutwards();
    mesh = std::move(m);
    normals = geometry::ambientOcclusionNormals(mesh);
    for (glm::dvec3& n : normals)
      if (glm::dot(n, n) == 0.0) n = {0.0, 0.0, 1.0};  // unused vertex
    const techniques::BoundingSphereOf bs = techniques::boundingSphere(mesh);
    center = bs.center;
    radius = bs.radius;
    meshKey = key;
    aoKey.clear();
    boundsState.clear();
  }

  // The scene's deformation at its time on the GPU, and the deformed surface's bounding sphere
  // (what the camera's automatic clip distances cover), from a CPU copy as ClosedMeshState does.
  void applyDeformation(const scene::Scene& s) {
    gpuMesh->deform(s.mesh_deform, s.time);  // nothing to do when its buffer holds this time
    const std::string state = geometry::deformStateKey(s.mesh_deform, s.time);
    if (state == boundsState) return;
    geometry::TriangleMesh shape = mesh;
    geometry::deformMesh(s.mesh_deform, s.time, shape);
    const techniques::BoundingSphereOf bs = techniques::boundingSphere(shape);
    center = bs.center;
    radius = bs.radius;
    if (!state.empty() && params.getBool("ao"))
      notes.push_back("empirical: the deformed mesh keeps the rest pose's per-vertex ambient "
                      "occlusion (precomputed once, as in Gascons 2011; not traced again per time)");
    boundsState = state;
  }

  void computeAo() {
    const std::string key = fmt::format("{}|{}|{}|{}", meshKey, params.getBool("ao"),
                                        params.getInt("ao_rays"), params.getBool("ao_cosine"));
    if (key == aoKey) return;
    if (params.getBool("ao")) {
      geometry::AmbientOcclusionOptions o;
      o.rays = params.getInt("ao_rays");
      o.cosineWeighted = params.getBool("ao_cosine");
      const geometry::AmbientOcclusion r = geometry::loadOrComputeAmbientOcclusion(mesh, o);
      ao = r.values;
      notes.push_back(r.fromCache
                          ? fmt::format("ambient occlusion: read from {}", r.file.string())
                          : fmt::format("ambient occlusion: {} rays per vertex, BVH {:.3f} s, "
                                        "rays {:.3f} s, cached in {}", o.rays, r.bvhSeconds,
                                        r.aoSeconds, r.file.string()));
      if (!r.note.empty()) notes.push_back("ambient occlusion cache: " + r.note);
    } else {
      ao.assign(mesh.vertexCount(), 1.0f);
    }
    aoKey = key;
    uploadDirty = true;
  }

  void upload() {
    if (!uploadDirty) return;
    gpuMesh.emplace(mesh, normals, ao);
    uploadDirty = false;
  }

  void resize(int w, int h) {
    if (w == width && h == height && frontFbo && (!hetero || frontFboHetero)) return;
    width = w;
    height = h;
    frontDepth = target(GL_DEPTH_COMPONENT32F, w, h);
    frontNormal = target(GL_RGBA32F, w, h);
    frontPosition = target(GL_RGBA32F, w, h);
    backDepth = target(GL_DEPTH_COMPONENT32F, w, h);
    color = target(GL_RGBA32F, w, h);
    debug = target(GL_RGBA32F, w, h);
    frontFbo = gpu::Framebuffer::create();
    glNamedFramebufferTexture(frontFbo.id(), GL_COLOR_ATTACHMENT0, frontNormal.id(), 0);
    glNamedFramebufferTexture(frontFbo.id(), GL_COLOR_ATTACHMENT1, frontPosition.id(), 0);
    glNamedFramebufferTexture(frontFbo.id(), GL_DEPTH_ATTACHMENT, frontDepth.id(), 0);
    const GLenum buffers[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    glNamedFramebufferDrawBuffers(frontFbo.id(), 2, buffers);
    backFbo = gpu::Framebuffer::create();
    glNamedFramebufferTexture(backFbo.id(), GL_DEPTH_ATTACHMENT, backDepth.id(), 0);
    glNamedFramebufferDrawBuffer(backFbo.id(), GL_NONE);
    if (hetero) {
      frontColour = target(GL_RGBA32F, w, h);
      frontFboHetero = gpu::Framebuffer::create();
      glNamedFramebufferTexture(frontFboHetero.id(), GL_COLOR_ATTACHMENT0, frontNormal.id(), 0);
      glNamedFramebufferTexture(frontFboHetero.id(), GL_COLOR_ATTACHMENT1, frontPosition.id(), 0);
      glNamedFramebufferTexture(frontFboHetero.id(), GL_COLOR_ATTACHMENT2, frontColour.id(), 0);
      glNamedFramebufferTexture(frontFboHetero.id(), GL_DEPTH_ATTACHMENT, frontDepth.id(), 0);
      const GLenum three[3] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
      glNamedFramebufferDrawBuffers(frontFboHetero.id(), 3, three);
      if (glCheckNamedFramebufferStatus(frontFboHetero.id(), GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw gpu::GlError(fmt::format("empirical: {}x{} colour layer: the framebuffer is incomplete", w, h));
    }
    for (GLuint fbo : {frontFbo.id(), backFbo.id()})
      if (glCheckNamedFramebufferStatus(fbo, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw gpu::GlError(fmt::format("empirical: {}x{} depth layers: the framebuffer is incomplete", w, h));
    gpu::checkGlError("creating the depth layers");
  }

  void drawLayer(GLuint fbo, const gpu::ShaderProgram& program, const glm::mat4& viewProj) {
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glViewport(0, 0, width, height);
    const float zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    const float one = 1.0f;
    const bool heteroFront = hetero && fbo == frontFboHetero.id();
    if (fbo == frontFbo.id() || heteroFront) {
      glClearNamedFramebufferfv(fbo, GL_COLOR, 0, zero);
      glClearNamedFramebufferfv(fbo, GL_COLOR, 1, zero);
    }
    if (heteroFront) glClearNamedFramebufferfv(fbo, GL_COLOR, 2, zero);
    glClearNamedFramebufferfv(fbo, GL_DEPTH, 0, &one);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDisable(GL_CULL_FACE);
    program.use();
    program.set("ViewProjection", viewProj);
    gpuMesh->draw();
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    gpu::checkGlError("rendering a depth layer");
  }

  techniques::Frame render(const techniques::FrameRequest& request) {
    if (!scene) throw ParameterError("empirical: render() before prepare(): expected a scene");
    const scene::Scene& s = *scene;
    const auto [w, h] = techniques::frameSize(request, s.camera);
    const int kernel = params.getInt("kernel_size");
    if (kernel % 2 == 0)
      throw ParameterError(fmt::format("kernel_size {}: expected an odd number", kernel));
    buildPrograms();
    computeAo();
    upload();
    applyDeformation(s);
    resize(w, h);
    if (!timer) timer.emplace();
    techniques::Frame frame;
    frame.notes = std::move(notes);
    notes.clear();

    const techniques::CameraMatrices cam =
        techniques::cameraMatrices(s.camera, s.clip_near, s.clip_far, center, radius, width, height);
    const glm::dmat4& proj = cam.projection;
    const glm::mat4 viewProj = cam.viewProjection();
    const float diameter = static_cast<float>(2.0 * radius);
    {
      auto t = timer->scope("front");
      if (hetero) {
        gpu::bindStorage(0, vertexColour);
        drawLayer(frontFboHetero.id(), *frontHetero, viewProj);
      } else {
        drawLayer(frontFbo.id(), *frontProgram, viewProj);
      }
    }
    const bool directOnly = params.getBool("direct_only");
    if (!directOnly) {
      auto t = timer->scope("back");
      const gpu::ShaderProgram& p = *backProgram;
      glBindTextureUnit(0, frontDepth.id());
      p.set("Projection", glm::mat4(proj));
      p.set("PeelEpsilon", static_cast<float>(params.getFloat("peel_epsilon")) * diameter);
      drawLayer(backFbo.id(), p, viewProj);
    }
    {
      auto t = timer->scope("shade");
      const gpu::ShaderProgram& p = hetero ? *shadeHetero : *shadeProgram;
      glBindTextureUnit(0, frontDepth.id());
      glBindTextureUnit(1, backDepth.id());
      if (hetero) glBindTextureUnit(4, frontColour.id());
      glBindTextureUnit(2, frontNormal.id());
      glBindTextureUnit(3, frontPosition.id());
      glBindImageTexture(0, color.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
      glBindImageTexture(1, debug.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
      glProgramUniform2i(p.id(), p.uniformLocation("Size"), w, h);
      p.set("Projection", glm::mat4(proj));
      p.set("Diameter", diameter);
      p.set("KernelRadius", params.getBool("smoothing") ? kernel / 2 : 0);
      p.set("Sigma", static_cast<float>(params.getFloat("sigma")));
      p.set("Threshold", static_cast<float>(params.getFloat("smoothing_threshold")));
      p.set("CameraPosition", glm::vec3(s.camera.position));
      p.set("CameraForward", glm::vec3(glm::normalize(s.camera.look_at - s.camera.position)));
      p.set("Orthographic", s.camera.projection == reference::Camera::Projection::Orthographic);
      p.set("LocalViewer", params.getBool("local_viewer"));
      const double cutoff = params.getFloat("spot_cutoff");
      // cos of the cutoff; -2 (below any cosine): no spot at 180°, as OpenGL.
      p.set("SpotCosCutoff", cutoff >= 180.0 ? -2.0f : static_cast<float>(std::cos(cutoff * std::numbers::pi / 180.0)));
      p.set("SpotExponent", static_cast<float>(params.getFloat("spot_exponent")));
      p.set("SpotTarget", glm::vec3(center));
      int count = 0;
      const bool randomLighting = params.getBool("random_lighting");
      for (const scene::Light& l : s.lights) {  // directional or point: checked in prepare()
        const glm::vec3 colour(float(l.color[0]), float(l.color[1]), float(l.color[2]));
        const auto* d = std::get_if<reference::DirectionalLight>(&l.emitter);
        const auto* pt = std::get_if<reference::PointLight>(&l.emitter);
        // Exactly one of d, pt is set (checked in prepare()).
        const bool point = pt != nullptr;
        glm::dvec3 towards = point ? pt->position : glm::normalize(std::get<0>(l.emitter).direction);
        if (randomLighting) {
          // A directional light turns; a point light keeps its distance from the mesh centre.
          const glm::dvec3 dir = randomLightDirection(
              static_cast<unsigned long long>(params.getInt("random_seed") + count), randomFrame);
          towards = point ? center + glm::length(towards - center) * dir : dir;
          frame.notes.push_back(fmt::format("random lighting, frame {}: light {} {} ({:.4f}, "
                                            "{:.4f}, {:.4f})", randomFrame, count,
                                            point ? "at" : "towards", towards.x, towards.y,
                                            towards.z));
        }
        p.set(fmt::format("LightIsPoint[{}]", count), point);
        p.set(fmt::format("LightDirection[{}]", count), glm::vec3(towards));
        p.set(fmt::format("LightValue[{}]", count),
              colour * static_cast<float>(d != nullptr ? d->irradiance : pt->intensity));
        ++count;
      }
      p.set("LightCount", count);
      if (randomLighting) ++randomFrame;
      p.set("Ia", static_cast<float>(params.getFloat("ambient_light")) *
                      glm::vec3(params.getFloat("ambient_red"), params.getFloat("ambient_green"),
                                params.getFloat("ambient_blue")));
      p.set("SpecularColour", glm::vec3(params.getFloat("specular_red"),
                                        params.getFloat("specular_green"),
                                        params.getFloat("specular_blue")));
      p.set("DirectOnly", directOnly);
      p.set("Kd", glm::vec3(params.getFloat("kd_red"), params.getFloat("kd_green"),
                            params.getFloat("kd_blue")));
      p.set("Ka", static_cast<float>(params.getFloat("ka")));
      p.set("Wd", static_cast<float>(params.getFloat("diffuse_contribution")));
      p.set("Ws", static_cast<float>(params.getFloat("specular_contribution")));
      p.set("Ks", static_cast<float>(params.getFloat("ks")));
      p.set("Shininess", static_cast<float>(params.getFloat("shininess")));
      p.set("Wb", static_cast<float>(params.getFloat("backlight")));
      p.set("R", static_cast<float>(params.getFloat("thickness_exponent")));
      p.set("Kb", static_cast<float>(params.getFloat("diffuse_weight")));
      p.use();
      glDispatchCompute(GLuint((w + 7) / 8), GLuint((h + 7) / 8), 1);
      glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
      gpu::checkGlError("the empirical shading pass");
    }

    frame.width = w;
    frame.height = h;
    if (!request.readback) {
      techniques::addPasses(frame, *timer);
      return frame;
    }
    const std::vector<float> rgba = readRows(color, w, h);
    const std::vector<float> dbg = readRows(debug, w, h);
    const size_t pixels = size_t(w) * size_t(h);
    frame.rgb.resize(pixels * 3);
    const char* names[4] = {"front_depth", "back_depth", "thickness", "ao"};
    float* layer[4];  // looked up once: a map lookup per texel cost more than the GPU frame
    for (int k = 0; k < 4; ++k) {
      std::vector<float>& l = frame.layers[names[k]];
      l.resize(pixels * 3);
      layer[k] = l.data();
    }
    for (size_t i = 0; i < pixels; ++i) {
      for (int c = 0; c < 3; ++c) frame.rgb[i * 3 + size_t(c)] = rgba[i * 4 + size_t(c)];
      for (int k = 0; k < 4; ++k)
        for (int c = 0; c < 3; ++c) layer[k][i * 3 + size_t(c)] = dbg[i * 4 + size_t(k)];
    }
    techniques::addPasses(frame, *timer);
    return frame;
  }
};

EmpiricalTechnique::EmpiricalTechnique() : impl_(std::make_unique<Impl>()) {}
EmpiricalTechnique::~EmpiricalTechnique() = default;

std::string_view EmpiricalTechnique::description() const {
  return "empirical translucency shader: screen-space thickness by depth peeling, per-vertex AO "
         "(Gascons 2011, chapter 3)";
}

const std::vector<techniques::ParameterInfo>& EmpiricalTechnique::parameters() const {
  return impl_->params.infos();
}

void EmpiricalTechnique::setParameter(std::string_view name, const techniques::ParameterValue& value) {
  impl_->params.set(name, value);
  if (name == "preset") {
    const std::string& preset = impl_->params.getEnum("preset");
    if (preset == "none") return;
    const SurveyPreset p = surveyPreset(std::stoi(preset.substr(6)));  // "surveyN"
    impl_->params.set("thickness_exponent", p.thicknessExponent);
    impl_->params.set("backlight", p.backlight);
    impl_->params.set("diffuse_weight", p.diffuseWeight);
  }
}

techniques::ParameterValue EmpiricalTechnique::parameter(std::string_view name) const {
  return impl_->params.get(name);
}

void EmpiricalTechnique::prepare(const scene::Scene& scene, gpu::Context& gl) {
  gl.makeCurrent();
  scene.camera.validate();
  for (size_t i = 0; i < scene.lights.size(); ++i) {
    const auto& e = scene.lights[i].emitter;
    if (!std::holds_alternative<reference::DirectionalLight>(e) &&
        !std::holds_alternative<reference::PointLight>(e))
      throw ParameterError(fmt::format("lights[{}]: the empirical technique takes directional and "
                                       "point lights only", i));
    if (int(i) >= kMaxLights)
      throw ParameterError(fmt::format("lights[{}]: the empirical technique takes at most {} "
                                       "lights", i, kMaxLights));
  }
  impl_->buildPrograms();
  impl_->loadMesh(scene);
  impl_->scene = scene;
  impl_->prepareMaterial(scene);
  impl_->computeAo();
  impl_->upload();
  impl_->applyDeformation(scene);
}

void EmpiricalTechnique::setMaterial(std::optional<material::Material> material) {
  impl_->materialOverride = std::move(material);
  impl_->materialKey.clear();
}

bool EmpiricalTechnique::heterogeneous() const { return impl_->hetero; }

techniques::Frame EmpiricalTechnique::render(const techniques::FrameRequest& request) {
  return impl_->render(request);
}

bool EmpiricalTechnique::setCamera(const reference::Camera& camera) {
  if (!impl_->scene) return false;
  camera.validate();
  impl_->scene->camera = camera;
  return true;
}

double EmpiricalTechnique::sceneDiameter() const { return 2.0 * impl_->radius; }

std::unique_ptr<techniques::Technique> makeEmpiricalTechnique() {
  return std::make_unique<EmpiricalTechnique>();
}

}  // namespace translucent::empirical
