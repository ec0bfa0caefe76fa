// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/techniques/tsis/tsis_technique.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <numbers>
#include <optional>

#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "translucent/bssrdf/bssrdf_file.h"
#include "translucent/bssrdf/exit_radiance.h"
#include "translucent/geometry/atlas.h"
#include "translucent/gpu/bssrdf_kernels.h"
#include "translucent/gpu/compute.h"
#include "translucent/gpu/pass_timer.h"
#include "translucent/techniques/common/gl_resources.h"
#include "translucent/techniques/common/specular.h"
#include "translucent/techniques/common/light_shadows.h"
#include "translucent/techniques/common/light_view_map.h"
#include "translucent/techniques/common/profile_kernel.h"
#include "translucent/techniques/common/surface_irradiance.h"
#include "translucent/techniques/tsis/hybrid_split.h"

namespace translucent::tsis {
namespace {

using techniques::GBuffer;
using techniques::GpuMesh;
using techniques::ParameterInfo;
using techniques::ShadowMap;

// SSBO bindings: 2, 3, 5, 7, 8 as the point cloud's shaders (the shared irradiance pass binds
// 2, 3, 4; kernel_table.glsl 5); 9.. the tsis buffers.
enum Binding : GLuint {
  kPoints = 2,
  kIrradiance = 3,
  kProfile = 5,
  kRadianceOut = 7,
  kExitanceOut = 8,
  kLevels = 9,
  kTexelPoint = 10,
  kSamples = 11,
  kAccum = 12,
  kPattern = 13,
  kLocalProfile = 14,
};

// Texture units of the radiance pass: 0, 1 the G-buffer, 2..4 the light-view map.
constexpr unsigned kLightViewUnit = 2;  // map m on units 2 + 3m .. 4 + 3m
constexpr int kLocalLights = 4;          // LVM_MAPS of shaders/tsis/radiance.comp

constexpr int kMaxLevels = 13;  // log2(4096) + 1: LevelOffset[14] in sample.comp

std::vector<ParameterInfo> parameterInfos() {
  std::vector<ParameterInfo> infos{
      ParameterInfo::integer("samples", 1024, 49, 14400,
                             "N: texture-space samples per frame, shared by every pixel (Eq. 3.5)")
          // Error falls as 1/√N per frame: each step quadruples N.
          .withSweep({64, 256, 1024, 4096, 14400}),
      ParameterInfo::enumeration("sequence", "stratified", {"stratified", "random"},
                                 "u of the inverse CDF: stratified (i + ½)/N, rotated every frame, or "
                                 "independent uniform (plain Monte Carlo: error exactly as 1/√N)"),
      // 1024 by default: at 512² 120 of the glmark2 bunny's 69,666 triangles own no texel (the
      // technique refuses that: their irradiance would be lost); at 1024² every one does.
      ParameterInfo::integer("atlas_size", 1024, 16, 4096,
                             "texels per side of the surface atlas the irradiance is rendered into",
                             "texels"),
      ParameterInfo::enumeration("atlas_method", "lscm", {"lscm", "authalic", "triangles"},
                                 "parameterisation of the atlas (geometry/atlas.h)"),
      ParameterInfo::enumeration("mode", "global", {"global", "hybrid"},
                                 "global: texture-space importance sampling of the whole Rd (Chang 2007, "
                                 "§3.1); hybrid (Chang 2007, §3.3): Rd W_g by TSIS plus Rd W_l by the Local "
                                 "Translucent Shadow Map of each directional or point light (1 to 4)"),
      ParameterInfo::enumeration("term", "full", {"full", "local", "global"},
                                 "which part of B the image shows: full B = B_l + B_g, or the "
                                 "local (Rd W_l) or global (Rd W_g) term alone (Chang 2007, Fig. 3.6); in "
                                 "global mode TSIS integrates that part"),
      ParameterInfo::floating("split_k", 1.5, 0.01, 100.0,
                              "K of the split's weighting W_l (Chang 2007, §3.3.1), per mm of the medium",
                              "1/mm"),
      ParameterInfo::floating("split_bound", 0.1, 1e-6, 100.0,
                              "R_p is the largest r with 2πr Rd(r) above this bound (Chang 2007, "
                              "Fig. 3.5), per mm", "1/mm", true),
      ParameterInfo::integer("circles", 20, 1, 64,
                             "L: circles of the local pattern (L×C + 1 samples; Chang 2007, Fig. 3.9)"),
      ParameterInfo::integer("circle_samples", 20, 1, 64,
                             "C: samples on each circle of the local pattern"),
      ParameterInfo::integer("ltsm_map_size", 1024, 64, 4096,
                             "resolution of the hybrid's light-view irradiance map", "texels"),
      ParameterInfo::boolean("accumulate", true,
                             "average the frames (rotated samples) into a converging image; false: "
                             "every frame is the real-time image of N samples"),
      ParameterInfo::integer("accumulate_samples", 65536, 49, 16777216,
                             "samples per pixel of a converged image: ⌈accumulate_samples / N⌉ "
                             "accumulated frames (a batch render renders them all at once)"),
      techniques::tableSizeParameter(),
      techniques::radianceConventionParameter(),
  };
  for (ParameterInfo& p : techniques::specularParameters()) infos.push_back(std::move(p));
  // The shared irradiance pass's shadow and environment settings (surface_irradiance.h).
  for (ParameterInfo& p : techniques::lightingParameters()) infos.push_back(std::move(p));
  return infos;
}


// Rotation of frame k: the golden-ratio additive recurrence, equidistributed in [0, 1), so the
// frames' stratified sample sets tile the u interval ever more finely as they accumulate.
float rotation(uint64_t frame) {
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  return static_cast<float>(std::fmod(double(frame) * g, 1.0));
}

}  // namespace

// ---------------------------------------------------------------------------------------------

// The mesh, its bounding sphere and GPU copy: techniques::ClosedMeshState.
struct TsisTechnique::Impl : techniques::ClosedMeshState {
  techniques::ParameterSet params{parameterInfos()};

