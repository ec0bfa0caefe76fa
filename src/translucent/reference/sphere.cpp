// SPDX-License-Identifier: GPL-3.0-or-later
// The lit sphere path tracer (sphere.h): the transport walk instantiated for the analytic sphere.
#include "translucent/reference/sphere.h"

#include <fmt/format.h>

#include <numbers>

#include "translucent/reference/transport_impl.h"

namespace translucent::reference {

namespace {
bool finiteNonZero(const glm::dvec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) && glm::length(v) > 0.0;
}
}  // namespace

void SphereScene::validate() const {
  // (1e-320 and 1e300 failed later as a camera at its own look-at point or with no up.)
  if (!std::isfinite(radius) || !(radius >= 1e-6 && radius <= 1e6))
    throw ParameterError(fmt::format("sphere: radius is {}: expected a value in [1e-6, 1e6]", radius));
  if (!finiteNonZero(light_direction))
    throw ParameterError("sphere: light direction must be a finite non-zero vector");
  if (!std::isfinite(irradiance) || !(irradiance > 0.0))
    throw ParameterError(
        fmt::format("sphere: irradiance is {}: expected a finite value > 0", irradiance));
  if (!finiteNonZero(view_direction))
    throw ParameterError("sphere: view direction must be a finite non-zero vector");
  if (!finiteNonZero(up)) throw ParameterError("sphere: up must be a finite non-zero vector");
  if (!std::isfinite(margin) || !(margin > 0.0))
    throw ParameterError(fmt::format("sphere: margin is {}: expected a finite value > 0", margin));
  if (!(cone_half_angle > 0.0 && cone_half_angle <= 90.0))
    throw ParameterError(fmt::format(
        "sphere: cone half-angle is {} degrees: expected a value in (0, 90]", cone_half_angle));
  camera().validate();
}

Camera SphereScene::camera() const {
  Camera c;
  c.projection = Camera::Projection::Orthographic;
  const glm::dvec3 v = glm::normalize(view_direction);
  c.position = 3.0 * radius * v;
  c.look_at = glm::dvec3(0.0);
  // Any up that is not along the view will do; fall back to another axis when it is.
  c.up = up;
  if (glm::length(glm::cross(glm::normalize(up), v)) < 1e-6)
    c.up = std::abs(v.x) < 0.9 ? glm::dvec3(1.0, 0.0, 0.0) : glm::dvec3(0.0, 1.0, 0.0);
  c.view_height = 2.0 * radius * margin;
  c.width = width;
  c.height = height;
  return c;
}

Light SphereScene::light() const {
  return Light{DirectionalLight{glm::normalize(light_direction), irradiance}, {1.0, 1.0, 1.0}};
}

namespace {
std::vector<double> etasOf(const std::vector<ScalarMedium>& channels) {
  std::vector<double> etas;
  for (const auto& c : channels) etas.push_back(c.eta);
  return etas;
}
}  // namespace

SpherePathTracer::SpherePathTracer(const SphereScene& scene, const Medium& medium,
                                   const TracerOptions& options)
    : scene_(scene), options_(options), body_(scene.radius) {
  scene_.validate();
  medium.validate();
  for (int c = 0; c < 3; ++c) channels_.push_back(medium.channel(c));
  tally_ = std::make_unique<ImageTally>(body_, scene_.camera(), etasOf(channels_),
                                        scene_.cone_half_angle, photonFlux(),
                                        options_.split_orders);
}

SpherePathTracer::SpherePathTracer(const SphereScene& scene, const ScalarMedium& medium,
                                   const TracerOptions& options)
    : scene_(scene), channels_{medium}, options_(options), body_(scene.radius) {
  scene_.validate();
  medium.validate();
  tally_ = std::make_unique<ImageTally>(body_, scene_.camera(), etasOf(channels_),
                                        scene_.cone_half_angle, photonFlux(),
                                        options_.split_orders);
}

TransportStats SpherePathTracer::addPass(uint64_t photons, const ProgressCallback& progress) {
  TransportStats pass = addBlocks(stats_.next_block, (photons + kBlockPhotons - 1) / kBlockPhotons,
                                  progress);
  ++passes_;
  return pass;
}

TransportStats SpherePathTracer::addBlocks(uint64_t first, uint64_t blocks,
                                           const ProgressCallback& progress) {
  const Light light = scene_.light();
  const std::span<const Light> lights(&light, 1);
  if (stats_.photons.empty()) stats_ = emptyStats(body_.bounds(), channels_.size(), lights);
  // An empty share (more shards than blocks) traces nothing; its state is zero.
  if (blocks == 0) return emptyStats(body_.bounds(), channels_.size(), lights);
  TransportStats pass;
  if (walker_) {
    const SphereWalkSetup setup = walkSetup();
    pass = scoreWalkedBlocks(
        body_.bounds(), lights, setup.channels, first, blocks,
        [&](int c, uint64_t b0, uint64_t nb, WalkedBatch& out) { walker_->trace(setup, c, b0, nb, out); },
        *tally_, progress);
  } else {
    TransportOptions o;
    o.photons = blocks * kBlockPhotons;
    o.seed = options_.seed;
    o.threads = options_.threads;
    o.long_path_roulette = options_.long_path_roulette;
    o.first_block = first;
    pass = detail::traceBlocks(body_, channels_, lights, o, *tally_, progress);
  }
  tally_->addPhotons(pass.photons);
  stats_.merge(pass);
  return pass;
}

SphereWalkSetup SpherePathTracer::walkSetup() const {
  const Light light = scene_.light();
  SphereWalkSetup s;
  s.radius = scene_.radius;
  s.light_direction = std::get<DirectionalLight>(light.emitter).direction;
  s.channels = walkChannels(body_.bounds(), channels_, std::span<const Light>(&light, 1));
  s.seed = options_.seed;
  s.long_path_roulette = options_.long_path_roulette;
  return s;
}

double SpherePathTracer::photonFlux() const {
  return scene_.irradiance * std::numbers::pi * scene_.radius * scene_.radius;
}

void SpherePathTracer::write(RunState& state) const {
  tally_->write(state, "images");
  stats_.write(state, "stats");
}

void SpherePathTracer::read(const RunState& state, double seconds, int threads) {
  tally_->read(state, "images");
  if (stats_.photons.empty()) {
    const Light light = scene_.light();
    stats_ = emptyStats(body_.bounds(), channels_.size(), std::span<const Light>(&light, 1));
  }
  stats_.read(state, "stats");
  stats_.seconds = seconds;
  stats_.threads = threads;
  stats_.partial = false;
}

}  // namespace translucent::reference
