// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/techniques/splatting/splatting_technique.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <optional>
#include <string>

#include <glm/geometric.hpp>

#include "translucent/bssrdf/exit_radiance.h"
#include "translucent/geometry/atlas.h"
#include "translucent/gpu/compute.h"
#include "translucent/gpu/pass_timer.h"
#include "translucent/material/material.h"
#include "translucent/material/material_desc.h"
#include "translucent/material/profile_atlas.h"
#include "translucent/material/surface_uv.h"
#include <fmt/ranges.h>
#include "translucent/scene/scene.h"
#include "translucent/techniques/common/profile_atlas_gpu.h"
#include "translucent/techniques/common/profile_kernel.h"
#include "translucent/techniques/common/specular.h"
#include "translucent/techniques/splatting/splatting_math.h"

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
  kMeshFloats = 14,
  kVertexRp = 15
};

constexpr int kRpSteps = 128;        // midpoint steps over [0, r_cut] for the 95% radius
constexpr size_t kMeanProfiles = 512;  // vertex profiles averaged into P̄ (Eq. 15), at most

std::vector<ParameterInfo> parameterInfos(bool shah) {
  std::vector<ParameterInfo> out = {
      ParameterInfo::integer("irradiance_size", 512, 16, 8192,
                             "resolution of each light's irradiance buffer (light-view map)", "texels")
          .withSweep({128, 256, 512, 1024}),
  };
  if (!shah) {
    out.push_back(ParameterInfo::integer("levels", 3, 1, 6,
                                         "levels of the splatting buffer (multires) and of "
                                         "the irradiance buffer (adaptive)", "levels"));
    out.push_back(ParameterInfo::boolean("adaptive", true,
                                         "adaptive sample selection from the hierarchical "
                                         "irradiance buffer (Eqs. 10-11, Algorithm 1)"));
    out.push_back(ParameterInfo::boolean("multires", true,
                                         "multiresolution splatting: per-sample ranges over the "
                                         "levels (Eqs. 13-16), bilateral upsampling (Eq. 17)"));
    out.push_back(ParameterInfo::floating("z0", 0.03, 0.0, 1.0,
                                          "depth threshold of Eq. 10 as a fraction of the bounding "
                                          "sphere's radius", "radius"));
    out.push_back(ParameterInfo::floating("alpha", 15.0, 0.0, 1000.0,
                                          "α of the material sampling rate (Eq. 11)", ""));
    out.push_back(ParameterInfo::enumeration(
        "selection_terms", "both", {"both", "discontinuity", "orientation"},
        "geometric terms of the adaptive selection (Eqs. 10-11): both, the depth discontinuity "
        "only, or the surface orientation |n·L| only (the ablation of Chen et al. 2012, Fig. 5)"));
    out.push_back(ParameterInfo::floating("epsilon", 0.001, 1e-6, 0.5,
                                          "ε of the minimal effective rendering radius (Eq. 14)", ""));
    out.push_back(ParameterInfo::floating("lambda_z", 8.0, 0.0, 100.0,
                                          "λz of the bilateral upsampling (Eq. 17)", ""));
    out.push_back(ParameterInfo::floating("lambda_m", 8.0, 0.0, 100.0,
                                          "λm of the bilateral upsampling (Eq. 17)", ""));
  }
  for (ParameterInfo& p : techniques::profileStorageParameters()) out.push_back(std::move(p));
  out.push_back(techniques::radianceConventionParameter());
  for (ParameterInfo& p : techniques::specularParameters()) out.push_back(std::move(p));
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
  gpu::Buffer vertexProfileBuffer, triangleBuffer, vertexRpBuffer;
  // profile_storage texture: the profiles at the atlas' texels (material/profile_atlas.h), as a
  // 2D array texture of n + 1 layers, and the triangles' corner UVs.
  std::optional<material::ProfileAtlas> profileAtlas;
  techniques::GpuProfileAtlas gpuProfileAtlas;
  std::vector<float> vertexRp;  // R_P per vertex: the 95% radius of its widest channel
  MeanProfile meanProfile{1024};
  MeanProfile firstProfile{1024};  // vertex 0's normalised profile alone (Fig. 3b's second plot)
  std::optional<RbarTable> rbar;
  std::optional<techniques::FramePlot> radiusPlot;  // Fig. 3b for the current profiles and ε
  double rbarEpsilon = -1.0;
  std::string programKey;  // the nodes and profile storage the programs were built for
  std::vector<std::string> notes;  // for the next frame (then cleared)

  std::optional<gpu::ShaderProgram> mapProgram, gbufferProgram, splatProgram, radianceProgram,
      downsampleProgram, upsampleProgram, irradianceMipProgram;

  struct LightState {
    scene::Light light;
    std::unique_ptr<techniques::LightViewMap> map;
    // Adaptive selection: the hierarchical irradiance buffer (irradiance_mip.comp), `hierLevels`
    // mip levels each.
    gpu::Texture hierA, hierB, hierC;
    int hierLevels = 0;
    bool hierBuilt = false;  // the hierarchy holds the current map
  };
  std::vector<LightState> lights;
  // The irradiance buffers (light-view maps) and their hierarchies depend on the mesh, the lights
  // and the vertex profiles, nothing of the camera's: rendered after prepare() or a new
  // irradiance_size only, and kept over camera moves and still frames. The splatting buffer is
  // the camera's G-buffer: it, the splats, the upsampling and the radiance are redone each frame.
  bool mapsDirty = true;

  techniques::GBuffer gbuffer;
  gpu::Texture accum;
  gpu::Framebuffer accumFbo;
  gpu::VertexArray emptyVao;
  int accumW = 0, accumH = 0;
  // Levels k >= 1 of the multiresolution splatting: the median-depth splatting buffer and the
  // level's accumulation target.
  struct Level {
    int w = 0, h = 0;
    gpu::Texture position, normal, accum;
    gpu::Framebuffer fbo;
  };
  std::vector<Level> levelTargets;
  gpu::Buffer radianceOut, exitanceOut;
  size_t outPixels = 0;
  std::optional<gpu::PassTimer> timer;
  techniques::SpecularPass specular;

  void buildPrograms(int nodes) {
    const std::string key = fmt::format("{}{}", nodes, profileAtlas ? " atlas" : "");
    if (splatProgram && programKey == key) return;
    gpu::Defines d{{"PC_HETERO", "1"}, {"PC_PROFILE_NODES", std::to_string(nodes)},
                   {"LVM_PRIMITIVE_ID", "1"}};
    if (profileAtlas) d.push_back({"PC_PROFILE_ATLAS", "1"});
    mapProgram.emplace(
        gpu::ShaderProgram::graphics("common/light_view_map.vert", "common/light_view_map.frag", d));
    gbufferProgram.emplace(
        gpu::ShaderProgram::graphics("pointcloud/gbuffer.vert", "pointcloud/gbuffer.frag", d));
    splatProgram.emplace(gpu::ShaderProgram::graphics("splatting/splat.vert", "splatting/splat.frag", d));
    radianceProgram.emplace(gpu::ShaderProgram::compute("splatting/radiance.comp"));
    downsampleProgram.emplace(gpu::ShaderProgram::compute("splatting/downsample.comp"));
    upsampleProgram.emplace(gpu::ShaderProgram::compute("splatting/upsample.comp", d));
    irradianceMipProgram.emplace(gpu::ShaderProgram::compute("splatting/irradiance_mip.comp", d));
    programKey = key;
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
    mapsDirty = true;
  }

  // R_P of profile i: the 95% radius of its widest channel (midpoint rule on [0, r_cut]), and
  // that channel.
  static std::pair<double, int> rpOf(const material::PointProfiles& p, size_t i) {
    std::array<std::vector<double>, 3> cum;
    for (auto& c : cum) c.assign(kRpSteps + 1, 0.0);
    const double dr = p.cutRadius() / kRpSteps;
    for (int k = 0; k < kRpSteps; ++k) {
      const double r = (k + 0.5) * dr;
      const glm::dvec3 pv = p.at(i, r);
      for (int c = 0; c < 3; ++c) cum[size_t(c)][size_t(k) + 1] = cum[size_t(c)][size_t(k)] + pv[c] * r * dr;
    }
    double rp = 0.0;
    int widest = 0;
    for (int c = 0; c < 3; ++c) {
      const auto& e = cum[size_t(c)];
      int k = 0;
      while (k < kRpSteps && e[size_t(k) + 1] < 0.95 * e.back()) ++k;
      const double r = (k + 1) * dr;
      if (r > rp) {
        rp = r;
        widest = c;
      }
    }
    return {rp, widest};
  }

  // Per-vertex profiles at the rest pose (once per mesh, material and profile storage), and with
  // profile_storage texture the profiles at the texels of an atlas of the rest mesh.
  void buildProfiles(const scene::Scene& s) {
    const geometry::TriangleMesh& restMesh = rest.positions.empty() ? mesh : rest;
    const bool texture = params.getEnum("profile_storage") == "texture";
    const int texels = params.getInt("profile_texels");
    const std::string key = fmt::format("{}|{}|{}", meshKey, scene::mediumKey(s),
                                        texture ? std::to_string(texels) : std::string("vertex"));
    if (key == profileKey && profileDesc && *profileDesc == s.material) return;
    profileKey.clear();
    const material::Material mat = scene::restMaterial(s, restMesh);
    const std::vector<glm::dvec3> normals = techniques::vertexNormals(restMesh);
    std::vector<glm::vec3> vp(restMesh.vertexCount()), vn(restMesh.vertexCount());
    for (size_t i = 0; i < vp.size(); ++i) {
      vp[i] = glm::vec3(restMesh.positions[i]);
      vn[i] = glm::vec3(normals[i]);
    }
    // A surface map (Kind::Surface) is read at each vertex's UV in the rest pose's default atlas,
    // as the point cloud reads it for its vertices (material/surface_uv.h: a vertex on a chart
    // seam takes the UV of the first triangle that uses it), so the map follows a deformation.
    std::optional<geometry::Atlas> surfaceAtlas;
    std::vector<glm::vec2> uvs;
    if (mat.kind == material::Material::Kind::Surface) {
      surfaceAtlas = geometry::loadOrBuildAtlas(restMesh, geometry::AtlasOptions{}).atlas;
      uvs = material::vertexAtlasUvs(restMesh, *surfaceAtlas);
    }
    profileAtlas.reset();
    material::ProfileOptions vertexOptions;
    if (texture) {
      // The texels' profiles first: their r_s (the largest 95% radius over the surface) is the
      // grid of the vertex profiles too, so that Eq. 8 combines nodes of one grid.
      geometry::AtlasOptions ao;
      ao.size = uint32_t(texels);
      const geometry::CachedAtlas atlas = geometry::loadOrBuildAtlas(restMesh, ao);
      profileAtlas = material::buildProfileAtlas(restMesh, atlas.atlas, mat, {},
                                                 surfaceAtlas ? &*surfaceAtlas : nullptr);
      vertexOptions = {profileAtlas->segments, profileAtlas->radius};
    }
    profiles = material::PointProfiles::build(mat, material::PointProfiles::surfaceMedia(mat, vp, vn, uvs),
                                              vertexOptions);
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
    // R_P per vertex (the 95% radius of the widest channel, midpoint rule on [0, r_cut]) and the
    // mean normalised profile P̄ (Eqs. 15-16) over at most kMeanProfiles vertices.
    vertexRp.assign(profiles.size(), 0.0f);
    meanProfile = MeanProfile(1024);
    firstProfile = MeanProfile(1024);
    radiusPlot.reset();
    const size_t stride = std::max<size_t>(1, profiles.size() / kMeanProfiles);
    for (size_t v = 0; v < profiles.size(); ++v) {
      const auto [rp, widest] = rpOf(profiles, v);
      vertexRp[v] = float(rp);
      if (v % stride == 0)
        meanProfile.add([&, v, w = widest](double r) { return profiles.at(v, r)[w]; }, rp);
      if (v == 0) firstProfile.add([&, w = widest](double r) { return profiles.at(0, r)[w]; }, rp);
    }
    if (profileAtlas) {
      // A splat's radius is interpolated from its triangle's vertices: each vertex takes the
      // largest R_P of the texels on the triangles around it, so that no texel's profile is cut
      // shorter than its own 95% radius. The distinct profiles only (a field of a few media).
      const material::ProfileAtlas& pa = *profileAtlas;
      std::map<std::vector<double>, float> seen;
      for (size_t i = 0; i < pa.owned; ++i) {
        std::vector<double> nodesOf(pa.profiles.nodes().begin() + std::ptrdiff_t(i * size_t(m) * 3),
                                    pa.profiles.nodes().begin() + std::ptrdiff_t((i + 1) * size_t(m) * 3));
        auto it = seen.find(nodesOf);
        if (it == seen.end())
          it = seen.emplace(std::move(nodesOf), float(rpOf(pa.profiles, i).first)).first;
        const glm::uvec3 t = restMesh.triangles[pa.texel_triangle[i]];
        for (int k = 0; k < 3; ++k) vertexRp[t[k]] = std::max(vertexRp[t[k]], it->second);
      }
      gpuProfileAtlas =
          techniques::uploadProfileAtlas(pa, fmt::format("{}: profile texture", techniqueName()));
      notes.push_back(techniques::describeProfileAtlas(techniqueName(), pa));
    }
    vertexRpBuffer = gpu::makeStorageBuffer(std::span<const float>(vertexRp));
    rbarEpsilon = -1.0;
    buildPrograms(m);
    profileKey = key;
    profileDesc = s.material;
  }

  // The profiles for a pass that reads them (splatting/profile.glsl).
  void bindProfiles() const {
    gpu::bindStorage(kVertexProfiles, vertexProfileBuffer);
    if (profileAtlas) gpuProfileAtlas.bind();
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

  static gpu::Texture levelTexture(int w, int h) {
    gpu::Texture t = gpu::Texture::create(GL_TEXTURE_2D);
    gpu::allocateTexture2D(t, 1, GL_RGBA32F, w, h, "splatting level");
    glTextureParameteri(t.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(t.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    return t;
  }

  void resizeLevels(int width, int height, int levels) {
    if (int(levelTargets.size()) == levels - 1 &&
        (levels == 1 || (levelTargets[0].w == (width + 1) / 2 && levelTargets[0].h == (height + 1) / 2)))
      return;
    levelTargets.clear();
    int w = width, h = height;
    for (int k = 1; k < levels; ++k) {
      w = (w + 1) / 2;
      h = (h + 1) / 2;
      Level l;
      l.w = w;
      l.h = h;
      l.position = levelTexture(w, h);
      l.normal = levelTexture(w, h);
      l.accum = levelTexture(w, h);
      l.fbo = gpu::Framebuffer::create();
      glNamedFramebufferTexture(l.fbo.id(), GL_COLOR_ATTACHMENT0, l.accum.id(), 0);
      if (glCheckNamedFramebufferStatus(l.fbo.id(), GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw gpu::GlError("splatting: a level's framebuffer is incomplete");
      levelTargets.push_back(std::move(l));
    }
  }

  // The hierarchical irradiance buffer of one light (levels mip levels).
  void buildHierarchy(LightState& st, int levels) {
    if (st.hierBuilt && st.hierLevels == levels) return;
    const int size = st.map->size();
    if (st.hierLevels != levels) {
      auto make = [&] {
        gpu::Texture t = gpu::Texture::create(GL_TEXTURE_2D);
        gpu::allocateTexture2D(t, levels, GL_RGBA32F, size, size, "hierarchical irradiance buffer");
        glTextureParameteri(t.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST_MIPMAP_NEAREST);
        glTextureParameteri(t.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        return t;
      };
      st.hierA = make();
      st.hierB = make();
      st.hierC = make();
      st.hierLevels = levels;
    }
    const gpu::ShaderProgram& p = *irradianceMipProgram;
    gpu::bindStorage(kTriangles, triangleBuffer);
    gpu::bindStorage(kMeshFloats, gpuMesh->vertexBuffer());
    gpu::bindStorage(kVertexRp, vertexRpBuffer);
    bindProfiles();
    p.set("SpFloatsPerVertex", gpuMesh->floatsPerVertex());
    st.map->bind(p, 1);
    glBindTextureUnit(4, st.hierA.id());
    glBindTextureUnit(5, st.hierB.id());
    glBindTextureUnit(6, st.hierC.id());
    int w = size;
    for (int j = 0; j < levels; ++j) {
      if (j > 0) w = (w + 1) / 2;
      glBindImageTexture(0, st.hierA.id(), j, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
      glBindImageTexture(1, st.hierB.id(), j, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
      glBindImageTexture(2, st.hierC.id(), j, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
      p.set("Level", j);
      glProgramUniform2ui(p.id(), p.uniformLocation("DstSize"), unsigned(w), unsigned(w));
      gpu::dispatch(p, {(unsigned(w) + 7u) / 8u, (unsigned(w) + 7u) / 8u, 1u});
      glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    }
    gpu::checkGlError("building the hierarchical irradiance buffer");
    st.hierBuilt = true;
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

  // Chen et al. 2012, Fig. 3b: the minimal effective rendering radius R̄ (Eq. 14, a fraction of
  // R_P) against the splatting resolution T across R_P, for the mean normalised profile P̄ (the
  // table the frames use) and for one point's profile (vertex 0's).
  techniques::FramePlot effectiveRadiusPlot(double eps) const {
    techniques::FramePlot plot;
    plot.title = fmt::format("Minimal effective rendering radius (Eq. 14, ε = {})", eps);
    plot.x_label = "T: splatting-buffer samples across the scattering range R_P";
    plot.y_label = "R̄ / R_P";
    plot.log_x = true;
    const RbarTable single = RbarTable::build(firstProfile, eps);
    for (const auto& [label, table] :
         {std::pair<std::string, const RbarTable*>{"mean profile P̄ (the lookup table)", &*rbar},
          std::pair<std::string, const RbarTable*>{"the profile of vertex 0", &single}}) {
      techniques::FramePlot::Series series;
      series.label = label;
      for (int j = 0; j < int(table->rbar.size()); ++j) {
        series.x.push_back(table->tAt(j));
        series.y.push_back(table->rbar[size_t(j)]);
      }
      plot.series.push_back(std::move(series));
    }
    return plot;
  }

  techniques::Frame render(const techniques::FrameRequest& request) {
    if (!scene) throw ParameterError(fmt::format("{}: render() before prepare(): expected a scene", techniqueName()));
    const scene::Scene& s = *scene;
    const auto [width, height] = techniques::frameSize(request, s.camera);
    if (!timer) timer.emplace();
    if (!emptyVao.id()) emptyVao = gpu::VertexArray::create();
    techniques::Frame frame;
    frame.notes = std::move(notes);
    notes.clear();
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
    if (mapsDirty) {
      auto t = timer->scope("irradiance");
      for (auto& st : lights) {
        renderMap(st);
        st.hierBuilt = false;
      }
      mapsDirty = false;
    }
    const bool adaptive = !shah && params.getBool("adaptive");
    // Irradiance-buffer levels: as many as splatting levels (the paper's three for both),
    // limited by the buffer's size.
    int irrLevels = 1;
    if (adaptive) {
      irrLevels = params.getInt("levels");
      const int size = params.getInt("irradiance_size");
      while (irrLevels > 1 && (size >> (irrLevels - 1)) < 1) --irrLevels;
      bool build = false;
      for (const auto& st : lights) build = build || !st.hierBuilt || st.hierLevels != irrLevels;
      if (build) {
        auto t = timer->scope("irradiance hierarchy");
        for (auto& st : lights) buildHierarchy(st, irrLevels);
      }
    }
    resizeAccum(width, height);
    const int levels = (!shah && params.getBool("multires")) ? params.getInt("levels") : 1;
    resizeLevels(width, height, levels);
    const double eps = shah ? 0.001 : params.getFloat("epsilon");
    if ((levels > 1 || (request.views && !shah)) && (!rbar || rbarEpsilon != eps)) {
      rbar = RbarTable::build(meanProfile, eps);
      rbarEpsilon = eps;
      radiusPlot.reset();
    }
    if (request.views && !shah) {
      if (!radiusPlot) radiusPlot = effectiveRadiusPlot(eps);
      frame.plots["effective_radius"] = *radiusPlot;
    }
    const glm::vec3 camPos = toVec3(s.camera.position);
    const glm::vec3 camFwd = toVec3(glm::normalize(s.camera.look_at - s.camera.position));
    if (levels > 1) {
      auto t = timer->scope("splatting buffer mipmap");
      const gpu::ShaderProgram& p = *downsampleProgram;
      p.set("CameraPosition", camPos);
      p.set("CameraForward", camFwd);
      for (int k = 1; k < levels; ++k) {
        const Level& l = levelTargets[size_t(k - 1)];
        glBindTextureUnit(0, k == 1 ? gbuffer.position().id() : levelTargets[size_t(k - 2)].position.id());
        glBindTextureUnit(1, k == 1 ? gbuffer.normal().id() : levelTargets[size_t(k - 2)].normal.id());
        glBindImageTexture(0, l.position.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
        glBindImageTexture(1, l.normal.id(), 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
        glProgramUniform2ui(p.id(), p.uniformLocation("CoarseSize"), unsigned(l.w), unsigned(l.h));
        gpu::dispatch(p, {(unsigned(l.w) + 7u) / 8u, (unsigned(l.h) + 7u) / 8u, 1u});
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
      }
    }
    for (int k = 0; k < levels; ++k) {
      auto t = timer->scope(levels > 1 ? fmt::format("splat level {}", k) : std::string("splat"));
      const int lw = k == 0 ? width : levelTargets[size_t(k - 1)].w;
      const int lh = k == 0 ? height : levelTargets[size_t(k - 1)].h;
      const GLuint fbo = k == 0 ? accumFbo.id() : levelTargets[size_t(k - 1)].fbo.id();
      const float zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
      glClearNamedFramebufferfv(fbo, GL_COLOR, 0, zero);
      glBindFramebuffer(GL_FRAMEBUFFER, fbo);
      glViewport(0, 0, lw, lh);
      glDisable(GL_DEPTH_TEST);
      glDisable(GL_CULL_FACE);
      glEnable(GL_BLEND);
      glBlendEquation(GL_FUNC_ADD);
      glBlendFunc(GL_ONE, GL_ONE);
      const gpu::ShaderProgram& p = *splatProgram;
      p.use();
      bindProfiles();
      gpu::bindStorage(kTriangles, triangleBuffer);
      gpu::bindStorage(kMeshFloats, gpuMesh->vertexBuffer());
      gpu::bindStorage(kVertexRp, vertexRpBuffer);
      glBindTextureUnit(0, k == 0 ? gbuffer.position().id() : levelTargets[size_t(k - 1)].position.id());
      p.set("ViewProjection", vp);
      p.set("SpFloatsPerVertex", gpuMesh->floatsPerVertex());
      p.set("HeteroRadius", static_cast<float>(profiles.radius()));
      p.set("CutRadius", static_cast<float>(profiles.cutRadius()));
      p.set("PixelSize", glm::vec2(2.0f / float(lw), 2.0f / float(lh)));
      p.set("Multires", levels > 1);
      p.set("Level", k);
      p.set("Levels", levels);
      p.set("LevelResolution", static_cast<float>(height));
      p.set("Orthographic", s.camera.projection == reference::Camera::Projection::Orthographic);
      p.set("TanHalfFov", static_cast<float>(std::tan(0.5 * s.camera.fov * 3.14159265358979323846 / 180.0)));
      p.set("ViewHeight", static_cast<float>(s.camera.view_height));
      p.set("CameraPosition", camPos);
      p.set("CameraForward", camFwd);
      if (levels > 1) {
        std::vector<float> table(rbar->rbar.begin(), rbar->rbar.end());
        table.resize(64, 1.0f);
        glProgramUniform1fv(p.id(), p.uniformLocation("Rbar"), 64, table.data());
        p.set("RbarCount", static_cast<int>(std::min<size_t>(64, rbar->rbar.size())));
        p.set("RbarTMin", static_cast<float>(rbar->tMin));
        p.set("RbarTMax", static_cast<float>(rbar->tMax));
      }
      p.set("Adaptive", adaptive);
      p.set("IrrLevels", irrLevels);
      p.set("Z0", static_cast<float>(shah ? 0.0 : params.getFloat("z0") * radius));
      p.set("Alpha", static_cast<float>(shah ? 15.0 : params.getFloat("alpha")));
      const std::string terms = shah ? std::string("both") : params.getEnum("selection_terms");
      p.set("UseDiscontinuity", terms != "orientation");
      p.set("UseOrientation", terms != "discontinuity");
      p.set("Rw", static_cast<float>(2.0 * radius));
      glBindVertexArray(emptyVao.id());
      for (auto& st : lights) {
        st.map->bind(p, 1);  // units 1, 2, 3
        p.set("MapSize", st.map->size());
        if (!adaptive) {
          glDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, st.map->size() * st.map->size());
          continue;
        }
        glBindTextureUnit(4, st.hierA.id());
        glBindTextureUnit(5, st.hierB.id());
        glBindTextureUnit(6, st.hierC.id());
        int w = st.map->size();
        for (int j = 0; j < irrLevels; ++j) {
          if (j > 0) w = (w + 1) / 2;
          p.set("IrrLevel", j);
          glDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, w * w);
        }
      }
      glBindVertexArray(0);
      glDisable(GL_BLEND);
      glBindFramebuffer(GL_FRAMEBUFFER, 0);
      gpu::checkGlError("splatting pass");
    }
    if (levels > 1) {
      auto t = timer->scope("accumulation");
      glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
      const gpu::ShaderProgram& p = *upsampleProgram;
      bindProfiles();
      gpu::bindStorage(kTriangles, triangleBuffer);
      gpu::bindStorage(kMeshFloats, gpuMesh->vertexBuffer());
      gpu::bindStorage(kVertexRp, vertexRpBuffer);
      p.set("SpFloatsPerVertex", gpuMesh->floatsPerVertex());
      p.set("CameraPosition", camPos);
      p.set("CameraForward", camFwd);
      p.set("Rw", static_cast<float>(2.0 * radius));
      p.set("LambdaZ", static_cast<float>(params.getFloat("lambda_z")));
      p.set("LambdaM", static_cast<float>(params.getFloat("lambda_m")));
      for (int k = levels - 2; k >= 0; --k) {
        const Level& c = levelTargets[size_t(k)];
        const int fw = k == 0 ? width : levelTargets[size_t(k - 1)].w;
        const int fh = k == 0 ? height : levelTargets[size_t(k - 1)].h;
        glBindTextureUnit(0, k == 0 ? gbuffer.position().id() : levelTargets[size_t(k - 1)].position.id());
        glBindTextureUnit(1, c.position.id());
        glBindTextureUnit(2, c.accum.id());
        glBindImageTexture(0, k == 0 ? accum.id() : levelTargets[size_t(k - 1)].accum.id(), 0, GL_FALSE, 0,
                           GL_READ_WRITE, GL_RGBA32F);
        gpu::dispatch(p, {(unsigned(fw) + 7u) / 8u, (unsigned(fh) + 7u) / 8u, 1u});
        glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
      }
    }
    {
      auto t = timer->scope("radiance");
      glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
      const gpu::ShaderProgram& p = *radianceProgram;
      gpu::bindStorage(kRadianceOut, radianceOut);
      gpu::bindStorage(kExitanceOut, exitanceOut);
      techniques::setExitRadianceUniforms(p, gbuffer, s, params, width, height);
      glBindTextureUnit(2, accum.id());
      gpu::dispatch(p, {(unsigned(width) + 7u) / 8u, (unsigned(height) + 7u) / 8u, 1u});
      glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    }
    specular.add(gbuffer, *scene, params, radianceOut, &*timer);
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
                     : "multiresolution splatting of adaptively selected light-view irradiance samples "
                       "(Chen, Peers, Zhang & Tong 2012)";
}

const std::vector<techniques::ParameterInfo>& SplattingTechnique::parameters() const {
  return impl_->params.infos();
}

void SplattingTechnique::setParameter(std::string_view name, const techniques::ParameterValue& value) {
  const techniques::ParameterValue checked = techniques::checkedValue(impl_->params.info(name), value);
  if (!impl_->params.set(name, checked)) return;
  if (name == "irradiance_size" && impl_->scene) impl_->prepareLights(*impl_->scene);
  if ((name == "profile_storage" || name == "profile_texels") && impl_->scene) {
    impl_->buildProfiles(*impl_->scene);
    impl_->mapsDirty = true;  // the irradiance hierarchy holds R_P
  }
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

bool SplattingTechnique::setCamera(const reference::Camera& camera) {
  if (!impl_->scene) return false;
  camera.validate();
  impl_->scene->camera = camera;
  return true;
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