  std::optional<scene::Scene> scene;

  // Atlas texels.
  bool atlasDirty = true;
  // A deformed mesh (mesh.deform) keeps the rest pose's atlas and coverage; at a new time only
  // the texels' surface points, normals and A_S/A_T (Eq. 3.3) are recomputed on the deformed mesh.
  bool motionDirty = false;
  std::optional<geometry::Atlas> atlas;
  geometry::AtlasCoverage coverage;
  uint32_t atlasSize = 0;
  int levelCount = 0;  // log2(atlasSize)
  std::array<uint32_t, kMaxLevels + 1> levelOffset{};
  std::vector<TexelPoint> texels;
  gpu::Buffer points, levels, texelPoint, samples, accum;
  size_t sampleCapacity = 0;

  // Kernel.
  std::string kernelKey;
  std::array<bssrdf::ProfileTable, 3> tables;
  gpu::Buffer profile;  // R, or R W_g / R W_l (term, hybrid)
  // Hybrid (seed 3.3): the split, R W_l for the local term, the LTSM pattern.
  HybridSplit split;
  gpu::Buffer localProfile, pattern;
  uint32_t patternCount = 0;
  // One light-view map per light of the hybrid's local term (at most kLocalLights).
  std::vector<std::unique_ptr<techniques::LightViewMap>> lightViews;
  std::optional<gpu::ShaderProgram> lightViewProgram;

  std::optional<gpu::ShaderProgram> gbufferProgram, importanceProgram, reduceProgram, sampleProgram,
      radianceProgram;

  // Stage 1's lights: the shared irradiance pass (techniques/common/surface_irradiance.h).
  techniques::SurfaceIrradiance lighting;
  bool lightingDirty = true;

  GBuffer gbuffer;
  gpu::Buffer radianceOut, exitanceOut;
  size_t outPixels = 0;
  bool irradianceFinal = true;  // false while an occluded environment still adds directions
  uint64_t frameIndex = 0;  // frames accumulated so far (and the next frame's rotation index)
  bool accumulationDirty = true;
  std::optional<gpu::PassTimer> timer;
  techniques::SpecularPass specular;
  std::vector<std::string> notes;

  void buildPrograms() {
    if (gbufferProgram) return;
    gbufferProgram.emplace(
        gpu::ShaderProgram::graphics("pointcloud/gbuffer.vert", "pointcloud/gbuffer.frag"));
    importanceProgram.emplace(gpu::ShaderProgram::compute("tsis/importance.comp"));
    reduceProgram.emplace(gpu::ShaderProgram::compute("tsis/reduce.comp"));
    sampleProgram.emplace(gpu::ShaderProgram::compute("tsis/sample.comp"));
    radianceProgram.emplace(gpu::ShaderProgram::compute("tsis/radiance.comp"));
    gpu::checkGlError("building the tsis programs");
  }

