// SPDX-License-Identifier: GPL-3.0-or-later
#include "material/debug_view.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "translucent/analysis/colormap.h"
#include "translucent/bssrdf/registry.h"
#include "translucent/material/material.h"
#include "material/material_worker.h"
#include "translucent/geometry/atlas.h"
#include "translucent/material/point_profiles.h"
#include "translucent/material/surface_uv.h"
#include "translucent/reference/camera.h"

namespace translucent::explorer {

const char* debugQuantityName(DebugQuantity q) {
  switch (q) {
    case DebugQuantity::SigmaA: return "σa";
    case DebugQuantity::SigmaSPrime: return "σs′";
    case DebugQuantity::Rd: return "Rd";
    case DebugQuantity::Radius95: return "95% radius";
  }
  return "?";
}

std::vector<double> vertexDebugValues(const scene::Scene& scene,
                                      const geometry::TriangleMesh& placed, DebugQuantity quantity,
                                      int channel) {
  const material::Material mat = scene::sceneMaterial(scene, placed);
  const bool needsModel = quantity == DebugQuantity::Rd || quantity == DebugQuantity::Radius95;
  if (needsModel && isBssrdfPath(mat.model))
    throw ParameterError("material debug view: " + std::string(debugQuantityName(quantity)) +
                         " needs a registered model, not the .bssrdf file '" + mat.model + "'");
  // A surface map is read at the vertices' atlas UVs: the default atlas, as the point-cloud
  // technique reads it (cached beside its other atlases).
  std::vector<glm::vec2> atlasUvs;
  if (mat.kind == material::Material::Kind::Surface)
    atlasUvs = material::vertexAtlasUvs(
        placed, geometry::loadOrBuildAtlas(placed, geometry::AtlasOptions{}).atlas);
  const bssrdf::Model* model = needsModel ? &bssrdf::model(mat.model) : nullptr;
  const double eta = mat.medium.eta, scale = mat.medium.scale;
  // The 95% radius of a unit medium (σt' = 1) by reduced albedo, binned as point_profiles does.
  std::map<long long, double> unitRadius;
  auto perChannel = [&](const material::LocalMedium& lm, int c) {
    const ScalarMedium sm = lm.medium(eta, 1.0).channel(c);  // per medium unit
    switch (quantity) {
      case DebugQuantity::SigmaA: return sm.sigma_a;
      case DebugQuantity::SigmaSPrime: return sm.sigmaSPrime();
      case DebugQuantity::Rd: return model->totalReflectance(sm.reducedAlbedo(), eta);
      case DebugQuantity::Radius95: {
        const double ap = sm.reducedAlbedo();
        const auto bin = static_cast<long long>(std::llround(std::log(std::max(1.0 - ap, 1e-300)) * 1000.0));
        auto it = unitRadius.find(bin);
        if (it == unitRadius.end()) {
          const double a = 1.0 - std::exp(double(bin) / 1000.0);
          const ScalarMedium unit{1.0 - a, a, 0.0, eta};
          it = unitRadius.emplace(bin, model->profile(unit)->radiusForFraction(material::kProfileRadiusFraction)).first;
        }
        return it->second / sm.sigmaTPrime() / scale;  // medium units -> scene units
      }
    }
    return 0.0;
  };
  std::vector<double> out(placed.vertexCount());
  for (size_t i = 0; i < placed.vertexCount(); ++i) {
    const glm::dvec3 n = i < placed.normals.size() ? placed.normals[i] : glm::dvec3(0.0, 0.0, 1.0);
    const glm::dvec2 uv = i < atlasUvs.size() ? glm::dvec2(atlasUvs[i]) : glm::dvec2(0.0);
    const material::LocalMedium lm = mat.surfaceMedium(placed.positions[i], n, uv);
    if (channel >= 0 && channel < 3) {
      out[i] = perChannel(lm, channel);
    } else {
      out[i] = 0.2126 * perChannel(lm, 0) + 0.7152 * perChannel(lm, 1) + 0.0722 * perChannel(lm, 2);
    }
  }
  return out;
}

DebugImage renderDebugView(const scene::Scene& scene, const geometry::TriangleMesh& placed,
                           DebugQuantity quantity, int channel, int max_size) {
  const std::vector<double> v = vertexDebugValues(scene, placed, quantity, channel);
  reference::Camera cam = scene.camera;
  const double s = double(max_size) / std::max(cam.width, cam.height);
  if (s < 1.0) {
    cam.width = std::max(1, int(std::lround(cam.width * s)));
    cam.height = std::max(1, int(std::lround(cam.height * s)));
  }
  const reference::CameraModel camera(cam);
  DebugImage img;
  img.width = cam.width;
  img.height = cam.height;
  const size_t n = size_t(img.width) * size_t(img.height);
  img.values.assign(n, std::numeric_limits<float>::quiet_NaN());
  std::vector<double> depth(n, std::numeric_limits<double>::infinity());
  // Vertices in the image: continuous pixel coordinates and distance (NaN: not projected).
  std::vector<glm::dvec3> p(placed.vertexCount());
  for (size_t i = 0; i < p.size(); ++i) {
    double px = 0.0, py = 0.0;
    glm::dvec3 dir;
    double dist = 0.0;
    camera.toCamera(placed.positions[i], dir, dist);
    // A triangle with a vertex behind the camera or outside the image is skipped (the debug
    // view is of a framed mesh).
    if (dist <= 0.0 || !camera.project(placed.positions[i], px, py)) {
      p[i] = glm::dvec3(std::numeric_limits<double>::quiet_NaN());
      continue;
    }
    p[i] = {px, py, dist};
  }
  for (const glm::uvec3& t : placed.triangles) {
    const glm::dvec3 a = p[t.x], b = p[t.y], c = p[t.z];
    if (std::isnan(a.x) || std::isnan(b.x) || std::isnan(c.x)) continue;
    const double area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    if (area == 0.0) continue;
    const int x0 = std::max(0, int(std::floor(std::min({a.x, b.x, c.x}))));
    const int x1 = std::min(img.width - 1, int(std::ceil(std::max({a.x, b.x, c.x}))));
    const int y0 = std::max(0, int(std::floor(std::min({a.y, b.y, c.y}))));
    const int y1 = std::min(img.height - 1, int(std::ceil(std::max({a.y, b.y, c.y}))));
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const double qx = x + 0.5, qy = y + 0.5;
        const double w0 = ((b.x - qx) * (c.y - qy) - (b.y - qy) * (c.x - qx)) / area;
        const double w1 = ((c.x - qx) * (a.y - qy) - (c.y - qy) * (a.x - qx)) / area;
        const double w2 = 1.0 - w0 - w1;
        if (w0 < 0.0 || w1 < 0.0 || w2 < 0.0) continue;
        const double z = w0 * a.z + w1 * b.z + w2 * c.z;
        const size_t k = size_t(y) * size_t(img.width) + size_t(x);
        if (z >= depth[k]) continue;
        depth[k] = z;
        img.values[k] = float(w0 * v[t.x] + w1 * v[t.y] + w2 * v[t.z]);
      }
  }
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (float f : img.values)
    if (std::isfinite(f)) {
      lo = std::min(lo, double(f));
      hi = std::max(hi, double(f));
    }
  if (!std::isfinite(lo)) lo = hi = 0.0;
  if (!(hi > lo)) hi = lo + std::max(1e-12, std::abs(lo) * 1e-6);
  img.lo = lo;
  img.hi = hi;
  img.rgb = analysis::falseColor(img.values, img.width, img.height, analysis::ColorMap::Viridis, lo, hi);
  for (size_t k = 0; k < n; ++k)
    if (!std::isfinite(img.values[k])) img.rgb[3 * k] = img.rgb[3 * k + 1] = img.rgb[3 * k + 2] = 0;
  return img;
}

}  // namespace translucent::explorer
