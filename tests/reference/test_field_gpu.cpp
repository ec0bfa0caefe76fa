// SPDX-License-Identifier: GPL-3.0-or-later
// The GLSL twins of the 3D material fields (shaders/reference/fields.glsl, packed by
// reference/gpu/field_gpu.h) against the CPU fields, point for point through
// shaders/tests/field_query.comp: every supported kind at ~2000 random points (fixed seeds) in
// and around its interesting region, and the refusals. The CPU evaluates (in double) at the very
// float points the GPU gets, so what differs is the GPU's float arithmetic only: within 1e-5 of
// the field's largest coefficient (and 1e-5 in g) everywhere for the smooth fields; for the
// discontinuous ones (checker, layers) a point within 1e-4 (relative) of a cell face or a layer
// boundary may land on the other side, and only such points may differ. GL runs on whatever EGL
// offers (llvmpipe here).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <random>
#include <span>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/matrix.hpp>

#include "translucent/geometry/icosphere.h"
#include "translucent/geometry/mesh.h"
#include "translucent/gpu/compute.h"
#include "gpu/gpu_test.h"
#include "translucent/gpu/program.h"
#include "translucent/material/checker.h"
#include "translucent/material/gradient.h"
#include "translucent/material/layers.h"
#include "translucent/material/medium_desc.h"
#include "translucent/material/surface_distance.h"
#include "translucent/material/veins.h"
#include "translucent/material/voxels.h"
#include "translucent/reference/gpu/field_gpu.h"

