// SPDX-License-Identifier: GPL-3.0-or-later
// Next-event estimation through a refractive boundary: every path by which a delta light
// (directional, point, or a beam of radius > 0) reaches an interior point x of a closed triangle
// mesh with one refraction, found exactly. The camera method (camera_paths.h) needs it at η ≠ 1,
// where a straight shadow ray cannot reach a delta light through the smooth dielectric boundary.
//
// The method. The boundary is the mesh's flat facets (as in the light method, mesh_tracer.h:
// refraction and Fresnel use each triangle's geometric normal), so the refractive connection
// through one facet has a closed form: for a directional light (or a beam) the light refracted
// by facet f travels inside along one direction d_f (Snell's law), so x is lit through f exactly
// when the line x - t d_f, t > 0, meets f first; for a point light the refraction point y on f's
// plane solves Fermat's principle in the plane of incidence through the light and x, a monotone
// one-dimensional equation (Snell: sin θi = η sin θt) solved to rounding by safeguarded Newton
// steps. Manifold next-event estimation (Hanika, Droske & Fascione 2015) finds one such solution
// per query by a Newton walk from a seed; on a faceted mesh there are usually several (the
// facets' refracted prisms overlap where the surface is convex: a faceted lens), and a Newton
// walk cannot say how many it missed. Here every solution is found instead: each lit facet's
// refracted volume (its triangle swept along its refracted directions, bounded conservatively:
// refraction into the denser medium contracts angles, so a point light's refracted directions
// through f lie within the angle its vertices subtend) is entered in the cells of a uniform
// grid over the mesh, and a query tests exactly the facets listed in x's cell. The estimate is
// the exact sum over facets: no variance and no bias from the connection, for any mesh the
// grid fits in memory (about facets × cells along a prism entries; the bunny's 70k triangles
// under a sun: a few million).
//
// What one path carries. With θi, θt the angles of incidence and refraction at y (cos θt from
// Snell), Ft(θi) the exact unpolarised Fresnel transmittance (optics/fresnel.h), the irradiance
// at x on a plane perpendicular to the refracted ray (radiance × solid angle is conserved up to
// Ft: η² cos θt dΩt = cos θi dΩi, the étendue of a refracted pencil):
//     directional (irradiance E):  E Ft cos θi / cos θt;
//     beam (power P, radius r):    the same with E = P / (π r²), for y inside its cylinder;
//     point (intensity I):         I Ft / [(a + b/η) (a cos θt / cos θi + b cos θi / (η cos θt))],
//                                  a = |y - light|, b = |x - y|: the sagittal and meridional
//                                  widths of the refracted pencil per unit angle in air (at η = 1
//                                  the inverse square law (a + b)²).
// A path counts when the straight segment from x to y meets no other boundary and the light
// reaches y through air without meeting the body (the segment from y to the light). The
// transmittance of the medium along x-y is the caller's (homogeneous or a field).
//
// Not found here: paths from the light with more than one specular event before their first
// scattering (refracted in, internally reflected, then scattered; or refracted through a thin part
// of the body and into another part). The camera method adds them by its light-traced complement
// (camera_paths.h: 5% of the bunny's exitance at η = 1.3).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "translucent/geometry/mesh.h"
#include "translucent/reference/mesh_tracer.h"
#include "translucent/reference/transport.h"

namespace translucent::reference {

class RefractedLight {
 public:
  struct Path {
    glm::dvec3 w{};           // unit, from x towards the entry point y
    double dist = 0.0;        // |y - x|
    double irradiance = 0.0;  // at x, on a plane perpendicular to w (before the light's colour
                              // and the medium's transmittance along x-y)
  };

  // Per triangle of `mesh`, its unit normal pointing out of the closed body (a ray-parity test
  // just off each triangle's centre: the transport never relies on the file's winding).
  static std::vector<glm::dvec3> outwardNormals(const geometry::TriangleMesh& mesh,
                                                const MeshBody& body);

