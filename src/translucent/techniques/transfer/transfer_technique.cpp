// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/techniques/transfer/transfer_technique.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <optional>

#include <glm/geometric.hpp>

#include "translucent/bssrdf/exit_radiance.h"
#include "translucent/geometry/hole_filling.h"
#include "translucent/geometry/point_cloud.h"
#include "translucent/gpu/compute.h"
#include "translucent/gpu/pass_timer.h"
#include "translucent/gpu/program.h"
#include "translucent/techniques/common/gl_resources.h"
#include "translucent/techniques/common/light_shadows.h"
#include "translucent/techniques/common/profile_kernel.h"
#include "translucent/techniques/common/single_scattering.h"
#include "translucent/techniques/common/specular.h"
#include "translucent/techniques/common/surface_irradiance.h"

namespace translucent::transfer {
namespace {

using techniques::ParameterInfo;
using techniques::ParameterValue;

// SSBO bindings (shaders/transfer/*.comp; 2 and 3 are the irradiance pass's points and output,
// 12 and 13 the mesh as pointcloud/hetero.glsl reads it).
enum Binding : GLuint {
  kPoints = 2,
  kIrradiance = 3,
  kRadianceOut = 7,
  kExitanceOut = 8,
  kMeshVertices = 12,
  kMeshTriangles = 13,
  kMatrixR = 20,
  kMatrixG = 25,
  kMatrixB = 26,
  kNodeExitance = 21,
  kVertexNodeList = 22,
  kVertexWeights = 23,
  kVertexExitance = 24,
  kLightDirections = 14,
  kFrames = 27,
  kTilted = 28,
  kNodeIrradiance = 29,
};

std::vector<ParameterInfo> parameterInfos() {
  std::vector<ParameterInfo> infos{
      ParameterInfo::integer("nodes", 2048, 64, 4096,
                             "surface nodes of the transfer matrix (its memory grows as nodes², "
                             "its detail as sqrt(nodes))")
          .withSweep({256, 512, 1024, 2048, 4096}),
      ParameterInfo::integer("photons", 512, 16, 65536,
                             "path-traced photons per node and colour channel in the "
                             "preprocessing (its noise falls as 1/sqrt(photons))"),
      ParameterInfo::integer("seed", 1, 0, 1000000000, "seed of the nodes and of the photons"),
      ParameterInfo::enumeration("incidence", "secant", {"normal", "first-order", "secant"},
                                 "how the transfer depends on the light's incident direction: not "
                                 "at all (normal incidence, one matrix), to first order (five "
                                 "beams per node in the preprocessing, three matrices of central "
                                 "differences) or secant (the same five beams kept as five "
                                 "matrices, each node interpolated towards the beam on its "
                                 "light's side)"),
      ParameterInfo::enumeration(
          "scattering", "auto", {"auto", "split", "operator", "single"},
          "which light the image holds and how: split, single scattering per pixel along the "
          "view ray (traced through the mesh) and the other orders through the transfer "
          "operator; operator, every order through the operator; single, single scattering "
          "alone; auto, split where every light is directional, point or beam, else operator"),
      techniques::radianceConventionParameter(),
  };
  for (ParameterInfo& p : techniques::singleScatteringParameters()) infos.push_back(std::move(p));
  for (ParameterInfo& p : techniques::specularParameters()) infos.push_back(std::move(p));
  for (ParameterInfo& p : techniques::lightingParameters()) infos.push_back(std::move(p));
  return infos;
}


// What the operator depends on: the placed mesh and the material (not the lights, camera or
// display), and the options.
std::string operatorKey(const scene::Scene& s, const TransferOptions& o) {
  scene::Scene k = s;
  k.lights.clear();
  k.camera = reference::Camera{};
  k.clip_near = k.clip_far = 0.0;
  k.technique = "transfer";
  k.settings.clear();
  k.exposure = 0.0;
  k.gamma = 2.2;
  k.cone_angle = 5.0;
  return fmt::format("transfer v5|{}|{}|nodes={}|photons={}|seed={}|incidence={}{}",
                     scene::meshKey(s), scene::toJson(k), o.nodes, o.photons, o.seed,
                     static_cast<int>(o.incidence), o.exclude_single ? "|single=excluded" : "");
}

}  // namespace

struct TransferTechnique::Impl : techniques::ClosedMeshState {
  techniques::ParameterSet params{parameterInfos()};
  std::optional<scene::Scene> scene;
  std::string opKey;  // the operator on the GPU
  bool operatorDirty = true;  // the scene or nodes, photons or seed changed since opKey was made
  TransferOperator op;
  techniques::SurfaceIrradiance lighting;
  bool lightingDirty = true;
  gpu::Buffer points, frames, nodeIrradiance, tilted, nodeExitance, vertexNodes, vertexWeights, vertexExitance,
      meshVertices, meshTriangles, radianceOut, exitanceOut;
  size_t outPixels = 0;
  std::optional<gpu::ShaderProgram> gbufferProgram, applyNormal, applyFirstOrder, applySecant, cellsNormal,
      cellsFirstOrder, vertexProgram, radianceProgram;
  techniques::GBuffer gbuffer;
  std::array<gpu::Buffer, 3> matrix;  // K per channel
  std::optional<gpu::PassTimer> timer;
  std::vector<std::string> notes;
  techniques::SingleScattering single;
  techniques::SpecularPass specular;
  bool singleDirty = true;  // the scene or the scattering mode changed since single.prepare

