// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/techniques/pointcloud/pointcloud_technique.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <sstream>

#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "translucent/bssrdf/bssrdf_file.h"
#include "translucent/bssrdf/exit_radiance.h"
#include "translucent/bssrdf/registry.h"
#include "translucent/geometry/atlas.h"
#include "translucent/gpu/bssrdf_kernels.h"
#include "translucent/gpu/bssrdf_profiles.h"
#include "translucent/gpu/compute.h"
#include "translucent/gpu/pass_timer.h"
#include "translucent/material/surface_uv.h"
#include "translucent/techniques/common/gl_resources.h"
#include "translucent/techniques/common/light_shadows.h"
#include "translucent/material/profile_atlas.h"
#include "translucent/techniques/common/profile_atlas_gpu.h"
#include "translucent/techniques/common/profile_kernel.h"
#include "translucent/techniques/common/specular.h"
#include "translucent/techniques/common/surface_irradiance.h"

namespace translucent::pointcloud {
namespace {

using techniques::GBuffer;
using techniques::GpuMesh;
using techniques::ShadowMap;
using techniques::cameraViewProjection;
using techniques::vertexNormals;
using techniques::ParameterInfo;
using techniques::ParameterValue;
namespace desc = geometry::descriptor;

// SSBO bindings shared by the shaders.
enum Binding : GLuint {
  kDescriptors = 0,
  kNodes = 1,
  kPoints = 2,
  kIrradiance = 3,
  kEnvAccum = 4,
  kProfile = 5,
  kLevels = 6,
  kRadianceOut = 7,
  kExitanceOut = 8,
  // Heterogeneous materials only (shaders/pointcloud/hetero.glsl).
  kPointProfiles = 9,
  kNodeProfiles = 10,
  kVertexProfiles = 11,
  kMeshVertices = 12,
  kMeshTriangles = 13,
  // Directional .bssrdf files: the lights' directions per point (techniques::SurfaceIrradiance)
  // and per node (refit.comp: light direction, lit normal, normal).
  kLightDirections = 14,
  kNodeLight = 15,
  // Traversals the driver cut (radiance.comp, llvmpipe's loop limit).
  kCut = 16,
};

std::vector<ParameterInfo> parameterInfos() {
  std::vector<ParameterInfo> infos{
      ParameterInfo::integer("points", 100000, 1000, 5000000,
                             "number of area-uniform surface samples (irradiance points)"),
      ParameterInfo::enumeration("sampling", "elimination", {"elimination", "random"},
                                 "point sampling: Yuksel's sample elimination (blue noise) or "
                                 "independent random samples"),
      ParameterInfo::integer("seed", 1, 0, 1000000000, "seed of the point sampling"),
      ParameterInfo::floating("epsilon", kDefaultEpsilon, 1e-4, 100.0,
                              "largest solid angle A_v/d² a cluster may span before it is "
                              "subdivided (Eq. 2.40; smaller is more accurate and slower)",
                              "sr", true)
          // The traversal's accuracy/time knob (seed 2.6.4): each halving opens more nodes.
          .withSweep({0.8, 0.4, 0.2, 0.1, 0.05, 0.025}),
      ParameterInfo::enumeration("criterion", "bbox", {"bbox", "centroid"},
                                 "distance d of the criterion: to the node's bounding box "
                                 "(conservative, Bitterli 2013, §2.6.4) or to its centroid (Jensen & Buhler)"),
      ParameterInfo::enumeration("kernel", "table", {"table", "shader"},
                                 "BSSRDF evaluation: tabulated radial profile, or the model's "
                                 ".bssrdf shader code in the traversal (a directional file with "
                                 "the direction of the light that lit each point)"),
      techniques::tableSizeParameter(),
      techniques::radianceConventionParameter(),
  };
  for (ParameterInfo& p : techniques::specularParameters()) infos.push_back(std::move(p));
  // Heterogeneous materials: the shading points' profiles at the vertices or in a texture.
  for (ParameterInfo& p : techniques::profileStorageParameters()) infos.push_back(std::move(p));
  // The shared irradiance pass's shadow and environment settings (surface_irradiance.h).
  for (ParameterInfo& p : techniques::lightingParameters()) infos.push_back(std::move(p));
  return infos;
}

glm::vec3 toVec3(const Rgb& c) {
  return {static_cast<float>(c[0]), static_cast<float>(c[1]), static_cast<float>(c[2])};
}

bool isBssrdfFile(const std::string& model) { return bssrdf::hasBssrdfExtension(model); }

}  // namespace

// ---------------------------------------------------------------------------------------------

// The mesh, its bounding sphere and GPU copy: techniques::ClosedMeshState.
struct PointCloudTechnique::Impl : techniques::ClosedMeshState {
  techniques::ParameterSet params{parameterInfos()};

