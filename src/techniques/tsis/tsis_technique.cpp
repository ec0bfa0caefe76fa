#include "techniques/tsis/tsis_technique.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <numbers>
#include <optional>

#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "bssrdf/bssrdf_file.h"
#include "bssrdf/exit_radiance.h"
#include "geometry/atlas.h"
#include "gpu/bssrdf_kernels.h"
#include "gpu/compute.h"
#include "gpu/pass_timer.h"
#include "techniques/common/gl_resources.h"
#include "techniques/common/light_shadows.h"
#include "techniques/common/profile_kernel.h"
#include "techniques/common/surface_irradiance.h"
#include "techniques/pointcloud/pointcloud_technique.h"  // kDefaultRadianceConvention

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
};

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
                                 "global: importance sampling of the whole Rd (seed 3.1); hybrid "
                                 "(seed 3.3): not implemented yet"),
      ParameterInfo::boolean("accumulate", true,
                             "average the frames (rotated samples) into a converging image; false: "
                             "every frame is the real-time image of N samples"),
      ParameterInfo::integer("accumulate_samples", 65536, 49, 16777216,
                             "samples per pixel of a converged image: ⌈accumulate_samples / N⌉ "
                             "accumulated frames (a batch render renders them all at once)"),
      ParameterInfo::integer("table_size", 4096, 64, 65536,
                             "entries of the tabulated profile (uniform in r up to the radius "
                             "holding 99.9% of Rd)"),
      ParameterInfo::enumeration("radiance_convention", pointcloud::kDefaultRadianceConvention,
                                 bssrdf::exitConventionNames(),
                                 "radiance from the exitance B (seed Eq. 2.16): jensen Ft B/π, or "
                                 "normalized Ft B/(π 4Cφ(1/η)); as the point-cloud technique"),
  };
  // The shared irradiance pass's shadow and environment settings (surface_irradiance.h).
  for (ParameterInfo& p : techniques::lightingParameters()) infos.push_back(std::move(p));
  return infos;
}

glm::vec3 toVec3(const glm::dvec3& v) { return glm::vec3(v); }

// Rotation of frame k: the golden-ratio additive recurrence, equidistributed in [0, 1), so the
// frames' stratified sample sets tile the u interval ever more finely as they accumulate.
float rotation(uint64_t frame) {
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  return static_cast<float>(std::fmod(double(frame) * g, 1.0));
}

}  // namespace

// ---------------------------------------------------------------------------------------------

struct TsisTechnique::Impl {
  techniques::ParameterSet params{parameterInfos()};

  std::optional<scene::Scene> scene;
  std::string meshKey;
  geometry::TriangleMesh mesh;
  std::optional<GpuMesh> gpuMesh;
  glm::dvec3 center{0.0};
  double radius = 1.0;

  // Atlas texels.
  bool atlasDirty = true;
  uint32_t atlasSize = 0;
  int levelCount = 0;  // log2(atlasSize)
  std::array<uint32_t, kMaxLevels + 1> levelOffset{};
  std::vector<TexelPoint> texels;
  gpu::Buffer points, levels, texelPoint, samples, accum;
  size_t sampleCapacity = 0;

