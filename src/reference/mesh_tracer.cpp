// Embree-backed mesh body and the mesh path tracer (mesh_tracer.h).
#include "reference/mesh_tracer.h"

#include <fmt/format.h>

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
  tally_ = std::make_unique<ImageTally>(body_, camera, etas, cone_half_angle);
}

TransportStats MeshPathTracer::addPass(uint64_t photons, const ProgressCallback& progress) {
  TransportOptions o;
  o.photons = photons;
  o.seed = options_.seed;
  o.threads = options_.threads;
  o.long_path_roulette = options_.long_path_roulette;
  o.first_block = stats_.next_block;
  TransportStats pass = volume_ ? tracePhotons(body_, *volume_, lights_, o, *tally_, progress)
                                : tracePhotons(body_, channels_, lights_, o, *tally_, progress);
  tally_->addPhotons(pass.photons);
  stats_.merge(pass);
  return pass;
}

}  // namespace translucent::reference