  // Scene.
  std::optional<scene::Scene> scene;

  // Point cloud and octree.
  bool geometryDirty = true;  // sample again (points, sampling, seed or the rest mesh changed)
  bool motionDirty = false;   // the deformation moved the surface: move the points, new octree
  geometry::PointCloud cloud;
  // A deformed mesh (mesh.deform): the cloud is sampled once on the rest pose, and each point
  // keeps its triangle and barycentrics there; at a new time it moves with that triangle of the
  // deformed mesh (no resampling, so the points and their noise stay put on the surface).
  geometry::PointCloud restCloud;
  std::vector<glm::dvec3> restBarycentrics;
  geometry::Octree octree;
  std::vector<std::pair<uint32_t, uint32_t>> levels;  // (offset, count) deepest first
  uint32_t stackSize = 1;
  gpu::Buffer descriptors, nodes, points, levelNodes, nodeLight;

  // Kernel.
  std::string kernelKey;
  std::array<bssrdf::ProfileTable, 3> tables;
  gpu::Buffer profile;
  std::optional<gpu::BssrdfEvaluator> evaluator;  // .bssrdf models
  std::optional<gpu::ShaderProgram> radianceProgram;
  bool shaderKernel = false;
  bool directionalKernel = false;  // a .bssrdf file without `radial`, evaluated as a shader

  // Programs.
  std::optional<gpu::ShaderProgram> gbufferProgram, refitProgram;

  // Material (prepare(): scene::sceneMaterial or setMaterial's). Heterogeneous (Volume, Surface):
  // per-point, per-vertex and per-node profiles, and the PC_HETERO variants of the g-buffer,
  // refit and radiance programs (built only then).
  std::optional<material::Material> materialOverride;
  material::ProfileOptions profileOptions;
  material::Material mat;
  bool hetero = false;
  bool heteroDirty = true;
  material::PointProfiles cloudProfiles, vertexProfiles;
  // profile_storage texture: the shading points' profiles at the texels of an atlas instead.
  std::optional<material::ProfileAtlas> profileAtlas;
  techniques::GpuProfileAtlas gpuProfileAtlas;
  gpu::Buffer pointProfiles, nodeProfiles, vertexProfileBuffer, meshVertices, meshTriangles;
  std::optional<gpu::ShaderProgram> gbufferHetero, refitHetero;
  int heteroProgramNodes = 0;

  // Lights: the shared irradiance pass (techniques/common/surface_irradiance.h).
  techniques::SurfaceIrradiance lighting;
  bool lightingDirty = true;

  // Frame.
  GBuffer gbuffer;
  gpu::Buffer radianceOut, exitanceOut;
  gpu::Buffer cutCounter;  // radiance.comp: traversals the driver cut
  size_t outPixels = 0;
  std::optional<gpu::PassTimer> timer;
  techniques::SpecularPass specular;
  std::vector<std::string> notes;

  // ---- preparation ----------------------------------------------------------------------------

  void buildPrograms() {
    if (gbufferProgram) return;
    gbufferProgram.emplace(
        gpu::ShaderProgram::graphics("pointcloud/gbuffer.vert", "pointcloud/gbuffer.frag"));
    refitProgram.emplace(gpu::ShaderProgram::compute("pointcloud/refit.comp"));
    gpu::checkGlError("building the point-cloud programs");
  }

  void loadMesh(const scene::Scene& s) {
    // The rest mesh once (GpuMesh deforms it on the GPU for the G-buffer and shadow maps);
    // `mesh` is the CPU-deformed copy at the scene's time.
    const std::string before = deformState;
    // Points need no interior (Eq. 3.5 sums over the surface): open meshes (a face mask, a patch
    // of terrain) are rendered with their winding as given.
    allowOpen = true;
    if (loadClosedMesh(s, /*gpuDeform=*/true)) geometryDirty = true;
    else if (deformState != before) motionDirty = true;
  }

