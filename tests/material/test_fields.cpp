// SPDX-License-Identifier: GPL-3.0-or-later
// The fields of material/ on their own: values against their definitions, majorants never below
// the field (random points in random boxes, every type), OpenVDB grids and surface maps written
// here and read back, and rd_map's inversion round trip.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <memory>
#include <random>

#include <glm/geometric.hpp>

#include <openvdb/openvdb.h>

#include "translucent/io/image_io.h"
#include "translucent/bssrdf/registry.h"
#include "translucent/geometry/mesh.h"
#include "translucent/material/checker.h"
#include "translucent/material/gradient.h"
#include "translucent/material/layers.h"
#include "translucent/material/noise.h"
#include "translucent/material/parse_context.h"
#include "translucent/material/surface_distance.h"
#include "translucent/material/surface_maps.h"
#include "translucent/material/veins.h"
#include "translucent/material/voxels.h"
#include "test_helpers.h"

namespace translucent::material {
namespace {

using testing::mediumA;
using testing::mediumB;
using testing::mediumC;
using testing::TempDir;

ParseContext context(const std::string& what = "test") {
  ParseContext c;
  c.reader.what = what;
  c.resolve = [](const std::string& name, const std::string&) { return std::filesystem::path(name); };
  return c;
}

void expectMedium(const LocalMedium& got, const LocalMedium& want, double tol = 0.0) {
  for (size_t c = 0; c < 3; ++c) {
    EXPECT_NEAR(got.sigma_a[c], want.sigma_a[c], tol * std::abs(want.sigma_a[c]) + 1e-300) << c;
    EXPECT_NEAR(got.sigma_s[c], want.sigma_s[c], tol * std::abs(want.sigma_s[c]) + 1e-300) << c;
  }
  EXPECT_NEAR(got.g, want.g, tol + 1e-300);
}

// Majorant ≥ σt at `points` random points in each of `boxes` random boxes around `centre`
// (sizes from 1e-3 to `extent`), for every channel.
void checkMajorant(const VolumeField& f, const glm::dvec3& centre, double extent,
                   int boxes = 300, int points = 40) {
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int checked = 0;
  for (int b = 0; b < boxes; ++b) {
    const double size = extent * std::pow(1e-3, u(rng));
    const glm::dvec3 lo = centre + extent * glm::dvec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5) -
                          0.5 * size;
    const glm::dvec3 hi = lo + size * glm::dvec3(u(rng), u(rng), u(rng)) + 1e-9;
    const Rgb m = f.majorant(lo, hi);
    for (int p = 0; p < points; ++p) {
      // Corners and faces too: they are in the box.
      glm::dvec3 t(u(rng), u(rng), u(rng));
      if (p < 8) t = glm::dvec3(p & 1, (p >> 1) & 1, (p >> 2) & 1);
      const glm::dvec3 q = lo + t * (hi - lo);
      const Rgb s = f.at(q).sigmaT();
      for (size_t c = 0; c < 3; ++c) {
        ASSERT_LE(s[c], m[c]) << "box [" << lo.x << "," << lo.y << "," << lo.z << "]-[" << hi.x
                              << "," << hi.y << "," << hi.z << "] point " << q.x << "," << q.y
                              << "," << q.z << " channel " << c;
        ++checked;
      }
    }
  }
  EXPECT_EQ(checked, boxes * points * 3);
}

// ---- checker, gradient ----------------------------------------------------------------------

TEST(CheckerField, CellsAlternateAndTheMajorantIsExactInsideOneCell) {
  CheckerDesc d;
  d.cell = {2.0, 3.0, 4.0};
  d.media = {mediumA(), mediumB()};
  const CheckerField f(d);
  expectMedium(f.at({0.5, 0.5, 0.5}), mediumA().medium);
  expectMedium(f.at({2.5, 0.5, 0.5}), mediumB().medium);
  expectMedium(f.at({2.5, 3.5, 0.5}), mediumA().medium);
  expectMedium(f.at({-0.5, 0.5, 0.5}), mediumB().medium);  // floor(-0.25) = -1
  expectMedium(f.at({-0.5, -0.5, 4.5}), mediumB().medium);  // -1 - 1 + 1 = -1: odd
  // One cell: that medium's σt (padded by 1e-12); across cells: the larger.
  const Rgb one = f.majorant({0.1, 0.1, 0.1}, {1.9, 2.9, 3.9});
  for (size_t c = 0; c < 3; ++c) EXPECT_NEAR(one[c], mediumA().medium.sigmaT()[c], 1e-9);
  const Rgb two = f.majorant({1.9, 0.1, 0.1}, {2.1, 0.2, 0.2});
  for (size_t c = 0; c < 3; ++c) EXPECT_NEAR(two[c], mediumB().medium.sigmaT()[c], 1e-9);
  checkMajorant(f, glm::dvec3(0.0), 20.0);
}

TEST(GradientField, BlendsLinearlyBetweenTheEndsAndClampsBeyond) {
  GradientDesc d;
  d.from = {1.0, 0.0, 0.0};
  d.to = {1.0, 4.0, 0.0};
  d.media = {mediumA(), mediumB()};
  const GradientField f(d);
  EXPECT_DOUBLE_EQ(f.t({7.0, 1.0, -3.0}), 0.25);  // only the component along a -> b counts
  expectMedium(f.at({1.0, 2.0, 0.0}), LocalMedium::mix(mediumA().medium, mediumB().medium, 0.5), 1e-15);
  expectMedium(f.at({0.0, -5.0, 0.0}), mediumA().medium, 1e-15);
  expectMedium(f.at({0.0, 9.0, 0.0}), mediumB().medium, 1e-15);  // a + (b − a): within an ulp
  // Exact majorant: a box over y in [1, 2] reaches t = 0.5 at most.
  const Rgb m = f.majorant({0.0, 1.0, 0.0}, {1.0, 2.0, 1.0});
  const Rgb want = LocalMedium::mix(mediumA().medium, mediumB().medium, 0.5).sigmaT();
  for (size_t c = 0; c < 3; ++c) EXPECT_NEAR(m[c], want[c], 1e-9 * want[c]);
  checkMajorant(f, glm::dvec3(1.0, 2.0, 0.0), 10.0);
}

// ---- veins ------------------------------------------------------------------------------------

TEST(VeinsField, EveryCoefficientLiesBetweenTheTwoMediaAndBothAppear) {
  VeinsDesc d;
  d.media = {mediumA(), mediumC()};
  d.period = 5.0;
  d.noise_size = 3.0;
  d.direction = glm::normalize(glm::dvec3(1.0, 0.3, 0.2));
  d.octaves = 5;
  d.turbulence = 1.5;
  d.sharpness = 6.0;
  const VeinsField f(d);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-50.0, 50.0);
  const LocalMedium& a = mediumA().medium;
  const LocalMedium& b = mediumC().medium;
  double wmin = 1.0, wmax = 0.0;
  for (int i = 0; i < 20000; ++i) {
    const glm::dvec3 q(u(rng), u(rng), u(rng));
    const double w = f.veinWeight(q);
    ASSERT_GE(w, 0.0);
    ASSERT_LE(w, 1.0);
    wmin = std::min(wmin, w);
    wmax = std::max(wmax, w);
    const LocalMedium m = f.at(q);
    for (size_t c = 0; c < 3; ++c) {
      ASSERT_GE(m.sigma_a[c], std::min(a.sigma_a[c], b.sigma_a[c]) * (1 - 1e-15));
      ASSERT_LE(m.sigma_a[c], std::max(a.sigma_a[c], b.sigma_a[c]) * (1 + 1e-15));
      ASSERT_GE(m.sigma_s[c], std::min(a.sigma_s[c], b.sigma_s[c]) * (1 - 1e-15));
      ASSERT_LE(m.sigma_s[c], std::max(a.sigma_s[c], b.sigma_s[c]) * (1 + 1e-15));
    }
    ASSERT_GE(m.g, std::min(a.g, b.g) - 1e-15);
    ASSERT_LE(m.g, std::max(a.g, b.g) + 1e-15);
  }
  EXPECT_LT(wmin, 1e-3);  // mostly base
  EXPECT_GT(wmax, 0.9);   // with veins
  checkMajorant(f, glm::dvec3(0.0), 40.0);
}

