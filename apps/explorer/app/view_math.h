// Camera and light manipulation for the viewport's mouse input (pure functions, tested).
#pragma once

#include <glm/vec3.hpp>

#include "reference/camera.h"

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

}  // namespace translucent::explorer