  // The rest cloud moved onto the deformed mesh: position and normal interpolated from the
  // deformed triangle's vertices at the point's barycentrics, the area scaled by the triangle's.
  geometry::PointCloud movedCloud() const {
    geometry::PointCloud c = restCloud;
    for (size_t i = 0; i < c.size(); ++i) {
      const glm::uvec3 t = mesh.triangles[c.faces[i]];
      const glm::dvec3 b = restBarycentrics[i];
      const glm::dvec3 &a0 = mesh.positions[t.x], &a1 = mesh.positions[t.y], &a2 = mesh.positions[t.z];
      c.positions[i] = glm::vec3(b.x * a0 + b.y * a1 + b.z * a2);
      const glm::dvec3 n = b.x * mesh.normals[t.x] + b.y * mesh.normals[t.y] + b.z * mesh.normals[t.z];
      const glm::dvec3 f = glm::cross(a1 - a0, a2 - a0);
      const double len = glm::length(n);
      c.normals[i] = glm::vec3(len > 0.0 ? n / len : glm::normalize(f));
      const glm::dvec3 &r0 = rest.positions[t.x], &r1 = rest.positions[t.y], &r2 = rest.positions[t.z];
      const double restArea = glm::length(glm::cross(r1 - r0, r2 - r0));
      c.areas[i] = float(double(c.areas[i]) * (restArea > 0.0 ? glm::length(f) / restArea : 1.0));
    }
    return c;
  }

  void prepareMaterial(const scene::Scene& s) {
    mat = materialOverride ? *materialOverride : scene::sceneMaterial(s, mesh);
    hetero = mat.heterogeneous();
    heteroDirty = true;
  }

  // Kind::Surface: the atlas UV of every cloud point (its triangle's corner UVs at the point's
  // barycentrics) and of every vertex (from the first triangle that uses it: a vertex on a chart
  // seam has one UV per chart, and the map is read at one of them). The atlas is the default one
  // (geometry::AtlasOptions{}, cached like tsis's): the surface map must be defined over it.
  void surfaceUvs(std::vector<glm::vec2>& cloudUvs, std::vector<glm::vec2>& vertexUvs) {
    if (cloud.faces.size() != cloud.size())
      throw ParameterError("pointcloud: a surface-map material needs the triangle of every point: "
                           "the point cloud has none");
    // The rest pose's atlas, at the points' rest positions: a map follows a deformed surface.
    const geometry::CachedAtlas cached = geometry::loadOrBuildAtlas(rest, geometry::AtlasOptions{});
    const geometry::Atlas& atlas = cached.atlas;
    notes.push_back(fmt::format("pointcloud: surface-map material over the {}² {} atlas ({} {})",
                                atlas.size, geometry::toString(atlas.method),
                                cached.fromCache ? "read from" : "cached in", cached.file.string()));
    cloudUvs = material::atlasUvs(rest, atlas, restCloud.faces, restCloud.positions);
    vertexUvs = material::vertexAtlasUvs(rest, atlas);
  }

  // The profiles of the cloud's points, of the mesh's vertices (the shading points' profiles are
  // interpolated from them) and room for the nodes' representatives (refit per frame).
  void buildHetero() {
    if (!hetero || !heteroDirty) return;
    const std::vector<glm::dvec3> normals = vertexNormals(mesh);
    std::vector<glm::vec3> vp(mesh.vertexCount()), vn(mesh.vertexCount());
    for (size_t i = 0; i < vp.size(); ++i) {
      vp[i] = glm::vec3(mesh.positions[i]);
      vn[i] = glm::vec3(normals[i]);
    }
    std::vector<glm::vec2> cloudUvs, vertexUvs;
    if (mat.kind == material::Material::Kind::Surface) surfaceUvs(cloudUvs, vertexUvs);
    cloudProfiles = material::PointProfiles::build(
        mat, material::PointProfiles::surfaceMedia(mat, cloud.positions, cloud.normals, cloudUvs),
        profileOptions);
    vertexProfiles = material::PointProfiles::build(
        mat, material::PointProfiles::surfaceMedia(mat, vp, vn, vertexUvs),
        {cloudProfiles.segments(), cloudProfiles.radius()});
    profileAtlas.reset();
    if (params.getEnum("profile_storage") == "texture") {
      // On the grid of the cloud's profiles (Eq. 8 combines a point's nodes with these).
      geometry::AtlasOptions ao;
      ao.size = uint32_t(params.getInt("profile_texels"));
      std::optional<geometry::Atlas> surfaceAtlas;
      if (mat.kind == material::Material::Kind::Surface)
        surfaceAtlas = geometry::loadOrBuildAtlas(rest, geometry::AtlasOptions{}).atlas;
      profileAtlas = material::buildProfileAtlas(
          mesh, geometry::loadOrBuildAtlas(mesh, ao).atlas, mat,
          {cloudProfiles.segments(), cloudProfiles.radius()}, surfaceAtlas ? &*surfaceAtlas : nullptr);
      gpuProfileAtlas = techniques::uploadProfileAtlas(*profileAtlas, "pointcloud: profile texture");
      notes.push_back(techniques::describeProfileAtlas("pointcloud", *profileAtlas));
    }
    const HeteroProfiles slots = heteroProfiles(octree, cloudProfiles);
    pointProfiles = gpu::makeStorageBuffer(std::span<const glm::vec4>(slots.points));
    nodeProfiles = gpu::makeStorageBuffer(slots.stride() * octree.nodeCount() * sizeof(glm::vec4));
    std::vector<glm::vec4> vprof;
    vprof.reserve(slots.stride() * mesh.vertexCount());
    for (size_t v = 0; v < mesh.vertexCount(); ++v)
      for (const glm::vec4& node : profileNodes(vertexProfiles, v)) vprof.push_back(node);
    vertexProfileBuffer = gpu::makeStorageBuffer(std::span<const glm::vec4>(vprof));
    techniques::uploadMeshStorage(mesh, meshVertices, meshTriangles);
    const int profileNodes = cloudProfiles.segments() + 1;
    if (!gbufferHetero || heteroProgramNodes != profileNodes) {
      const gpu::Defines d{{"PC_HETERO", "1"}, {"PC_PROFILE_NODES", std::to_string(profileNodes)}};
      gbufferHetero.emplace(
          gpu::ShaderProgram::graphics("pointcloud/gbuffer.vert", "pointcloud/gbuffer.frag", d));
      refitHetero.emplace(gpu::ShaderProgram::compute("pointcloud/refit.comp", d));
      heteroProgramNodes = profileNodes;
    }
    notes.push_back(fmt::format("pointcloud: heterogeneous material, {} segments of ln P on "
                                "[0, r_s = {:.4g}] per point (Eq. 8)", cloudProfiles.segments(),
                                cloudProfiles.radius()));
    gpu::checkGlError("building the heterogeneous profiles");
    heteroDirty = false;
  }