  void loadMesh(const scene::Scene& s) {
    // The rest mesh once, deformed on the GPU for the G-buffer and shadow maps; `mesh` is the
    // CPU-deformed copy at the scene's time.
    const std::string before = deformState;
    if (loadClosedMesh(s, /*gpuDeform=*/true)) atlasDirty = true;
    else if (deformState != before) motionDirty = true;
  }

  void prepareLights(const scene::Scene& s) {
    lighting.prepareLights(s, center, radius, params.getInt("shadow_map_size"), "tsis");
    lightingDirty = true;
  }

  // The atlas's covered texels, their surface points and areas, and the sum mipmap's storage.
  void buildAtlas() {
    if (!atlasDirty && !motionDirty) return;
    if (atlasDirty) {
      geometry::AtlasOptions opt;
      opt.size = static_cast<uint32_t>(params.getInt("atlas_size"));
      opt.method = geometry::parseAtlasMethod(params.getEnum("atlas_method"));
      if (!std::has_single_bit(opt.size))
        throw ParameterError(fmt::format("tsis: atlas_size {}: expected a power of two (the sum mipmap "
                                         "halves it down to 1×1)", opt.size));
      geometry::CachedAtlas cached = geometry::loadOrBuildAtlas(rest, opt);
      notes.push_back(fmt::format("atlas: {}² {} {} {}", opt.size, geometry::toString(cached.atlas.method),
                                  cached.fromCache ? "read from" : "built, cached in", cached.file.string()));
      if (!cached.note.empty()) notes.push_back("atlas cache: " + cached.note);
      atlas = std::move(cached.atlas);
      coverage = geometry::rasterizeCoverage(*atlas);
      if (coverage.uncovered > 0)
        throw ParameterError(fmt::format("tsis: atlas_size {}: {} triangles own no texel (their "
                                         "irradiance would be lost): use a larger atlas",
                                         opt.size, coverage.uncovered));
      atlasSize = opt.size;
    }
    motionDirty = false;
    // The surface the texels lie on: the rest mesh, or the deformed one with the rest pose's kind
    // of normals (texelSurfacePoint takes face normals where the mesh has none) and its own
    // triangle areas A_S.
    const bool deformed = mesh.positions != rest.positions;
    geometry::TriangleMesh deformedSurface;
    if (deformed) {
      deformedSurface = mesh;
      if (rest.normals.empty()) deformedSurface.normals.clear();
    }
    const geometry::TriangleMesh& surface = deformed ? deformedSurface : rest;
    auto surfaceArea = [&](uint32_t t) {
      if (!deformed) return atlas->surfaceArea[t];
      const glm::uvec3 tri = surface.triangles[t];
      return 0.5 * glm::length(glm::cross(surface.positions[tri.y] - surface.positions[tri.x],
                                          surface.positions[tri.z] - surface.positions[tri.x]));
    };
    levelCount = std::countr_zero(atlasSize);
    texels.clear();
    texels.reserve(coverage.ownedTexels);
    std::vector<uint32_t> texelToPoint(size_t(atlasSize) * atlasSize, ~0u);
    for (uint32_t y = 0; y < atlasSize; ++y)
      for (uint32_t x = 0; x < atlasSize; ++x) {
        const auto sp = geometry::texelSurfacePoint(surface, *atlas, coverage, x, y);
        if (!sp) continue;
        TexelPoint t;
        t.position = glm::vec3(sp->position);
        t.normal = glm::vec3(sp->normal);
        // Eq. 3.3's A_S/A_T per texel, A_T counted in the texels the triangle owns.
        t.area = static_cast<float>(surfaceArea(sp->triangle) /
                                    double(coverage.texels[sp->triangle]));
        t.texel = y * atlasSize + x;
        texelToPoint[t.texel] = static_cast<uint32_t>(texels.size());
        texels.push_back(t);
      }
    // PcPoint records (pointcloud/common.glsl) for the shared irradiance pass; normal.w carries
    // the texel index (exact in a float: < 4096² = 2^24).
    std::vector<glm::vec4> records(texels.size() * 2);
    for (size_t i = 0; i < texels.size(); ++i) {
      records[2 * i] = glm::vec4(texels[i].position, texels[i].area);
      records[2 * i + 1] = glm::vec4(texels[i].normal, float(texels[i].texel));
    }
    points = gpu::makeStorageBuffer(std::span<const glm::vec4>(records));
    texelPoint = gpu::makeStorageBuffer(std::span<const uint32_t>(texelToPoint));
    uint32_t offset = 0;
    for (int k = 0; k <= levelCount; ++k) {
      levelOffset[size_t(k)] = offset;
      const uint32_t side = atlasSize >> k;
      offset += side * side;
    }
    // Zeros: uncovered texels keep importance 0 (importance.comp writes covered ones only).
    const std::vector<float> zeros(offset, 0.0f);
    levels = gpu::makeStorageBuffer(std::span<const float>(zeros));
    notes.push_back(fmt::format("atlas: {} covered texels ({} charts, {} triangles)", texels.size(),
                                atlas->chartCount, atlas->triangleCount()));
    atlasDirty = false;
    accumulationDirty = true;
  }

