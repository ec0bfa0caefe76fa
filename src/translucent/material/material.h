// SPDX-License-Identifier: GPL-3.0-or-later
// Spatially varying (heterogeneous) translucent materials: the layer between optics/geometry/
// bssrdf and the renderers (design.md, layer 3). A material is either homogeneous (today's
// `material` of the scene format, the default), a 3D field inside the object (layers, marble
// veins, a 3D checker, a gradient, a voxel grid), or a 2D map over the surface atlas (images of
// σa and σs' or of Rd and ℓd, a procedural checker). Every form names the radial model from which
// local profiles are derived (material/point_profiles.h, SubEdit Eqs. 8-9).
//
// Frames and units. A field is defined in *material space*: the mesh's rest-pose frame (after the
// scene's `normalize`, before its rotate and translate) measured in medium units (the units of the
// coefficients, mm for the presets). A scene point x of the placed, undeformed mesh maps to
//     q = material.scale · Rᵀ (x − translate)
// (x = s R p + translate for the normalised point p, and q = s · material.scale · p), so a pattern
// turns and moves with the object, keeps its physical size (mm) when the mesh is scaled, and a
// later deformation evaluates the field at the rest position of a point. Coefficients are per
// medium unit, as in Medium; Medium::scale converts them to per scene unit.
//
// η is one value per object: the surface is the only refracting interface, and the media of a
// field are index-matched to each other (as in a layered MCML slab with equal η). σa, σs and g
// vary per point.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "translucent/geometry/deform.h"
#include "translucent/optics/medium.h"

namespace translucent::material {

// The medium at one point: per-channel coefficients per medium unit, and the phase function's g.
struct LocalMedium {
  Rgb sigma_a{0.0, 0.0, 0.0};
  Rgb sigma_s{0.0, 0.0, 0.0};
  double g = 0.0;

  Rgb sigmaT() const {
    return {sigma_a[0] + sigma_s[0], sigma_a[1] + sigma_s[1], sigma_a[2] + sigma_s[2]};
  }
  // The point's medium as a full Medium with the object's η and scale.
  Medium medium(double eta, double scale) const { return {sigma_a, sigma_s, g, eta, scale}; }
  static LocalMedium of(const Medium& m) { return {m.sigma_a, m.sigma_s, m.g}; }
  // (1 − t) a + t b for σa, σs and g alike (t in [0, 1]): the blend of two media that the
  // two-media fields (veins, gradient, voxel density) use. Every coefficient stays between the
  // two media's, so their larger σt bounds the blend.
  static LocalMedium mix(const LocalMedium& a, const LocalMedium& b, double t) {
    LocalMedium m;
    for (size_t c = 0; c < 3; ++c) {
      m.sigma_a[c] = a.sigma_a[c] + t * (b.sigma_a[c] - a.sigma_a[c]);
      m.sigma_s[c] = a.sigma_s[c] + t * (b.sigma_s[c] - a.sigma_s[c]);
    }
    m.g = a.g + t * (b.g - a.g);
    return m;
  }
  bool operator==(const LocalMedium&) const = default;
};

// A 3D field over material space. Implementations are immutable once built and safe to query
// from several threads at once.
class VolumeField {
 public:
  virtual ~VolumeField() = default;
  // The medium at material-space point q.
  virtual LocalMedium at(const glm::dvec3& q) const = 0;
  // Per channel, an upper bound of σt = σa + σs [1/medium unit] over every point of the
  // material-space box [lo, hi]. Need not be tight, must never be below the field anywhere in
  // the box: delta tracking with a majorant below σt is biased. The tighter it is, the fewer
  // null collisions the tracer pays for (reference: the majorant grid).
  virtual Rgb majorant(const glm::dvec3& lo, const glm::dvec3& hi) const = 0;
};

// A 2D map over the surface atlas (geometry/atlas.h): the medium at atlas UV in [0, 1]².
class SurfaceMap {
 public:
  virtual ~SurfaceMap() = default;
  virtual LocalMedium at(const glm::dvec2& uv) const = 0;
};

// Scene → material space: q = scale · Rᵀ (x − translate), from the scene's placement (the mesh's
// rotation R, its translation, and material.scale).
//
// A deformed mesh (mesh.deform, geometry/deform.h) carries its material with it: materials are
// defined in the rest pose (the placed, undeformed mesh), so toMaterial first maps a point of the
// deformed object back to its rest position (geometry::undeformPoint at `time`), and toScene
// deforms a rest-pose point. Without a deformation both are the rigid maps above.
struct MaterialFrame {
  glm::dmat3 rotation{1.0};      // R: the mesh's rotation
  glm::dvec3 translate{0.0};     // the mesh's translation [scene units]
  double scale = 1.0;            // material.scale: medium units per scene unit
  std::vector<geometry::Deformation> deform;  // the scene's mesh.deform (applied after placement)
  double time = 0.0;                          // the scene's time

  bool deformed() const { return !geometry::isIdentity(deform, time); }
  glm::dvec3 toMaterial(const glm::dvec3& x) const {
    const glm::dvec3 rest = deform.empty() ? x : geometry::undeformPoint(deform, time, x);
    return scale * (glm::transpose(rotation) * (rest - translate));
  }
  // A unit direction at scene point x (a surface normal, a covector) in material space: through
  // the rest pose's normal when deformed.
  glm::dvec3 toMaterialNormal(const glm::dvec3& x, const glm::dvec3& n) const {
    if (!deformed()) return glm::transpose(rotation) * n;
    return glm::transpose(rotation) *
           geometry::undeformNormal(deform, time, geometry::undeformPoint(deform, time, x), n);
  }
  glm::dvec3 toScene(const glm::dvec3& q) const {
    const glm::dvec3 rest = rotation * (q / scale) + translate;
    return deform.empty() ? rest : geometry::deformPoint(deform, time, rest);
  }
};

// The built material that renderers and tracers read (made from the scene's material
// description and placed mesh, see material/material_desc.h).
struct Material {
  enum class Kind { Homogeneous, Volume, Surface };
  Kind kind = Kind::Homogeneous;
  // The homogeneous medium; for a heterogeneous material η, scale and a representative medium
  // (the one a technique without heterogeneous support renders; the description says which).
  Medium medium;
  std::string model = "dipole";  // registered model name or a .bssrdf file (resolved)
  MaterialFrame frame;
  std::shared_ptr<const VolumeField> volume;   // Kind::Volume
  std::shared_ptr<const SurfaceMap> surface;   // Kind::Surface
  // Kind::Volume: how deep below the surface surfaceMedium averages [medium units] (the local
  // medium of a surface point is the one the light diffusing out there has travelled through).
  double surface_depth = 0.0;

  bool heterogeneous() const { return kind != Kind::Homogeneous; }
  // The medium at scene point x (Volume: the field at frame.toMaterial(x); otherwise `medium`).
  LocalMedium atScenePoint(const glm::dvec3& x) const;
  // The local medium of a surface point: scene position x, outward unit normal n, atlas UV (used
  // by Kind::Surface only; ignored otherwise). Volume: the field averaged along −n over
  // [0, surface_depth], weighted by e^(−z / surface_depth) (material.cpp says why); Surface: the
  // map at uv; Homogeneous: `medium`.
  LocalMedium surfaceMedium(const glm::dvec3& x, const glm::dvec3& n, const glm::dvec2& uv) const;
};

}  // namespace translucent::material
