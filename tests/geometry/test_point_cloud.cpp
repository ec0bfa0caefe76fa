// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>
#include <tbb/task_arena.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <optional>
#include <string>

#include <glm/geometric.hpp>

#include "translucent/geometry/icosphere.h"
#include "translucent/geometry/point_cloud.h"
#include "test_meshes.h"

namespace translucent::geometry {
namespace {
namespace fs = std::filesystem;

// A fresh folder under the system temporary directory, removed at the end of the test.
class TempDir {
 public:
  explicit TempDir(const std::string& name)
      : path_(fs::temp_directory_path() / ("translucent-test-" + name + "-" +
                                           std::to_string(::getpid()))) {
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

PointCloud sample(const TriangleMesh& mesh, size_t count, SamplingMethod method, uint64_t seed = 1) {
  SamplingOptions o;
  o.count = count;
  o.method = method;
  o.seed = seed;
  return samplePointCloud(mesh, o);
}

bool identical(const PointCloud& a, const PointCloud& b) {
  return a.positions == b.positions && a.normals == b.normals && a.areas == b.areas &&
         a.faces == b.faces && a.irradiance == b.irradiance;
}

// Every point lies on the triangle it names: distance to the plane and barycentric coordinates
// within float rounding of the positions.
void expectOnSurface(const TriangleMesh& mesh, const PointCloud& cloud) {
  ASSERT_EQ(cloud.faces.size(), cloud.size());
  const double scale = mesh.bounds().radius();
  for (size_t i = 0; i < cloud.size(); ++i) {
    ASSERT_LT(cloud.faces[i], mesh.triangleCount());
    const auto& t = mesh.triangles[cloud.faces[i]];
    const glm::dvec3 a = mesh.positions[t.x], b = mesh.positions[t.y], c = mesh.positions[t.z];
    const glm::dvec3 p(cloud.positions[i]);
    const glm::dvec3 n = glm::cross(b - a, c - a);
    const double area2 = glm::length(n);
    ASSERT_LT(std::abs(glm::dot(p - a, n / area2)), 1e-6 * scale) << "point " << i;
    const double u = glm::dot(glm::cross(c - b, p - b), n) / (area2 * area2);
    const double v = glm::dot(glm::cross(a - c, p - c), n) / (area2 * area2);
    const double tol = 1e-6 * scale / std::sqrt(area2);  // float rounding over the triangle size
    ASSERT_GE(u, -tol) << "point " << i;
    ASSERT_GE(v, -tol) << "point " << i;
    ASSERT_LE(u + v, 1.0 + tol) << "point " << i;
    ASSERT_NEAR(glm::length(glm::dvec3(cloud.normals[i])), 1.0, 1e-6);
  }
}

TEST(Icosphere, ClosedOutwardAndOnTheSphere) {
  for (unsigned s : {0u, 1u, 3u}) {
    const TriangleMesh m = makeIcosphere(s, 2.0, glm::dvec3(1, 2, 3));
    EXPECT_EQ(m.triangleCount(), 20u << (2 * s));
    EXPECT_EQ(m.vertexCount(), 10u * (1u << (2 * s)) + 2u);
    EXPECT_EQ(m.openEdgeCount(), 0u);
    for (const auto& p : m.positions) EXPECT_NEAR(glm::length(p - glm::dvec3(1, 2, 3)), 2.0, 1e-12);
    for (const auto& t : m.triangles) {
      const glm::dvec3 n = glm::cross(m.positions[t.y] - m.positions[t.x],
                                      m.positions[t.z] - m.positions[t.x]);
      EXPECT_GT(glm::dot(n, m.positions[t.x] - glm::dvec3(1, 2, 3)), 0.0);  // outward winding
    }
  }
  // The area converges to 4π r² from below.
  EXPECT_NEAR(makeIcosphere(6).area(), 4.0 * std::numbers::pi, 2e-3 * 4.0 * std::numbers::pi);
  EXPECT_THROW((void)makeIcosphere(10), MeshError);
  EXPECT_THROW((void)makeIcosphere(2, -1.0), MeshError);
}

TEST(PointCloudSampling, ExactCountOnTheSurfaceAreasSumToTheMeshArea) {
  const TriangleMesh sphere = makeIcosphere(3);
  const TriangleMesh box = makeBox(glm::dvec3(-1, 0, 2), glm::dvec3(3, 0.5, 2.25));
  for (const auto method : {SamplingMethod::Random, SamplingMethod::Elimination}) {
    for (const TriangleMesh* mesh : {&sphere, &box, &testing::bunny()}) {
      for (size_t count : {1u, 7u, 3001u}) {
        const PointCloud c = sample(*mesh, count, method, 3);
        ASSERT_EQ(c.size(), count) << toString(method);
        EXPECT_NO_THROW(c.validate("sampled"));
        EXPECT_NEAR(c.totalArea(), mesh->area(), 1e-6 * mesh->area());
        EXPECT_FALSE(c.hasIrradiance());
        expectOnSurface(*mesh, c);
      }
    }
  }
  // With vertex normals (the icosphere's are radial) the normals are interpolated: outward.
  const PointCloud c = sample(sphere, 2000, SamplingMethod::Elimination);
  for (size_t i = 0; i < c.size(); ++i)
    EXPECT_GT(glm::dot(glm::normalize(glm::dvec3(c.positions[i])), glm::dvec3(c.normals[i])),
              0.999);
}

TEST(PointCloudSampling, EliminationIsFarMoreUniformThanRandom) {
  // Coefficient of variation of the nearest-neighbour distance. For a Poisson process in the
  // plane the distance is Rayleigh distributed: CV = sqrt(4/π - 1) = 0.5227; for n = 8000 its
  // standard error is about 0.006, and curvature changes it little. Blue noise from sample
  // elimination measures about 0.08 (see the report in BENCHMARKS.md of commit 91fe617).
  const double poisson = std::sqrt(4.0 / std::numbers::pi - 1.0);
  for (const TriangleMesh* mesh : {&testing::bunny()}) {
    const auto random = nearestNeighbourStats(sample(*mesh, 8000, SamplingMethod::Random, 5));
    const auto blue = nearestNeighbourStats(sample(*mesh, 8000, SamplingMethod::Elimination, 5));
    std::printf("NN distance CV: random %.4f, elimination %.4f (bunny, 8000 points)\n",
                random.cv, blue.cv);
    EXPECT_NEAR(random.cv, poisson, 0.04);
    EXPECT_LT(blue.cv, 0.12);
    EXPECT_LT(blue.cv, 0.25 * random.cv);
    // Poisson-disk property: no two points much closer than the mean spacing.
    EXPECT_GT(blue.min, 0.6 * blue.mean);
    EXPECT_LT(random.min, 0.05 * random.mean);
  }
  const TriangleMesh sphere = makeIcosphere(5);
  const auto random = nearestNeighbourStats(sample(sphere, 8000, SamplingMethod::Random, 5));
  const auto blue = nearestNeighbourStats(sample(sphere, 8000, SamplingMethod::Elimination, 5));
  std::printf("NN distance CV: random %.4f, elimination %.4f (icosphere, 8000 points)\n",
              random.cv, blue.cv);
  EXPECT_NEAR(random.cv, poisson, 0.04);
  EXPECT_LT(blue.cv, 0.25 * random.cv);
}

TEST(PointCloudSampling, NearestNeighbourStatsOfAKnownConfiguration) {
  // Four points on a line at spacings 1, 2, 4: nearest distances 1, 1, 2, 4.
  PointCloud c;
  c.positions = {{0, 0, 0}, {1, 0, 0}, {3, 0, 0}, {7, 0, 0}};
  c.normals.assign(4, glm::vec3(0, 0, 1));
  c.areas.assign(4, 0.01f);  // small area: cells much finer than the spacing (ring search)
  const auto s = nearestNeighbourStats(c);
  EXPECT_DOUBLE_EQ(s.mean, 2.0);
  EXPECT_DOUBLE_EQ(s.min, 1.0);
  EXPECT_DOUBLE_EQ(s.max, 4.0);
  EXPECT_NEAR(s.stddev, std::sqrt((1.0 + 1.0 + 0.0 + 4.0) / 3.0), 1e-12);
  c.positions.resize(1);
  c.normals.resize(1);
  c.areas.resize(1);
  EXPECT_THROW((void)nearestNeighbourStats(c), PointCloudError);
}

TEST(PointCloudSampling, DeterministicForASeedWhateverTheThreadCount) {
  const TriangleMesh& mesh = testing::bunny();
  for (const auto method : {SamplingMethod::Random, SamplingMethod::Elimination}) {
    PointCloud one, two, four;
    tbb::task_arena(1).execute([&] { one = sample(mesh, 5000, method, 11); });
    tbb::task_arena(2).execute([&] { two = sample(mesh, 5000, method, 11); });
    tbb::task_arena(4).execute([&] { four = sample(mesh, 5000, method, 11); });
    EXPECT_TRUE(identical(one, two)) << toString(method);
    EXPECT_TRUE(identical(one, four)) << toString(method);
    EXPECT_FALSE(identical(one, sample(mesh, 5000, method, 12))) << "another seed";
  }
}

TEST(PointCloudSampling, RejectsBadOptionsWithMessages) {
  const TriangleMesh sphere = makeIcosphere(1);
  SamplingOptions o;
  o.count = 0;
  try {
    (void)samplePointCloud(sphere, o);
    FAIL() << "count 0 accepted";
  } catch (const PointCloudError& e) {
    EXPECT_NE(std::string(e.what()).find("point count is 0"), std::string::npos) << e.what();
  }
  o.count = 1u << 24;
  EXPECT_THROW((void)samplePointCloud(sphere, o), PointCloudError);
  o.count = 10;
  o.oversampling = 1.0;
  try {
    (void)samplePointCloud(sphere, o);
    FAIL() << "oversampling 1 accepted";
  } catch (const PointCloudError& e) {
    EXPECT_NE(std::string(e.what()).find("oversampling is 1"), std::string::npos) << e.what();
  }
  EXPECT_THROW((void)samplePointCloud(TriangleMesh{}, SamplingOptions{10}), MeshError);
  EXPECT_EQ(parseSamplingMethod("random"), SamplingMethod::Random);
  EXPECT_EQ(parseSamplingMethod(toString(SamplingMethod::Elimination)), SamplingMethod::Elimination);
  try {
    (void)parseSamplingMethod("turk");
    FAIL();
  } catch (const PointCloudError& e) {
    EXPECT_NE(std::string(e.what()).find("'elimination'"), std::string::npos) << e.what();
  }
}

TEST(PointCloud, ValidateNamesTheProblem) {
  PointCloud c = sample(makeIcosphere(2), 50, SamplingMethod::Random);
  EXPECT_NO_THROW(c.validate("c"));
  auto expectError = [](const PointCloud& bad, const std::string& text) {
    try {
      bad.validate("cloud X");
      FAIL() << "accepted: " << text;
    } catch (const PointCloudError& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find("cloud X"), std::string::npos) << m;
      EXPECT_NE(m.find(text), std::string::npos) << m;
    }
  };
  PointCloud bad = c;
  bad.areas[3] = 0.0f;
  expectError(bad, "area 3 is 0");
  bad = c;
  bad.normals[4] = glm::vec3(0, 0, 2);
  expectError(bad, "normal 4 has length 2");
  bad = c;
  bad.irradiance.assign(c.size(), glm::vec3(1.0f));
  bad.irradiance[5].y = -1.0f;
  expectError(bad, "irradiance 5");
  bad = c;
  bad.positions[6].x = std::nanf("");
  expectError(bad, "point 6");
  bad = c;
  bad.areas.pop_back();
  expectError(bad, "49 areas for 50 points");
  expectError(PointCloud{}, "empty");
}

// ---- PLY -------------------------------------------------------------------------------------
TEST(PointCloudPly, BinaryRoundTripIsExact) {
  TempDir dir("ply-roundtrip");
  PointCloud c = sample(testing::bunny(), 1234, SamplingMethod::Random, 9);
  writePointCloudPly(c, dir.path() / "a.ply");
  EXPECT_TRUE(identical(readPointCloudPly(dir.path() / "a.ply"), c));
  // With irradiance, without faces.
  c.irradiance.resize(c.size());
  for (size_t i = 0; i < c.size(); ++i)
    c.irradiance[i] = glm::vec3(0.5f * float(i), 1.0f / float(i + 1), 0.0f);
  c.faces.clear();
  writePointCloudPly(c, dir.path() / "b.ply");
  EXPECT_TRUE(identical(readPointCloudPly(dir.path() / "b.ply"), c));
  // No temporary file is left behind.
  size_t files = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir.path())) ++files;
  EXPECT_EQ(files, 2u);
}

TEST(PointCloudPly, ReadsAsciiAndBigEndianWithOtherPropertiesAndElements) {
  TempDir dir("ply-formats");
  {
    std::ofstream f(dir.path() / "a.ply");
    f << "ply\nformat ascii 1.0\ncomment hand-written\n"
         "element vertex 2\nproperty double area\nproperty float z\nproperty float y\n"
         "property float x\nproperty uchar red\nproperty float nz\nproperty float ny\n"
         "property float nx\nproperty list uchar int extra\n"
         "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
         "0.25 3 2 1 255 1 0 0 2 7 8\n"
         "0.5 -3 -2 -1 0 0 1 0 0\n"
         "2 0 1\n";
  }
  const PointCloud a = readPointCloudPly(dir.path() / "a.ply");
  ASSERT_EQ(a.size(), 2u);
  EXPECT_EQ(a.positions[0], glm::vec3(1, 2, 3));
  EXPECT_EQ(a.positions[1], glm::vec3(-1, -2, -3));
  EXPECT_EQ(a.normals[1], glm::vec3(0, 1, 0));
  EXPECT_EQ(a.areas[1], 0.5f);
  EXPECT_TRUE(a.faces.empty());
  EXPECT_FALSE(a.hasIrradiance());

  // Big endian: an element before the vertices (skipped), double positions, int face.
  std::string bytes =
      "ply\nformat binary_big_endian 1.0\nelement camera 1\nproperty float k\n"
      "element vertex 1\nproperty double x\nproperty double y\nproperty double z\n"
      "property float nx\nproperty float ny\nproperty float nz\nproperty float area\n"
      "property int face\nend_header\n";
  const auto putBig = [&bytes](const auto v) {
    char b[sizeof(v)];
    std::memcpy(b, &v, sizeof(v));
    for (size_t i = sizeof(v); i-- > 0;) bytes.push_back(b[i]);
  };
  putBig(9.0f);
  putBig(1.5);
  putBig(-2.25);
  putBig(1e-3);
  putBig(0.0f);
  putBig(0.0f);
  putBig(-1.0f);
  putBig(0.125f);
  putBig(int32_t(42));
  {
    std::ofstream f(dir.path() / "b.ply", std::ios::binary);
    f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  }
  const PointCloud b = readPointCloudPly(dir.path() / "b.ply");
  ASSERT_EQ(b.size(), 1u);
  EXPECT_EQ(b.positions[0], glm::vec3(1.5f, -2.25f, 1e-3f));
  EXPECT_EQ(b.normals[0], glm::vec3(0, 0, -1));
  EXPECT_EQ(b.areas[0], 0.125f);
  ASSERT_EQ(b.faces.size(), 1u);
  EXPECT_EQ(b.faces[0], 42u);
}

// Surfel clouds give a disc radius instead of an area: p_a = π r²; an area wins when both are there.
TEST(PointCloudPly, RadiusGivesTheDiscArea) {
  TempDir dir("ply-radius");
  {
    std::ofstream f(dir.path() / "r.ply");
    f << "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
         "property float z\nproperty float nx\nproperty float ny\nproperty float nz\n"
         "property double radius\nend_header\n0 0 0 0 0 1 0.5\n1 0 0 1 0 0 2\n";
  }
  const PointCloud a = readPointCloudPly(dir.path() / "r.ply");
  ASSERT_EQ(a.size(), 2u);
  EXPECT_FLOAT_EQ(a.areas[0], static_cast<float>(std::numbers::pi * 0.25));
  EXPECT_FLOAT_EQ(a.areas[1], static_cast<float>(std::numbers::pi * 4.0));
  {
    std::ofstream f(dir.path() / "both.ply");
    f << "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
         "property float z\nproperty float nx\nproperty float ny\nproperty float nz\n"
         "property float radius\nproperty float area\nend_header\n0 0 0 0 0 1 0.5 3\n";
  }
  EXPECT_FLOAT_EQ(readPointCloudPly(dir.path() / "both.ply").areas[0], 3.0f);
}

TEST(PointCloudPly, BadFilesGiveClearErrors) {
  TempDir dir("ply-errors");
  const auto expectError = [](const fs::path& path, const std::string& text) {
    try {
      (void)readPointCloudPly(path);
      FAIL() << "accepted " << path;
    } catch (const PointCloudError& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find(path.string()), std::string::npos) << m;
      EXPECT_NE(m.find(text), std::string::npos) << m;
    }
  };
  expectError(dir.path() / "missing.ply", "does not exist");
  const auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir.path() / name, std::ios::binary) << text;
    return dir.path() / name;
  };
  expectError(write("obj.ply", "v 1 2 3\n"), "no PLY header");
  expectError(write("noarea.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                                  "property float y\nproperty float z\nproperty float nx\n"
                                  "property float ny\nproperty float nz\nend_header\n0 0 0 0 0 1\n"),
              "no vertex property 'area'");
  expectError(write("short.ply", "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\n"
                                 "property float y\nproperty float z\nproperty float nx\n"
                                 "property float ny\nproperty float nz\nproperty float area\n"
                                 "end_header\n0 0 0 0 0 1 1\n"),
              "truncated");
  expectError(write("nan.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                               "property float y\nproperty float z\nproperty float nx\n"
                               "property float ny\nproperty float nz\nproperty float area\n"
                               "end_header\n0 0 0 0 0 1 abc\n"),
              "'abc' is not a number");
  expectError(write("badradius.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                                     "property float y\nproperty float z\nproperty float nx\n"
                                     "property float ny\nproperty float nz\nproperty float radius\n"
                                     "end_header\n0 0 0 0 0 1 -0.5\n"),
              "vertex 0 has radius -0.5");
  expectError(write("badtype.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty half x\n"
                                   "end_header\n"),
              "property type 'half'");
  // A truncated binary file (as a crash during a non-atomic write would leave).
  PointCloud c = sample(makeIcosphere(1), 100, SamplingMethod::Random);
  writePointCloudPly(c, dir.path() / "full.ply");
  fs::resize_file(dir.path() / "full.ply", fs::file_size(dir.path() / "full.ply") - 10);
  expectError(dir.path() / "full.ply", "truncated");
}