  // "operator", "split" or "single": the scattering parameter, with auto resolved for the scene
  // (split unless a light is one that single scattering cannot trace).
  std::string scattering() const {
    const std::string& m = params.getEnum("scattering");
    if (m != "auto") return m;
    return scene && !techniques::singleScatteringRefusal(*scene).empty() ? "operator" : "split";
  }

  bool tiltReachable() const { return !scene || kTilt * scene->medium.eta <= 0.99; }

  TransferOptions options() const {
    TransferOptions o;
    o.nodes = params.getInt("nodes");
    o.photons = static_cast<uint64_t>(params.getInt("photons"));
    o.seed = static_cast<uint64_t>(params.getInt("seed"));
    // The tilted beams lean by kTilt inside, which light from outside reaches only where
    // kTilt · η < 1: above that (η > 1.98) every mode traces normal beams (a note says so).
    const std::string& mode = params.getEnum("incidence");
    o.incidence = mode == "normal" || !tiltReachable() ? Incidence::Normal
                  : mode == "first-order"               ? Incidence::FirstOrder
                                                        : Incidence::Secant;
    o.exclude_single = scattering() == "split";
    return o;
  }

  void buildPrograms() {
    if (gbufferProgram) return;
    const gpu::Defines hetero{{"PC_HETERO", "1"}, {"PC_PROFILE_NODES", "2"}};
    gbufferProgram.emplace(
        gpu::ShaderProgram::graphics("pointcloud/gbuffer.vert", "pointcloud/gbuffer.frag", hetero));
    const gpu::Defines firstOrder{{"TX_FIRST_ORDER", "1"}};
    const gpu::Defines secant{{"TX_FIRST_ORDER", "1"}, {"TX_SECANT", "1"}};
    applyNormal.emplace(gpu::ShaderProgram::compute("transfer/apply.comp"));
    applyFirstOrder.emplace(gpu::ShaderProgram::compute("transfer/apply.comp", firstOrder));
    applySecant.emplace(gpu::ShaderProgram::compute("transfer/apply.comp", secant));
    cellsNormal.emplace(gpu::ShaderProgram::compute("transfer/cells.comp"));
    cellsFirstOrder.emplace(gpu::ShaderProgram::compute("transfer/cells.comp", firstOrder));
    vertexProgram.emplace(gpu::ShaderProgram::compute("transfer/vertex.comp"));
    radianceProgram.emplace(gpu::ShaderProgram::compute("transfer/radiance.comp", hetero));
    gpu::checkGlError("building the transfer programs");
  }