TEST(Noise, StaysInRangeAndVanishesOnTheLattice) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-300.0, 300.0);
  for (int i = 0; i < 10000; ++i) {
    const glm::dvec3 p(u(rng), u(rng), u(rng));
    const double n = perlinNoise(p);
    ASSERT_GE(n, -1.0);
    ASSERT_LE(n, 1.0);
    const double t = turbulence(p, 6);
    ASSERT_GE(t, 0.0);
    ASSERT_LT(t, 2.0);
  }
  EXPECT_EQ(perlinNoise({3.0, -7.0, 12.0}), 0.0);
  EXPECT_EQ(perlinNoise({1e12, 0.5, 0.5}), perlinNoise({1e12, 0.5, 0.5}));  // finite, no overflow
}

// ---- layers -------------------------------------------------------------------------------

LayersDesc threeLayers(LayersDesc::From from) {
  LayersDesc d;
  d.from = from;
  d.layers = {{mediumA(), 0.5}, {mediumB(), 1.5}, {mediumC(), std::nullopt}};
  return d;
}

TEST(LayersField, PlaneDepthsPutPointsInTheirLayer) {
  LayersDesc d = threeLayers(LayersDesc::From::Plane);
  d.normal = glm::normalize(glm::dvec3(0.0, 1.0, 1.0));
  d.offset = 2.0;
  const LayersField f(d, nullptr);
  auto at = [&](double depth) { return f.at((2.0 - depth) * d.normal); };
  expectMedium(at(-1.0), mediumA().medium);  // above the top plane: the top layer
  expectMedium(at(0.25), mediumA().medium);
  expectMedium(at(0.75), mediumB().medium);
  expectMedium(at(1.99), mediumB().medium);
  expectMedium(at(2.01), mediumC().medium);
  expectMedium(at(100.0), mediumC().medium);
  // Moving along the plane changes nothing.
  const glm::dvec3 along = glm::dvec3(1.0, 0.0, 0.0);
  EXPECT_NEAR(f.depth((2.0 - 0.7) * d.normal + 5.0 * along), 0.7, 1e-12);
  // A box inside the middle layer: exactly its σt.
  const glm::dvec3 c = (2.0 - 1.0) * d.normal;
  const Rgb m = f.majorant(c - 0.1, c + 0.1);
  for (size_t ch = 0; ch < 3; ++ch) EXPECT_NEAR(m[ch], mediumB().medium.sigmaT()[ch], 1e-9);
  checkMajorant(f, glm::dvec3(0.0, 1.0, 1.0), 6.0);
}

