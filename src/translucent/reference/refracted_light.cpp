// SPDX-License-Identifier: GPL-3.0-or-later
// Exact next-event estimation through one refractive facet (refracted_light.h).
#include "translucent/reference/refracted_light.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <variant>

#include <glm/geometric.hpp>

#include "translucent/optics/fresnel.h"
#include "translucent/reference/transport_impl.h"

namespace translucent::reference {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// The grid holds at most about this many (cell, facet) entries: the cells grow for large meshes.
constexpr double kEntryBudget = 2.5e7;

// Snell refraction of the unit direction d into the body through a facet of outward unit normal
// n (d·n < 0), η = n_inside / n_outside >= 1 (the walks' detail::refract); cos θi and cos θt on
// the way.
glm::dvec3 refractIn(const glm::dvec3& d, const glm::dvec3& n, double eta, double& cosI,
                     double& cosT) {
  cosI = -glm::dot(d, n);
  cosT = refractedCosine(cosI, eta);
  return detail::refract(d, -n, 1.0 / eta, cosT);
}

// The refraction point of a point light through a plane, in its plane of incidence: the distance
// u from the light's foot towards x's foot (D apart; heights hp above, hx below) where
// sin θi = η sin θt, i.e. g(u) = u / sqrt(u² + hp²) - η (D - u) / sqrt((D - u)² + hx²) = 0. g
// increases from g(0) < 0 to g(D) > 0: Newton steps kept inside the bracket, bisection where a
// step would leave it.
double refractionPoint(double D, double hp, double hx, double eta) {
  double lo = 0.0, hi = D;
  double u = D * hp / (hp + hx);  // the straight line's crossing: the root lies beyond it for η > 1
  for (int i = 0; i < 100; ++i) {
    const double a2 = u * u + hp * hp, b2 = (D - u) * (D - u) + hx * hx;
    const double a = std::sqrt(a2), b = std::sqrt(b2);
    const double g = u / a - eta * (D - u) / b;
    if (g == 0.0) return u;
    if (g > 0.0)
      hi = u;
    else
      lo = u;
    const double dg = hp * hp / (a2 * a) + eta * hx * hx / (b2 * b);
    double next = u - g / dg;
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (std::abs(next - u) <= 1e-15 * D) return next;
    u = next;
  }
  return u;
}

}  // namespace

std::vector<glm::dvec3> RefractedLight::outwardNormals(const geometry::TriangleMesh& mesh,
                                                       const MeshBody& body) {
  const BoundingSphere b = body.bounds();
  const double floor = 4e-7 * (glm::length(b.center) + b.radius);
  std::vector<glm::dvec3> out(mesh.triangleCount());
  for (size_t i = 0; i < out.size(); ++i) {
    const glm::uvec3 t = mesh.triangles[i];
    const glm::dvec3 a = mesh.positions[t.x], e1 = mesh.positions[t.y] - a,
                     e2 = mesh.positions[t.z] - a;
    const glm::dvec3 c = glm::cross(e1, e2);
    const double len = glm::length(c);
    const glm::dvec3 n = c / len;
    // A point just off the triangle's centre on the winding's side (1% of its size: far from the
    // body's other sheets, well above the ray queries' single precision) is outside, or not.
    const double off = std::max(0.01 * std::sqrt(0.5 * len), floor);
    const glm::dvec3 probe = a + (e1 + e2) / 3.0 + off * n;
    out[i] = body.inside(probe) ? -n : n;
  }
  return out;
}