  // `light`: validated (unit directions), not an environment light nor a pencil beam; `eta` >= 1
  // (n_inside / n_outside); `outward`: outwardNormals(mesh, body).
  RefractedLight(const geometry::TriangleMesh& mesh, std::span<const glm::dvec3> outward,
                 const MeshBody& body, const Light& light, double eta);

  // Calls f(path) for every refracted path from the light to x (x inside the body, or on its
  // surface with `onSurface`: then the segment to y ignores hits closer than the body's epsilon).
  template <class F>
  void forEach(const glm::dvec3& x, bool onSurface, F&& f) const {
    forEachWeighted(
        x, onSurface, [](const Path&) { return 1.0; }, [&](const Path& p, double) { f(p); });
  }
  // As forEach, asking weight(path) before the path's ray queries (the visibility tests): 0
  // skips it unseen (e.g. a caller's Russian roulette on the transmittance it will apply: an
  // unbiased way to spend no rays on paths through many mean free paths), else f(path, weight).
  template <class W, class F>
  void forEachWeighted(const glm::dvec3& x, bool onSurface, W&& weight, F&& f) const {
    const size_t cell = cellOf(x);
    for (uint32_t i = start_[cell]; i < start_[cell + 1]; ++i) {
      Path p;
      if (!candidate(items_[i], x, onSurface, p)) continue;
      const double k = weight(p);
      if (!(k > 0.0) || !visible(x, onSurface, p)) continue;
      f(p, k);
    }
  }

  size_t litFacets() const { return facets_.size(); }
  size_t gridEntries() const { return items_.size(); }
  glm::ivec3 gridCells() const { return dims_; }

  // What a device copy of candidate() and visible() reads (reference/gpu/camera_gpu.cpp).
  enum class Kind { Directional, Point, Beam };
  struct Facet {
    glm::dvec3 v0, e1, e2, n;  // vertex, edges, outward unit normal
    glm::dvec3 a, b;           // barycentric coordinates of y: (y - v0)·a, (y - v0)·b
    glm::dvec3 din;            // directional / beam: the refracted direction of travel
    double irradiance = 0.0;   // directional / beam: E Ft cos θi / cos θt
  };
  Kind kind() const { return kind_; }
  double eta() const { return eta_; }
  const glm::dvec3& toLight() const { return toLight_; }
  const glm::dvec3& origin() const { return origin_; }
  double power() const { return power_; }
  double radius() const { return radius_; }
  std::span<const Facet> facets() const { return facets_; }
  const glm::dvec3& gridLower() const { return lower_; }
  const glm::dvec3& gridCell() const { return cell_; }
  // Per cell (x fastest), the facets listed in it: items()[start()[c] .. start()[c + 1]).
  std::span<const uint32_t> start() const { return start_; }
  std::span<const uint32_t> items() const { return items_; }

 private:
  // The connection through one facet by its closed form (y in the triangle, the beam's cylinder),
  // and whether light takes it (the ray queries).
  bool candidate(uint32_t facet, const glm::dvec3& x, bool onSurface, Path& p) const;
  bool visible(const glm::dvec3& x, bool onSurface, const Path& p) const;
  size_t cellOf(const glm::dvec3& x) const;

  const MeshBody& body_;
  Kind kind_ = Kind::Directional;
  double eta_ = 1.0;
  glm::dvec3 toLight_{};  // directional: unit, towards the light; beam: -direction
  glm::dvec3 origin_{};   // point: position; beam: origin
  double power_ = 0.0;    // point: intensity; directional / beam: irradiance
  double radius_ = 0.0;   // beam
  double eps_ = 0.0;
  std::vector<Facet> facets_;
  glm::dvec3 lower_{}, cell_{};
  glm::ivec3 dims_{1, 1, 1};
  std::vector<uint32_t> start_, items_;  // per cell, the facets whose refracted volume meets it
};

}  // namespace translucent::reference