TEST(LayersField, SurfaceDepthIsTheDistanceToTheMeshInsideABox) {
  const geometry::TriangleMesh box = geometry::makeBox(glm::dvec3(-5.0), glm::dvec3(5.0));
  auto dist = std::make_shared<const SurfaceDistance>(box.positions, box.triangles);
  // Inside a box: the distance to the nearest face.
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-4.999, 4.999);
  for (int i = 0; i < 2000; ++i) {
    const glm::dvec3 q(u(rng), u(rng), u(rng));
    const double want = std::min({5.0 - std::abs(q.x), 5.0 - std::abs(q.y), 5.0 - std::abs(q.z)});
    ASSERT_NEAR(dist->distance(q), want, 1e-12);
  }
  EXPECT_NEAR(dist->distance({8.0, 9.0, 0.0}), std::sqrt(9.0 + 16.0), 1e-12);  // outside: to the edge
  const LayersField f(threeLayers(LayersDesc::From::Surface), dist);
  expectMedium(f.at({0.0, 4.8, 0.0}), mediumA().medium);   // 0.2 deep
  expectMedium(f.at({0.0, 0.0, -4.2}), mediumB().medium);  // 0.8 deep
  expectMedium(f.at({3.1, 0.0, 0.0}), mediumB().medium);   // 1.9 deep
  expectMedium(f.at({0.0, 0.0, 0.0}), mediumC().medium);   // 5 deep
  checkMajorant(f, glm::dvec3(0.0), 11.0);
}