  void prepareLights(const scene::Scene& s) {
    lighting.prepareLights(s, center, radius, params.getInt("shadow_map_size"), "point-cloud");
    lightingDirty = true;
  }

  void buildGeometry() {
    if (!geometryDirty && !motionDirty) return;
    if (geometryDirty) {
      if (openEdges > 0)
        notes.push_back(fmt::format("pointcloud: the mesh is open ({} edges not shared by two "
                                    "triangles): its winding is taken as outward as given, and "
                                    "light reaches its back only through the surface",
                                    openEdges));
      if (filePoints) {
        // A point-cloud file: its own points are the samples (the explorer paper renders such
        // files directly); the reconstructed surface only draws the G-buffer.
        restCloud = filePoints->cloud;
        notes.push_back(fmt::format("point cloud: the {} points of the mesh file (points, "
                                    "sampling and seed do not apply); surface reconstructed for "
                                    "display: {}",
                                    restCloud.size(), geometry::describe(filePoints->reconstruction)));
      } else {
        geometry::SamplingOptions opt;
        opt.count = static_cast<size_t>(params.getInt("points"));
        opt.seed = static_cast<uint64_t>(params.getInt("seed"));
        opt.method = geometry::parseSamplingMethod(params.getEnum("sampling"));
        geometry::CachedPointCloud cached = geometry::loadOrSamplePointCloud(rest, opt);
        notes.push_back(fmt::format("point cloud: {} points {} {}", opt.count,
                                    cached.fromCache ? "read from" : "sampled, cached in",
                                    cached.file.string()));
        if (!cached.note.empty()) notes.push_back("point cloud cache: " + cached.note);
        restCloud = std::move(cached.cloud);
      }
      restCloud.irradiance.clear();
      restBarycentrics.clear();
    }
    if (mesh.positions == rest.positions) {
      cloud = restCloud;  // not deformed at this time
    } else {
      if (restCloud.faces.size() != restCloud.size())
        throw ParameterError("pointcloud: a deformed mesh needs the triangle of every point: the "
                             "point cloud has none");
      if (restBarycentrics.empty()) {
        restBarycentrics.resize(restCloud.size());
        for (size_t i = 0; i < restCloud.size(); ++i) {
          const glm::uvec3 t = rest.triangles[restCloud.faces[i]];
          const glm::dvec3 a = rest.positions[t.x], e1 = rest.positions[t.y] - a,
                           e2 = rest.positions[t.z] - a, q = glm::dvec3(restCloud.positions[i]) - a;
          // Least squares in the triangle's plane (the point is on it up to float rounding).
          const double d11 = glm::dot(e1, e1), d12 = glm::dot(e1, e2), d22 = glm::dot(e2, e2);
          const double q1 = glm::dot(q, e1), q2 = glm::dot(q, e2), det = d11 * d22 - d12 * d12;
          const double v = det > 0.0 ? (d22 * q1 - d12 * q2) / det : 1.0 / 3.0;
          const double w = det > 0.0 ? (d11 * q2 - d12 * q1) / det : 1.0 / 3.0;
          restBarycentrics[i] = {1.0 - v - w, v, w};
        }
      }
      cloud = movedCloud();
    }
    motionDirty = false;
    octree = geometry::Octree(cloud);

    // Levels, deepest first (a child's index is always larger than its parent's).
    const auto& d = octree.descriptors();
    std::vector<uint32_t> depth(d.size(), 0);
    uint32_t maxDepth = 0;
    for (uint32_t v = 0; v < d.size(); ++v) {
      if (!desc::isLeaf(d[v]))
        for (uint32_t c = desc::index(d[v]), e = c + desc::childCount(d[v]); c < e; ++c)
          depth[c] = depth[v] + 1;
      maxDepth = std::max(maxDepth, depth[v]);
    }
    std::vector<uint32_t> order;
    order.reserve(d.size());
    levels.clear();
    for (uint32_t level = maxDepth + 1; level-- > 0;) {
      const auto offset = static_cast<uint32_t>(order.size());
      for (uint32_t v = 0; v < d.size(); ++v)
        if (depth[v] == level) order.push_back(v);
      levels.emplace_back(offset, static_cast<uint32_t>(order.size()) - offset);
    }
    stackSize = std::max<uint32_t>(1, octree.depth() > 0 ? octree.depth() - 1 : 1);

    descriptors = gpu::makeStorageBuffer(std::span<const uint32_t>(d));
    nodes = gpu::makeStorageBuffer(std::span<const geometry::OctreeNode>(octree.nodes()));
    nodeLight = gpu::makeStorageBuffer(std::max<size_t>(octree.nodes().size(), 1) * 3 * sizeof(glm::vec4));
    points = gpu::makeStorageBuffer(std::span<const geometry::OctreePoint>(octree.points()));
    levelNodes = gpu::makeStorageBuffer(std::span<const uint32_t>(order));
    geometryDirty = false;
    lightingDirty = true;
    heteroDirty = true;
  }