namespace translucent::reference {
namespace {

using gpu::testing::GpuTest;
using material::LocalMedium;

constexpr double kTolerance = 1e-5;  // of the largest coefficient; absolute in g
constexpr double kBand = 1e-4;       // relative width of the band around a discontinuity

material::MediumDesc mediumA() { return material::mediumDesc({0.01, 0.02, 0.03}, {1.0, 1.5, 2.0}, 0.0); }
material::MediumDesc mediumB() { return material::mediumDesc({0.5, 0.4, 0.3}, {5.0, 4.0, 3.0}, 0.5); }
material::MediumDesc mediumC() { return material::mediumDesc({0.1, 0.1, 0.1}, {0.2, 8.0, 0.5}, -0.2); }

struct GpuQuery {  // field_query.comp's Query (std430)
  float q[4];
  float a[4];  // σa, w = g
  float s[4];
};
static_assert(sizeof(GpuQuery) == 48);

std::vector<GpuQuery> gpuAt(const std::vector<uint32_t>& words, const std::vector<glm::vec3>& points) {
  const gpu::ShaderProgram p = gpu::ShaderProgram::compute("tests/field_query.comp");
  std::vector<GpuQuery> queries(points.size());
  for (size_t i = 0; i < points.size(); ++i)
    queries[i] = GpuQuery{{points[i].x, points[i].y, points[i].z, 0.0f}, {}, {}};
  const gpu::Buffer q = gpu::makeStorageBuffer(std::span<const GpuQuery>(queries));
  const gpu::Buffer f = gpu::makeStorageBuffer(std::span<const uint32_t>(words));
  gpu::bindStorage(0, q);
  gpu::bindStorage(7, f);
  p.set("Count", static_cast<unsigned>(points.size()));
  gpu::dispatch1D(p, points.size());
  return gpu::download<GpuQuery>(q, points.size());
}

double largestCoefficient(const std::vector<LocalMedium>& media) {
  double m = 0.0;
  for (const LocalMedium& x : media)
    for (size_t c = 0; c < 3; ++c) m = std::max({m, x.sigma_a[c], x.sigma_s[c]});
  return m;
}

// Evaluates `f` at `points` on both sides and checks the agreement described at the top;
// `inBand` says which points lie within the band of a discontinuity (none for smooth fields).
// Returns the largest difference outside the band, relative to `scale` (the largest
// coefficient).
double expectAgreement(const char* name, const material::VolumeField& f,
                       const std::vector<glm::dvec3>& points, double scale,
                       const std::function<bool(const glm::dvec3&)>& inBand = {}) {
  std::vector<glm::vec3> fp(points.size());
  for (size_t i = 0; i < points.size(); ++i) fp[i] = glm::vec3(points[i]);
  const std::vector<GpuQuery> gpu = gpuAt(gpu_field::pack(f), fp);
  double maxSigma = 0.0, maxG = 0.0;
  size_t band = 0, bandDiffer = 0, failures = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    const glm::dvec3 q(fp[i]);  // the float point, exactly
    const LocalMedium cpu = f.at(q);
    double ds = 0.0;
    for (size_t c = 0; c < 3; ++c) {
      ds = std::max(ds, std::abs(double(gpu[i].a[c]) - cpu.sigma_a[c]));
      ds = std::max(ds, std::abs(double(gpu[i].s[c]) - cpu.sigma_s[c]));
    }
    ds /= scale;
    const double dg = std::abs(double(gpu[i].a[3]) - cpu.g);
    const bool agree = ds <= kTolerance && dg <= kTolerance;  // false for NaN too
    if (inBand && inBand(q)) {
      ++band;
      bandDiffer += !agree;
      continue;
    }
    maxSigma = std::max(maxSigma, ds);
    maxG = std::max(maxG, dg);
    if (!agree && ++failures <= 5)
      ADD_FAILURE() << name << ": point " << i << " (" << q.x << ", " << q.y << ", " << q.z
                    << "): GPU sigma_a " << gpu[i].a[0] << " " << gpu[i].a[1] << " " << gpu[i].a[2]
                    << ", sigma_s " << gpu[i].s[0] << " " << gpu[i].s[1] << " " << gpu[i].s[2]
                    << ", g " << gpu[i].a[3] << "; CPU sigma_a " << cpu.sigma_a[0] << " "
                    << cpu.sigma_a[1] << " " << cpu.sigma_a[2] << ", sigma_s " << cpu.sigma_s[0]
                    << " " << cpu.sigma_s[1] << " " << cpu.sigma_s[2] << ", g " << cpu.g;
  }
  EXPECT_EQ(failures, 0u) << name;
  std::printf("%s: %zu points, max |d sigma| %.3g of the largest coefficient, max |d g| %.3g; "
              "%zu within the band of a discontinuity, %zu of them differ\n",
              name, points.size(), maxSigma, maxG, band, bandDiffer);
  return maxSigma;
}

glm::dvec3 uniformIn(std::mt19937_64& rng, const glm::dvec3& lo, const glm::dvec3& hi) {
  std::uniform_real_distribution<double> u;
  return lo + glm::dvec3(u(rng), u(rng), u(rng)) * (hi - lo);
}

// ±10^-U(1, 7): offsets from a discontinuity, some inside the band and some just outside.
double nearOffset(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u;
  return (u(rng) < 0.5 ? -1.0 : 1.0) * std::pow(10.0, -1.0 - 6.0 * u(rng));
}

class FieldGpu : public GpuTest {};

// Cells of 0.7 x 1.3 x 2.1: random points, and points 1e-7 to 1e-1 cells off a face (and on
// faces: a point on a face is in the cell above it). The band: within 1e-4 cells of a face.
TEST_F(FieldGpu, CheckerMatchesTheCpu) {
  material::CheckerDesc d;
  d.cell = {0.7, 1.3, 2.1};
  d.media = {mediumA(), mediumB()};
  const material::CheckerField f(d);
  std::mt19937_64 rng(1);
  std::uniform_int_distribution<int> cellIndex(-4, 4), axis(0, 2);
  std::vector<glm::dvec3> points;
  for (int i = 0; i < 1000; ++i) points.push_back(uniformIn(rng, glm::dvec3(-4.0), glm::dvec3(4.0)));
  for (int i = 0; i < 1000; ++i) {
    glm::dvec3 q = uniformIn(rng, glm::dvec3(-4.0), glm::dvec3(4.0));
    const int k = axis(rng);
    q[k] = d.cell[k] * (cellIndex(rng) + (i % 10 == 0 ? 0.0 : nearOffset(rng)));
    points.push_back(q);
  }
  auto inBand = [&](const glm::dvec3& q) {
    for (int k = 0; k < 3; ++k) {
      const double u = q[k] / d.cell[k];
      if (std::abs(u - std::round(u)) < kBand) return true;
    }
    return false;
  };
  expectAgreement("checker", f, points, largestCoefficient({mediumA().medium, mediumB().medium}),
                  inBand);
}

// From a to b and beyond both ends (t from -0.5 to 1.5 before the clamp), off the axis too.
TEST_F(FieldGpu, GradientMatchesTheCpu) {
  material::GradientDesc d;
  d.from = {1.0, -2.0, 0.5};
  d.to = {3.0, 1.0, 2.0};
  d.media = {mediumA(), mediumC()};
  const material::GradientField f(d);
  std::mt19937_64 rng(2);
  std::uniform_real_distribution<double> t(-0.5, 1.5);
  std::vector<glm::dvec3> points;
  for (int i = 0; i < 2000; ++i)
    points.push_back(d.from + t(rng) * (d.to - d.from) + uniformIn(rng, glm::dvec3(-2.0), glm::dvec3(2.0)));
  expectAgreement("gradient", f, points, largestCoefficient({mediumA().medium, mediumC().medium}));
}

// Five octaves of turbulence, strong and sharp, at points of a 24-unit cube (six periods), and
// twelve octaves (the most a scene may ask for) of a milder one.
TEST_F(FieldGpu, VeinsMatchTheCpu) {
  for (const int octaves : {5, 12}) {
    material::VeinsDesc d;
    d.media = {mediumA(), mediumB()};
    d.period = octaves == 5 ? 4.0 : 7.0;
    d.direction = glm::normalize(octaves == 5 ? glm::dvec3(1.0, 0.5, 0.2) : glm::dvec3(-0.2, 0.3, 1.0));
    d.noise_size = octaves == 5 ? 3.0 : 5.0;
    d.octaves = octaves;
    d.turbulence = octaves == 5 ? 1.5 : 0.7;
    d.sharpness = octaves == 5 ? 6.0 : 2.5;
    const material::VeinsField f(d);
    std::mt19937_64 rng(3 + uint64_t(octaves));
    std::vector<glm::dvec3> points;
    size_t veins = 0;
    for (int i = 0; i < 2000; ++i) {
      points.push_back(uniformIn(rng, glm::dvec3(-12.0), glm::dvec3(12.0)));
      veins += f.veinWeight(points.back()) > 0.5;
    }
    EXPECT_GT(veins, 20u);  // the veins themselves are compared too
    expectAgreement(octaves == 5 ? "veins (5 octaves)" : "veins (12 octaves)", f, points,
                    largestCoefficient({mediumA().medium, mediumB().medium}));
  }
}

// Three layers below a tilted plane: points from 1.5 above the top plane to 2.5 below it, and
// points 1e-7 to 1e-1 off the two bottoms. The band: within 1e-4 (|offset| + |q|) of a bottom.
TEST_F(FieldGpu, PlaneLayersMatchTheCpu) {
  material::LayersDesc d;
  d.from = material::LayersDesc::From::Plane;
  d.normal = glm::normalize(glm::dvec3(0.3, 1.0, -0.4));
  d.offset = 1.5;
  d.layers = {{mediumA(), 0.4}, {mediumB(), 0.9}, {mediumC(), std::nullopt}};
  const material::LayersField f(d, nullptr);
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> depth(-1.5, 2.5);
  std::uniform_int_distribution<int> bottom(0, 1);
  std::vector<glm::dvec3> points;
  size_t above = 0;
  for (int i = 0; i < 2000; ++i) {
    const glm::dvec3 p = uniformIn(rng, glm::dvec3(-3.0), glm::dvec3(3.0));
    const double z = i < 1200 ? depth(rng) : f.bottoms()[size_t(bottom(rng))] + nearOffset(rng);
    points.push_back(p + (d.offset - glm::dot(p, d.normal) - z) * d.normal);
    above += f.depth(points.back()) < 0.0;
  }
  EXPECT_GT(above, 100u);
  auto inBand = [&](const glm::dvec3& q) {
    const double z = f.depth(q);
    for (double b : f.bottoms())
      if (std::abs(z - b) < kBand * (std::abs(d.offset) + glm::length(q))) return true;
    return false;
  };
  expectAgreement("layers (plane)", f, points,
                  largestCoefficient({mediumA().medium, mediumB().medium, mediumC().medium}), inBand);
}

// Layers below the surface of an icosphere of radius 3 (1280 triangles: a tree of several
// levels): points inside and a little outside it, and near the bottoms. The band: within 1e-4 · 3 of a bottom.
TEST_F(FieldGpu, SurfaceLayersMatchTheCpu) {
  const geometry::TriangleMesh sphere = geometry::makeIcosphere(3, 3.0);
  auto distance = std::make_shared<const material::SurfaceDistance>(sphere.positions, sphere.triangles);
  material::LayersDesc d;
  d.from = material::LayersDesc::From::Surface;
  d.layers = {{mediumA(), 0.35}, {mediumB(), 0.7}, {mediumC(), std::nullopt}};
  const material::LayersField f(d, distance);
  ASSERT_EQ(gpu_field::refusal(f), "");
  std::mt19937_64 rng(5);
  std::uniform_int_distribution<int> bottom(0, 1);
  std::vector<glm::dvec3> points;
  size_t deep = 0;
  while (points.size() < 1200) {
    const glm::dvec3 q = uniformIn(rng, glm::dvec3(-3.3), glm::dvec3(3.3));
    if (glm::length(q) > 3.3) continue;
    points.push_back(q);
    deep += f.depth(q) > 1.05;
  }
  EXPECT_GT(deep, 100u);
  // Points 1e-7 to 1e-1 off a bottom: moved along the radius until their depth is the one
  // wanted (the depth changes along it at a rate close to 1).
  while (points.size() < 2000) {
    const glm::dvec3 dir = glm::normalize(uniformIn(rng, glm::dvec3(-1.0), glm::dvec3(1.0)));
    const double want = f.bottoms()[size_t(bottom(rng))] + nearOffset(rng);
    glm::dvec3 q = (3.0 - want) * dir;
    for (int k = 0; k < 4; ++k) q += (f.depth(q) - want) * dir;
    points.push_back(q);
  }
  auto inBand = [&](const glm::dvec3& q) {
    const double z = f.depth(q);
    for (double b : f.bottoms())
      if (std::abs(z - b) < kBand * 3.0) return true;
    return false;
  };
  expectAgreement("layers (surface)", f, points,
                  largestCoefficient({mediumA().medium, mediumB().medium, mediumC().medium}), inBand);
}

// Layers below a real scan at the size the scenes give it (the glmark2 bunny, 69,666 triangles:
// a deep, uneven tree), scaled to a radius of 220 medium units as head-layered-skin.json's
// "scale": 220: a thin top layer of 0.3 below a surface hundreds of units from the origin, at
// points near the surface (a triangle's point moved in by 0 to 3 units) and throughout the box.
TEST_F(FieldGpu, SurfaceLayersBelowALargeScanMatchTheCpu) {
  geometry::TriangleMesh mesh = geometry::loadMesh(TRANSLUCENT_BUNNY_OBJ);
  const geometry::Bounds b = mesh.bounds();
  mesh.transform(220.0 / b.radius(), -b.center() * (220.0 / b.radius()));
  auto distance = std::make_shared<const material::SurfaceDistance>(mesh.positions, mesh.triangles);
  material::LayersDesc d;
  d.from = material::LayersDesc::From::Surface;
  d.layers = {{mediumA(), 0.3}, {mediumB(), 2.0}, {mediumC(), std::nullopt}};
  const material::LayersField f(d, distance);
  ASSERT_EQ(gpu_field::refusal(f), "");
  const geometry::Bounds box = mesh.bounds();
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<glm::dvec3> points;
  while (points.size() < 1500) points.push_back(uniformIn(rng, box.lower, box.upper));
  while (points.size() < 3000) {
    const glm::uvec3 t = mesh.triangles[size_t(u(rng) * double(mesh.triangles.size())) % mesh.triangles.size()];
    const glm::dvec3 a = mesh.positions[t.x], bb = mesh.positions[t.y], c = mesh.positions[t.z];
    double r1 = u(rng), r2 = u(rng);
    if (r1 + r2 > 1.0) r1 = 1.0 - r1, r2 = 1.0 - r2;
    const glm::dvec3 n = glm::normalize(glm::cross(bb - a, c - a));
    points.push_back(a + r1 * (bb - a) + r2 * (c - a) - 3.0 * u(rng) * n);
  }
  auto inBand = [&](const glm::dvec3& q) {
    const double z = f.depth(q);
    for (double bottom : f.bottoms())
      if (std::abs(z - bottom) < kBand * 220.0) return true;
    return false;
  };
  expectAgreement("layers (surface of the bunny at 220)", f, points,
                  largestCoefficient({mediumA().medium, mediumB().medium, mediumC().medium}), inBand);
}

// A grid whose voxels are turned and sheared in material space (index_to_world not diagonal).
material::DenseGrid denseGrid(glm::ivec3 origin, glm::ivec3 dims, int channels, double lo, double hi,
                              Rgb background, const glm::dmat3& toWorld, glm::dvec3 translation,
                              uint64_t seed) {
  material::DenseGrid g;
  g.origin = origin;
  g.dims = dims;
  g.channels = channels;
  g.background = background;
  g.index_to_world = toWorld;
  g.translation = translation;
  g.world_to_index = glm::inverse(toWorld);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(lo, hi);
  g.values.resize(size_t(dims.x) * size_t(dims.y) * size_t(dims.z) * size_t(channels));
  for (float& v : g.values) v = static_cast<float>(u(rng));
  return g;
}

glm::dmat3 turnedAndSheared() {
  const glm::dmat3 r(glm::rotate(glm::dmat4(1.0), 0.4, glm::normalize(glm::dvec3(1.0, 2.0, 3.0))));
  glm::dmat3 s(0.0);
  s[0] = {0.5, 0.0, 0.0};
  s[1] = {0.1, 0.4, 0.0};
  s[2] = {0.0, -0.05, 0.6};
  return r * s;
}

// Points over the grid's index box and two voxels beyond (the background), in material space.
std::vector<glm::dvec3> aroundGrid(const material::DenseGrid& g, size_t count, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<glm::dvec3> points;
  for (size_t i = 0; i < count; ++i) {
    const glm::dvec3 p = uniformIn(rng, glm::dvec3(g.origin) - 2.0, glm::dvec3(g.origin + g.dims) + 1.0);
    points.push_back(g.index_to_world * p + g.translation);
  }
  return points;
}

// Density below 0 and above 1 (clamped), blending two media.
TEST_F(FieldGpu, VoxelDensityMatchesTheCpu) {
  material::VoxelsDesc d;
  d.mode = material::VoxelsDesc::Mode::Density;
  d.media = {mediumA(), mediumB()};
  d.density_grid = std::make_shared<const material::DenseGrid>(
      denseGrid({-1, 0, 2}, {6, 5, 4}, 1, -0.2, 1.2, {0.15, 0.15, 0.15}, turnedAndSheared(),
                {0.3, -0.2, 1.0}, 6));
  const material::VoxelsField f(d);
  expectAgreement("voxels (density)", f, aroundGrid(*d.density_grid, 2000, 7),
                  largestCoefficient({mediumA().medium, mediumB().medium}));
}

// σa an RGB grid, σs a grey one with its own placement; points around both.
TEST_F(FieldGpu, VoxelCoefficientsMatchTheCpu) {
  material::VoxelsDesc d;
  d.mode = material::VoxelsDesc::Mode::Coefficients;
  d.g = 0.3;
  d.sigma_a_grid = std::make_shared<const material::DenseGrid>(
      denseGrid({-1, 0, 2}, {6, 5, 4}, 3, 0.0, 2.0, {0.01, 0.02, 0.03}, turnedAndSheared(),
                {0.3, -0.2, 1.0}, 8));
  d.sigma_s_grid = std::make_shared<const material::DenseGrid>(
      denseGrid({2, -3, 0}, {4, 6, 5}, 1, 0.0, 10.0, {1.0, 1.0, 1.0}, glm::dmat3(0.45),
                {-0.5, 1.0, -0.3}, 9));
  const material::VoxelsField f(d);
  std::vector<glm::dvec3> points = aroundGrid(*d.sigma_a_grid, 1000, 10);
  const std::vector<glm::dvec3> more = aroundGrid(*d.sigma_s_grid, 1000, 11);
  points.insert(points.end(), more.begin(), more.end());
  expectAgreement("voxels (coefficients)", f, points, 10.0);
}

// A zeroed buffer (what the walk binds without a field) reads as no field: zeros.
TEST_F(FieldGpu, ZeroedBufferIsNoField) {
  const std::vector<GpuQuery> gpu = gpuAt(std::vector<uint32_t>(4, 0u), {{0.5f, -1.0f, 2.0f}});
  for (int c = 0; c < 4; ++c) {
    EXPECT_EQ(gpu[0].a[c], 0.0f) << c;
    EXPECT_EQ(gpu[0].s[c], 0.0f) << c;
  }
}

// A field fields.glsl does not know.
struct OpaqueField final : material::VolumeField {
  LocalMedium at(const glm::dvec3&) const override { return {{0.1, 0.1, 0.1}, {1.0, 1.0, 1.0}, 0.0}; }
  Rgb majorant(const glm::dvec3&, const glm::dvec3&) const override { return {1.1, 1.1, 1.1}; }
};

TEST(FieldGpuPacking, RefusesUnknownFieldsAndPacksTheKnownOnes) {
  const OpaqueField opaque;
  const std::string why = gpu_field::refusal(opaque);
  EXPECT_EQ(why, "this kind of heterogeneous material is traced on the CPU only");
  try {
    (void)gpu_field::pack(opaque);
    ADD_FAILURE() << "an unknown field was packed";
  } catch (const ParameterError& e) {
    EXPECT_EQ(std::string(e.what()), why);
  }

  material::CheckerDesc c;
  c.cell = glm::dvec3(0.5);
  c.media = {mediumA(), mediumB()};
  const material::CheckerField checker(c);
  EXPECT_EQ(gpu_field::refusal(checker), "");
  const std::vector<uint32_t> words = gpu_field::pack(checker);
  ASSERT_GE(words.size(), 4u);
  EXPECT_EQ(words[0], 1u);             // kind: checker
  EXPECT_EQ(words[1], words.size());   // the word count
  EXPECT_EQ(words[2], 2u);             // media
  EXPECT_EQ(words[3], 4u + 8u * 2u);   // P
  EXPECT_EQ(words.size(), 4u + 16u + 3u);

  material::LayersDesc l;
  l.from = material::LayersDesc::From::Plane;
  l.layers = {{mediumA(), 0.4}, {mediumB(), std::nullopt}};
  EXPECT_EQ(gpu_field::refusal(material::LayersField(l, nullptr)), "");
}

}  // namespace
}  // namespace translucent::reference