TEST(SurfaceDistance, MatchesBruteForceOnTheBunny) {
  // glmark2-data is installed by scripts/install-deps: a missing bunny is a failure, not a skip.
  const geometry::TriangleMesh bunny = geometry::loadMesh("/usr/share/glmark2/models/bunny.obj");
  const SurfaceDistance d(bunny.positions, bunny.triangles);
  std::mt19937_64 rng(5);
  const geometry::Bounds b = bunny.bounds();
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < 30; ++i) {
    const glm::dvec3 q = b.lower + glm::dvec3(u(rng), u(rng), u(rng)) * (b.upper - b.lower);
    double best = 1e300;
    for (const glm::uvec3& t : bunny.triangles) {
      const glm::dvec3 p = closestPointOnTriangle(q, bunny.positions[t.x], bunny.positions[t.y],
                                                  bunny.positions[t.z]);
      best = std::min(best, glm::length(p - q));
    }
    ASSERT_NEAR(d.distance(q), best, 1e-12);
  }
}

// ---- voxels (OpenVDB) ------------------------------------------------------------------------

// A 4 x 3 x 2 float grid of value 0.1 (x + 3 y + 12 z) / 2.3 (in [0, 1)), voxel size 0.5 at
// translation (1, 2, 3), and (coefficient mode) grids sigma_a (vec3s) and sigma_s (float).
std::filesystem::path writeTestVdb(const TempDir& dir) {
  openvdb::initialize();
  auto transform = openvdb::math::Transform::createLinearTransform(0.5);
  transform->postTranslate(openvdb::Vec3d(1.0, 2.0, 3.0));
  auto density = openvdb::FloatGrid::create(0.0f);
  density->setName("density");
  density->setTransform(transform);
  auto sa = openvdb::Vec3SGrid::create(openvdb::Vec3s(0.01f, 0.02f, 0.03f));
  sa->setName("sigma_a");
  sa->setTransform(transform->copy());
  auto ss = openvdb::FloatGrid::create(1.0f);
  ss->setName("sigma_s");
  ss->setTransform(transform->copy());
  for (int z = 0; z < 2; ++z)
    for (int y = 0; y < 3; ++y)
      for (int x = 0; x < 4; ++x) {
        const float v = 0.1f * static_cast<float>(x + 3 * y + 12 * z) / 2.3f;
        density->tree().setValue(openvdb::Coord(x, y, z), v);
        sa->tree().setValue(openvdb::Coord(x, y, z), openvdb::Vec3s(v, 2 * v, 0.5f * v));
        ss->tree().setValue(openvdb::Coord(x, y, z), 10.0f * v + 2.0f);
      }
  const auto path = dir / "test.vdb";
  openvdb::io::File f(path.string());
  f.write({density, sa, ss});
  f.close();
  return path;
}

glm::dvec3 voxelCentre(int x, int y, int z) { return glm::dvec3(1.0, 2.0, 3.0) + 0.5 * glm::dvec3(x, y, z); }
double voxelValue(int x, int y, int z) {
  return static_cast<double>(0.1f * static_cast<float>(x + 3 * y + 12 * z) / 2.3f);
}

TEST(VoxelsField, DensityGridReadsBackAtVoxelCentresTrilinearBetweenAndMajorantCoversIt) {
  TempDir dir;
  const auto file = writeTestVdb(dir);
  const json mat = {{"type", "voxels"}, {"file", file.string()}, {"density", "density"},
                    {"media", json::array({toJson(mediumA()), toJson(mediumB())})}};
  const VoxelsDesc d = parseVoxels(context(), mat, "material");
  ASSERT_TRUE(d.density_grid);
  const VoxelsField f(d);
  for (int z = 0; z < 2; ++z)
    for (int y = 0; y < 3; ++y)
      for (int x = 0; x < 4; ++x) {
        EXPECT_NEAR(d.density_grid->trilinear(voxelCentre(x, y, z))[0], voxelValue(x, y, z), 1e-7);
        expectMedium(f.at(voxelCentre(x, y, z)),
                     LocalMedium::mix(mediumA().medium, mediumB().medium, voxelValue(x, y, z)), 1e-6);
      }
  // Halfway between two voxels: the mean; outside the grid: the background (0: media[0]).
  EXPECT_NEAR(d.density_grid->trilinear(0.5 * (voxelCentre(1, 1, 0) + voxelCentre(2, 1, 0)))[0],
              0.5 * (voxelValue(1, 1, 0) + voxelValue(2, 1, 0)), 1e-7);
  expectMedium(f.at({-10.0, 0.0, 0.0}), mediumA().medium);
  // The majorant of a box around voxel (3, 2, 1) (the largest) is the blend at its value.
  const Rgb m = f.majorant(voxelCentre(3, 2, 1) - 0.01, voxelCentre(3, 2, 1) + 0.01);
  const Rgb want = LocalMedium::mix(mediumA().medium, mediumB().medium, voxelValue(3, 2, 1)).sigmaT();
  for (size_t c = 0; c < 3; ++c) EXPECT_NEAR(m[c], want[c], 1e-6 * want[c]);
  checkMajorant(f, voxelCentre(2, 1, 0), 4.0);
}