// ---- Cache -----------------------------------------------------------------------------------
TEST(PointCloudCache, HitReturnsIdenticalDataAndAChangedMeshMisses) {
  TempDir dir("cache");
  TriangleMesh mesh = makeIcosphere(3);
  SamplingOptions o;
  o.count = 3000;
  o.seed = 4;
  const auto first = loadOrSamplePointCloud(mesh, o, dir.path());
  EXPECT_FALSE(first.fromCache);
  EXPECT_TRUE(first.note.empty()) << first.note;
  EXPECT_TRUE(fs::exists(first.file));
  EXPECT_EQ(first.file.parent_path(), dir.path());
  EXPECT_TRUE(identical(first.cloud, samplePointCloud(mesh, o)));

  const auto second = loadOrSamplePointCloud(mesh, o, dir.path());
  EXPECT_TRUE(second.fromCache);
  EXPECT_EQ(second.file, first.file);
  EXPECT_TRUE(identical(second.cloud, first.cloud));

  // Another count, seed or method is another file.
  for (SamplingOptions other : {SamplingOptions{3001, 4}, SamplingOptions{3000, 5},
                                SamplingOptions{3000, 4, SamplingMethod::Random}}) {
    EXPECT_NE(cacheFileName(mesh, other), cacheFileName(mesh, o));
    EXPECT_FALSE(loadOrSamplePointCloud(mesh, other, dir.path()).fromCache);
  }
  // A changed mesh (moved by a tiny amount) has another hash, hence misses.
  TriangleMesh moved = mesh;
  moved.transform(1.0, glm::dvec3(0.0, 0.0, 1e-9));
  EXPECT_NE(meshHash(moved), meshHash(mesh));
  const auto third = loadOrSamplePointCloud(moved, o, dir.path());
  EXPECT_FALSE(third.fromCache);
  EXPECT_NE(third.file, first.file);
  EXPECT_TRUE(loadOrSamplePointCloud(mesh, o, dir.path()).fromCache);  // the first is still there
}