  void buildKernel() {
    const scene::Scene& s = *scene;
    const std::string key = fmt::format(
        "{}|{}|{}|{}|{}|{}|{}|{}", scene::mediumKey(s), params.getInt("table_size"), params.getEnum("mode"),
        params.getEnum("term"), params.getFloat("split_k"), params.getFloat("split_bound"),
        params.getInt("circles"), params.getInt("circle_samples"));
    if (key == kernelKey) return;
    kernelKey.clear();
    s.medium.validate();
    std::optional<gpu::BssrdfEvaluator> evaluator;
    if (bssrdf::hasBssrdfExtension(s.model)) {
      evaluator.emplace(s.model);
      evaluator->setMedium(s.medium);
    }
    techniques::RgbProfileTable t = techniques::tabulateRgbProfile(
        s, static_cast<size_t>(params.getInt("table_size")), evaluator ? &*evaluator : nullptr);
    tables = std::move(t.tables);
    // The split: K and the bound per mm, one scene unit = scale mm (hybrid_split.h).
    split = makeHybridSplit(tables, params.getFloat("split_k"), params.getFloat("split_bound"),
                            s.medium.scale);
    const bool hybrid = params.getEnum("mode") == "hybrid";
    const std::string& term = params.getEnum("term");
    // TSIS's table: R W_g in hybrid mode (the local part is the LTSM's), else the part shown.
    if (hybrid || term == "global")
      profile = gpu::makeStorageBuffer(std::span<const glm::vec4>(weightedProfile(tables, split, false)));
    else if (term == "local")
      profile = gpu::makeStorageBuffer(std::span<const glm::vec4>(weightedProfile(tables, split, true)));
    else
      profile = gpu::makeStorageBuffer(std::span<const glm::vec4>(t.gpu));
    localProfile = gpu::makeStorageBuffer(std::span<const glm::vec4>(weightedProfile(tables, split, true)));
    const std::vector<glm::vec4> pat =
        localPattern(tables, split, params.getInt("circles"), params.getInt("circle_samples"));
    pattern = gpu::makeStorageBuffer(std::span<const glm::vec4>(pat));
    patternCount = static_cast<uint32_t>(pat.size() / 2);
    if (hybrid)
      notes.push_back(fmt::format("hybrid: R_p = {:.4g}, {:.4g}, {:.4g} scene units, K = {:.4g} per unit, "
                                  "{} + {} samples", split.rp[0], split.rp[1], split.rp[2], split.k,
                                  params.getInt("samples"), patternCount));
    kernelKey = key;
    accumulationDirty = true;
  }

  // Hybrid: every light must have a light-view map (Chang 2007 §3.3.2's LTSM is rendered from
  // it): 1 to kLocalLights directional or point lights, each with a map of its own.
  void checkHybridLights() const {
    if (params.getEnum("mode") != "hybrid" || params.getEnum("term") == "global") return;
    const auto& lights = scene->lights;
    if (lights.empty() || lights.size() > size_t(kLocalLights))
      throw ParameterError(fmt::format("tsis: mode 'hybrid' takes 1 to {} lights (its local term is a "
                                       "light-view map per directional or point light): the scene has {}",
                                       kLocalLights, lights.size()));
    for (size_t i = 0; i < lights.size(); ++i) {
      const auto& e = lights[i].emitter;
      if (!std::holds_alternative<reference::DirectionalLight>(e) &&
          !std::holds_alternative<reference::PointLight>(e))
        throw ParameterError(fmt::format(
            "lights[{}]: mode 'hybrid' of the tsis technique needs a directional or point light for "
            "its local term (a light-view map); use mode 'global' for this light", i));
    }
  }

