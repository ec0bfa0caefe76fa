// SPDX-License-Identifier: GPL-3.0-or-later
// The surface through a point cloud (geometry/surface_reconstruction.h): closed where the samples
// cover a closed surface, every point a vertex with its normal, outward by the points' normals,
// the area of the sampled surface. (A point-cloud file as a scene's mesh: tests/scene.)
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

#include "translucent/geometry/icosphere.h"
#include "translucent/geometry/point_cloud.h"
#include "translucent/geometry/surface_reconstruction.h"

namespace translucent::geometry {
namespace {

SamplingOptions sampling(size_t count) {
  SamplingOptions o;
  o.count = count;
  o.seed = 1;
  o.method = SamplingMethod::Elimination;
  return o;
}

// Blue-noise samples of the unit sphere: a closed surface through all of them, outward, whose area
// is the sphere's within the chordal deficit of triangles of its sample spacing (~0.2% at 4000).
TEST(SurfaceReconstruction, SphereSamplesGiveTheClosedOutwardSphere) {
  const PointCloud cloud = samplePointCloud(makeIcosphere(5, 1.0), sampling(4000));
  ReconstructionStats st;
  std::vector<uint32_t> vertexOf;
  const TriangleMesh mesh = reconstructSurface(cloud, "sphere", &st, &vertexOf);
  EXPECT_EQ(st.points, 4000u);
  EXPECT_EQ(st.unused_points, 0u);
  EXPECT_EQ(st.open_edges, 0u);
  EXPECT_EQ(mesh.openEdgeCount(), 0u);
  EXPECT_EQ(mesh.vertexCount(), 4000u);
  EXPECT_EQ(st.triangles, 2 * 4000u - 4);  // Euler: a closed genus-0 surface
  EXPECT_NEAR(mesh.area(), 4.0 * std::numbers::pi, 0.01 * 4.0 * std::numbers::pi);
  size_t inward = 0;
  for (const glm::uvec3& t : mesh.triangles) {
    const glm::dvec3 a = mesh.positions[t.x], b = mesh.positions[t.y], c = mesh.positions[t.z];
    inward += glm::dot(glm::cross(b - a, c - a), a + b + c) < 0.0 ? 1 : 0;
  }
  EXPECT_EQ(inward, 0u);
  // The vertices are the points, with the points' normals.
  ASSERT_EQ(vertexOf.size(), cloud.size());
  for (size_t i = 0; i < cloud.size(); ++i) {
    ASSERT_LT(vertexOf[i], mesh.vertexCount());
    EXPECT_EQ(glm::vec3(mesh.positions[vertexOf[i]]), cloud.positions[i]);
    EXPECT_EQ(glm::vec3(mesh.normals[vertexOf[i]]), cloud.normals[i]);
  }
  EXPECT_NE(describe(st).find("4000 points, 7996 triangles, 0 points unused, closed"),
            std::string::npos)
      << describe(st);
}

TEST(SurfaceReconstruction, TooFewOrFlatPointsAreRefusedNamingTheInput) {
  PointCloud three;
  for (int i = 0; i < 3; ++i) {
    three.positions.emplace_back(float(i), float(i * i), 0.0f);
    three.normals.emplace_back(0.0f, 0.0f, 1.0f);
    three.areas.push_back(1.0f);
  }
  try {
    (void)reconstructSurface(three, "cloud.ply");
    FAIL() << "accepted";
  } catch (const MeshError& e) {
    EXPECT_NE(std::string(e.what()).find("cloud.ply: no surface could be reconstructed through "
                                         "its 3 points"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace translucent::geometry
