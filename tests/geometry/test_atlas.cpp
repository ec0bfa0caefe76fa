// SPDX-License-Identifier: GPL-3.0-or-later
// The surface atlas (geometry/atlas.h): the properties texture-space importance sampling relies
// on (seed 3.1.1, 3.2.1): every triangle owns a texel, no two triangles overlap, the texels give
// back the surface area, and the mesh's own UVs are kept when valid and refused with a reason
// otherwise.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <unistd.h>

#include <cstdlib>
#include <map>
#include <filesystem>
#include <fstream>
#include <glm/geometric.hpp>

#include "translucent/geometry/atlas.h"
#include "test_meshes.h"

namespace translucent::geometry {
namespace {

// The CGAL example meshes, where scripts/install-test-data puts them.
const TriangleMesh& cgalMesh(const std::string& name) {
  static std::map<std::string, TriangleMesh> meshes;
  if (const auto it = meshes.find(name); it != meshes.end()) return it->second;
  std::filesystem::path dir;
  if (const char* d = std::getenv("TRANSLUCENT_DATA"); d && *d)
    dir = d;
  else if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x)
    dir = std::filesystem::path(x) / "translucent" / "data";
  else
    dir = std::filesystem::path(std::getenv("HOME") ? std::getenv("HOME") : "") / ".cache" /
          "translucent" / "data";
  const auto path = dir / "cgal" / (name + ".off");
  if (!std::filesystem::exists(path))
    throw std::runtime_error("the test mesh " + path.string() +
                             " is missing: run scripts/install-test-data");
  return meshes.emplace(name, loadMesh(path.string())).first->second;
}

std::vector<glm::dvec2> cornerUVs(const Atlas& atlas) {
  return {atlas.uvs.begin(), atlas.uvs.end()};
}

// Everything the issue asks of an atlas at 1024²: UVs in [0,1]², no overlapping triangles (exact
// separating-axis tests, and no texel centre inside two triangles), every triangle owns at least
// one texel, and Σ over texels of A_S/A_T recovers ΣA_S within 1%.
void expectUsableAtlas(const TriangleMesh& mesh, const Atlas& atlas) {
  ASSERT_EQ(atlas.triangleCount(), mesh.triangleCount());
  ASSERT_EQ(atlas.uvs.size(), 3 * mesh.triangleCount());
  for (const glm::vec2& uv : atlas.uvs) {
    ASSERT_GE(uv.x, 0.0f);
    ASSERT_LE(uv.x, 1.0f);
    ASSERT_GE(uv.y, 0.0f);
    ASSERT_LE(uv.y, 1.0f);
  }
  for (size_t t = 0; t < atlas.triangleCount(); ++t) {
    ASSERT_GT(atlas.texelArea[t], 0.0) << "triangle " << t;
    ASSERT_LT(atlas.chart[t], atlas.chartCount);
  }
  EXPECT_EQ(countUVOverlaps(cornerUVs(atlas)), 0u);
  const AtlasCoverage cov = rasterizeCoverage(atlas);
  EXPECT_EQ(cov.conflicts, 0u);
  EXPECT_EQ(cov.uncovered, 0u);
  size_t without = 0;
  for (const uint32_t n : cov.texels) without += n == 0 ? 1 : 0;
  EXPECT_EQ(without, 0u) << "triangles owning no texel";
  const AtlasStatistics st = atlasStatistics(atlas, cov);
  EXPECT_NEAR(st.recoveredAreaRatio, 1.0, 0.01);
  EXPECT_GT(st.utilisation, 0.05);
}

TEST(AtlasLscm, Bunny1024EveryTriangleOwnsATexelNoOverlapsAreaRecovered) {
  const TriangleMesh& mesh = testing::bunny();
  AtlasOptions o;
  o.method = AtlasMethod::Lscm;
  expectUsableAtlas(mesh, buildAtlas(mesh, o));
}

TEST(AtlasLscm, Armadillo1024EveryTriangleOwnsATexelNoOverlapsAreaRecovered) {
  const TriangleMesh& mesh = cgalMesh("armadillo");
  AtlasOptions o;
  o.method = AtlasMethod::Lscm;
  expectUsableAtlas(mesh, buildAtlas(mesh, o));
}

TEST(AtlasLscm, Cow1024EveryTriangleOwnsATexelNoOverlapsAreaRecovered) {
  const TriangleMesh& mesh = cgalMesh("cow");
  AtlasOptions o;
  o.method = AtlasMethod::Lscm;
  const Atlas atlas = buildAtlas(mesh, o);
  expectUsableAtlas(mesh, atlas);
  // Charts are split until their maps distort little: measured RMS 0.085.
  EXPECT_LT(atlasStatistics(atlas, rasterizeCoverage(atlas)).distortionRms, 0.2);
}

TEST(AtlasAuthalic, Cow1024EveryTriangleOwnsATexelNoOverlapsAreaRecovered) {
  const TriangleMesh& mesh = cgalMesh("cow");
  expectUsableAtlas(mesh, buildAtlas(mesh, AtlasOptions{}));
}

TEST(AtlasTriangles, CowHasNoAreaDistortion) {
  const TriangleMesh& mesh = cgalMesh("cow");
  AtlasOptions o;
  o.method = AtlasMethod::Triangles;
  const Atlas atlas = buildAtlas(mesh, o);
  expectUsableAtlas(mesh, atlas);
  EXPECT_EQ(atlas.chartCount, mesh.triangleCount());
  // One global scale: ln(A_T/A_S) normalised is 0 up to float rounding of the UVs.
  const AtlasStatistics st = atlasStatistics(atlas, rasterizeCoverage(atlas));
  EXPECT_LT(st.distortionRms, 1e-3);
  EXPECT_LT(std::max(-st.distortionMin, st.distortionMax), 1e-2);
}

TEST(AtlasLookup, TexelSurfacePointLiesOnItsTriangle) {
  const TriangleMesh& mesh = cgalMesh("cow");
  const Atlas atlas = buildAtlas(mesh, AtlasOptions{});
  const AtlasCoverage cov = rasterizeCoverage(atlas);
  // Every owned texel (every third row and column) maps to a point of its triangle (barycentric
  // in [0, 1] within 1e-9, on its plane within 1e-9) with a unit normal.
  size_t checked = 0;
  for (uint32_t y = 0; y < atlas.size; y += 3)
    for (uint32_t x = 0; x < atlas.size; x += 3) {
      const auto p = texelSurfacePoint(mesh, atlas, cov, x, y);
      if (!p) continue;
      ++checked;
      ASSERT_EQ(static_cast<int32_t>(p->triangle), cov.at(x, y));
      for (int k = 0; k < 3; ++k) {
        ASSERT_GE(p->barycentric[k], -1e-9);
        ASSERT_LE(p->barycentric[k], 1.0 + 1e-9);
      }
      const glm::uvec3 t = mesh.triangles[p->triangle];
      const glm::dvec3 n = glm::normalize(glm::cross(mesh.positions[t.y] - mesh.positions[t.x],
                                                     mesh.positions[t.z] - mesh.positions[t.x]));
      EXPECT_NEAR(glm::dot(p->position - mesh.positions[t.x], n), 0.0, 1e-9);
      EXPECT_NEAR(glm::length(p->normal), 1.0, 1e-9);
    }
  EXPECT_GT(checked, 1000u);
  EXPECT_FALSE(texelSurfacePoint(mesh, atlas, cov, atlas.size, 0).has_value());
}

TEST(AtlasDeterminism, SameAtlasForOneAndTwoThreads) {
  const TriangleMesh& mesh = cgalMesh("cow");
  Atlas one, two;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = buildAtlas(mesh, AtlasOptions{});
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
    two = buildAtlas(mesh, AtlasOptions{});
  }
  ASSERT_EQ(one.uvs.size(), two.uvs.size());
  for (size_t i = 0; i < one.uvs.size(); ++i) ASSERT_EQ(one.uvs[i], two.uvs[i]) << i;
  EXPECT_EQ(one.chart, two.chart);
}

