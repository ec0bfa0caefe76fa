// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/geometry/deform.h"

#include <fmt/format.h>

#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

namespace translucent::geometry {
namespace {

constexpr double kDegree = std::numbers::pi / 180.0;

// sin(x)/x, 1 at 0; the series below 1e-4, where the quotient loses digits and its error
// (x⁴/120) is below 1e-18.
double sinc(double x) { return std::abs(x) < 1e-4 ? 1.0 - x * x / 6.0 : std::sin(x) / x; }

// The frame of a deformation: e = a × d completes it (bend; a twist needs a only).
struct Local {
  glm::dvec3 q;  // p - o
  double u, v;   // q·a, q·d
};
Local local(const Deformation& d, const glm::dvec3& p) {
  const glm::dvec3 q = p - d.origin;
  return {q, glm::dot(q, d.axis), glm::dot(q, d.direction)};
}

// Bend in the (a, d) plane: the displacement (u' - u, v' - v), written so that κ = 0 gives 0
// exactly and small κ loses no digits (sin(κu)/κ = u sinc(κu), (1 - cos κu)/κ = u sin(κu/2)
// sinc(κu/2), cos κu - 1 = -2 sin²(κu/2)).
glm::dvec3 bendDisplacement(const Deformation& d, double m, const glm::dvec3& p) {
  const double k = m * kDegree;
  const Local l = local(d, p);
  const double s = std::sin(k * l.u), h = std::sin(0.5 * k * l.u);
  const double du = l.u * sinc(k * l.u) - l.u - l.v * s;
  const double dv = l.u * h * sinc(0.5 * k * l.u) - 2.0 * l.v * h * h;
  return du * d.axis + dv * d.direction;
}

// Rotation of q about the unit axis a by θ, as the displacement q' - q (0 exactly at θ = 0).
glm::dvec3 rotationDisplacement(const glm::dvec3& a, double theta, const glm::dvec3& q) {
  const double c1 = 1.0 - std::cos(theta);
  return std::sin(theta) * glm::cross(a, q) + c1 * (glm::dot(a, q) * a - q);
}

glm::dmat3 rotationMatrix(const glm::dvec3& a, double theta) {
  // [a]×, the matrix of q -> a × q (columns: a × x̂, a × ŷ, a × ẑ).
  const glm::dmat3 cross(0.0, a.z, -a.y, -a.z, 0.0, a.x, a.y, -a.x, 0.0);
  return std::cos(theta) * glm::dmat3(1.0) + std::sin(theta) * cross +
         (1.0 - std::cos(theta)) * glm::outerProduct(a, a);
}

}  // namespace

double Deformation::magnitude(double time) const {
  return period > 0.0 ? amount * std::sin(2.0 * std::numbers::pi * time / period) : amount;
}

const char* toString(Deformation::Type type) {
  switch (type) {
    case Deformation::Type::Bend: return "bend";
    case Deformation::Type::Twist: return "twist";
    case Deformation::Type::Wave: return "wave";
  }
  return "?";
}

glm::dvec3 deformPoint(const Deformation& d, double m, const glm::dvec3& p) {
  switch (d.type) {
    case Deformation::Type::Twist: {
      const Local l = local(d, p);
      return p + rotationDisplacement(d.axis, m * kDegree * l.u, l.q);
    }
    case Deformation::Type::Bend: return p + bendDisplacement(d, m, p);
    case Deformation::Type::Wave: {
      const double w = glm::dot(p - d.origin, d.direction);
      return p + (m * std::sin(2.0 * std::numbers::pi * w / d.wavelength)) * d.axis;
    }
  }
  return p;
}

glm::dmat3 deformJacobian(const Deformation& d, double m, const glm::dvec3& p) {
  using glm::outerProduct;
  switch (d.type) {
    case Deformation::Type::Twist: {
      // p' = o + R(κu) q: J = R + κ (a × R q) aᵀ (dR/dθ q = a × R q).
      const double k = m * kDegree;
      const Local l = local(d, p);
      const glm::dmat3 r = rotationMatrix(d.axis, k * l.u);
      return r + k * outerProduct(glm::cross(d.axis, r * l.q), d.axis);
    }
    case Deformation::Type::Bend: {
      // ∂(u', v')/∂(u, v) = [[(1 - κv) c, -s], [(1 - κv) s, c]]; e is unchanged.
      const double k = m * kDegree;
      const Local l = local(d, p);
      const double s = std::sin(k * l.u), c = std::cos(k * l.u), f = 1.0 - k * l.v;
      const glm::dvec3 &a = d.axis, &n = d.direction;
      return glm::dmat3(1.0) + (f * c - 1.0) * outerProduct(a, a) - s * outerProduct(a, n) +
             f * s * outerProduct(n, a) + (c - 1.0) * outerProduct(n, n);
    }
    case Deformation::Type::Wave: {
      const double k = 2.0 * std::numbers::pi / d.wavelength;
      const double w = glm::dot(p - d.origin, d.direction);
      return glm::dmat3(1.0) + (m * k * std::cos(k * w)) * outerProduct(d.axis, d.direction);
    }
  }
  return glm::dmat3(1.0);
}

glm::dvec3 deformPoint(const std::vector<Deformation>& chain, double time, const glm::dvec3& p) {
  glm::dvec3 x = p;
  for (const Deformation& d : chain) x = deformPoint(d, d.magnitude(time), x);
  return x;
}

void deformPointNormal(const std::vector<Deformation>& chain, double time, glm::dvec3& p,
                       glm::dvec3& n) {
  for (const Deformation& d : chain) {
    const double m = d.magnitude(time);
    if (m == 0.0) continue;  // the identity: p and n exactly as they are
    const glm::dmat3 j = deformJacobian(d, m, p);
    n = glm::normalize(glm::transpose(glm::inverse(j)) * n);
    p = deformPoint(d, m, p);
  }
}

DeformUniforms deformUniforms(const std::vector<Deformation>& chain, double time) {
  DeformUniforms u;
  for (const Deformation& d : chain) {
    u.a.emplace_back(glm::vec3(d.origin), static_cast<float>(static_cast<int>(d.type)));
    u.b.emplace_back(glm::vec3(d.axis), static_cast<float>(d.magnitude(time)));
    u.c.emplace_back(glm::vec3(d.direction), static_cast<float>(d.wavelength));
  }
  return u;
}

glm::dvec3 undeformPoint(const std::vector<Deformation>& chain, double time, const glm::dvec3& x) {
  glm::dvec3 p = x;
  for (auto it = chain.rbegin(); it != chain.rend(); ++it) {
    const Deformation& d = *it;
    const double m = d.magnitude(time);
    if (m == 0.0) continue;
    switch (d.type) {
      case Deformation::Type::Twist: {
        // A twist keeps u: rotate back by -κu.
        const Local l = local(d, p);
        p += rotationDisplacement(d.axis, -m * kDegree * l.u, l.q);
        break;
      }
      case Deformation::Type::Wave: {
        // The displacement is along a, perpendicular to d: w is unchanged.
        const double w = glm::dot(p - d.origin, d.direction);
        p -= (m * std::sin(2.0 * std::numbers::pi * w / d.wavelength)) * d.axis;
        break;
      }
      case Deformation::Type::Bend: {
        // Newton from the deformed point (the bend's displacement is smooth and J invertible
        // where 1 - κv ≠ 0, i.e. away from the centre of curvature).
        const glm::dvec3 target = p;
        const double tol = 1e-12 * (1.0 + glm::length(target - d.origin));
        glm::dvec3 r = p;
        for (int i = 0; i < 50; ++i) {
          const glm::dvec3 err = deformPoint(d, m, r) - target;
          if (glm::length(err) <= tol) break;
          r -= glm::inverse(deformJacobian(d, m, r)) * err;
        }
        p = r;
        break;
      }
    }
  }
  return p;
}

glm::dvec3 undeformNormal(const std::vector<Deformation>& chain, double time, const glm::dvec3& p,
                          const glm::dvec3& n) {
  glm::dmat3 j(1.0);
  glm::dvec3 x = p;
  for (const Deformation& d : chain) {
    const double m = d.magnitude(time);
    if (m == 0.0) continue;
    j = deformJacobian(d, m, x) * j;
    x = deformPoint(d, m, x);
  }
  const glm::dvec3 r = glm::transpose(j) * n;
  const double len = glm::length(r);
  return len > 0.0 ? r / len : n;
}

bool isIdentity(const std::vector<Deformation>& chain, double time) {
  for (const Deformation& d : chain)
    if (d.magnitude(time) != 0.0) return false;
  return true;
}

std::vector<glm::dvec3> smoothVertexNormals(const TriangleMesh& mesh) {
  if (mesh.normals.size() == mesh.positions.size()) return mesh.normals;
  std::vector<glm::dvec3> n(mesh.positions.size(), glm::dvec3(0.0));
  for (const glm::uvec3& t : mesh.triangles) {
    // The cross product's length is twice the area: area-weighted sum.
    const glm::dvec3 f = glm::cross(mesh.positions[t.y] - mesh.positions[t.x],
                                    mesh.positions[t.z] - mesh.positions[t.x]);
    n[t.x] += f;
    n[t.y] += f;
    n[t.z] += f;
  }
  for (glm::dvec3& v : n) {
    const double len = glm::length(v);
    v = len > 0.0 ? v / len : glm::dvec3(0.0, 0.0, 1.0);
  }
  return n;
}

void deformMesh(const std::vector<Deformation>& chain, double time, TriangleMesh& mesh) {
  if (isIdentity(chain, time)) return;
  mesh.normals = smoothVertexNormals(mesh);
  for (size_t i = 0; i < mesh.positions.size(); ++i)
    deformPointNormal(chain, time, mesh.positions[i], mesh.normals[i]);
}

std::string deformKey(const std::vector<Deformation>& chain) {
  std::string key;
  for (const Deformation& d : chain)
    key += fmt::format("{}:{},{}|{},{},{}|{},{},{}|{},{},{}|{};", toString(d.type), d.amount,
                       d.period, d.origin.x, d.origin.y, d.origin.z, d.axis.x, d.axis.y, d.axis.z,
                       d.direction.x, d.direction.y, d.direction.z, d.wavelength);
  return key;
}

std::string deformStateKey(const std::vector<Deformation>& chain, double time) {
  return isIdentity(chain, time) ? "" : fmt::format("{}|t{}", deformKey(chain), time);
}

}  // namespace translucent::geometry