  // The exitance is interpolated over the mesh's triangles from its vertices: a mesh whose
  // typical (median) edge is longer than the node spacing (a box of 12 triangles) would blur it
  // to its few vertices (a thin plate rendered 41% too dark at its 8 corners). Such a mesh is
  // refined to half the spacing (geometry::refineMesh: isotropic remeshing, sharp edges kept),
  // for the G-buffer, the shadow maps and the operator alike; the surface, and so the transport,
  // stays the same. A fine mesh with a few long edges is left alone (remeshing would also
  // collapse its short ones: the bunny's 69666 triangles would become 22352).
  void refineCoarseMesh(int nodes) {
    std::vector<double> lengths;
    lengths.reserve(3 * mesh.triangleCount());
    for (const glm::uvec3& t : mesh.triangles)
      for (int k = 0; k < 3; ++k)
        lengths.push_back(glm::length(mesh.positions[t[k]] - mesh.positions[t[(k + 1) % 3]]));
    if (lengths.empty()) return;
    std::nth_element(lengths.begin(), lengths.begin() + lengths.size() / 2, lengths.end());
    const double median = lengths[lengths.size() / 2];
    const double spacing = std::sqrt(mesh.area() / double(nodes));
    if (median <= spacing) return;
    const size_t before = mesh.triangleCount();
    geometry::refineMesh(mesh, 0.5 * spacing, fmt::format("mesh file '{}'", scene->mesh_file.string()));
    mesh.orientOutwards();
    gpuMesh.emplace(mesh);
    singleDirty = true;
    notes.push_back(fmt::format("transfer: the mesh's median edge ({:.3g}) exceeds the node "
                                "spacing ({:.3g}): refined from {} to {} triangles for the "
                                "per-vertex exitance", median, spacing, before,
                                mesh.triangleCount()));
  }

  // The operator for the scene and parameters: cached on disk, uploaded once per key (the key is
  // made only after prepare() or a change of nodes, photons or seed, not every frame).
  void buildOperator() {
    if (!operatorDirty) return;
    if (scattering() == "single") {  // no operator: the mesh for the G-buffer pass only
      if (opKey != "single") techniques::uploadMeshStorage(mesh, meshVertices, meshTriangles);
      opKey = "single";
      operatorDirty = false;
      return;
    }
    const scene::Scene& s = *scene;
    const TransferOptions o = options();
    const std::string key = operatorKey(s, o);
    if (key == opKey) {
      operatorDirty = false;
      return;
    }
    opKey.clear();
    // The largest storage buffer the driver takes must hold one channel's matrix.
    GLint64 maxBlock = 0;
    glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &maxBlock);
    const uint64_t matrixBytes =
        incidenceMatrices(o.incidence) * uint64_t(o.nodes) * uint64_t(o.nodes) * sizeof(float);
    if (maxBlock > 0 && matrixBytes > uint64_t(maxBlock))
      throw ParameterError(fmt::format(
          "transfer: nodes {} needs a {:.0f} MiB matrix per channel; the GL driver's storage "
          "buffers hold at most {:.0f} MiB: use fewer nodes", o.nodes,
          double(matrixBytes) / 1048576.0, double(maxBlock) / 1048576.0));
    if (params.getEnum("incidence") != "normal" && !tiltReachable())
      notes.push_back(fmt::format("transfer: incidence {}: η = {} refracts no outside light {}° "
                                  "from the normal (the tilted beams'); normal incidence used",
                                  params.getEnum("incidence"), s.medium.eta,
                                  std::lround(std::asin(kTilt) * 180.0 / std::numbers::pi)));
    refineCoarseMesh(o.nodes);
    const material::Material mat = scene::sceneMaterial(s, mesh);
    CachedTransfer cached = loadOrBuildTransferOperator(mesh, techniques::vertexNormals(mesh), mat,
                                                        o, key, geometry::defaultCacheDirectory());
    op = std::move(cached.op);
    notes.push_back(fmt::format(
        "transfer: {} nodes, {} photons per node and channel: {:.1f} s of path tracing ({} "
        "photons), {:.1f} MiB; {} {}", op.nodes, o.photons, op.seconds, op.photons,
        double(op.bytes()) / 1048576.0, cached.fromCache ? "read from" : "cached in",
        cached.file.string()));
    if (!cached.note.empty()) notes.push_back("transfer cache: " + cached.note);
    if (op.missedEntries > 0)
      notes.push_back(fmt::format("transfer: {} of {} node discs were not entered by their beam "
                                  "(their columns are 0)", op.missedEntries, op.nodes));