// A mesh whose vertices are the corners of `atlas`, with the atlas's UVs as its own.
TriangleMesh withUVs(const TriangleMesh& mesh, const Atlas& atlas) {
  TriangleMesh m;
  for (size_t t = 0; t < mesh.triangleCount(); ++t) {
    for (int k = 0; k < 3; ++k) {
      m.positions.push_back(mesh.positions[mesh.triangles[t][k]]);
      m.texcoords.emplace_back(atlas.uv(t, k));
    }
    const auto b = static_cast<uint32_t>(3 * t);
    m.triangles.emplace_back(b, b + 1, b + 2);
  }
  return m;
}

TEST(AtlasMeshUVs, ValidUVsAreKept) {
  const TriangleMesh& cow = cgalMesh("cow");
  AtlasOptions lscm;
  lscm.method = AtlasMethod::Lscm;
  const TriangleMesh mesh = withUVs(cow, buildAtlas(cow, lscm));
  EXPECT_EQ(meshUVProblem(mesh), "");
  AtlasOptions o;
  o.useMeshUVs = true;
  const Atlas atlas = buildAtlas(mesh, o);
  EXPECT_EQ(atlas.method, AtlasMethod::MeshUVs);
  EXPECT_EQ(atlas.meshUVRejection, "");
  for (size_t t = 0; t < mesh.triangleCount(); ++t)
    for (int k = 0; k < 3; ++k)
      ASSERT_EQ(atlas.uv(t, k), glm::vec2(mesh.texcoords[mesh.triangles[t][k]]));
  // Corners are separate vertices, so every triangle is its own chart here.
  EXPECT_EQ(atlas.chartCount, mesh.triangleCount());
  expectUsableAtlas(mesh, atlas);
}

