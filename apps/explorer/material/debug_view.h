// SPDX-License-Identifier: GPL-3.0-or-later
// The material debug view (issue 12, §5): σa, σs', Rd or the 95% radius of the scene's material
// over the mesh, in false colour, seen from the scene's camera. Computed on the CPU (no GL):
//   - per vertex of the placed mesh, the local medium Material::surfaceMedium (a 3D field: the
//     medium below the surface that light diffusing out there has travelled through; a surface
//     map: its texel at the vertex's UV in the default atlas, geometry::loadOrBuildAtlas, as the
//     point-cloud technique reads it);
//   - the quantity per channel: σa and σs' = σs (1 − g) [1/medium unit], Rd = the model's total
//     diffuse reflectance Rd(α', η), the radius holding 95% of the model's profile energy
//     (RadialProfile::radiusForFraction(0.95)) [scene units]; one channel or the luminance
//     (0.2126 r + 0.7152 g + 0.0722 b) of the three;
//   - triangles rasterised with a depth test at the camera's aspect ratio (at most `max_size`
//     pixels on a side), the value interpolated linearly; pixels the mesh does not cover are NaN
//     (drawn mid grey by falseColor: the background is black here instead).
// The colour range is the minimum and maximum over the covered pixels (viridis).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "translucent/geometry/mesh.h"
#include "translucent/scene/scene.h"

namespace translucent::explorer {

enum class DebugQuantity { SigmaA, SigmaSPrime, Rd, Radius95 };
inline constexpr int kLuminanceChannel = -1;

const char* debugQuantityName(DebugQuantity q);  // "σa", "σs′", "Rd", "95% radius"

struct DebugImage {
  int width = 0, height = 0;
  std::vector<float> values;  // width * height, row 0 at the top, NaN off the mesh
  std::vector<uint8_t> rgb;   // false colour, 8-bit, black off the mesh
  double lo = 0.0, hi = 0.0;  // the colour range
};

// The quantity at each vertex of `placed` (loadSceneMesh(scene)). Throws ParameterError for a
// .bssrdf model (Rd, radius: no CPU evaluator); AtlasError when a surface map's atlas cannot be
// built.
std::vector<double> vertexDebugValues(const scene::Scene& scene,
                                      const geometry::TriangleMesh& placed, DebugQuantity quantity,
                                      int channel);
DebugImage renderDebugView(const scene::Scene& scene, const geometry::TriangleMesh& placed,
                           DebugQuantity quantity, int channel, int max_size = 256);

}  // namespace translucent::explorer