  void renderLightViews() {
    const int size = params.getInt("ltsm_map_size");
    const auto& lights = scene->lights;
    lightViews.resize(lights.size());
    if (!lightViewProgram) lightViewProgram.emplace(techniques::LightViewMap::program());
    const double eta = scene->medium.eta;
    for (size_t i = 0; i < lights.size(); ++i) {
      auto& map = lightViews[i];
      if (!map || map->size() != size) map = std::make_unique<techniques::LightViewMap>(size);
      const scene::Light& light = lights[i];
      const glm::vec3 color(float(light.color[0]), float(light.color[1]), float(light.color[2]));
      if (const auto* d = std::get_if<reference::DirectionalLight>(&light.emitter))
        map->renderDirectional(*gpuMesh, *lightViewProgram, d->direction, color * float(d->irradiance),
                               eta, center, radius);
      else if (const auto* pl = std::get_if<reference::PointLight>(&light.emitter))
        map->renderPoint(*gpuMesh, *lightViewProgram, pl->position, color * float(pl->intensity), eta,
                         center, radius);
    }
  }

  // Stages 1 and 2 and the radiance of one frame into the output (and accumulation) buffers.
  void renderOnce(int width, int height, int sampleCount, bool accumulate, bool irradiancePass,
                  bool converge) {
    const scene::Scene& s = *scene;
    if (irradiancePass) {
      // Stage 1: E of every texel point (every light type, shadowed), then s_t = ΣE'_c a_t.
      // Nothing the texels' lighting depends on changed (a camera move, a later frame): the
      // shadow maps and the direct irradiance are kept.
      const bool reuse = !lightingDirty;
      if (lightingDirty) lighting.restartEnvironment();
      lightingDirty = false;
      irradianceFinal = lighting.update(*gpuMesh, points, texels.size(), static_cast<float>(s.medium.eta),
                                        techniques::shadowLookup(params),
                                        techniques::environmentBudget(params, converge), &*timer,
                                        reuse);
    }
    gpu::bindStorage(kPoints, points);
    gpu::bindStorage(kIrradiance, lighting.irradiance());
    gpu::bindStorage(kLevels, levels);
    gpu::bindStorage(kTexelPoint, texelPoint);
    gpu::bindStorage(kSamples, samples);
    gpu::bindStorage(kProfile, profile);
    const bool hybrid = params.getEnum("mode") == "hybrid";
    const std::string& term = params.getEnum("term");
    const bool local = hybrid && term != "global";
    if (local && irradiancePass) {
      auto t = timer->scope("light-view map");
      renderLightViews();
    }
    if (irradiancePass) {
      auto t = timer->scope("importance");
      importanceProgram->set("PointCount", static_cast<unsigned>(texels.size()));
      gpu::dispatch1D(*importanceProgram, texels.size());
    }
    if (irradiancePass) {
      auto t = timer->scope("sum mipmap");
      const gpu::ShaderProgram& rp = *reduceProgram;
      for (int k = 1; k <= levelCount; ++k) {
        const uint32_t side = atlasSize >> k;
        rp.set("ChildOffset", levelOffset[size_t(k - 1)]);
        rp.set("ParentOffset", levelOffset[size_t(k)]);
        rp.set("ParentSize", side);
        gpu::dispatch(rp, {(side + 7u) / 8u, (side + 7u) / 8u, 1u});
      }
    }
    {
      auto t = timer->scope("sampling");
      const gpu::ShaderProgram& sp = *sampleProgram;
      sp.set("SampleCount", static_cast<unsigned>(sampleCount));
      sp.set("Levels", levelCount);
      glProgramUniform1uiv(sp.id(), sp.uniformLocation("LevelOffset"), levelCount + 1, levelOffset.data());
      sp.set("Rotation", rotation(frameIndex));
      sp.set("Random", params.getEnum("sequence") == "random");
      sp.set("Frame", static_cast<unsigned>(frameIndex));
      gpu::dispatch1D(sp, size_t(sampleCount));
    }
    {
      auto t = timer->scope("radiance");
      const gpu::ShaderProgram& p = *radianceProgram;
      gpu::bindStorage(kRadianceOut, radianceOut);
      gpu::bindStorage(kExitanceOut, exitanceOut);
      gpu::bindStorage(kAccum, accum);
      techniques::setExitRadianceUniforms(p, gbuffer, s, params, width, height);
      p.set("SampleCount", static_cast<unsigned>(sampleCount));
      p.set("ProfileRMax", static_cast<float>(tables[0].r_max));
      p.set("ProfileCount", static_cast<unsigned>(tables[0].size()));
      p.set("Accumulate", accumulate);
      p.set("FrameIndex", static_cast<unsigned>(accumulate ? frameIndex : 0));
      p.set("Global", !hybrid || term != "local");
      p.set("Local", local);
      gpu::bindStorage(kPattern, pattern);
      gpu::bindStorage(kLocalProfile, localProfile);
      p.set("PatternCount", patternCount);
      p.set("PatternAngle", static_cast<float>(2.0 * std::numbers::pi * double(rotation(frameIndex))));
      p.set("LocalMaps", local ? int(lightViews.size()) : 0);
      if (local)
        for (size_t m = 0; m < lightViews.size(); ++m)
          lightViews[m]->bind(p, kLightViewUnit + 3u * unsigned(m), int(m));
      gpu::dispatch(p, {(unsigned(width) + 7u) / 8u, (unsigned(height) + 7u) / 8u, 1u});
    }
    ++frameIndex;
  }