RefractedLight::RefractedLight(const geometry::TriangleMesh& mesh,
                               std::span<const glm::dvec3> outward, const MeshBody& body,
                               const Light& light, double eta)
    : body_(body), eta_(eta), eps_(body.epsilon()) {
  if (!(eta >= 1.0)) throw std::invalid_argument("refracted light: eta must be >= 1");
  if (outward.size() != mesh.triangleCount())
    throw std::invalid_argument("refracted light: one outward normal per triangle expected");
  if (const auto* dl = std::get_if<DirectionalLight>(&light.emitter)) {
    kind_ = Kind::Directional;
    toLight_ = dl->direction;
    power_ = dl->irradiance;
  } else if (const auto* pl = std::get_if<PointLight>(&light.emitter)) {
    kind_ = Kind::Point;
    origin_ = pl->position;
    power_ = pl->intensity;
  } else if (const auto* bl = std::get_if<BeamLight>(&light.emitter); bl && bl->radius > 0.0) {
    kind_ = Kind::Beam;
    toLight_ = -bl->direction;
    origin_ = bl->origin;
    radius_ = bl->radius;
    power_ = bl->power / (std::numbers::pi * bl->radius * bl->radius);
  } else {
    throw std::invalid_argument("refracted light: a directional, point or beam (radius > 0) light expected");
  }

  // The lit facets and, per facet, a box holding its refracted directions (refracted_light.h).
  struct Sweep {
    glm::dvec3 lo, hi, dlo, dhi;
  };
  std::vector<Sweep> sweeps;
  double edgeSum = 0.0;
  for (size_t i = 0; i < mesh.triangleCount(); ++i) {
    const glm::uvec3 t = mesh.triangles[i];
    const glm::dvec3 v[3] = {mesh.positions[t.x], mesh.positions[t.y], mesh.positions[t.z]};
    edgeSum += glm::length(v[1] - v[0]) + glm::length(v[2] - v[1]) + glm::length(v[0] - v[2]);
    Facet f;
    f.v0 = v[0];
    f.e1 = v[1] - v[0];
    f.e2 = v[2] - v[0];
    f.n = outward[i];
    {
      // Dual vectors of the edges in the triangle's plane: y - v0 = s e1 + t e2 gives
      // s = (y - v0)·a, t = (y - v0)·b.
      const double d00 = glm::dot(f.e1, f.e1), d01 = glm::dot(f.e1, f.e2), d11 = glm::dot(f.e2, f.e2);
      const double den = d00 * d11 - d01 * d01;
      f.a = (d11 * f.e1 - d01 * f.e2) / den;
      f.b = (d00 * f.e2 - d01 * f.e1) / den;
    }
    Sweep s{glm::min(v[0], glm::min(v[1], v[2])), glm::max(v[0], glm::max(v[1], v[2])), {}, {}};
    if (kind_ != Kind::Point) {
      double cosI = 0.0, cosT = 0.0;
      if (!(glm::dot(toLight_, f.n) > 0.0)) continue;
      if (kind_ == Kind::Beam) {
        // Facets the cylinder cannot touch: their bounding sphere misses it or lies upstream.
        const glm::dvec3 c = (v[0] + v[1] + v[2]) / 3.0;
        const double rb = std::max({glm::length(v[0] - c), glm::length(v[1] - c), glm::length(v[2] - c)});
        const glm::dvec3 r = c - origin_;
        const double along = -glm::dot(r, toLight_);
        if (along + rb < 0.0 || glm::length(r + along * toLight_) > radius_ + rb) continue;
      }
      f.din = refractIn(-toLight_, f.n, eta, cosI, cosT);
      f.irradiance = power_ * fresnelTransmittance(cosI, eta) * cosI / cosT;
      s.dlo = s.dhi = f.din;
    } else {
      if (!(glm::dot(origin_ - f.v0, f.n) > 0.0)) continue;
      glm::dvec3 inc[3], ref[3];
      for (int k = 0; k < 3; ++k) {
        double cosI = 0.0, cosT = 0.0;
        inc[k] = glm::normalize(v[k] - origin_);
        ref[k] = refractIn(inc[k], f.n, eta, cosI, cosT);
      }
      // Refraction into the denser medium contracts angles (dθt/dθi = cos θi / (η cos θt) <= 1,
      // sin θt / sin θi = 1/η), and the farthest direction of the cone over a triangle from
      // one of its vertices' is another vertex's: every refracted direction through the facet
      // lies within the angle α of ref[0], so within the chord 2 sin(α/2) of it.
      const double alpha = std::max(std::acos(std::clamp(glm::dot(inc[0], inc[1]), -1.0, 1.0)),
                                    std::acos(std::clamp(glm::dot(inc[0], inc[2]), -1.0, 1.0)));
      const double chord = 2.0 * std::sin(0.5 * alpha) + 1e-9;
      s.dlo = ref[0] - glm::dvec3(chord);
      s.dhi = ref[0] + glm::dvec3(chord);
    }
    facets_.push_back(f);
    sweeps.push_back(s);
  }

  // The grid: cells of about a mean edge, fewer where the entries would exceed the budget.
  const geometry::Bounds b = mesh.bounds();
  const double pad = 1e-6 * (glm::length(b.center()) + b.radius()) + 1e-300;
  lower_ = b.lower - glm::dvec3(pad);
  const glm::dvec3 extent = b.upper - b.lower + glm::dvec3(2.0 * pad);
  const double longest = std::max({extent.x, extent.y, extent.z});
  const double meanEdge = edgeSum / (3.0 * static_cast<double>(std::max<size_t>(1, mesh.triangleCount())));
  int n = std::clamp(static_cast<int>(longest / meanEdge), 4, 256);
  // Measured on the bunny (70k triangles, cells of two mean edges): 2.2 N entries per lit facet
  // (its prism crosses the grid in about N cells, two or three wide); the budget assumes 4 N.
  while (n > 4 && static_cast<double>(facets_.size()) * 4.0 * n > kEntryBudget) n = n * 3 / 4;
  const double h = longest / n;
  for (int a = 0; a < 3; ++a) {
    dims_[a] = std::max(1, static_cast<int>(std::ceil(extent[a] / h)));
    cell_[a] = extent[a] / dims_[a];
  }
  const glm::dvec3 upper = lower_ + extent;
  const double step = std::min({cell_.x, cell_.y, cell_.z});
  const double reach = glm::length(extent) + step;
  const size_t cells = static_cast<size_t>(dims_.x) * static_cast<size_t>(dims_.y) * static_cast<size_t>(dims_.z);

  // Each facet's refracted volume, in steps of one cell along its directions: the box of the
  // triangle moved by t·d for t in [t0, t1] and d in the direction box. The steps that meet the
  // grid form one interval of t (the box's faces move linearly in t), so the sweep ends when it
  // leaves the grid.
  // A cell is listed once per facet: stamped with the facet's index (+1) when first met.
  std::vector<uint32_t> perFacet, facetStart{0}, stamp(cells, 0);
  for (size_t fi = 0; fi < sweeps.size(); ++fi) {
    const Sweep& s = sweeps[fi];
    const uint32_t mark = static_cast<uint32_t>(fi + 1);
    for (double t0 = 0.0; t0 < reach; t0 += step) {
      const double t1 = t0 + step;
      const glm::dvec3 lo = s.lo + glm::min(t0 * s.dlo, t1 * s.dlo);
      const glm::dvec3 hi = s.hi + glm::max(t0 * s.dhi, t1 * s.dhi);
      if (lo.x > upper.x || lo.y > upper.y || lo.z > upper.z || hi.x < lower_.x ||
          hi.y < lower_.y || hi.z < lower_.z) {
        if (t0 > 0.0) break;
        continue;
      }
      glm::ivec3 i0, i1;
      for (int a = 0; a < 3; ++a) {
        i0[a] = std::clamp(static_cast<int>(std::floor((lo[a] - lower_[a]) / cell_[a])), 0, dims_[a] - 1);
        i1[a] = std::clamp(static_cast<int>(std::floor((hi[a] - lower_[a]) / cell_[a])), 0, dims_[a] - 1);
      }
      for (int z = i0.z; z <= i1.z; ++z)
        for (int y = i0.y; y <= i1.y; ++y)
          for (int x = i0.x; x <= i1.x; ++x) {
            const size_t c = (static_cast<size_t>(z) * static_cast<size_t>(dims_.y) +
                              static_cast<size_t>(y)) * static_cast<size_t>(dims_.x) +
                             static_cast<size_t>(x);
            if (stamp[c] == mark) continue;
            stamp[c] = mark;
            perFacet.push_back(static_cast<uint32_t>(c));
          }
    }
    facetStart.push_back(static_cast<uint32_t>(perFacet.size()));
  }
  start_.assign(cells + 1, 0);
  for (const uint32_t c : perFacet) ++start_[c + 1];
  for (size_t c = 0; c < cells; ++c) start_[c + 1] += start_[c];
  items_.resize(perFacet.size());
  std::vector<uint32_t> fill(start_.begin(), start_.end() - 1);
  for (size_t f = 0; f + 1 < facetStart.size(); ++f)
    for (uint32_t k = facetStart[f]; k < facetStart[f + 1]; ++k)
      items_[fill[perFacet[k]]++] = static_cast<uint32_t>(f);
}