TEST(VoxelsField, CoefficientGridsVec3AndFloatReadBackWithTheirMajorant) {
  TempDir dir;
  const auto file = writeTestVdb(dir);
  const json mat = {{"type", "voxels"}, {"file", file.string()}, {"sigma_a", "sigma_a"},
                    {"sigma_s", "sigma_s"}, {"g", 0.3}};
  const VoxelsDesc d = parseVoxels(context(), mat, "material");
  const VoxelsField f(d);
  const LocalMedium m = f.at(voxelCentre(2, 1, 1));
  const double v = voxelValue(2, 1, 1);
  EXPECT_NEAR(m.sigma_a[0], v, 1e-7);
  EXPECT_NEAR(m.sigma_a[1], 2 * v, 1e-7);
  EXPECT_NEAR(m.sigma_a[2], 0.5 * v, 1e-7);
  EXPECT_NEAR(m.sigma_s[1], 10 * v + 2, 1e-6);
  EXPECT_EQ(m.g, 0.3);
  // Background outside: sigma_a (0.01, 0.02, 0.03), sigma_s 1.
  const LocalMedium out = f.at({100.0, 100.0, 100.0});
  EXPECT_NEAR(out.sigma_a[2], 0.03, 1e-7);
  EXPECT_NEAR(out.sigma_s[0], 1.0, 1e-7);
  checkMajorant(f, voxelCentre(2, 1, 0), 4.0);
  // The representative (Scene::medium) is the mean over the active box.
  EXPECT_GT(d.representative().sigma_s[0], 2.0);
}