  // Chang 2007, Figs. 3.4 and 3.5: the hybrid's split of the profile, 2πr R_d(r) and its local
  // and global parts 2πr R_d W_l, 2πr R_d W_g (hybrid_split.h), for the channel that reaches
  // farthest (the largest R_p), with R_p marked by the crossing of the two weights.
  techniques::FramePlot splitPlot() const {
    size_t c = 0;
    for (size_t k = 1; k < 3; ++k)
      if (split.rp[k] > split.rp[c]) c = k;
    const bssrdf::ProfileTable& t = tables[c];
    techniques::FramePlot plot;
    plot.title = fmt::format("Hybrid split of the profile ({} channel, R_p = {:.3g}, K = {:.3g} per "
                             "unit)", c == 0 ? "red" : c == 1 ? "green" : "blue", split.rp[c], split.k);
    plot.x_label = "r [scene units]";
    plot.y_label = "2πr R_d(r) [1/unit]";
    techniques::FramePlot::Series whole{"2πr R_d", {}, {}}, local{"2πr R_d W_l (local)", {}, {}},
        global{"2πr R_d W_g (global)", {}, {}};
    for (size_t i = 1; i < t.size(); ++i) {
      const double r = t.radius(i), f = 2.0 * std::numbers::pi * r * double(t.R[i]);
      const double wl = localWeight(r, split.rp[c], split.k);
      for (auto* sr : {&whole, &local, &global}) sr->x.push_back(r);
      whole.y.push_back(f);
      local.y.push_back(f * wl);
      global.y.push_back(f * (1.0 - wl));
    }
    plot.series = {std::move(whole), std::move(local), std::move(global)};
    return plot;
  }

  techniques::Frame render(const techniques::FrameRequest& request) {
    if (!scene) throw ParameterError("tsis: render() before prepare(): expected a scene");
    const scene::Scene& s = *scene;
    const auto [width, height] = techniques::frameSize(request, s.camera);
    buildPrograms();
    checkHybridLights();
    buildAtlas();
    buildKernel();
    if (!timer) timer.emplace();
    techniques::Frame frame;
    frame.notes = std::move(notes);
    notes.clear();

    const int sampleCount = params.getInt("samples");
    if (size_t(sampleCount) != sampleCapacity) {
      samples = gpu::makeStorageBuffer(size_t(sampleCount) * 2 * sizeof(glm::vec4));
      sampleCapacity = size_t(sampleCount);
    }
    const size_t pixels = size_t(width) * size_t(height);
    if (pixels != outPixels || gbuffer.width() != width || gbuffer.height() != height) {
      radianceOut = gpu::makeStorageBuffer(pixels * sizeof(glm::vec4));
      exitanceOut = gpu::makeStorageBuffer(pixels * sizeof(glm::vec4));
      accum = gpu::makeStorageBuffer(pixels * sizeof(glm::vec4));
      outPixels = pixels;
      accumulationDirty = true;
    }
    {
      auto t = timer->scope("g-buffer");
      gbuffer.resize(width, height);
      const glm::mat4 vp = techniques::cameraViewProjection(s.camera, s.clip_near, s.clip_far, center,
                                                            radius, width, height);
      gbuffer.render(*gpuMesh, *gbufferProgram, vp);
    }
    const bool accumulate = params.getBool("accumulate");
    // A parameter, the scene or the image size changed: the accumulated frames are stale. (Without
    // accumulation frameIndex only advances the rotation.)
    if (accumulate && accumulationDirty) frameIndex = 0;
    accumulationDirty = false;
    const auto perFrame = static_cast<uint64_t>(sampleCount);
    const uint64_t target =
        (static_cast<uint64_t>(params.getInt("accumulate_samples")) + perFrame - 1) / perFrame;
    uint64_t count = 1;
    if (accumulate && request.converge && frameIndex < target) count = target - frameIndex;
    // The lights and the scene stay the same within one call: Stage 1 and the sum mipmap once,
    // then only new samples and their sums.
    for (uint64_t f = 0; f < count; ++f)
      renderOnce(width, height, sampleCount, accumulate, f == 0, request.converge);
    frame.converged = (!accumulate || frameIndex >= target) && irradianceFinal;
    specular.add(gbuffer, *scene, params, radianceOut, &*timer);
    gpu::checkGlError("tsis frame");

    frame.width = width;
    frame.height = height;
    if (request.readback) techniques::readRadianceAndExitance(frame, radianceOut, exitanceOut, pixels);
    if (request.views && params.getEnum("mode") == "hybrid") frame.plots["hybrid_split"] = splitPlot();
    if (request.views) frame.views["atlas"] = atlasView();
    techniques::addPasses(frame, *timer);
    return frame;
  }