size_t RefractedLight::cellOf(const glm::dvec3& x) const {
  glm::ivec3 i;
  for (int a = 0; a < 3; ++a)
    i[a] = std::clamp(static_cast<int>(std::floor((x[a] - lower_[a]) / cell_[a])), 0, dims_[a] - 1);
  return (static_cast<size_t>(i.z) * static_cast<size_t>(dims_.y) + static_cast<size_t>(i.y)) *
             static_cast<size_t>(dims_.x) + static_cast<size_t>(i.x);
}

bool RefractedLight::candidate(uint32_t index, const glm::dvec3& x, bool onSurface, Path& p) const {
  const Facet& f = facets_[index];
  const double hx = -glm::dot(x - f.v0, f.n);  // depth of x below the facet's plane
  if (!(hx > 0.0)) return false;
  glm::dvec3 y;
  double irradiance = 0.0;
  if (kind_ != Kind::Point) {
    y = x - (hx / -glm::dot(f.din, f.n)) * f.din;
    irradiance = f.irradiance;
  } else {
    // In the plane of incidence through the light and x (refracted_light.h).
    const double hp = glm::dot(origin_ - f.v0, f.n);
    const glm::dvec3 pf = origin_ - hp * f.n, xf = x + hx * f.n;
    {
      // For η >= 1 the refraction point lies between the straight line's crossing y0 and x's
      // foot xf (refractionPoint): a facet that segment misses is not a connection, found
      // without solving (the barycentric coordinates are linear along the segment).
      const glm::dvec3 y0 = origin_ + (hp / (hp + hx)) * (x - origin_);
      const double s0 = glm::dot(y0 - f.v0, f.a), t0 = glm::dot(y0 - f.v0, f.b);
      const double s1 = glm::dot(xf - f.v0, f.a), t1 = glm::dot(xf - f.v0, f.b);
      double lo = 0.0, hi = 1.0;
      auto keep = [&](double a, double b) {  // a + b λ >= 0 on [lo, hi]
        if (b > 0.0)
          lo = std::max(lo, -a / b);
        else if (b < 0.0)
          hi = std::min(hi, -a / b);
        else if (a < 0.0)
          hi = -1.0;
      };
      keep(s0, s1 - s0);
      keep(t0, t1 - t0);
      keep(1.0 - s0 - t0, (s0 + t0) - (s1 + t1));
      if (!(lo <= hi)) return false;
    }
    glm::dvec3 e = xf - pf;
    const double D = glm::length(e);
    double u = 0.0;
    if (D > 1e-12 * (hp + hx)) {
      e /= D;
      u = refractionPoint(D, hp, hx, eta_);
    }
    y = pf + u * e;
    const double a = std::sqrt(u * u + hp * hp), bb = std::sqrt((D - u) * (D - u) + hx * hx);
    const double cosI = hp / a, cosT = hx / bb;
    irradiance = power_ * fresnelTransmittance(cosI, eta_) /
                 ((a + bb / eta_) * (a * cosT / cosI + bb * cosI / (eta_ * cosT)));
  }
  // y inside the triangle (barycentric coordinates in its plane).
  const glm::dvec3 r = y - f.v0;
  const double s = glm::dot(r, f.a), t = glm::dot(r, f.b);
  if (!(s >= 0.0 && t >= 0.0 && s + t <= 1.0)) return false;
  glm::dvec3 w = y - x;
  const double dist = glm::length(w);
  if (!(dist > (onSurface ? eps_ : 0.0))) return false;
  w /= dist;
  // Inside the beam's cylinder.
  if (kind_ == Kind::Beam) {
    const glm::dvec3 q = y - origin_;
    const double air = -glm::dot(q, toLight_);
    if (!(air > 0.0) || glm::length(q + air * toLight_) > radius_) return false;
  }
  p.w = w;
  p.dist = dist;
  p.irradiance = irradiance;
  return true;
}

bool RefractedLight::visible(const glm::dvec3& x, bool onSurface, const Path& p) const {
  const glm::dvec3 y = x + p.dist * p.w;
  glm::dvec3 toLight = toLight_;
  double air = kInf;
  if (kind_ == Kind::Beam) {
    air = -glm::dot(y - origin_, toLight_);
  } else if (kind_ == Kind::Point) {
    toLight = origin_ - y;
    air = glm::length(toLight);
    toLight /= air;
  }
  // Nothing of the boundary between x and y (then y is where the line from x leaves the body),
  // and nothing of the body between y and the light in air.
  const double t0 = onSurface ? eps_ : 0.0, t1 = p.dist - eps_;
  if (t1 > t0 && body_.occluded(x, p.w, t0, t1)) return false;
  return !body_.occluded(y, toLight, eps_, air);
}

}  // namespace translucent::reference
