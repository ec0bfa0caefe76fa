// SPDX-License-Identifier: GPL-3.0-or-later
// Time-dependent procedural deformations of a mesh (issue #13 §3, seed: "deformable objects, no
// precomputation"): bend, twist and wave, composed in order, each with a magnitude that may
// oscillate in time. The math lives here, pure and without GL, so that the CPU (the references,
// techniques that keep CPU-side geometry, the tests) and the GPU (shaders/common/deform.glsl,
// which mirrors these formulas line by line in float) deform the same way.
//
// Every deformation acts on scene coordinates (after the mesh's placement) in an orthonormal
// frame (a, d, e = a × d) about an origin o; u = (p - o)·a, v = (p - o)·d:
//
//   twist: rotation about the line (o, a) by θ = m u  (m in degrees per unit length).
//   bend:  the line (o, a) bends into a circular arc of curvature κ = m (degrees per unit length,
//          i.e. radians κ = m π/180 per unit length) towards +d; a point keeps its distance to the
//          neutral line: u' = sin(κu)/κ - v sin(κu), v' = (1 - cos(κu))/κ + v cos(κu) (Barr 1984's
//          bend without the bounded region). The arc turns by κ u: past |κ u| = π it wraps.
//   wave:  p' = p + m sin(2π (p - o)·d / λ) a: a displacement along a that varies along d (a
//          standing wave of wavelength λ; a shear, so volume preserving and exactly invertible).
//
// The magnitude at time T is m(T) = amount · sin(2π T / period) when period > 0, amount when
// period = 0; m = 0 is the identity, bit for bit (the displacement is 0 exactly).
//
// Normals transform with the inverse transpose of the deformation's Jacobian J (a covector), so a
// vertex normal of the rest pose becomes the deformed surface's normal to first order; the GPU
// does the same with the same J.
#pragma once

#include <string>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "translucent/geometry/mesh.h"

namespace translucent::geometry {

// The longest chain a scene may give (the GPU takes it as uniform arrays of this size).
inline constexpr size_t kMaxDeformations = 8;

struct Deformation {
  enum class Type { Bend, Twist, Wave };
  Type type = Type::Twist;
  double amount = 0.0;  // degrees per unit length (bend, twist) or scene units (wave)
  double period = 0.0;  // of the oscillation [time units]; 0: constant, m = amount
  glm::dvec3 origin{0.0};
  // Unit. Twist: the axis of rotation; bend: the neutral line's direction at the origin; wave:
  // the displacement's direction.
  glm::dvec3 axis{0.0, 1.0, 0.0};
  // Unit, perpendicular to axis (bend, wave; a twist ignores it). Bend: towards the centre of
  // curvature; wave: the direction along which the displacement varies.
  glm::dvec3 direction{1.0, 0.0, 0.0};
  double wavelength = 1.0;  // wave [scene units], > 0

  // m(T) (see above).
  double magnitude(double time) const;
  bool operator==(const Deformation&) const = default;
};

const char* toString(Deformation::Type type);

// The deformation with magnitude m (m(T) of its own description) of point p, and its Jacobian.
glm::dvec3 deformPoint(const Deformation& d, double m, const glm::dvec3& p);
glm::dmat3 deformJacobian(const Deformation& d, double m, const glm::dvec3& p);

// The chain applied in order at time T.
glm::dvec3 deformPoint(const std::vector<Deformation>& chain, double time, const glm::dvec3& p);
// The rest-pose point p and its unit normal n, deformed: n by J^{-T} of each step, normalised.
void deformPointNormal(const std::vector<Deformation>& chain, double time, glm::dvec3& p,
                       glm::dvec3& n);
// The rest-pose point whose deformation at time T is x (the inverse, step by step in reverse
// order: twist and wave exactly, bend by Newton's method from x, converged to 1e-12 of the
// displacement). For points the deformation reaches (a bend wrapped past half a turn has several).
glm::dvec3 undeformPoint(const std::vector<Deformation>& chain, double time, const glm::dvec3& x);

// The rest-pose normal of a deformed surface's normal n at the rest point p: the deformation
// maps rest normals by J^{-T} (the chain's J at p), so this is J^T n, normalised.
glm::dvec3 undeformNormal(const std::vector<Deformation>& chain, double time, const glm::dvec3& p,
                          const glm::dvec3& n);

// The chain at time T in the GPU's form (shaders/common/deform.glsl): three vec4 per deformation,
// a = (origin, type), b = (axis, magnitude at T), c = (direction, wavelength), type as the enum.
struct DeformUniforms {
  std::vector<glm::vec4> a, b, c;
};
DeformUniforms deformUniforms(const std::vector<Deformation>& chain, double time);

// True when the chain is the identity at time T (empty, or every magnitude 0).
bool isIdentity(const std::vector<Deformation>& chain, double time);

// Area-weighted smooth vertex normals (the face normals, weighted by area, summed at each vertex
// and normalised); the mesh's own normals when it has one per vertex. What the GPU mesh draws
// with (techniques::vertexNormals) and so what the deformation transforms.
std::vector<glm::dvec3> smoothVertexNormals(const TriangleMesh& mesh);

// Deforms the mesh in place at time T: positions, and the normals (smoothVertexNormals of the
// rest pose when the mesh had none, so that a deformed mesh always carries the normals the GPU
// computes). Nothing changes when the chain is the identity at T.
void deformMesh(const std::vector<Deformation>& chain, double time, TriangleMesh& mesh);

// A text that changes exactly when the chain does (for cache keys; with the time when `time`).
std::string deformKey(const std::vector<Deformation>& chain);
// The chain at time T as a key: "" when it is the identity there (the rest pose), else deformKey
// and T. What a deformed vertex buffer or anything derived from the deformed mesh is keyed by.
std::string deformStateKey(const std::vector<Deformation>& chain, double time);

}  // namespace translucent::geometry