  // Seed Fig. 3.1: the atlas's importance s_t = ΣE'_c a_t (the sum mipmap's base), white on black
  // scaled to its maximum with a square root (the irradiance spans decades), uncovered texels dark
  // blue, and the last frame's N samples in red over it; at most 1024² (blocks of texels summed).
  techniques::FrameView atlasView() const {
    const uint32_t side = atlasSize;
    const uint32_t factor = std::max<uint32_t>(1, side / 1024);
    const auto w = int(side / factor);
    const std::vector<float> s = gpu::download<float>(levels, size_t(side) * side);
    std::vector<double> v(size_t(w) * size_t(w), 0.0);
    std::vector<uint8_t> covered(v.size(), 0);
    for (const TexelPoint& t : texels) covered[size_t((t.texel / side) / factor) * size_t(w) + (t.texel % side) / factor] = 1;
    double peak = 0.0;
    for (uint32_t y = 0; y < side; ++y)
      for (uint32_t x = 0; x < side; ++x) {
        double& b = v[size_t(y / factor) * size_t(w) + x / factor];
        b += double(s[size_t(y) * side + x]);
        peak = std::max(peak, b);
      }
    techniques::FrameView out;
    out.width = out.height = w;
    out.rgb.assign(v.size() * 3, 0.0f);
    // Atlas row y = 0 is v = 0, drawn at the bottom.
    auto at = [&](size_t i) { return ((size_t(w) - 1 - i / size_t(w)) * size_t(w) + i % size_t(w)) * 3; };
    for (size_t i = 0; i < v.size(); ++i) {
      const size_t o = at(i);
      if (!covered[i]) {
        out.rgb[o + 2] = 0.12f;
        continue;
      }
      const auto g = static_cast<float>(peak > 0.0 ? std::sqrt(v[i] / peak) : 0.0);
      out.rgb[o] = out.rgb[o + 1] = out.rgb[o + 2] = 0.85f * g;
    }
    const auto samp = gpu::download<glm::vec4>(samples, 2 * sampleCapacity);
    for (size_t i = 0; i < sampleCapacity; ++i) {
      const auto t = static_cast<uint32_t>(samp[2 * i].w);
      if (t >= side * side) continue;
      // A cross a few pixels wide, so that the samples show at any atlas size.
      const int cx = int((t % side) / factor), cy = int((t / side) / factor), arm = std::max(1, w / 256);
      for (int d = -arm; d <= arm; ++d)
        for (const auto& [x, y] : {std::pair{cx + d, cy}, std::pair{cx, cy + d}}) {
          if (x < 0 || y < 0 || x >= w || y >= w) continue;
          const size_t o = at(size_t(y) * size_t(w) + size_t(x));
          out.rgb[o] = 1.0f;
          out.rgb[o + 1] = out.rgb[o + 2] = 0.1f;
        }
    }
    out.description = fmt::format("irradiance atlas {}² (importance E' a_t, square root, scaled to its "
                                  "maximum; blue: no surface) with the frame's {} samples in red",
                                  side, sampleCapacity);
    return out;
  }
};

// ---------------------------------------------------------------------------------------------

TsisTechnique::TsisTechnique() : impl_(std::make_unique<Impl>()) {}
TsisTechnique::~TsisTechnique() = default;

std::string_view TsisTechnique::description() const {
  return "texture-space importance sampling of the irradiance over a surface atlas (Chang 2007, chapter 3)";
}

const std::vector<techniques::ParameterInfo>& TsisTechnique::parameters() const {
  return impl_->params.infos();
}

void TsisTechnique::setParameter(std::string_view name, const techniques::ParameterValue& value) {
  const techniques::ParameterValue checked = techniques::checkedValue(impl_->params.info(name), value);
  if (!impl_->params.set(name, checked)) return;
  impl_->accumulationDirty = true;
  if (name == "atlas_size" || name == "atlas_method") impl_->atlasDirty = true;
  if (name == "shadow_map_size" && impl_->scene) impl_->prepareLights(*impl_->scene);
  if (name.starts_with("shadow_") || name.starts_with("ibl_")) impl_->lightingDirty = true;
}

techniques::ParameterValue TsisTechnique::parameter(std::string_view name) const {
  return impl_->params.get(name);
}

void TsisTechnique::prepare(const scene::Scene& scene, gpu::Context& gl) {
  gl.makeCurrent();
  scene.camera.validate();
  scene.medium.validate();
  techniques::requireHomogeneousMaterial(scene, "tsis");
  impl_->buildPrograms();
  impl_->scene.reset();  // until this preparation succeeds
  impl_->loadMesh(scene);
  impl_->prepareLights(scene);
  impl_->scene = scene;
  impl_->buildAtlas();
  impl_->buildKernel();
  impl_->accumulationDirty = true;
}

techniques::Frame TsisTechnique::render(const techniques::FrameRequest& request) {
  return impl_->render(request);
}

bool TsisTechnique::setCamera(const reference::Camera& camera) {
  if (!impl_->scene) return false;
  camera.validate();
  impl_->scene->camera = camera;
  impl_->accumulationDirty = true;  // the accumulated image is the old view's
  return true;
}

const geometry::TriangleMesh& TsisTechnique::mesh() const { return impl_->mesh; }
uint32_t TsisTechnique::atlasSize() const { return impl_->atlasSize; }
const std::vector<TexelPoint>& TsisTechnique::texelPoints() const { return impl_->texels; }

std::vector<glm::vec3> TsisTechnique::texelIrradiance() const {
  const auto e = gpu::download<glm::vec4>(impl_->lighting.irradiance(), impl_->texels.size());
  std::vector<glm::vec3> out(e.size());
  for (size_t i = 0; i < e.size(); ++i) out[i] = glm::vec3(e[i]);
  return out;
}

std::vector<float> TsisTechnique::importance() const {
  return gpu::download<float>(impl_->levels, size_t(impl_->atlasSize) * impl_->atlasSize);
}

float TsisTechnique::totalImportance() const {
  return gpu::download<float>(impl_->levels, 1, impl_->levelOffset[size_t(impl_->levelCount)])[0];
}

std::vector<uint32_t> TsisTechnique::sampleTexels() const {
  const auto s = gpu::download<glm::vec4>(impl_->samples, 2 * impl_->sampleCapacity);
  std::vector<uint32_t> out(impl_->sampleCapacity);
  for (size_t i = 0; i < out.size(); ++i) out[i] = static_cast<uint32_t>(s[2 * i].w);
  return out;
}

std::vector<glm::vec4> TsisTechnique::gbufferPositions() const {
  const int w = impl_->gbuffer.width(), h = impl_->gbuffer.height();
  std::vector<glm::vec4> rows(size_t(w) * size_t(h));
  glGetTextureImage(impl_->gbuffer.position().id(), 0, GL_RGBA, GL_FLOAT,
                    static_cast<GLsizei>(rows.size() * sizeof(glm::vec4)), rows.data());
  gpu::checkGlError("reading the G-buffer");
  std::vector<glm::vec4> out(rows.size());
  for (int y = 0; y < h; ++y)
    std::copy_n(rows.begin() + ptrdiff_t(y) * w, w, out.begin() + ptrdiff_t(h - 1 - y) * w);
  return out;
}

const std::array<bssrdf::ProfileTable, 3>& TsisTechnique::profileTables() const { return impl_->tables; }
int TsisTechnique::accumulatedFrames() const { return static_cast<int>(impl_->frameIndex); }

std::unique_ptr<techniques::Technique> makeTsisTechnique() { return std::make_unique<TsisTechnique>(); }

}  // namespace translucent::tsis
