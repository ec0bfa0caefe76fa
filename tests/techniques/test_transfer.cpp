// SPDX-License-Identifier: GPL-3.0-or-later
// The transfer technique (techniques/transfer): its operator against the path tracer it is made
// from, the GPU passes against the CPU, and its image against the mesh path tracer's.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <numbers>

#include <glm/geometric.hpp>

#include "translucent/geometry/icosphere.h"
#include "translucent/geometry/point_grid.h"
#include "translucent/optics/fresnel.h"
#include "translucent/reference/mesh_tracer.h"
#include "translucent/reference/surface_transfer.h"
#include "translucent/techniques/common/gl_resources.h"
#include "translucent/techniques/registry.h"
#include "translucent/techniques/transfer/transfer_technique.h"
#include "render_helpers.h"

namespace translucent::transfer {
namespace {

using pointcloud::testing::TempDir;
using pointcloud::testing::writeObj;

// A unit sphere of a moderately absorbing medium (some 10 mean free paths across, walks of a few
// tens of events: the tests stay fast) with a refractive boundary, lit by a sun along +z.
Medium sphereMedium() { return Medium::fromReduced({0.2, 0.5, 1.0}, {40.0, 40.0, 40.0}, 0.0, 1.3, 1.0); }
constexpr int kBands = 8;  // of cos θ = n · z in [-1, 1]
int band(double cosTheta) { return std::clamp(int((cosTheta + 1.0) / 2.0 * kBands), 0, kBands - 1); }

// The exiting flux per band of the exit normal, from photons of the sun (the path tracer).
class BandTally final : public reference::ExitTally {
 public:
  explicit BandTally(std::function<int(const reference::ExitRecord&)> bandOf) : bandOf_(std::move(bandOf)) {}
  struct Sums {
    std::array<std::array<reference::Moments, kBands>, 3> m{};
  };
  class Block final : public reference::ExitTally::Block {
   public:
    explicit Block(const BandTally& t) : tally(t) {}
    void record(const reference::ExitRecord& e) override {
      photon[size_t(e.channel)][size_t(tally.bandOf_(e))] += e.weight;
      channel = e.channel;
    }
    void endPhoton() override {
      for (size_t c = 0; c < 3; ++c)
        for (size_t b = 0; b < kBands; ++b) {
          if (photon[c][b] != 0.0) sums.m[c][b].add(photon[c][b]);
          photon[c][b] = 0.0;
        }
    }
    Sums sums;
    std::array<std::array<double, kBands>, 3> photon{};
    int channel = 0;
    const BandTally& tally;
  };
  std::unique_ptr<reference::ExitTally::Block> newBlock() const override {
    return std::make_unique<Block>(*this);
  }
  void merge(reference::ExitTally::Block& b) override {
    const auto& s = static_cast<Block&>(b).sums;
    for (size_t c = 0; c < 3; ++c)
      for (size_t k = 0; k < kBands; ++k) total.m[c][k].merge(s.m[c][k]);
  }
  Sums total;