TEST(PointCloudCache, CorruptFilesAreResampledAndUnwritableFoldersReported) {
  TempDir dir("cache-corrupt");
  const TriangleMesh mesh = makeIcosphere(2);
  SamplingOptions o;
  o.count = 500;
  const auto first = loadOrSamplePointCloud(mesh, o, dir.path());
  fs::resize_file(first.file, 100);
  const auto again = loadOrSamplePointCloud(mesh, o, dir.path());
  EXPECT_FALSE(again.fromCache);
  EXPECT_NE(again.note.find("resampled"), std::string::npos) << again.note;
  EXPECT_TRUE(identical(again.cloud, first.cloud));
  EXPECT_TRUE(loadOrSamplePointCloud(mesh, o, dir.path()).fromCache);  // rewritten

  // A cache "folder" below a regular file cannot be created: sampled anyway, and said so.
  std::ofstream(dir.path() / "file") << "x";
  const auto nowhere = loadOrSamplePointCloud(mesh, o, dir.path() / "file" / "cache");
  EXPECT_FALSE(nowhere.fromCache);
  EXPECT_NE(nowhere.note.find("not cached"), std::string::npos) << nowhere.note;
  EXPECT_TRUE(identical(nowhere.cloud, first.cloud));
}

TEST(PointCloudCache, DefaultDirectoryFollowsTheEnvironment) {
  const auto saved = [](const char* name) {
    const char* v = std::getenv(name);
    return v == nullptr ? std::optional<std::string>() : std::optional<std::string>(v);
  };
  const auto restore = [](const char* name, const std::optional<std::string>& v) {
    if (v) ::setenv(name, v->c_str(), 1);
    else ::unsetenv(name);
  };
  const auto own = saved("TRANSLUCENT_CACHE_DIR"), xdg = saved("XDG_CACHE_HOME"),
             home = saved("HOME");
  ::setenv("TRANSLUCENT_CACHE_DIR", "/tmp/own-cache", 1);
  ::setenv("XDG_CACHE_HOME", "/tmp/xdg", 1);
  ::setenv("HOME", "/home/someone", 1);
  EXPECT_EQ(defaultCacheDirectory(), fs::path("/tmp/own-cache"));
  ::unsetenv("TRANSLUCENT_CACHE_DIR");
  EXPECT_EQ(defaultCacheDirectory(), fs::path("/tmp/xdg/translucent"));
  ::setenv("XDG_CACHE_HOME", "relative/ignored", 1);
  EXPECT_EQ(defaultCacheDirectory(), fs::path("/home/someone/.cache/translucent"));
  ::unsetenv("XDG_CACHE_HOME");
  EXPECT_EQ(defaultCacheDirectory(), fs::path("/home/someone/.cache/translucent"));
  restore("TRANSLUCENT_CACHE_DIR", own);
  restore("XDG_CACHE_HOME", xdg);
  restore("HOME", home);
}