TEST(AtlasMeshUVs, InvalidUVsAreRejectedWithTheReason) {
  const TriangleMesh& cow = cgalMesh("cow");
  AtlasOptions lscm;
  lscm.method = AtlasMethod::Lscm;
  const TriangleMesh valid = withUVs(cow, buildAtlas(cow, lscm));
  const auto rejection = [](const TriangleMesh& m) {
    AtlasOptions o;
    o.useMeshUVs = true;
    o.method = AtlasMethod::Triangles;
    const Atlas a = buildAtlas(m, o);
    EXPECT_EQ(a.method, AtlasMethod::Triangles);  // built instead
    return a.meshUVRejection;
  };
  EXPECT_NE(rejection(cow).find("no texture coordinates"), std::string::npos);
  TriangleMesh outside = valid;
  outside.texcoords[4] = {1.25, 0.5};
  EXPECT_NE(rejection(outside).find("outside [0, 1]"), std::string::npos) << rejection(outside);
  TriangleMesh flipped = valid;
  std::swap(flipped.texcoords[0], flipped.texcoords[1]);
  EXPECT_NE(rejection(flipped).find("triangle 0 has UV area"), std::string::npos);
  TriangleMesh overlapping = valid;  // triangle 1 moved onto triangle 0
  for (int k = 0; k < 3; ++k) overlapping.texcoords[3 + k] = overlapping.texcoords[k];
  EXPECT_NE(rejection(overlapping).find("overlap"), std::string::npos) << rejection(overlapping);
}

TEST(AtlasMeshUVs, ObjTexcoordsAreLoaded) {
  const auto path = std::filesystem::temp_directory_path() / "translucent-test-atlas-quad.obj";
  {
    std::ofstream f(path);
    f << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0.1 0.1\nvt 0.9 0.1\nvt 0.9 0.9\nvt 0.1 0.9\n"
         "f 1/1 2/2 3/3\nf 1/1 3/3 4/4\n";
  }
  const TriangleMesh m = loadMesh(path.string());
  std::filesystem::remove(path);
  ASSERT_EQ(m.texcoords.size(), m.positions.size());
  EXPECT_EQ(meshUVProblem(m), "");
  AtlasOptions o;
  o.useMeshUVs = true;
  o.size = 64;
  const Atlas a = buildAtlas(m, o);
  EXPECT_EQ(a.method, AtlasMethod::MeshUVs);
  EXPECT_EQ(a.chartCount, 1u);
  // The file's UVs cover 0.8² of the atlas, kept as they are.
  EXPECT_NEAR(a.texelArea[0] + a.texelArea[1], 0.64 * 64 * 64, 1e-3);
}

TEST(AtlasCache, SecondCallReadsTheFileAndACorruptFileIsRebuilt) {
  const TriangleMesh& mesh = cgalMesh("cow");
  const auto dir = std::filesystem::temp_directory_path() /
                   ("translucent-test-atlas-cache-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  AtlasOptions o;
  o.size = 256;
  const CachedAtlas first = loadOrBuildAtlas(mesh, o, dir);
  EXPECT_FALSE(first.fromCache);
  EXPECT_EQ(first.note, "");
  ASSERT_TRUE(std::filesystem::exists(first.file));
  EXPECT_NE(first.file.filename().string().find("-n256-lscm-"), std::string::npos);
  const CachedAtlas second = loadOrBuildAtlas(mesh, o, dir);
  EXPECT_TRUE(second.fromCache);
  EXPECT_EQ(second.atlas.uvs, first.atlas.uvs);
  EXPECT_EQ(second.atlas.chart, first.atlas.chart);
  EXPECT_EQ(second.atlas.texelArea, first.atlas.texelArea);
  std::filesystem::resize_file(first.file, 100);
  const CachedAtlas third = loadOrBuildAtlas(mesh, o, dir);
  EXPECT_FALSE(third.fromCache);
  EXPECT_NE(third.note.find("rebuilt"), std::string::npos);
  EXPECT_EQ(third.atlas.uvs, first.atlas.uvs);
  // Another method or size is another file.
  AtlasOptions other = o;
  other.method = AtlasMethod::Authalic;
  EXPECT_NE(atlasCacheFileName(mesh, other), atlasCacheFileName(mesh, o));
  other = o;
  other.size = 512;
  EXPECT_NE(atlasCacheFileName(mesh, other), atlasCacheFileName(mesh, o));
  std::filesystem::remove_all(dir);
}

TEST(AtlasOptionsCheck, OutOfRangeOptionsNameTheParameter) {
  const TriangleMesh& mesh = cgalMesh("cow");
  AtlasOptions o;
  o.size = 8;
  try {
    (void)buildAtlas(mesh, o);
    FAIL() << "expected AtlasError";
  } catch (const AtlasError& e) {
    EXPECT_NE(std::string(e.what()).find("size 8"), std::string::npos) << e.what();
  }
  o = {};
  o.maxChartAngle = 120.0;
  EXPECT_THROW((void)buildAtlas(mesh, o), AtlasError);
  EXPECT_THROW((void)parseAtlasMethod("abf"), AtlasError);
  EXPECT_EQ(parseAtlasMethod("lscm"), AtlasMethod::Lscm);
  // Too many triangles for a tiny atlas: an error that says to enlarge it.
  o = {};
  o.size = 16;
  o.method = AtlasMethod::Triangles;
  try {
    (void)buildAtlas(mesh, o);
    FAIL() << "expected AtlasError";
  } catch (const AtlasError& e) {
    EXPECT_NE(std::string(e.what()).find("larger"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace translucent::geometry
