// SPDX-License-Identifier: GPL-3.0-or-later
// Camera and light manipulation for the viewport's mouse input (pure functions, tested).
#pragma once

#include <vector>

#include <glm/vec3.hpp>

#include "translucent/reference/camera.h"

namespace translucent::explorer {

// Orbits the camera about its look-at point: `yaw` about the up vector, `pitch` about the
// camera's right axis [radians]; the elevation stays within 1 degree of the poles.
reference::Camera orbit(const reference::Camera& camera, double yaw, double pitch);
// Moves camera and look-at point in the image plane by (dx, dy) [fractions of the view height;
// +x right, +y up].
reference::Camera pan(const reference::Camera& camera, double dx, double dy);
// Scales the distance to the look-at point by `factor` (> 0); orthographic: the view height.
reference::Camera zoom(const reference::Camera& camera, double factor);
// Turns a direction (towards a light) about the camera's up axis by `yaw` and about its right
// axis by `pitch` [radians]; the result is a unit vector.
glm::dvec3 turnDirection(const reference::Camera& camera, const glm::dvec3& direction, double yaw,
                         double pitch);

// The overlay of the viewport (issue 14 §7, empirical seed appendix A: bounding box and axes):
// the 12 edges of the box [lo, hi] and the three unit axes from the origin (x, y, z, in that order
// after the box's edges) as 2D segments in the pixels of a `width` x `height` image of `camera`
// (x right, y down). A segment with an end behind the camera is left out (`visible` false).
struct OverlaySegment {
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  int kind = 0;  // 0: box edge, 1/2/3: the x/y/z axis
  bool visible = false;
};
std::vector<OverlaySegment> overlaySegments(const reference::Camera& camera, const glm::dvec3& lo,
                                            const glm::dvec3& hi, int width, int height);

}  // namespace translucent::explorer