TEST(MeshHash, DependsOnEveryPartOfTheMesh) {
  const TriangleMesh m = makeIcosphere(1);
  EXPECT_EQ(meshHash(m), meshHash(makeIcosphere(1)));
  TriangleMesh a = m;
  a.positions[5].y = std::nextafter(a.positions[5].y, 2.0);
  EXPECT_NE(meshHash(a), meshHash(m));
  TriangleMesh b = m;
  std::swap(b.triangles[0].x, b.triangles[0].y);
  EXPECT_NE(meshHash(b), meshHash(m));
  TriangleMesh c = m;
  c.normals.clear();
  EXPECT_NE(meshHash(c), meshHash(m));
}

}  // namespace
}  // namespace translucent::geometry

namespace translucent::geometry {
namespace {

// TriangleMesh::orientOutwards (shared by the GPU techniques): an inside-out closed box is turned
// back, with its normals; an outward box is left alone.
TEST(TriangleMeshOrientation, FlipsInsideOutMeshAndItsNormals) {
  TriangleMesh box = makeBox({-1, -1, -1}, {1, 2, 3});
  box.normals.assign(box.positions.size(), glm::dvec3(0, 0, 1));
  const TriangleMesh original = box;
  EXPECT_FALSE(box.orientOutwards());
  EXPECT_EQ(box.triangles, original.triangles);
  for (glm::uvec3& t : box.triangles) std::swap(t.y, t.z);  // inside out
  EXPECT_TRUE(box.orientOutwards());
  EXPECT_EQ(box.triangles, original.triangles);
  for (const auto& n : box.normals) EXPECT_EQ(n, glm::dvec3(0, 0, -1));
}

}  // namespace
}  // namespace translucent::geometry