  // The profile R(r) per channel (techniques/common/profile_kernel.h): from the C++ model, or,
  // for a .bssrdf file, from its GPU kernel (a registered model keeps its C++ profile even when
  // the traversal runs its .bssrdf shader).
  void tabulateKernel(const scene::Scene& s) {
    techniques::RgbProfileTable t = techniques::tabulateRgbProfile(
        s, static_cast<size_t>(params.getInt("table_size")),
        isBssrdfFile(s.model) ? &*evaluator : nullptr);
    tables = std::move(t.tables);
    profile = gpu::makeStorageBuffer(std::span<const glm::vec4>(t.gpu));
  }

  void buildKernel() {
    const scene::Scene& s = *scene;
    const bool wantShader = params.getEnum("kernel") == "shader";
    // Heterogeneous: the PC_HETERO variant with n + 1 profile nodes (0: homogeneous).
    const int heteroNodes = hetero ? (profileOptions.segments + 1) : 0;
    const bool profileTexture = hetero && params.getEnum("profile_storage") == "texture";
    const std::string key = fmt::format("{}|{}|{}|{}|{}|{}", scene::mediumKey(s),
                                        params.getInt("table_size"), wantShader, stackSize,
                                        heteroNodes, profileTexture);
    if (key == kernelKey && radianceProgram) return;
    kernelKey.clear();  // until this build succeeds: a failure must not leave a stale kernel
    if (hetero && wantShader)
      throw ParameterError("pointcloud: kernel 'shader' with a heterogeneous material: expected "
                           "kernel 'table' (per-point profiles come from the registered model)");
    s.medium.validate();
    evaluator.reset();
    std::filesystem::path file;
    if (isBssrdfFile(s.model)) {
      file = s.model;
    } else if (wantShader) {
      (void)bssrdf::model(s.model);  // an unknown name lists the registered models
      file = gpu::bssrdfDirectory() / (s.model + ".bssrdf");
      std::error_code ec;
      if (!std::filesystem::exists(file, ec))
        throw ParameterError(fmt::format("kernel 'shader': model '{}' has no .bssrdf file ({} does not "
                                         "exist): use kernel 'table' or a .bssrdf model", s.model,
                                         file.string()));
    }
    if (!file.empty()) {
      evaluator.emplace(file);
      evaluator->setMedium(s.medium);
    }
    tabulateKernel(s);
    shaderKernel = wantShader;
    const bool directionalFile = evaluator && !evaluator->file().attributes.radial;
    directionalKernel = wantShader && directionalFile;
    if (directionalFile && !wantShader)
      notes.push_back(fmt::format(
          "pointcloud: {} is directional; kernel 'table' renders its normal-incidence profile "
          "(kernel 'shader' evaluates it with the direction of the light that lit each point)",
          evaluator->file().path));
    else if (!evaluator && bssrdf::model(s.model).directional(s.medium.channel(0)))
      notes.push_back(fmt::format(
          "pointcloud: model '{}' is directional; kernel 'table' renders its normal-incidence "
          "profile (kernel 'shader' evaluates its .bssrdf twin with the lights' directions)",
          s.model));

    // The radiance program with the chosen kernel and the octree's stack size.
    const auto stack = stackSize;
    std::shared_ptr<const bssrdf::BssrdfFile> bssrdfFile;
    if (wantShader) bssrdfFile = std::make_shared<const bssrdf::BssrdfFile>(evaluator->file());
    const bool directional = directionalKernel;
    auto recipe = [stack, bssrdfFile, heteroNodes, directional, profileTexture]() {
      gpu::ShaderPreprocessor pp = bssrdfFile ? gpu::bssrdfPreprocessor(*bssrdfFile) : gpu::ShaderPreprocessor();
      pp.define("PC_STACK_SIZE", std::to_string(stack));
      if (directional) pp.define("PC_DIRECTIONAL", "1");
      if (heteroNodes > 0) {
        pp.define("PC_HETERO", "1");
        pp.define("PC_PROFILE_NODES", std::to_string(heteroNodes));
        if (profileTexture) pp.define("PC_PROFILE_ATLAS", "1");
      }
      gpu::SourceFile kernel;
      kernel.path = bssrdfFile ? "<pointcloud kernel: .bssrdf shader>" : "<pointcloud kernel: table>";
      kernel.text = bssrdfFile ? "#include \"bssrdf/interface.glsl\"\n"
                                 "#include \"bssrdf:parameters\"\n"
                                 "#include \"bssrdf:initializer\"\n"
                                 "#include \"bssrdf:diffuseReflectance\"\n"
                                 "#include \"bssrdf:shader\"\n"
                                 "#include \"pointcloud/kernel_bssrdf.glsl\"\n"
                               : "#include \"pointcloud/kernel_table.glsl\"\n";
      pp.addVirtualFile("pointcloud:kernel", kernel);
      return pp.load("pointcloud/radiance.comp");
    };
    radianceProgram.emplace("pointcloud radiance", std::vector<gpu::StageRecipe>{{GL_COMPUTE_SHADER, recipe}});
    kernelKey = key;
  }