    // The irradiance pass's points (PcPoint: position and area, normal): the cells' samples.
    const size_t samples = op.samplePositions.size();
    std::vector<glm::vec4> pts(2 * samples);
    for (size_t k = 0; k < samples; ++k) {
      pts[2 * k] = glm::vec4(op.samplePositions[k], op.areas[k / kCellSamples] / float(kCellSamples));
      pts[2 * k + 1] = glm::vec4(op.sampleNormals[k], 0.0f);
    }
    points = gpu::makeStorageBuffer(std::span<const glm::vec4>(pts));
    std::vector<glm::vec4> frame(2 * op.nodes);
    for (size_t i = 0; i < op.nodes; ++i) {
      frame[2 * i] = glm::vec4(op.normals[i], 0.0f);
      frame[2 * i + 1] = glm::vec4(op.tangents[i], 0.0f);
    }
    frames = gpu::makeStorageBuffer(std::span<const glm::vec4>(frame));
    nodeIrradiance = gpu::makeStorageBuffer(op.nodes * sizeof(glm::vec4));
    tilted = gpu::makeStorageBuffer(2 * op.nodes * sizeof(glm::vec4));
    const size_t plane = op.matrices * op.nodes * op.nodes;
    for (size_t c = 0; c < 3; ++c)
      matrix[c] = gpu::makeStorageBuffer(std::span<const float>(op.matrix.data() + c * plane, plane));
    nodeExitance = gpu::makeStorageBuffer(op.nodes * sizeof(glm::vec4));
    vertexNodes = gpu::makeStorageBuffer(std::span<const uint32_t>(op.vertexNodes));
    vertexWeights = gpu::makeStorageBuffer(std::span<const float>(op.vertexWeights));
    vertexExitance = gpu::makeStorageBuffer(mesh.vertexCount() * sizeof(glm::vec4));
    techniques::uploadMeshStorage(mesh, meshVertices, meshTriangles);
    gpu::checkGlError("uploading the transfer operator");
    lightingDirty = true;
    opKey = key;
    operatorDirty = false;
  }

  // The camera's G-buffer, and the per-pixel outputs sized for the image.
  void gbufferAndOutputs(int width, int height) {
    const scene::Scene& s = *scene;
    {
      auto t = timer->scope("g-buffer");
      gbuffer.resize(width, height);
      const glm::mat4 vp = techniques::cameraViewProjection(s.camera, s.clip_near, s.clip_far,
                                                            center, radius, width, height);
      gbuffer.render(*gpuMesh, *gbufferProgram, vp);
    }
    const size_t pixels = size_t(width) * size_t(height);
    if (pixels != outPixels) {
      radianceOut = gpu::makeStorageBuffer(pixels * sizeof(glm::vec4));
      exitanceOut = gpu::makeStorageBuffer(pixels * sizeof(glm::vec4));
      outPixels = pixels;
    }
  }

