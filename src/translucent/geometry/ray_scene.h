// SPDX-License-Identifier: GPL-3.0-or-later
// Ray queries against a triangle mesh through Embree 3: one robust BVH over the mesh, closest-hit
// and any-hit (occlusion) queries in single precision. Shared by the ambient occlusion of the
// empirical shader (ambient_occlusion.h) and the reference path tracer's mesh body
// (reference/mesh_tracer.h); Embree's headers stay in ray_scene.cpp.
//
// Rays are o + t d for t in [t_min, t_max] (t_max = infinity allowed); d need not be unit length
// (t is then in units of |d|). Thread-safe for queries once built.
#pragma once

#include <cstddef>
#include <memory>
#include <string>

#include <glm/vec3.hpp>

#include "translucent/geometry/mesh.h"

namespace translucent::geometry {

struct RayHit {
  double t = 0.0;
  glm::dvec3 normal{0.0};  // unit geometric normal of the hit triangle (its winding's side)
  size_t triangle = 0;
};

class RayScene {
 public:
  // Build quality: High spends longer on the BVH for faster queries (many rays per triangle,
  // the path tracer); Medium is Embree's default (ambient occlusion times its build).
  enum class Quality { Medium, High };

  // Builds the BVH (the mesh must pass validate()). Embree failures throw std::runtime_error
  // naming `what` and the step that failed.
  RayScene(const TriangleMesh& mesh, const std::string& what, Quality quality = Quality::Medium);
  ~RayScene();
  RayScene(const RayScene&) = delete;
  RayScene& operator=(const RayScene&) = delete;

  // Closest hit in [t_min, t_max]; false when the ray misses. `incoherent`: a hint for rays
  // that do not travel in bundles (random directions).
  bool intersect(const glm::dvec3& o, const glm::dvec3& d, double t_min, double t_max,
                 RayHit& hit, bool incoherent = false) const;
  // True when anything lies on the ray within [t_min, t_max].
  bool occluded(const glm::dvec3& o, const glm::dvec3& d, double t_min, double t_max,
                bool incoherent = false) const;

  double deviceSeconds() const { return device_seconds_; }  // creating the Embree device
  double buildSeconds() const { return build_seconds_; }    // copying the mesh, building the BVH

 private:
  struct Embree;
  std::unique_ptr<Embree> embree_;
  double device_seconds_ = 0.0, build_seconds_ = 0.0;
};

// Whether p lies inside the closed mesh of `rays`: the parity of the surface crossings along
// three fixed, mutually skew directions, by majority (a ray that grazes an edge or a vertex can
// count one crossing too many or too few; three independent rays rarely all do). Only meaningful
// for a closed (watertight) mesh.
bool insideClosedMesh(const RayScene& rays, const glm::dvec3& p);

}  // namespace translucent::geometry
