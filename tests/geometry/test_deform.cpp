// SPDX-License-Identifier: GPL-3.0-or-later
// Procedural deformations (geometry/deform.h): amount 0 is the identity bit for bit; a twist
// preserves a cylinder's area; bend and wave are finite, continuous and periodic in time; the
// Jacobian matches finite differences; undeformPoint inverts deformPoint; deformed normals are
// the deformed surface's.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>

#include "translucent/geometry/deform.h"
#include "translucent/geometry/icosphere.h"

namespace translucent::geometry {
namespace {

using Type = Deformation::Type;

Deformation make(Type type, double amount, double period = 0.0) {
  Deformation d;
  d.type = type;
  d.amount = amount;
  d.period = period;
  d.origin = {0.1, -0.2, 0.05};
  d.axis = glm::normalize(glm::dvec3(0.2, 1.0, 0.1));
  // Perpendicular to the axis.
  d.direction = glm::normalize(glm::cross(d.axis, glm::dvec3(0.0, 0.0, 1.0)));
  d.wavelength = 0.7;
  return d;
}

// A closed cylinder of radius r from y = 0 to y = h along +y: `around` segments, `along` rings,
// with caps (a fan about a centre vertex at each end).
TriangleMesh cylinder(double r, double h, int around, int along) {
  TriangleMesh m;
  for (int j = 0; j <= along; ++j)
    for (int i = 0; i < around; ++i) {
      const double a = 2.0 * std::numbers::pi * i / around;
      m.positions.push_back({r * std::cos(a), h * j / along, r * std::sin(a)});
    }
  auto idx = [&](int i, int j) { return unsigned(j * around + (i % around)); };
  for (int j = 0; j < along; ++j)
    for (int i = 0; i < around; ++i) {
      m.triangles.push_back({idx(i, j), idx(i, j + 1), idx(i + 1, j)});
      m.triangles.push_back({idx(i + 1, j), idx(i, j + 1), idx(i + 1, j + 1)});
    }
  const unsigned bottom = unsigned(m.positions.size()), top = bottom + 1;
  m.positions.push_back({0.0, 0.0, 0.0});
  m.positions.push_back({0.0, h, 0.0});
  for (int i = 0; i < around; ++i) {
    m.triangles.push_back({bottom, idx(i + 1, 0), idx(i, 0)});
    m.triangles.push_back({top, idx(i, along), idx(i + 1, along)});
  }
  return m;
}

const std::vector<glm::dvec3> kPoints = {
    {0.0, 0.0, 0.0}, {0.3, 0.4, -0.2}, {-0.45, 0.1, 0.3}, {0.2, -0.5, 0.25}, {0.05, 0.45, 0.4}};

TEST(Deform, AmountZeroIsTheIdentityExactly) {
  for (Type type : {Type::Bend, Type::Twist, Type::Wave}) {
    SCOPED_TRACE(toString(type));
    const std::vector<Deformation> chain = {make(type, 0.0)};
    EXPECT_TRUE(isIdentity(chain, 0.7));
    for (const glm::dvec3& p : kPoints) {
      EXPECT_EQ(deformPoint(chain, 0.7, p), p);
      EXPECT_EQ(deformPoint(make(type, 0.0), 0.0, p), p);  // magnitude 0 directly
      EXPECT_EQ(undeformPoint(chain, 0.7, p), p);
    }
    // A periodic deformation at time 0 (sin 0 = 0) and the whole mesh.
    const std::vector<Deformation> periodic = {make(type, 30.0, 2.0)};
    EXPECT_TRUE(isIdentity(periodic, 0.0));
    TriangleMesh m = makeIcosphere(2);
    const TriangleMesh before = m;
    deformMesh(periodic, 0.0, m);
    EXPECT_EQ(m.positions, before.positions);
    EXPECT_EQ(m.normals, before.normals);
  }
}

TEST(Deform, TwistPreservesTheAreaOfACylinderAlongItsAxis) {
  // A twist is an isometry of the continuous cylinder surface about its axis (a helix stays on
  // it), so the area of a triangulated cylinder changes only by the discretisation, to second
  // order in the turn per segment: around, the angle between a ring's tangent (along which it
  // turns) and a triangle's chord, π/N for N segments, times r θ'; along, the turn θ' Δy between
  // neighbouring rings (the triangles' edges between rings cut inside the surface). Radius
  // r = 0.25, height 2, θ' = 180 degrees per unit (π rad: a full turn over the cylinder); N = 256
  // and Δy = 0.005 (400 rings): (r θ' π/N)² = 9e-6 and (θ' Δy)² = 2.5e-4; measured 1.1e-4
  // (tolerance 2e-4), and 4.4e-4 at half both resolutions: the error must grow by about four
  // (second order; more than three times is required).
  Deformation d;
  d.type = Type::Twist;
  d.amount = 180.0;
  d.axis = {0.0, 1.0, 0.0};
  auto areaError = [&](int around, int along) {
    TriangleMesh c = cylinder(0.25, 2.0, around, along);
    const double before = c.area();
    deformMesh({d}, 0.0, c);
    return c.area() / before - 1.0;
  };
  const double fine = areaError(256, 400), coarse = areaError(128, 200);
  EXPECT_LT(std::abs(fine), 2e-4);
  EXPECT_GT(std::abs(coarse), 3.0 * std::abs(fine));
  TriangleMesh m = cylinder(0.25, 2.0, 256, 50);
  deformMesh({d}, 0.0, m);
  // The caps rotate rigidly, the rings stay on the cylinder.
  for (const glm::dvec3& p : m.positions)
    if (glm::length(glm::dvec2(p.x, p.z)) > 0.1) {
      EXPECT_NEAR(glm::length(glm::dvec2(p.x, p.z)), 0.25, 1e-12);
    }
  // The top ring turned by 360 degrees: back where it started; the middle by 180.
  const TriangleMesh rest = cylinder(0.25, 2.0, 256, 50);
  EXPECT_NEAR(glm::length(m.positions[50 * 256] - rest.positions[50 * 256]), 0.0, 1e-12);
  const glm::dvec3 r = rest.positions[25 * 256];
  EXPECT_NEAR(glm::length(m.positions[25 * 256] - glm::dvec3(-r.x, r.y, -r.z)), 0.0, 1e-12);
}

TEST(Deform, BendAndWaveAreFiniteContinuousAndPeriodicInTime) {
  const double period = 1.5;
  for (Type type : {Type::Bend, Type::Wave, Type::Twist}) {
    SCOPED_TRACE(toString(type));
    const std::vector<Deformation> chain = {make(type, type == Type::Wave ? 0.2 : 120.0, period)};
    for (const glm::dvec3& p : kPoints)
      for (double t : {0.0, 0.1, 0.37, 0.75, 1.2}) {
        const glm::dvec3 x = deformPoint(chain, t, p);
        EXPECT_TRUE(std::isfinite(x.x) && std::isfinite(x.y) && std::isfinite(x.z));
        // Periodic: T and T + P, T + 3P give the same point (to rounding of sin's argument).
        EXPECT_NEAR(glm::length(deformPoint(chain, t + period, p) - x), 0.0, 1e-12);
        EXPECT_NEAR(glm::length(deformPoint(chain, t + 3.0 * period, p) - x), 0.0, 1e-12);
        // Continuous in time: a step of 1e-6 moves the point by O(1e-6) (|dx/dT| is at most
        // 2π/P times the displacement's size, here below 10 scene units per time unit).
        EXPECT_LT(glm::length(deformPoint(chain, t + 1e-6, p) - x), 1e-5);
        // And in space (no seam): a step of 1e-6 in space moves the image by O(1e-6).
        EXPECT_LT(glm::length(deformPoint(chain, t, p + glm::dvec3(1e-6, -1e-6, 1e-6)) - x), 1e-5);
      }
    // Half a period later the magnitude is the negative: sin(2π(T + P/2)/P) = -sin(2πT/P).
    EXPECT_NEAR(chain[0].magnitude(0.2) + chain[0].magnitude(0.2 + period / 2), 0.0, 1e-12);
    // Amount at period 0.
    EXPECT_EQ(make(type, 7.0).magnitude(123.0), 7.0);
  }
}

TEST(Deform, JacobianMatchesFiniteDifferencesAndTheInverseUndoes) {
  for (Type type : {Type::Bend, Type::Twist, Type::Wave}) {
    SCOPED_TRACE(toString(type));
    const Deformation d = make(type, type == Type::Wave ? 0.15 : 75.0);
    const std::vector<Deformation> chain = {d, make(Type::Twist, 40.0), make(Type::Wave, 0.05)};
    for (const glm::dvec3& p : kPoints) {
      const glm::dmat3 j = deformJacobian(d, d.amount, p);
      const double h = 1e-6;
      for (int c = 0; c < 3; ++c) {
        glm::dvec3 e(0.0);
        e[c] = h;
        const glm::dvec3 fd = (deformPoint(d, d.amount, p + e) - deformPoint(d, d.amount, p - e)) / (2.0 * h);
        EXPECT_NEAR(glm::length(fd - j[c]), 0.0, 1e-8) << "column " << c;
      }
      // The inverse of the chain (twist and wave exactly, bend by Newton).
      const glm::dvec3 x = deformPoint(chain, 0.0, p);
      EXPECT_NEAR(glm::length(undeformPoint(chain, 0.0, x) - p), 0.0, 1e-11);
      // Normals: deformed by J^{-T}, back by J^T (undeformNormal).
      glm::dvec3 q = p, n = glm::normalize(glm::dvec3(0.3, -0.5, 0.8));
      const glm::dvec3 n0 = n;
      deformPointNormal(chain, 0.0, q, n);
      EXPECT_NEAR(glm::length(undeformNormal(chain, 0.0, p, n) - n0), 0.0, 1e-12);
    }
  }
}

TEST(Deform, NormalsAreTheDeformedSurfacesNormals) {
  // A fine sphere: the transformed smooth normals agree with the deformed mesh's own smooth
  // (face-averaged) normals up to the discretisation (icosphere level 5, edges about 0.04:
  // a few degrees at most where the deformation curves the surface most).
  for (Type type : {Type::Bend, Type::Twist, Type::Wave}) {
    SCOPED_TRACE(toString(type));
    TriangleMesh m = makeIcosphere(5);
    m.normals.clear();
    deformMesh({make(type, type == Type::Wave ? 0.05 : 60.0)}, 0.0, m);
    ASSERT_EQ(m.normals.size(), m.positions.size());
    TriangleMesh faces = m;
    faces.normals.clear();
    const std::vector<glm::dvec3> recomputed = smoothVertexNormals(faces);
    double worst = 1.0, mean = 0.0;
    for (size_t i = 0; i < m.normals.size(); ++i) {
      EXPECT_NEAR(glm::length(m.normals[i]), 1.0, 1e-12);
      const double c = glm::dot(m.normals[i], recomputed[i]);
      worst = std::min(worst, c);
      mean += c / double(m.normals.size());
    }
    EXPECT_GT(worst, std::cos(5.0 * std::numbers::pi / 180.0));
    EXPECT_GT(mean, std::cos(1.0 * std::numbers::pi / 180.0));
  }
}

TEST(Deform, KeysChangeWithEveryParameter) {
  const Deformation d = make(Type::Wave, 0.2, 1.0);
  const std::string key = deformKey({d});
  for (int k = 0; k < 6; ++k) {
    Deformation e = d;
    if (k == 0) e.type = Type::Bend;
    if (k == 1) e.amount = 0.3;
    if (k == 2) e.period = 2.0;
    if (k == 3) e.origin.x += 1.0;
    if (k == 4) e.axis = -e.axis;
    if (k == 5) e.wavelength = 2.0;
    EXPECT_NE(deformKey({e}), key) << k;
  }
  EXPECT_EQ(deformKey({}), "");
}

}  // namespace
}  // namespace translucent::geometry