  techniques::Frame render(const techniques::FrameRequest& request) {
    if (!scene) throw ParameterError("transfer: render() before prepare(): expected a scene");
    const scene::Scene& s = *scene;
    const auto [width, height] = techniques::frameSize(request, s.camera);
    buildPrograms();
    buildOperator();
    if (!timer) timer.emplace();
    techniques::Frame frame;
    frame.notes = std::move(notes);
    notes.clear();

    const std::string mode = scattering();
    if (mode != "operator" && singleDirty) {
      single.prepare(mesh, fmt::format("{}|{}", meshKey, mesh.triangleCount()), s, "transfer");
      singleDirty = false;
    }
    if (mode == "single") return renderSingle(request, width, height, std::move(frame));
    const bool reuse = !lightingDirty;
    if (lightingDirty) lighting.restartEnvironment();
    lightingDirty = false;
    const bool lit = lighting.update(*gpuMesh, points, op.samplePositions.size(),
                                     static_cast<float>(s.medium.eta),
                                     techniques::shadowLookup(params),
                                     techniques::environmentBudget(params, request.converge),
                                     &*timer, reuse);
    if (lighting.hasOccludedEnvironment()) frame.converged = lit;
    const bool firstOrder = op.matrices >= 3;
    {
      auto t = timer->scope("cells");
      const gpu::ShaderProgram& cells = firstOrder ? *cellsFirstOrder : *cellsNormal;
      gpu::bindStorage(kIrradiance, lighting.irradiance());
      gpu::bindStorage(kLightDirections, lighting.lightDirections());
      gpu::bindStorage(kFrames, frames);
      gpu::bindStorage(kNodeIrradiance, nodeIrradiance);
      gpu::bindStorage(kTilted, tilted);
      cells.set("Nodes", static_cast<unsigned>(op.nodes));
      if (firstOrder) cells.set("Eta", static_cast<float>(s.medium.eta));
      gpu::dispatch1D(cells, op.nodes);
    }
    {
      auto t = timer->scope("transfer");
      const gpu::ShaderProgram& apply =
          op.matrices == incidenceMatrices(Incidence::Secant) ? *applySecant
          : firstOrder                                        ? *applyFirstOrder
                                                              : *applyNormal;
      gpu::bindStorage(kNodeIrradiance, nodeIrradiance);
      if (firstOrder) gpu::bindStorage(kTilted, tilted);
      if (op.matrices == incidenceMatrices(Incidence::Secant)) apply.set("Tilt", float(kTilt));
      gpu::bindStorage(kMatrixR, matrix[0]);
      gpu::bindStorage(kMatrixG, matrix[1]);
      gpu::bindStorage(kMatrixB, matrix[2]);
      gpu::bindStorage(kNodeExitance, nodeExitance);
      apply.set("Nodes", static_cast<unsigned>(op.nodes));
      gpu::dispatch1D(apply, op.nodes);
    }
    {
      auto t = timer->scope("vertices");
      gpu::bindStorage(kNodeExitance, nodeExitance);
      gpu::bindStorage(kVertexNodeList, vertexNodes);
      gpu::bindStorage(kVertexWeights, vertexWeights);
      gpu::bindStorage(kVertexExitance, vertexExitance);
      vertexProgram->set("Vertices", static_cast<unsigned>(mesh.vertexCount()));
      gpu::dispatch1D(*vertexProgram, mesh.vertexCount());
    }
    gbufferAndOutputs(width, height);
    {
      auto t = timer->scope("radiance");
      const gpu::ShaderProgram& p = *radianceProgram;
      gpu::bindStorage(kVertexExitance, vertexExitance);
      gpu::bindStorage(kMeshVertices, meshVertices);
      gpu::bindStorage(kMeshTriangles, meshTriangles);
      gpu::bindStorage(kRadianceOut, radianceOut);
      gpu::bindStorage(kExitanceOut, exitanceOut);
      techniques::setExitRadianceUniforms(p, gbuffer, s, params, width, height);
      gpu::dispatch(p, {(unsigned(width) + 7u) / 8u, (unsigned(height) + 7u) / 8u, 1u});
    }
    const techniques::SingleScatteringOptions so = techniques::singleScatteringOptions(params);
    if (mode == "split")
      single.render(gbuffer, meshVertices, meshTriangles, s, so, radianceOut, exitanceOut, &*timer);
    specular.add(gbuffer, s, params, radianceOut, &*timer);
    gpu::checkGlError("transfer frame");
    return finish(std::move(frame), request, width, height, mode == "split" && so.directions == 0);
  }

  // scattering single: the G-buffer and single scattering alone (no operator, no lighting pass).
  techniques::Frame renderSingle(const techniques::FrameRequest& request, int width, int height,
                                 techniques::Frame frame) {
    const scene::Scene& s = *scene;
    gbufferAndOutputs(width, height);
    const float zero = 0.0f;
    glClearNamedBufferData(radianceOut.id(), GL_R32F, GL_RED, GL_FLOAT, &zero);
    glClearNamedBufferData(exitanceOut.id(), GL_R32F, GL_RED, GL_FLOAT, &zero);
    const techniques::SingleScatteringOptions so = techniques::singleScatteringOptions(params);
    single.render(gbuffer, meshVertices, meshTriangles, s, so, radianceOut, exitanceOut, &*timer);
    specular.add(gbuffer, s, params, radianceOut, &*timer);
    gpu::checkGlError("transfer frame (single scattering)");
    return finish(std::move(frame), request, width, height, so.directions == 0);
  }

  techniques::Frame finish(techniques::Frame frame, const techniques::FrameRequest& request,
                           int width, int height, bool noSingleExitance) {
    frame.width = width;
    frame.height = height;
    const size_t pixels = size_t(width) * size_t(height);
    if (request.readback) techniques::readRadianceAndExitance(frame, radianceOut, exitanceOut, pixels);
    // single_directions 0: the exitance would lack single scattering (a silently wrong layer).
    if (noSingleExitance) frame.layers.erase("exitance");
    techniques::addPasses(frame, *timer);
    return frame;
  }
};

TransferTechnique::TransferTechnique() : impl_(std::make_unique<Impl>()) {}
TransferTechnique::~TransferTechnique() = default;