TEST(VoxelsField, ErrorsNameTheFileAndGrid) {
  TempDir dir;
  const auto file = writeTestVdb(dir);
  auto error = [&](const json& mat) {
    try {
      (void)parseVoxels(context("scene"), mat, "material");
    } catch (const ParameterError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string missing = error({{"type", "voxels"}, {"file", file.string()}, {"density", "smoke"},
                                     {"media", json::array({toJson(mediumA()), toJson(mediumB())})}});
  EXPECT_NE(missing.find("material.density"), std::string::npos) << missing;
  EXPECT_NE(missing.find("grid 'smoke': no such grid; the file holds density, sigma_a, sigma_s"),
            std::string::npos) << missing;
  const std::string type = error({{"type", "voxels"}, {"file", file.string()}, {"density", "sigma_a"},
                                  {"media", json::array({toJson(mediumA()), toJson(mediumB())})}});
  EXPECT_NE(type.find("expected float"), std::string::npos) << type;
  const std::string junk = error({{"type", "voxels"}, {"file", dir.write("junk.vdb", "not a vdb").string()},
                                  {"sigma_a", "a"}, {"sigma_s", "s"}});
  EXPECT_NE(junk.find("junk.vdb"), std::string::npos) << junk;
  EXPECT_NE(junk.find("cannot be read as OpenVDB"), std::string::npos) << junk;
  const std::string both = error({{"type", "voxels"}, {"file", file.string()}, {"sigma_a", "sigma_a"},
                                  {"media", json::array()}});
  EXPECT_NE(both.find("not both"), std::string::npos) << both;
}

// Coefficient grids where σa + σs' is 0 (outside the active voxels of grids whose background is
// 0, or at a voxel where both are 0) are refused as a homogeneous medium that neither absorbs nor
// scatters is: a photon there flew on forever (a mesh of index > 1 reflects it totally), and
// `pathtrace mesh` never finished. The message names the scene, the file, the grids and where.
TEST(VoxelsField, RefusesGridsThatNeitherAbsorbNorScatterSomewhere) {
  TempDir dir;
  openvdb::initialize();
  auto write = [&](const std::string& name, float background, bool hole) {
    auto sa = openvdb::FloatGrid::create(background);
    sa->setName("sigma_a");
    auto ss = openvdb::FloatGrid::create(background);
    ss->setName("sigma_s");
    for (int z = 0; z < 2; ++z)
      for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 2; ++x) {
          const bool zero = hole && x == 1 && y == 0 && z == 1;
          sa->tree().setValue(openvdb::Coord(x, y, z), zero ? 0.0f : 0.1f);
          ss->tree().setValue(openvdb::Coord(x, y, z), zero ? 0.0f : 1.0f);
        }
    const auto path = dir / name;
    openvdb::io::File f(path.string());
    f.write({sa, ss});
    f.close();
    return path;
  };
  auto error = [&](const std::filesystem::path& file) {
    try {
      (void)parseVoxels(context("scene.json"), {{"type", "voxels"}, {"file", file.string()},
                                                {"sigma_a", "sigma_a"}, {"sigma_s", "sigma_s"}},
                        "material");
    } catch (const ParameterError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string outside = error(write("zero_background.vdb", 0.0f, false));
  EXPECT_NE(outside.find("scene.json: material ('"), std::string::npos) << outside;
  EXPECT_NE(outside.find("zero_background.vdb', grids 'sigma_a' and 'sigma_s'): sigma_a is 0 and "
                         "sigma_s' is 0 in channel red at the background"),
            std::string::npos)
      << outside;
  const std::string hole = error(write("hole.vdb", 0.5f, true));
  EXPECT_NE(hole.find("at voxel (1, 0, 1) of grid 'sigma_a'"), std::string::npos) << hole;
  EXPECT_NE(hole.find("the medium neither absorbs nor scatters there"), std::string::npos) << hole;
  EXPECT_EQ(error(write("fine.vdb", 0.5f, false)), "no error");
}

// ---- surface maps -------------------------------------------------------------------------------

TEST(SurfaceMaps, MapImagesReadBackAtTexelCentresRowZeroAtVZero) {
  TempDir dir;
  constexpr int w = 4, h = 3;
  std::vector<float> sa(w * h * 3), sp(w * h * 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) {
        const size_t i = static_cast<size_t>(3 * (y * w + x) + c);
        sa[i] = 0.01f * static_cast<float>(1 + x + 10 * y + 100 * c);
        sp[i] = 1.0f + static_cast<float>(x + 2 * y + c);
      }
  analysis::writeExr((dir / "sa.exr").string(), w, h, sa);
  analysis::writeExr((dir / "sp.exr").string(), w, h, sp);
  const json mat = {{"type", "map"}, {"sigma_a", (dir / "sa.exr").string()},
                    {"sigma_s_prime", (dir / "sp.exr").string()}, {"g", 0.5}};
  const MapDesc d = parseMap(context(), mat, "material");
  const TexelMap map(d.data);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const LocalMedium m = map.at({(x + 0.5) / w, (y + 0.5) / h});
      for (size_t c = 0; c < 3; ++c) {
        const size_t i = static_cast<size_t>(3 * (y * w + x)) + c;
        EXPECT_NEAR(m.sigma_a[c], sa[i], 1e-7);
        EXPECT_NEAR(m.sigma_s[c], static_cast<double>(sp[i]) / 0.5, 1e-6);  // σs = σs' / (1 − g)
      }
      EXPECT_EQ(m.g, 0.5);
    }
  // Bilinear between centres, clamped at the border.
  const LocalMedium mid = map.at({1.0 / w, 0.5 / h});  // between texels (0, 0) and (1, 0)
  EXPECT_NEAR(mid.sigma_a[0], 0.5 * static_cast<double>(sa[0] + sa[3]), 1e-7);
  const LocalMedium corner = map.at({0.0, 0.0});
  EXPECT_NEAR(corner.sigma_a[0], sa[0], 1e-7);
}

TEST(SurfaceMaps, PngValuesAreReadAsStored) {
  TempDir dir;
  std::vector<uint8_t> px = {51, 102, 204, 255, 0, 128};  // 2 x 1
  analysis::writePng8((dir / "sp.png").string(), 2, 1, px);
  std::vector<float> sa(6, 0.1f);
  analysis::writeExr((dir / "sa.exr").string(), 2, 1, sa);
  const json mat = {{"type", "map"}, {"sigma_a", (dir / "sa.exr").string()},
                    {"sigma_s_prime", (dir / "sp.png").string()}};
  const MapDesc d = parseMap(context(), mat, "material");
  EXPECT_NEAR(d.data->at({0.25, 0.5}).sigma_s[1], 102.0 / 255.0, 1e-6);
  EXPECT_NEAR(d.data->at({0.75, 0.5}).sigma_s[2], 128.0 / 255.0, 1e-6);
}

// rd_map: per texel (Rd, ℓd) -> (σa, σs'); forward Rd(α') of the model at the inverted α' and
// ℓd = 1/σtr agree with the texel within 1e-5 (the table's interpolation error is ~1e-7).
TEST(SurfaceMaps, RdMapInversionRoundTripsThroughTheModel) {
  TempDir dir;
  constexpr int w = 16, h = 8;
  std::vector<float> rd(w * h * 3), ld(w * h * 3);
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (size_t i = 0; i < rd.size(); ++i) {
    rd[i] = static_cast<float>(0.01 + 0.6 * u(rng));
    ld[i] = static_cast<float>(0.2 + 5.0 * u(rng));
  }
  analysis::writeExr((dir / "rd.exr").string(), w, h, rd);
  analysis::writeExr((dir / "ld.exr").string(), w, h, ld);
  for (const std::string model : {"dipole", "better-dipole"}) {
    SCOPED_TRACE(model);
    ParseContext c = context();
    c.model = model;
    c.eta = 1.4;
    const json mat = {{"type", "rd_map"}, {"rd", (dir / "rd.exr").string()},
                      {"ld", (dir / "ld.exr").string()}, {"g", 0.2}};
    const RdMapDesc d = parseRdMap(c, mat, "material");
    const bssrdf::Model& m = bssrdf::model(model);
    double worst = 0.0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const LocalMedium t = d.data->at({(x + 0.5) / w, (y + 0.5) / h});
        for (size_t ch = 0; ch < 3; ++ch) {
          const size_t i = static_cast<size_t>(3 * (y * w + x)) + ch;
          const ScalarMedium s{t.sigma_a[ch], t.sigma_s[ch], t.g, 1.4};
          const double back = m.totalReflectance(s.reducedAlbedo(), 1.4);
          worst = std::max(worst, std::abs(back - static_cast<double>(rd[i])));
          EXPECT_NEAR(s.diffuseMeanFreePath(), static_cast<double>(ld[i]), 1e-9 * static_cast<double>(ld[i]));
        }
      }
    EXPECT_LT(worst, 1e-5);
  }
  // A constant ℓd and an Rd beyond the model's reach (the dipole reaches Rd = 1 at α' = 1): the
  // error names the file, texel and channel.
  std::vector<float> bad(w * h * 3, 0.3f);
  bad[3 * (2 * w + 5) + 1] = 1.25f;
  analysis::writeExr((dir / "bad.exr").string(), w, h, bad);
  try {
    (void)parseRdMap(context("scene"), {{"type", "rd_map"}, {"rd", (dir / "bad.exr").string()}, {"ld", 2.0}},
                     "material");
    ADD_FAILURE() << "no error";
  } catch (const ParameterError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("material.rd '" + (dir / "bad.exr").string() + "': texel (5, 2) green is 1.25"),
              std::string::npos) << msg;
    EXPECT_NE(msg.find("expected Rd in (0, "), std::string::npos) << msg;
  }
}

TEST(SurfaceMaps, SurfaceCheckerAlternatesInUv) {
  SurfaceCheckerDesc d;
  d.cells = {4.0, 2.0};
  d.media = {mediumA(), mediumB()};
  const SurfaceCheckerMap map(d);
  expectMedium(map.at({0.1, 0.1}), mediumA().medium);
  expectMedium(map.at({0.3, 0.1}), mediumB().medium);
  expectMedium(map.at({0.3, 0.6}), mediumA().medium);
  expectMedium(map.at({0.9, 0.9}), mediumA().medium);  // 3 + 1: even
  expectMedium(map.at({0.9, 0.2}), mediumB().medium);  // 3 + 0
}

}  // namespace
}  // namespace translucent::material