  // ---- frame ------------------------------------------------------------------------------------

  techniques::Frame render(const techniques::FrameRequest& request) {
    if (!scene) throw ParameterError("pointcloud: render() before prepare(): expected a scene");
    const scene::Scene& s = *scene;
    const auto [width, height] = techniques::frameSize(request, s.camera);
    buildPrograms();
    buildGeometry();
    buildKernel();
    buildHetero();
    if (!timer) timer.emplace();
    techniques::Frame frame;
    frame.notes = std::move(notes);
    notes.clear();

    // Buffers shared by the passes.
    gpu::bindStorage(kDescriptors, descriptors);
    gpu::bindStorage(kNodes, nodes);
    gpu::bindStorage(kPoints, points);
    gpu::bindStorage(kProfile, profile);
    gpu::bindStorage(kLevels, levelNodes);
    if (hetero) {
      gpu::bindStorage(kPointProfiles, pointProfiles);
      gpu::bindStorage(kNodeProfiles, nodeProfiles);
      gpu::bindStorage(kVertexProfiles, vertexProfileBuffer);
      gpu::bindStorage(kMeshVertices, meshVertices);
      gpu::bindStorage(kMeshTriangles, meshTriangles);
      if (profileAtlas) gpuProfileAtlas.bind();
    }

    // The irradiance of every light at the points (the shared pass), then bound for the refit and
    // the traversal.
    // Nothing the lighting depends on changed since the last frame (a camera move): the shadow
    // maps and the direct irradiance are kept (an occluded environment goes on accumulating).
    const bool reuse = !lightingDirty;
    if (lightingDirty) lighting.restartEnvironment();
    lightingDirty = false;
    const bool lit = lighting.update(*gpuMesh, points, octree.pointCount(),
                                     static_cast<float>(s.medium.eta), techniques::shadowLookup(params),
                                     techniques::environmentBudget(params, request.converge), &*timer,
                                     reuse);
    if (lighting.hasOccludedEnvironment()) frame.converged = lit;
    gpu::bindStorage(kIrradiance, lighting.irradiance());
    gpu::bindStorage(kLightDirections, lighting.lightDirections());
    gpu::bindStorage(kNodeLight, nodeLight);

    // Refit, deepest level first.
    {
      auto t = timer->scope("refit");
      const gpu::ShaderProgram& rp = hetero ? *refitHetero : *refitProgram;
      for (const auto& [offset, count] : levels) {
        rp.set("LevelOffset", offset);
        rp.set("LevelCount", count);
        gpu::dispatch1D(rp, count);
      }
    }

    // G-buffer.
    {
      auto t = timer->scope("g-buffer");
      gbuffer.resize(width, height);
      const glm::mat4 vp = cameraViewProjection(s.camera, s.clip_near, s.clip_far, center, radius,
                                                width, height);
      gbuffer.render(*gpuMesh, hetero ? *gbufferHetero : *gbufferProgram, vp);
    }

    // Radiance.
    const size_t pixels = size_t(width) * size_t(height);
    if (pixels != outPixels) {
      radianceOut = gpu::makeStorageBuffer(pixels * sizeof(glm::vec4));
      exitanceOut = gpu::makeStorageBuffer(pixels * sizeof(glm::vec4));
      outPixels = pixels;
    }
    {
      auto t = timer->scope("radiance");
      const gpu::ShaderProgram& p = *radianceProgram;
      gpu::bindStorage(kRadianceOut, radianceOut);
      gpu::bindStorage(kExitanceOut, exitanceOut);
      techniques::setExitRadianceUniforms(p, gbuffer, s, params, width, height);
      p.set("Epsilon", static_cast<float>(params.getFloat("epsilon")));
      p.set("Criterion", params.getEnum("criterion") == "bbox" ? 0 : 1);
      p.set("ProfileRMax", static_cast<float>(tables[0].r_max));
      p.set("ProfileCount", static_cast<unsigned>(tables[0].size()));
      if (hetero) p.set("HeteroRadius", static_cast<float>(cloudProfiles.radius()));
      if (shaderKernel) setBssrdfUniforms(p);
      if (!cutCounter) cutCounter = gpu::makeStorageBuffer(sizeof(uint32_t));
      const uint32_t zero = 0;
      gpu::uploadBytes(cutCounter, 0, sizeof(zero), &zero);
      gpu::bindStorage(kCut, cutCounter);
      gpu::dispatch(p, {(unsigned(width) + 7u) / 8u, (unsigned(height) + 7u) / 8u, 1u});
    }
    specular.add(gbuffer, s, params, radianceOut, &*timer);
    gpu::checkGlError("point-cloud frame");
    // Where the driver ends long loops (llvmpipe), a traversal of many clusters per pixel (a
    // small epsilon over many points) stops half-way and its pixel comes out dark or black: an
    // error, not that image. Elsewhere there is no such limit and no read-back here.
    if (const gpu::LoopLimit loopLimit = gpu::loopLimit(); loopLimit.limited) {
      uint32_t cut = 0;
      gpu::downloadBytes(cutCounter, 0, sizeof(cut), &cut);
      if (cut > 0)
        throw gpu::GlError(fmt::format(
            "pointcloud: the GL driver ({}) stopped the traversal of {} of {} pixels after its "
            "limit of {} loop iterations: epsilon {} visits too many clusters per pixel for it; "
            "raise epsilon, use fewer points, or render on a hardware GPU",
            reinterpret_cast<const char*>(glGetString(GL_RENDERER)), cut, pixels,
            loopLimit.iterations, params.getFloat("epsilon")));
    }

    // Read back.
    frame.width = width;
    frame.height = height;
    if (!request.readback) {
      techniques::addPasses(frame, *timer);
      return frame;
    }
    techniques::readRadianceAndExitance(frame, radianceOut, exitanceOut, pixels);
    techniques::addPasses(frame, *timer);
    return frame;
  }

