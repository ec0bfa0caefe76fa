// SPDX-License-Identifier: GPL-3.0-or-later
// Embree-backed mesh body and the mesh path tracer (mesh_tracer.h).
#include "translucent/reference/mesh_tracer.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <glm/geometric.hpp>

namespace translucent::reference {
namespace {
// The checks run before the BVH is built (the member initialiser).
const geometry::TriangleMesh& closedMesh(const geometry::TriangleMesh& mesh, const std::string& what) {
  mesh.validate(what);
  mesh.requireClosed(what);
  return mesh;
}
}  // namespace

// A high-quality BVH: the walk casts many rays per triangle.
MeshBody::MeshBody(const geometry::TriangleMesh& mesh, const std::string& what)
    : scene_(closedMesh(mesh, what), what, geometry::RayScene::Quality::High) {
  const geometry::Bounds b = mesh.bounds();
  bounds_ = {b.center(), b.radius() * (1.0 + 1e-6)};
  epsilon_ = 1e-5 * (glm::length(bounds_.center) + bounds_.radius);
  triangles_ = mesh.triangleCount();
}

MeshBody::~MeshBody() = default;

bool MeshBody::intersect(const glm::dvec3& o, const glm::dvec3& d, double t_min, double t_max,
                         SurfaceHit& hit) const {
  geometry::RayHit h;
  if (!scene_.intersect(o, d, t_min, t_max, h)) return false;
  hit.t = h.t;
  hit.normal = h.normal;
  return true;
}

bool MeshBody::inside(const glm::dvec3& p) const { return geometry::insideClosedMesh(scene_, p); }

bool MeshBody::occluded(const glm::dvec3& o, const glm::dvec3& d, double t_min,
                        double t_max) const {
  return scene_.occluded(o, d, t_min, t_max);
}

// ---------------------------------------------------------------------------------------------

MeshPathTracer::MeshPathTracer(const geometry::TriangleMesh& mesh, const Medium& medium,
                               std::vector<Light> lights, const Camera& camera,
                               double cone_half_angle, const TracerOptions& options)
    : lights_(std::move(lights)), options_(options), body_(mesh) {
  medium.validate();
  for (int c = 0; c < 3; ++c) channels_.push_back(medium.channel(c));
  init(camera, cone_half_angle);
}

MeshPathTracer::MeshPathTracer(const geometry::TriangleMesh& mesh, const ScalarMedium& medium,
                               std::vector<Light> lights, const Camera& camera,
                               double cone_half_angle, const TracerOptions& options)
    : channels_{medium}, lights_(std::move(lights)), options_(options), body_(mesh) {
  medium.validate();
  init(camera, cone_half_angle);
}

namespace {
std::vector<ScalarMedium> materialChannels(const material::Material& m) {
  if (m.kind == material::Material::Kind::Surface)
    throw ParameterError(
        "mesh tracer: a surface-map material (2D maps over the atlas) has no volume to trace; "
        "its reference is the compare report's model reference (brute-force Eq. 8)");
  m.medium.validate();
  std::vector<ScalarMedium> ch;
  for (int c = 0; c < 3; ++c) ch.push_back(m.medium.channel(c));
  return ch;
}
}  // namespace

MeshPathTracer::MeshPathTracer(const geometry::TriangleMesh& mesh, const material::Material& material,
                               std::vector<Light> lights, const Camera& camera,
                               double cone_half_angle, const TracerOptions& options,
                               glm::ivec3 majorant_cells)
    : channels_(materialChannels(material)), lights_(std::move(lights)), options_(options),
      body_(mesh) {
  if (material.kind == material::Material::Kind::Volume) {
    // The grid over the mesh's box, enlarged by a hair so that boundary points are inside it.
    const geometry::Bounds b = mesh.bounds();
    const glm::dvec3 pad(1e-6 * (glm::length(b.center()) + b.radius()));
    volume_ = VolumeMedium::make(material, b.lower - pad, b.upper + pad, majorant_cells);
  }
  init(camera, cone_half_angle);
}

void MeshPathTracer::init(const Camera& camera, double cone_half_angle) {
  if (lights_.empty()) throw ParameterError("mesh tracer: no lights: expected at least one");
  for (size_t i = 0; i < lights_.size(); ++i)
    lights_[i] = lights_[i].validated(fmt::format("light {}", i + 1));
  std::vector<double> etas;
  for (const auto& c : channels_) etas.push_back(c.eta);
  // What a photon carries (transport.h: every photon of a channel carries the channel's total
  // flux), the largest channel's: the grid of the images' exact sums.
  double flux = 0.0;
  for (size_t c = 0; c < channels_.size(); ++c) {
    double channel = 0.0;
    for (const Light& l : lights_) channel += emittedFlux(l, body_.bounds(), static_cast<int>(c));
    flux = std::max(flux, channel);
  }
  tally_ = std::make_unique<ImageTally>(body_, camera, etas, cone_half_angle, flux,
                                        options_.split_orders);
}

TransportStats MeshPathTracer::addPass(uint64_t photons, const ProgressCallback& progress) {
  return addBlocks(stats_.next_block, (photons + kBlockPhotons - 1) / kBlockPhotons, progress);
}

TransportStats MeshPathTracer::addBlocks(uint64_t first, uint64_t blocks,
                                         const ProgressCallback& progress) {
  if (stats_.photons.empty()) stats_ = emptyStats(body_.bounds(), channels_.size(), lights_);
  // An empty share (more shards than blocks) traces nothing; its state is zero.
  if (blocks == 0) return emptyStats(body_.bounds(), channels_.size(), lights_);
  TransportStats pass;
  if (walker_) {
    const MeshWalkSetup setup = walkSetup();
    pass = scoreWalkedBlocks(
        body_.bounds(), lights_, setup.channels, first, blocks,
        [&](int c, uint64_t b0, uint64_t nb, WalkedBatch& out) { walker_->trace(setup, c, b0, nb, out); },
        *tally_, progress);
  } else {
    TransportOptions o;
    o.photons = blocks * kBlockPhotons;
    o.seed = options_.seed;
    o.threads = options_.threads;
    o.long_path_roulette = options_.long_path_roulette;
    o.after_specular_only = options_.after_specular_only;
    o.first_block = first;
    pass = volume_ ? tracePhotons(body_, *volume_, lights_, o, *tally_, progress)
                   : tracePhotons(body_, channels_, lights_, o, *tally_, progress);
  }
  tally_->addPhotons(pass.photons);
  stats_.merge(pass);
  return pass;
}

MeshWalkSetup MeshPathTracer::walkSetup() const {
  MeshWalkSetup s;
  s.lights = lights_;
  s.bounds = body_.bounds();
  s.epsilon = body_.epsilon();
  s.channels = walkChannels(s.bounds, channels_, lights_);
  s.seed = options_.seed;
  s.long_path_roulette = options_.long_path_roulette;
  s.volume = volume_ ? &*volume_ : nullptr;
  s.after_specular_only = options_.after_specular_only;
  return s;
}

void MeshPathTracer::write(RunState& state) const {
  tally_->write(state, "images");
  stats_.write(state, "stats");
  state.putCounts("majorant_violations", {majorantViolations()});
}

void MeshPathTracer::read(const RunState& state, double seconds, int threads) {
  tally_->read(state, "images");
  if (stats_.photons.empty()) stats_ = emptyStats(body_.bounds(), channels_.size(), lights_);
  stats_.read(state, "stats");
  stats_.seconds = seconds;
  stats_.threads = threads;
  stats_.partial = false;
  mergedMajorantViolations_ = state.getCounts("majorant_violations", 1)[0];
}

}  // namespace translucent::reference