std::string_view TransferTechnique::description() const {
  return "precomputed subsurface transfer of a static mesh, path-traced once (in the spirit of "
         "Wang et al. 2005 and Hašan et al. 2006)";
}

const std::vector<ParameterInfo>& TransferTechnique::parameters() const {
  return impl_->params.infos();
}

void TransferTechnique::setParameter(std::string_view name, const ParameterValue& value) {
  if (!impl_->params.set(name, value)) return;
  if (name == "nodes" || name == "photons" || name == "seed" || name == "incidence" ||
      name == "scattering")
    impl_->operatorDirty = true;
  if (name == "scattering") impl_->singleDirty = true;
  if (name == "shadow_map_size" && impl_->scene)
    impl_->lighting.prepareLights(*impl_->scene, impl_->center, impl_->radius,
                                  impl_->params.getInt("shadow_map_size"), "transfer");
  if (name.starts_with("shadow_") || name.starts_with("ibl_")) impl_->lightingDirty = true;
}

ParameterValue TransferTechnique::parameter(std::string_view name) const {
  return impl_->params.get(name);
}

void TransferTechnique::prepare(const scene::Scene& scene, gpu::Context& gl) {
  gl.makeCurrent();
  scene.camera.validate();
  scene.medium.validate();
  if (!scene.mesh_deform.empty())
    throw ParameterError(
        "mesh.deform: the transfer technique precomputes the transport of one shape and renders "
        "static meshes only: expected no deformation, or the pointcloud or splatting technique");
  impl_->buildPrograms();
  if (impl_->loadClosedMesh(scene)) impl_->opKey.clear();
  impl_->operatorDirty = true;
  impl_->lighting.prepareLights(scene, impl_->center, impl_->radius,
                                impl_->params.getInt("shadow_map_size"), "transfer");
  impl_->lightingDirty = true;
  impl_->scene = scene;
  impl_->singleDirty = true;
  if (impl_->scattering() != "operator" && impl_->params.getInt("single_directions") == 0)
    impl_->notes.push_back("transfer: single_directions 0: no exitance layer (single "
                           "scattering's exitance is not computed)");
  if (impl_->params.getEnum("scattering") == "auto" && impl_->scattering() == "operator")
    impl_->notes.push_back("transfer: scattering auto: " + techniques::singleScatteringRefusal(scene) +
                           "; every order goes through the operator");
  if (impl_->scattering() != "operator")
    if (const std::string why = techniques::singleScatteringRefusal(scene); !why.empty())
      throw ParameterError(fmt::format("{}: expected the transfer technique's scattering "
                                       "'operator'", why));
  impl_->buildOperator();
}

techniques::Frame TransferTechnique::render(const techniques::FrameRequest& request) {
  return impl_->render(request);
}

bool TransferTechnique::setCamera(const reference::Camera& camera) {
  if (!impl_->scene) return false;
  camera.validate();
  impl_->scene->camera = camera;
  return true;
}

const TransferOperator& TransferTechnique::transferOperator() const { return impl_->op; }
const geometry::TriangleMesh& TransferTechnique::mesh() const { return impl_->mesh; }

std::vector<glm::vec3> TransferTechnique::gpuIrradiance() const {
  const auto v = gpu::download<glm::vec4>(impl_->nodeIrradiance, impl_->op.nodes);
  return {v.begin(), v.end()};
}
std::array<std::vector<glm::vec3>, 2> TransferTechnique::gpuTiltedIrradiance() const {
  std::array<std::vector<glm::vec3>, 2> out;
  if (impl_->op.matrices < 3) return out;
  const auto v = gpu::download<glm::vec4>(impl_->tilted, 2 * impl_->op.nodes);
  for (size_t i = 0; i < impl_->op.nodes; ++i) {
    out[0].emplace_back(v[2 * i]);
    out[1].emplace_back(v[2 * i + 1]);
  }
  return out;
}
std::vector<glm::vec3> TransferTechnique::gpuNodeExitance() const {
  const auto v = gpu::download<glm::vec4>(impl_->nodeExitance, impl_->op.nodes);
  return {v.begin(), v.end()};
}

std::unique_ptr<techniques::Technique> makeTransferTechnique() {
  return std::make_unique<TransferTechnique>();
}

}  // namespace translucent::transfer
