// SPDX-License-Identifier: GPL-3.0-or-later
// Per-vertex ambient occlusion (geometry/ambient_occlusion.h, seed Eq. 3.5) against geometry
// whose visible-sky fraction is known in closed form.
#include <gtest/gtest.h>
#include <tbb/task_arena.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

#include <glm/geometric.hpp>

#include "translucent/geometry/ambient_occlusion.h"

namespace translucent::geometry {
namespace {

// A square [-1, 1]² in the plane z = 0, counter-clockwise seen from +z (normal +z).
TriangleMesh plane() {
  TriangleMesh m;
  m.positions = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  return m;
}

// A unit cube [-0.5, 0.5]² × [0, 1] without its top face: the floor is a fan about a centre
// vertex (index 0), then four walls.
TriangleMesh openTopBox() {
  TriangleMesh m;
  m.positions = {{0, 0, 0},
                 {-0.5, -0.5, 0}, {0.5, -0.5, 0}, {0.5, 0.5, 0}, {-0.5, 0.5, 0},
                 {-0.5, -0.5, 1}, {0.5, -0.5, 1}, {0.5, 0.5, 1}, {-0.5, 0.5, 1}};
  for (unsigned i = 0; i < 4; ++i) {
    const unsigned a = 1 + i, b = 1 + (i + 1) % 4;
    m.triangles.push_back({0, a, b});              // floor, counter-clockwise from above
    m.triangles.push_back({a, b + 4, b});          // wall
    m.triangles.push_back({a, a + 4, b + 4});
  }
  return m;
}

// Standard error of a fraction p estimated from n independent rays.
double sigma(double p, int n) { return std::sqrt(p * (1.0 - p) / n); }

TEST(AmbientOcclusion, LonePlaneSeesTheWholeSky) {
  for (bool cosine : {false, true}) {
    AmbientOcclusionOptions options;
    options.cosineWeighted = cosine;
    const AmbientOcclusion ao = computeAmbientOcclusion(plane(), options);
    ASSERT_EQ(ao.values.size(), 4u);
    for (float v : ao.values) EXPECT_EQ(v, 1.0f) << "cosine " << cosine;
    EXPECT_GE(ao.bvhSeconds, 0.0);
    EXPECT_GT(ao.aoSeconds, 0.0);
  }
}

TEST(AmbientOcclusion, ConvexBoxVerticesAreUnoccludedAndItsInsideIsDark) {
  const TriangleMesh box = makeBox({-1, -1, -1}, {1, 1, 1});
  const AmbientOcclusion outside = computeAmbientOcclusion(box, {});
  for (float v : outside.values) EXPECT_EQ(v, 1.0f);
  const AmbientOcclusion inside = computeAmbientOcclusion(
      box, {{0, 0, 0}, {0.3, -0.7, 0.9}}, {{0, 0, 1}, glm::normalize(glm::dvec3(1, 2, -3))}, {});
  for (float v : inside.values) EXPECT_EQ(v, 0.0f);
}

// Centre of the floor of a unit cube open at the top: the opening is a 1 × 1 square at height 1.
// Uniform AO = Ω / 2π with Ω = 4 asin(ab / sqrt((a² + 4d²)(b² + 4d²))) = 4 asin(1/5) (the solid
// angle of a rectangle seen from a point on its axis). Cosine-weighted AO = the view factor to the
// opening: four times that of a 0.5 × 0.5 rectangle at height 1 seen from below a corner,
// F = (1/2π)[A/√(1+A²) atan(B/√(1+A²)) + B/√(1+B²) atan(A/√(1+B²))], A = B = 0.5.
TEST(AmbientOcclusion, FloorOfOpenTopBoxMatchesTheSolidAngleOfTheOpening) {
  const TriangleMesh box = openTopBox();
  const int rays = 40000;
  const double uniform = 4.0 * std::asin(0.2) / (2.0 * std::numbers::pi);
  const double a = 0.5, s = std::sqrt(1.0 + a * a);
  const double cosine = 4.0 * (2.0 * a / s * std::atan(a / s)) / (2.0 * std::numbers::pi);
  for (bool cos : {false, true}) {
    AmbientOcclusionOptions options;
    options.rays = rays;
    options.cosineWeighted = cos;
    options.seed = 7;
    const double expected = cos ? cosine : uniform;
    // The floor's centre vertex (per-vertex path) and the same point through the point query.
    const AmbientOcclusion perVertex = computeAmbientOcclusion(box, options);
    const AmbientOcclusion atPoint = computeAmbientOcclusion(box, {{0, 0, 0}}, {{0, 0, 1}}, options);
    EXPECT_NEAR(perVertex.values[0], expected, 4.0 * sigma(expected, rays)) << "cosine " << cos;
    EXPECT_EQ(perVertex.values[0], atPoint.values[0]);
  }
}

TEST(AmbientOcclusion, SameSeedSameValuesWhateverTheThreadCount) {
  const TriangleMesh box = openTopBox();
  std::vector<glm::dvec3> points, normals;
  for (int i = 0; i < 40; ++i)
    for (int j = 0; j < 40; ++j) {
      points.push_back({-0.49 + 0.98 * i / 39.0, -0.49 + 0.98 * j / 39.0, 0.0});
      normals.push_back({0, 0, 1});
    }
  AmbientOcclusionOptions options;
  options.rays = 64;
  const AmbientOcclusion many = computeAmbientOcclusion(box, points, normals, options);
  AmbientOcclusion one;
  tbb::task_arena(1).execute([&] { one = computeAmbientOcclusion(box, points, normals, options); });
  EXPECT_EQ(many.values, one.values);
  options.seed = 2;
  EXPECT_NE(computeAmbientOcclusion(box, points, normals, options).values, many.values);
}

TEST(AmbientOcclusion, CacheStoresAndRereadsAndReplacesCorruptFiles) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("translucent-ao-test-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  const TriangleMesh box = openTopBox();
  AmbientOcclusionOptions options;
  options.rays = 256;
  const AmbientOcclusion first = loadOrComputeAmbientOcclusion(box, options, dir);
  EXPECT_FALSE(first.fromCache);
  EXPECT_TRUE(first.note.empty()) << first.note;
  ASSERT_TRUE(std::filesystem::exists(first.file));
  const AmbientOcclusion second = loadOrComputeAmbientOcclusion(box, options, dir);
  EXPECT_TRUE(second.fromCache);
  EXPECT_EQ(second.values, first.values);
  // Another ray count is another file.
  options.rays = 128;
  EXPECT_NE(ambientOcclusionCacheFileName(box, options), first.file.filename().string());
  options.rays = 256;
  std::filesystem::resize_file(first.file, 20);
  const AmbientOcclusion third = loadOrComputeAmbientOcclusion(box, options, dir);
  EXPECT_FALSE(third.fromCache);
  EXPECT_NE(third.note.find("corrupt"), std::string::npos) << third.note;
  EXPECT_EQ(third.values, first.values);
  std::filesystem::remove_all(dir);
}

TEST(AmbientOcclusion, RejectsBadInput) {
  AmbientOcclusionOptions options;
  options.rays = 0;
  EXPECT_THROW(computeAmbientOcclusion(plane(), options), AmbientOcclusionError);
  TriangleMesh m = plane();
  m.normals = {{0, 0, 1}, {0, 0, 0}, {0, 0, 1}, {0, 0, 1}};
  EXPECT_THROW(computeAmbientOcclusion(m, {}), AmbientOcclusionError);
  EXPECT_THROW(computeAmbientOcclusion(plane(), {{0, 0, 1}}, {}, {}), AmbientOcclusionError);
}

}  // namespace
}  // namespace translucent::geometry