 private:
  std::function<int(const reference::ExitRecord&)> bandOf_;
};

geometry::TriangleMesh unitSphere() {
  geometry::TriangleMesh m = geometry::makeIcosphere(4, 1.0);
  m.orientOutwards();
  return m;
}

// The sun along +z on a sphere: the transmitted irradiance E_j = E0 Ft(η, cos θ_j) cos θ_j per
// node (a convex body: no shadow but its own back) and the first-order inputs E^u = E τ·u,
// E^v = E τ·v of its refracted direction, τ = -(z - (z·n) n) / η (transfer_operator.h).
struct SunInputs {
  std::vector<glm::vec3> E, Eu, Ev;
};
SunInputs sunInputs(const TransferOperator& op, const Medium& medium, double E0) {
  SunInputs in;
  for (size_t j = 0; j < op.nodes; ++j) {
    const double mu = std::max(0.0, double(op.normals[j].z));
    const glm::vec3 e(float(E0 * mu * (1.0 - fresnelReflectance(mu, medium.eta))));
    const glm::dvec3 n(op.normals[j]), u(op.tangents[j]), v = glm::cross(n, u), z(0.0, 0.0, 1.0);
    const glm::dvec3 tau = -(z - glm::dot(z, n) * n) / medium.eta;
    in.E.push_back(e);
    in.Eu.push_back(e * float(glm::dot(tau, u)));
    in.Ev.push_back(e * float(glm::dot(tau, v)));
  }
  return in;
}

using Bands = std::array<std::array<double, kBands>, 3>;

// The operator's exiting flux per band of the node normal (cos θ = n · z).
Bands operatorBands(const TransferOperator& op, const std::vector<glm::vec3>& B) {
  Bands F{};
  for (int c = 0; c < 3; ++c)
    for (size_t i = 0; i < op.nodes; ++i)
      F[size_t(c)][size_t(band(op.normals[i].z))] += double(B[i][c]) * double(op.areas[i]);
  return F;
}

// The variance of the normal part's band fluxes, from the per-entry Bernoulli-like scores (each
// photon of a convex body exits at most once: Var p̂ <= p̂ (1 - p̂) / photons).
Bands operatorBandVariance(const TransferOperator& op, const std::vector<glm::vec3>& E,
                           uint64_t photons) {
  Bands var{};
  for (size_t c = 0; c < 3; ++c)
    for (size_t j = 0; j < op.nodes; ++j) {
      std::array<double, kBands> p{};
      for (size_t i = 0; i < op.nodes; ++i)
        p[size_t(band(op.normals[i].z))] +=
            double(op.matrix[(c * op.matrices * op.nodes + i) * op.nodes + j]) *
            double(op.areas[i]) / double(op.areas[j]);
      const double phi = double(E[j][int(c)]) * double(op.areas[j]);
      for (int b = 0; b < kBands; ++b)
        var[c][size_t(b)] += phi * phi * std::clamp(p[size_t(b)] * (1.0 - p[size_t(b)]), 0.0, 0.25) /
                             double(photons);
    }
  return var;
}

// The path tracer's photons from that sun, their exits binned as the operator bins them (the
// nearest node on the exit's side, transfer_operator.h), then by that node's band: both sides
// then sum over the same cells. Per channel and band: flux and standard error.
std::array<std::array<reference::Estimate, kBands>, 3> pathTracedBands(
    const TransferOperator& op, const geometry::TriangleMesh& mesh, const Medium& medium,
    double E0) {
  reference::MeshBody body(mesh);
  std::vector<ScalarMedium> ch;
  for (int c = 0; c < 3; ++c) ch.push_back(medium.channel(c));
  reference::Light sun{reference::DirectionalLight{{0.0, 0.0, 1.0}, E0}, Rgb{1.0, 1.0, 1.0}};
  reference::TransportOptions to;
  to.photons = 400'000;
  to.seed = 11;
  to.threads = 2;
  const geometry::PointGrid grid(op.positions, std::sqrt(4.0 * std::numbers::pi / double(op.nodes)));
  BandTally tally([&](const reference::ExitRecord& e) {
    for (const auto& [d2, i] : grid.nearest(glm::vec3(e.position), kExitCandidates))
      if (glm::dot(glm::dvec3(op.normals[i]), e.normal) > 0.0) return band(op.normals[i].z);
    return band(e.normal.z);
  });
  const reference::TransportStats st =
      reference::tracePhotons(body, ch, std::span(&sun, 1), to, tally);
  std::array<std::array<reference::Estimate, kBands>, 3> out{};
  for (size_t c = 0; c < 3; ++c)
    for (size_t b = 0; b < kBands; ++b) out[c][b] = tally.total.m[c][b].estimate(st.photons[c]);
  return out;
}

TransferOperator sphereOperator(const geometry::TriangleMesh& mesh, const Medium& medium,
                                bool secant) {
  material::Material mat;
  mat.medium = medium;
  TransferOptions o;
  o.nodes = 512;
  o.photons = 256;
  o.seed = 7;
  o.threads = 2;
  o.incidence = secant ? Incidence::Secant : Incidence::FirstOrder;
  return buildTransferOperator(mesh, techniques::vertexNormals(mesh), mat, o);
}

// Band fluxes of the operator under the sun (with the tilted inputs and at normal incidence
// alone), the normal part's variance, and the path tracer's.
struct SphereBands {
  Bands tilted, normal, variance;
  std::array<std::array<reference::Estimate, kBands>, 3> traced;
};
SphereBands sphereBands(const geometry::TriangleMesh& mesh, const Medium& medium,
                        const TransferOperator& op) {
  const double E0 = 2.0;
  const SunInputs in = sunInputs(op, medium, E0);
  return {operatorBands(op, op.exitance(in.E, in.Eu, in.Ev)), operatorBands(op, op.exitance(in.E)),
          operatorBandVariance(op, in.E, 256), pathTracedBands(op, mesh, medium, E0)};
}

TEST(TransferOperator, MatchesThePathTracerOnALitSphere) {
  // The operator's exitance under the sun against the path tracer's photons from that sun, as
  // flux per band of the exit normal. What may differ beyond noise: the entries at normal
  // incidence (the first collision moves by less than a mean free path, 0.1 here) and the
  // binning into node cells (a cell that straddles a band edge): 2% of a band's flux is allowed
  // for both, plus 4 combined standard errors.
  const geometry::TriangleMesh mesh = unitSphere();
  const Medium medium = sphereMedium();
  const TransferOperator op = sphereOperator(mesh, medium, false);
  ASSERT_EQ(op.nodes, 512u);
  EXPECT_EQ(op.missedEntries, 0u);
  EXPECT_EQ(op.photons, 512u * 5u * 256u * 3u);  // five beams per node
  ASSERT_EQ(op.matrices, 3u);
  const SphereBands r = sphereBands(mesh, medium, op);
  const Bands &F = r.tilted, &F0 = r.normal, &var = r.variance;
  const auto& pts = r.traced;
  // Per channel: the total exiting flux, and per band of the node normal (cos θ = n · z).
  // Normal incidence (K⁰ alone, F0): the bands lit at μ >= 0.5 (6, 7) and the total within 3%
  // for the discretisation and 4 combined standard errors. In the bands lit at grazing incidence
  // (4, 5: μ < 0.5) the normal beams miss that refracted light of a grazing sun enters at up to
  // 50° (η = 1.3) towards the dark side: measured 5-17% less flux there (12-30% with 4x the mean
  // free path), held to 20% as a regression bound, not a claim of accuracy.
  // First order in the incident direction (F): every lit band within 8% (measured: at most 7%,
  // in the blue channel, where the mean free path is shortest), and the grazing band 4 closer to
  // the path tracer than with normal incidence, summed over the channels (measured 0.046 against
  // 0.099 of absolute error). The standard errors are the normal part's; the derivative terms,
  // from beams on the same random numbers, add less than the tolerances' margin.
  double litFlux = 0.0, grazingFirst = 0.0, grazingNormal = 0.0;
  for (size_t c = 0; c < 3; ++c) {
    double mine0 = 0.0, mine = 0.0, theirs = 0.0, theirsVar = 0.0, mineVar = 0.0;
    for (size_t b = 0; b < kBands; ++b) {
      const reference::Estimate pt = pts[c][b];
      const double sigma = std::sqrt(pt.std_error * pt.std_error + var[c][b]);
      mine0 += F0[c][b];
      mine += F[c][b];
      theirs += pt.value;
      theirsVar += pt.std_error * pt.std_error;
      mineVar += var[c][b];
      const double allowed = b >= 6 ? 0.03 : (b >= 4 ? 0.2 : -1.0);
      if (allowed > 0.0) {
        EXPECT_NEAR(F0[c][b], pt.value, allowed * pt.value + 4.0 * sigma) << "normal incidence, channel " << c << ", band " << b;
      }
      if (b >= 4) {
        EXPECT_NEAR(F[c][b], pt.value, 0.08 * pt.value + 4.0 * sigma) << "first order, channel " << c << ", band " << b;
      }
      if (b == 4) {
        grazingFirst += std::abs(F[c][b] - pt.value);
        grazingNormal += std::abs(F0[c][b] - pt.value);
      }
      if (b >= kBands / 2) litFlux += pt.value;
    }
    const double totalTol = 0.03 * theirs + 4.0 * std::sqrt(theirsVar + mineVar);
    EXPECT_NEAR(mine0, theirs, totalTol) << "normal incidence, channel " << c;
    EXPECT_NEAR(mine, theirs, totalTol) << "first order, channel " << c;
  }
  EXPECT_LT(grazingFirst, grazingNormal);
  EXPECT_GT(litFlux, 0.1);  // the test has something to compare
}

// incidence secant (five matrices, each node interpolated towards the beam on its light's side)
// on a sphere four times as translucent (some 2.5 mean free paths across the radius at the
// shortest), where light entering at grazing incidence is carried far along its own direction:
// the normal beams send it towards the centre instead, and the bands lit at grazing incidence
// come out far from the path tracer. Measured (seed 7, 512 nodes, 256 photons; 4·10⁵ photons of
// the sun): the normal beams 17-21% low at grazing incidence (band 4) and 8-9% high facing the
// sun (band 7); the secant within 3% + 4 standard errors in every lit band, its summed error a
// third of theirs (0.33 against 0.96; extending the line beyond the tilted beams instead of
// clamping gave 0.07 here, but overshot on the backlit bunny). Held to those bounds and to half
// the normal beams' summed error.
TEST(TransferOperator, SecantFollowsTheIncidenceOnATranslucentSphere) {
  const geometry::TriangleMesh mesh = unitSphere();
  const Medium medium = Medium::fromReduced({0.05, 0.125, 0.25}, {10.0, 10.0, 10.0}, 0.0, 1.3, 1.0);
  const TransferOperator op = sphereOperator(mesh, medium, true);
  ASSERT_EQ(op.matrices, 5u);
  const SphereBands r = sphereBands(mesh, medium, op);
  const Bands &F = r.tilted, &F0 = r.normal, &var = r.variance;
  const auto& pts = r.traced;
  double errSecant = 0.0, errNormal = 0.0;
  for (size_t c = 0; c < 3; ++c)
    for (size_t b = kBands / 2; b < kBands; ++b) {
      const reference::Estimate pt = pts[c][b];
      const double sigma = std::sqrt(pt.std_error * pt.std_error + var[c][b]);
      EXPECT_NEAR(F[c][b], pt.value, 0.03 * pt.value + 4.0 * sigma) << "channel " << c << ", band " << b;
      errSecant += std::abs(F[c][b] - pt.value);
      errNormal += std::abs(F0[c][b] - pt.value);
    }
  EXPECT_LT(errSecant, 0.5 * errNormal);
}

TEST(TransferOperator, CacheRoundTripsAndRefusesOtherKeys) {
  const geometry::TriangleMesh mesh = unitSphere();
  material::Material mat;
  mat.medium = sphereMedium();
  TransferOptions o;
  o.nodes = 64;
  o.photons = 16;
  TempDir dir;
  const CachedTransfer first =
      loadOrBuildTransferOperator(mesh, techniques::vertexNormals(mesh), mat, o, "key A", dir.path());
  EXPECT_FALSE(first.fromCache);
  EXPECT_TRUE(first.note.empty()) << first.note;
  const CachedTransfer again =
      loadOrBuildTransferOperator(mesh, techniques::vertexNormals(mesh), mat, o, "key A", dir.path());
  EXPECT_TRUE(again.fromCache);
  EXPECT_EQ(again.op.matrix, first.op.matrix);
  EXPECT_EQ(again.op.vertexWeights, first.op.vertexWeights);
  EXPECT_THROW((void)readTransferOperator(first.file, "key B"), std::runtime_error);
  // A truncated file is rebuilt, with a note.
  std::filesystem::resize_file(first.file, 100);
  const CachedTransfer rebuilt =
      loadOrBuildTransferOperator(mesh, techniques::vertexNormals(mesh), mat, o, "key A", dir.path());
  EXPECT_FALSE(rebuilt.fromCache);
  EXPECT_NE(rebuilt.note.find("truncated"), std::string::npos) << rebuilt.note;
  EXPECT_EQ(rebuilt.op.matrix, first.op.matrix);  // deterministic
}

TEST(TransferOperator, IsTheSameForAnyThreadCount) {
  const geometry::TriangleMesh mesh = unitSphere();
  material::Material mat;
  mat.medium = sphereMedium();
  TransferOptions o;
  o.nodes = 64;
  o.photons = 32;
  o.threads = 1;
  const TransferOperator one = buildTransferOperator(mesh, techniques::vertexNormals(mesh), mat, o);
  o.threads = 2;
  const TransferOperator two = buildTransferOperator(mesh, techniques::vertexNormals(mesh), mat, o);
  EXPECT_EQ(one.matrix, two.matrix);
}

class TransferGpu : public gpu::testing::GpuTest {};

// The GPU's node exitance against the CPU's product: equal to 1e-4 of the largest value (float
// sums in another order).
void expectSameExitance(const std::vector<glm::vec3>& cpu, const std::vector<glm::vec3>& gpuB) {
  ASSERT_EQ(cpu.size(), gpuB.size());
  double maxB = 0.0, maxDiff = 0.0;
  for (size_t i = 0; i < cpu.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      maxB = std::max(maxB, double(cpu[i][c]));
      maxDiff = std::max(maxDiff, std::abs(double(cpu[i][c]) - double(gpuB[i][c])));
    }
  ASSERT_GT(maxB, 0.0);
  EXPECT_LT(maxDiff, 1e-4 * maxB);
}

TEST_F(TransferGpu, RendersThePathTracersExitanceOfALitSphere) {
  pointcloud::testing::useTestCache();
  TempDir dir;
  const geometry::TriangleMesh mesh = unitSphere();
  scene::Scene s = pointcloud::testing::testScene(writeObj(mesh, dir.path() / "sphere.obj"), 32);
  s.medium = sphereMedium();
  s.lights[0].emitter = reference::DirectionalLight{{0.0, 0.0, 1.0}, 2.0};
  auto t = techniques::make("transfer");
  t->setParameter("nodes", 1024);
  t->setParameter("photons", 256);
  t->setParameter("scattering", std::string("operator"));
  t->prepare(s, gpu::testing::context());
  const techniques::Frame f = t->render({});
  auto& tt = dynamic_cast<TransferTechnique&>(*t);
  // split: the operator without single scattering, and single scattering per pixel (its
  // exitance over 8 exit directions); the same scene and nodes.
  auto split = techniques::make("transfer");
  split->setParameter("nodes", 1024);
  split->setParameter("photons", 256);
  split->setParameter("scattering", std::string("split"));
  split->setParameter("single_directions", 8);
  split->prepare(s, gpu::testing::context());
  const techniques::Frame fs = split->render({});

  // Each node's irradiance is the mean over its cell's samples (the sun along +z on a convex
  // body: E = E0 Ft(η, μ) μ where μ = n·z > 0); within 1% of the largest (the shadow map's
  // filtered edge at the terminator).
  const TransferOperator& op = tt.transferOperator();
  const std::vector<glm::vec3> nodeE = tt.gpuIrradiance();
  double maxE = 0.0, maxEDiff = 0.0;
  for (size_t j = 0; j < op.nodes; ++j) {
    double mean = 0.0;
    for (uint32_t k = 0; k < kCellSamples; ++k) {
      const double mu = std::max(0.0, double(op.sampleNormals[j * kCellSamples + k].z));
      mean += 2.0 * mu * (1.0 - fresnelReflectance(mu, s.medium.eta)) / kCellSamples;
    }
    maxE = std::max(maxE, mean);
    maxEDiff = std::max(maxEDiff, std::abs(double(nodeE[j].y) - mean));
  }
  EXPECT_LT(maxEDiff, 0.01 * maxE);

  // GPU transfer against the CPU's product with the same irradiance (incidence secant by
  // default: with the tilted inputs).
  ASSERT_EQ(op.matrices, 5u);
  const auto tilted = tt.gpuTiltedIrradiance();
  expectSameExitance(op.exitance(tt.gpuIrradiance(), tilted[0], tilted[1]), tt.gpuNodeExitance());

  // The image's exitance against the mesh path tracer's (the physical reference compare uses),
  // averaged over rings of the image disc (the sun is along the view: B depends on the ring).
  reference::TracerOptions po;
  po.seed = 5;
  po.threads = 2;
  const reference::Light sun{reference::DirectionalLight{{0.0, 0.0, 1.0}, 2.0}, Rgb{1.0, 1.0, 1.0}};
  reference::MeshPathTracer pt(tt.mesh(), s.medium, {sun}, s.camera, 5.0, po);
  pt.addPass(600'000);
  const auto& ref = pt.images().exitance;
  const int n = 32;
  std::array<std::vector<uint32_t>, 4> rings;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      // Pixel centre in units of the sphere's radius (view height 2.2).
      const double u = ((x + 0.5) / n - 0.5) * 2.2, v = ((y + 0.5) / n - 0.5) * 2.2;
      const double r = std::sqrt(u * u + v * v);
      if (r >= 0.9) continue;  // silhouette pixels: partial coverage
      const size_t k = size_t(r / 0.9 * 4.0);
      rings[k].push_back(uint32_t(y * n + x));
    }
  for (const techniques::Frame* frame : {&f, &fs}) {
    const auto& img = frame->layers.at("exitance");
    for (size_t k = 0; k < 4; ++k)
      for (int c = 0; c < 3; ++c) {
        ASSERT_FALSE(rings[k].empty());
        const reference::Estimate e = ref.average(rings[k], c);
        double mine = 0.0;
        for (uint32_t i : rings[k]) mine += double(img[size_t(i) * 3 + size_t(c)]);
        mine /= double(rings[k].size());
        // 3% for the discretisation (node cells, the vertex interpolation, the secant's linear
        // interpolation in the tilt) and the operator's noise (1024 nodes x 256 photons), plus
        // 4 standard errors.
        EXPECT_NEAR(mine, e.value, 0.03 * e.value + 4.0 * e.std_error)
            << (frame == &f ? "operator" : "split") << ", ring " << k << ", channel " << c;
      }
  }
}

TEST_F(TransferGpu, FirstOrderInputsAndProductMatchTheCpu) {
  // incidence first-order and secant: the tilt pass's E^u, E^v against the CPU's τ of a sun along
  // +z (transfer_operator.h: τ = -(z - (z·n) n) / η, shadowed nodes 0), and the GPU's product
  // (three matrices; five, interpolated per node) against TransferOperator::exitance.
  pointcloud::testing::useTestCache();
  for (const auto& [mode, matrices] : {std::pair{"first-order", 3u}, std::pair{"secant", 5u}}) {
  SCOPED_TRACE(mode);
  TempDir dir;
  scene::Scene s = pointcloud::testing::testScene(writeObj(unitSphere(), dir.path() / "sphere.obj"), 16);
  s.medium = sphereMedium();
  auto t = techniques::make("transfer");
  t->setParameter("nodes", 256);
  t->setParameter("photons", 32);
  t->setParameter("incidence", std::string(mode));
  t->prepare(s, gpu::testing::context());
  (void)t->render({});
  auto& tt = dynamic_cast<TransferTechnique&>(*t);
  const TransferOperator& op = tt.transferOperator();
  ASSERT_EQ(op.matrices, matrices);
  const auto E = tt.gpuIrradiance();
  const auto tilted = tt.gpuTiltedIrradiance();
  ASSERT_EQ(tilted[0].size(), op.nodes);
  double maxE = 0.0, maxTiltDiff = 0.0, maxTilt = 0.0;
  for (size_t j = 0; j < op.nodes; ++j) {
    const glm::dvec3 n(op.normals[j]), u(op.tangents[j]), v = glm::cross(n, u), z(0.0, 0.0, 1.0);
    const glm::dvec3 tau = -(z - glm::dot(z, n) * n) / s.medium.eta;
    for (int c = 0; c < 3; ++c) {
      const double e = double(E[j][c]);
      maxE = std::max(maxE, e);
      maxTilt = std::max(maxTilt, std::abs(double(tilted[0][j][c])));
      maxTiltDiff = std::max({maxTiltDiff, std::abs(double(tilted[0][j][c]) - e * glm::dot(tau, u)),
                              std::abs(double(tilted[1][j][c]) - e * glm::dot(tau, v))});
    }
  }
  ASSERT_GT(maxE, 0.0);
  EXPECT_GT(maxTilt, 0.1 * maxE);  // oblique light reaches some nodes
  EXPECT_LT(maxTiltDiff, 1e-4 * maxE);
  expectSameExitance(op.exitance(E, tilted[0], tilted[1]), tt.gpuNodeExitance());
  }
}

TEST_F(TransferGpu, RefusesWhatItCannotRender) {
  pointcloud::testing::useTestCache();
  TempDir dir;
  scene::Scene s = pointcloud::testing::testScene(writeObj(unitSphere(), dir.path() / "sphere.obj"), 16);
  s.mesh_deform.push_back(geometry::Deformation{});
  auto t = techniques::make("transfer");
  t->setParameter("nodes", 64);
  t->setParameter("photons", 16);
  try {
    t->prepare(s, gpu::testing::context());
    FAIL() << "a deformed mesh was accepted";
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("mesh.deform"), std::string::npos) << e.what();
  }
  EXPECT_THROW(t->setParameter("nodes", 8), ParameterError);
}

// η above 1/kTilt (1.98): no light from outside refracts as steeply as the tilted beams, so the
// default incidence (secant) traces normal beams instead, with a note, rather than refusing.
TEST_F(TransferGpu, FallsBackToNormalBeamsWhereNoLightRefractsThatSteeply) {
  pointcloud::testing::useTestCache();
  TempDir dir;
  scene::Scene s = pointcloud::testing::testScene(writeObj(unitSphere(), dir.path() / "sphere.obj"), 16);
  s.medium = sphereMedium();
  s.medium.eta = 2.2;
  auto t = techniques::make("transfer");
  t->setParameter("nodes", 64);
  t->setParameter("photons", 16);
  t->prepare(s, gpu::testing::context());
  const techniques::Frame f = t->render({});
  EXPECT_EQ(dynamic_cast<TransferTechnique&>(*t).transferOperator().matrices, 1u);
  bool noted = false;
  for (const std::string& n : f.notes) noted = noted || n.find("normal incidence used") != std::string::npos;
  EXPECT_TRUE(noted);
  s.medium.eta = 1.3;  // and the secant where it can
  t->prepare(s, gpu::testing::context());
  (void)t->render({});
  EXPECT_EQ(dynamic_cast<TransferTechnique&>(*t).transferOperator().matrices, 5u);
}

}  // namespace
}  // namespace translucent::transfer