  // Kernel.
  std::string kernelKey;
  std::array<bssrdf::ProfileTable, 3> tables;
  gpu::Buffer profile;

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
    const std::string key = scene::meshKey(s);
    if (key == meshKey && gpuMesh) return;
    geometry::TriangleMesh m = scene::loadSceneMesh(s);
    // Closed and outward: the shadow maps draw back faces only (gl_resources.h).
    m.requireClosed(fmt::format("mesh file '{}'", s.mesh_file.string()));
    m.orientOutwards();
    mesh = std::move(m);
    const techniques::BoundingSphereOf bs = techniques::boundingSphere(mesh);
    center = bs.center;
    radius = bs.radius;
    gpuMesh.emplace(mesh);
    meshKey = key;
    atlasDirty = true;
  }

  void prepareLights(const scene::Scene& s) {
    lighting.prepareLights(s, center, radius, params.getInt("shadow_map_size"), "tsis");
    lightingDirty = true;
  }

  // The atlas's covered texels, their surface points and areas, and the sum mipmap's storage.
  void buildAtlas() {
    if (!atlasDirty) return;
    geometry::AtlasOptions opt;
    opt.size = static_cast<uint32_t>(params.getInt("atlas_size"));
    opt.method = geometry::parseAtlasMethod(params.getEnum("atlas_method"));
    if (!std::has_single_bit(opt.size))
      throw ParameterError(fmt::format("tsis: atlas_size {}: expected a power of two (the sum mipmap "
                                       "halves it down to 1×1)", opt.size));
    geometry::CachedAtlas cached = geometry::loadOrBuildAtlas(mesh, opt);
    notes.push_back(fmt::format("atlas: {}² {} {} {}", opt.size, geometry::toString(cached.atlas.method),
                                cached.fromCache ? "read from" : "built, cached in", cached.file.string()));
    if (!cached.note.empty()) notes.push_back("atlas cache: " + cached.note);
    const geometry::Atlas& atlas = cached.atlas;
    const geometry::AtlasCoverage coverage = geometry::rasterizeCoverage(atlas);
    if (coverage.uncovered > 0)
      throw ParameterError(fmt::format("tsis: atlas_size {}: {} triangles own no texel (their "
                                       "irradiance would be lost): use a larger atlas",
                                       opt.size, coverage.uncovered));
    atlasSize = opt.size;
    levelCount = std::countr_zero(atlasSize);
    texels.clear();
    texels.reserve(coverage.ownedTexels);
    std::vector<uint32_t> texelToPoint(size_t(atlasSize) * atlasSize, ~0u);
    for (uint32_t y = 0; y < atlasSize; ++y)
      for (uint32_t x = 0; x < atlasSize; ++x) {
        const auto sp = geometry::texelSurfacePoint(mesh, atlas, coverage, x, y);
        if (!sp) continue;
        TexelPoint t;
        t.position = glm::vec3(sp->position);
        t.normal = glm::vec3(sp->normal);
        // Eq. 3.3's A_S/A_T per texel, A_T counted in the texels the triangle owns.
        t.area = static_cast<float>(atlas.surfaceArea[sp->triangle] /
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
                                atlas.chartCount, atlas.triangleCount()));
    atlasDirty = false;
    accumulationDirty = true;
  }

  void buildKernel() {
    const scene::Scene& s = *scene;
    const std::string key = fmt::format("{}|{}|{}|{}|{}|{}|{}", s.model, s.medium.sigma_a, s.medium.sigma_s,
                                        s.medium.g, s.medium.eta, s.medium.scale,
                                        params.getInt("table_size"));
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
    profile = gpu::makeStorageBuffer(std::span<const glm::vec4>(t.gpu));
    kernelKey = key;
    accumulationDirty = true;
  }

  // Stages 1 and 2 and the radiance of one frame into the output (and accumulation) buffers.
  void renderOnce(int width, int height, int sampleCount, bool accumulate, bool irradiancePass,
                  bool converge) {
    const scene::Scene& s = *scene;
    if (irradiancePass) {
      // Stage 1: E of every texel point (every light type, shadowed), then s_t = ΣE'_c a_t.
      if (lightingDirty) lighting.restartEnvironment();
      lightingDirty = false;
      irradianceFinal = lighting.update(*gpuMesh, points, texels.size(), static_cast<float>(s.medium.eta),
                                        techniques::shadowLookup(params),
                                        techniques::environmentBudget(params, converge), &*timer);
    }
    gpu::bindStorage(kPoints, points);
    gpu::bindStorage(kIrradiance, lighting.irradiance());
    gpu::bindStorage(kLevels, levels);
    gpu::bindStorage(kTexelPoint, texelPoint);
    gpu::bindStorage(kSamples, samples);
    gpu::bindStorage(kProfile, profile);
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
      glBindTextureUnit(0, gbuffer.position().id());
      glBindTextureUnit(1, gbuffer.normal().id());
      glProgramUniform2ui(p.id(), p.uniformLocation("Size"), unsigned(width), unsigned(height));
      p.set("SampleCount", static_cast<unsigned>(sampleCount));
      p.set("Eta", static_cast<float>(s.medium.eta));
      p.set("ExitScale", glm::vec3(static_cast<float>(bssrdf::exitConventionScale(
                             bssrdf::parseExitConvention(params.getEnum("radiance_convention")),
                             s.medium.eta))));
      p.set("CameraPosition", toVec3(s.camera.position));
      p.set("CameraForward", toVec3(glm::normalize(s.camera.look_at - s.camera.position)));
      p.set("Orthographic", s.camera.projection == reference::Camera::Projection::Orthographic);
      p.set("ProfileRMax", static_cast<float>(tables[0].r_max));
      p.set("ProfileCount", static_cast<unsigned>(tables[0].size()));
      p.set("Accumulate", accumulate);
      p.set("FrameIndex", static_cast<unsigned>(accumulate ? frameIndex : 0));
      gpu::dispatch(p, {(unsigned(width) + 7u) / 8u, (unsigned(height) + 7u) / 8u, 1u});
    }
    ++frameIndex;
  }

  techniques::Frame render(const techniques::FrameRequest& request) {
    if (!scene) throw ParameterError("tsis: render() before prepare(): expected a scene");
    const scene::Scene& s = *scene;
    const int width = request.width > 0 ? request.width : s.camera.width;
    const int height = request.height > 0 ? request.height : s.camera.height;
    if (width < 1 || height < 1 || width > 16384 || height > 16384)
      throw ParameterError(fmt::format("image size {}x{}: expected width and height in [1, 16384]",
                                       width, height));
    buildPrograms();
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
    gpu::checkGlError("tsis frame");

    frame.width = width;
    frame.height = height;
    if (request.readback) {
      const auto rad = gpu::download<glm::vec4>(radianceOut, pixels);
      const auto ex = gpu::download<glm::vec4>(exitanceOut, pixels);
      frame.rgb.resize(pixels * 3);
      std::vector<float>& exitance = frame.layers["exitance"];
      exitance.resize(pixels * 3);
      for (size_t i = 0; i < pixels; ++i)
        for (int c = 0; c < 3; ++c) {
          frame.rgb[i * 3 + size_t(c)] = rad[i][c];
          exitance[i * 3 + size_t(c)] = ex[i][c];
        }
    }
    for (const auto& pass : timer->collect()) frame.passes.push_back({pass.name, pass.ms, pass.depth});
    return frame;
  }
};

// ---------------------------------------------------------------------------------------------

TsisTechnique::TsisTechnique() : impl_(std::make_unique<Impl>()) {}
TsisTechnique::~TsisTechnique() = default;

std::string_view TsisTechnique::description() const {
  return "texture-space importance sampling of the irradiance over a surface atlas (seed chapter 3)";
}

const std::vector<techniques::ParameterInfo>& TsisTechnique::parameters() const {
  return impl_->params.infos();
}

void TsisTechnique::setParameter(std::string_view name, const techniques::ParameterValue& value) {
  const techniques::ParameterValue checked = techniques::checkedValue(impl_->params.info(name), value);
  if (name == "mode" && std::get<std::string>(checked) == "hybrid")
    throw ParameterError("tsis: mode 'hybrid' (the local/global split of seed 3.3) is not implemented "
                         "yet: expected 'global'");
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