  void setBssrdfUniforms(const gpu::ShaderProgram& p) const {
    const Medium& m = scene->medium;
    glm::vec3 a, sgm;
    for (int c = 0; c < 3; ++c) {
      a[c] = static_cast<float>(m.channel(c).sigma_a);
      sgm[c] = static_cast<float>(m.channel(c).sigma_s);
    }
    p.set("SigmaA", a);
    p.set("SigmaS", sgm);
    p.set("G", static_cast<float>(m.g));
    p.set("IOR", static_cast<float>(m.eta));
    for (const auto& param : evaluator->file().parameters) {
      const gpu::ParameterValue v = evaluator->parameter(param.name);
      if (const auto* d = std::get_if<double>(&v))
        p.set(param.name, static_cast<float>(*d));
      else if (const auto* b = std::get_if<bool>(&v))
        p.set(param.name, *b);
      else
        p.set(param.name, toVec3(std::get<Rgb>(v)));
    }
  }
};

// ---------------------------------------------------------------------------------------------

PointCloudTechnique::PointCloudTechnique() : impl_(std::make_unique<Impl>()) {}
PointCloudTechnique::~PointCloudTechnique() = default;

std::string_view PointCloudTechnique::description() const {
  return "hierarchical point-cloud BSSRDF evaluation (Jensen & Buhler 2002; Bitterli 2013, §2.6.4, §3.3)";
}

const std::vector<techniques::ParameterInfo>& PointCloudTechnique::parameters() const {
  return impl_->params.infos();
}

void PointCloudTechnique::setParameter(std::string_view name, const techniques::ParameterValue& value) {
  if (!impl_->params.set(name, value)) return;
  if (name == "points" || name == "sampling" || name == "seed") impl_->geometryDirty = true;
  if (name == "profile_storage" || name == "profile_texels") impl_->heteroDirty = true;
  if (name == "shadow_map_size" && impl_->scene) impl_->prepareLights(*impl_->scene);
  if (name.starts_with("shadow_") || name.starts_with("ibl_")) impl_->lightingDirty = true;
}

techniques::ParameterValue PointCloudTechnique::parameter(std::string_view name) const {
  return impl_->params.get(name);
}

void PointCloudTechnique::prepare(const scene::Scene& scene, gpu::Context& gl) {
  gl.makeCurrent();
  scene.camera.validate();
  scene.medium.validate();
  impl_->buildPrograms();
  impl_->loadMesh(scene);
  impl_->prepareLights(scene);
  impl_->scene = scene;
  impl_->prepareMaterial(scene);
  impl_->buildGeometry();
  impl_->buildKernel();
  impl_->buildHetero();
}

void PointCloudTechnique::setMaterial(std::optional<material::Material> material,
                                      const material::ProfileOptions& options) {
  impl_->materialOverride = std::move(material);
  impl_->profileOptions = options;
  impl_->heteroDirty = true;
}

bool PointCloudTechnique::heterogeneous() const { return impl_->hetero; }
const material::PointProfiles& PointCloudTechnique::cloudProfiles() const { return impl_->cloudProfiles; }
const material::PointProfiles& PointCloudTechnique::vertexProfiles() const { return impl_->vertexProfiles; }

techniques::Frame PointCloudTechnique::render(const techniques::FrameRequest& request) {
  return impl_->render(request);
}

bool PointCloudTechnique::setCamera(const reference::Camera& camera) {
  if (!impl_->scene) return false;
  camera.validate();
  impl_->scene->camera = camera;
  return true;
}

const geometry::TriangleMesh& PointCloudTechnique::mesh() const { return impl_->mesh; }
const geometry::PointCloud& PointCloudTechnique::pointCloud() const { return impl_->cloud; }

std::vector<glm::vec3> PointCloudTechnique::gpuIrradiance() const {
  const auto slots = gpu::download<glm::vec4>(impl_->lighting.irradiance(), impl_->octree.pointCount());
  const auto& order = impl_->octree.pointOrder();
  std::vector<glm::vec3> out(slots.size());
  for (size_t s = 0; s < slots.size(); ++s) out[order[s]] = glm::vec3(slots[s]);
  return out;
}

geometry::Octree PointCloudTechnique::octreeWithGpuIrradiance() const {
  geometry::Octree copy = impl_->octree;
  copy.refit(gpuIrradiance());
  return copy;
}

RgbKernel PointCloudTechnique::cpuKernel() const { return RgbKernel::fromTables(impl_->tables); }

std::vector<glm::vec4> PointCloudTechnique::gbufferPositions() const {
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

TraversalOptions PointCloudTechnique::traversalOptions() const {
  TraversalOptions o;
  o.epsilon = impl_->params.getFloat("epsilon");
  o.criterion = impl_->params.getEnum("criterion") == "bbox" ? Criterion::BoundingBox : Criterion::Centroid;
  return o;
}

std::unique_ptr<techniques::Technique> makePointCloudTechnique() {
  return std::make_unique<PointCloudTechnique>();
}

}  // namespace translucent::pointcloud
