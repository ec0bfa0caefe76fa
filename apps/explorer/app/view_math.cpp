// SPDX-License-Identifier: GPL-3.0-or-later
#include "app/view_math.h"

#include <glm/geometric.hpp>
#include <glm/gtc/constants.hpp>
#include <glm/gtx/rotate_vector.hpp>

#include <algorithm>
#include <cmath>

namespace translucent::explorer {
namespace {

struct Frame {
  glm::dvec3 forward, right, up;
  double distance;
};

Frame cameraFrame(const reference::Camera& c) {
  glm::dvec3 d = c.look_at - c.position;
  const double distance = glm::length(d);
  const glm::dvec3 forward = distance > 0.0 ? d / distance : glm::dvec3(0, 0, -1);
  glm::dvec3 right = glm::cross(forward, c.up);
  if (glm::length(right) < 1e-12) right = glm::cross(forward, glm::dvec3(1, 0, 0));
  right = glm::normalize(right);
  return {forward, right, glm::cross(right, forward), distance};
}

}  // namespace

reference::Camera orbit(const reference::Camera& camera, double yaw, double pitch) {
  reference::Camera c = camera;
  const glm::dvec3 up = glm::normalize(c.up);
  glm::dvec3 offset = c.position - c.look_at;  // from the centre to the eye
  const double r = glm::length(offset);
  if (!(r > 0.0)) return c;
  offset = glm::rotate(offset, -yaw, up);
  // Elevation of the eye above the plane perpendicular to up, kept off the poles.
  const double limit = glm::half_pi<double>() - glm::radians(1.0);
  const double elevation = std::asin(std::clamp(glm::dot(offset / r, up), -1.0, 1.0));
  const double target = std::clamp(elevation + pitch, -limit, limit);
  const glm::dvec3 axis = glm::cross(up, offset);
  if (glm::length(axis) > 1e-12) offset = glm::rotate(offset, -(target - elevation), glm::normalize(axis));
  c.position = c.look_at + offset;
  return c;
}

reference::Camera pan(const reference::Camera& camera, double dx, double dy) {
  reference::Camera c = camera;
  const Frame f = cameraFrame(c);
  const double height = c.projection == reference::Camera::Projection::Orthographic
                            ? c.view_height
                            : 2.0 * f.distance * std::tan(glm::radians(c.fov) / 2.0);
  const glm::dvec3 move = (-dx * f.right - dy * f.up) * height;
  c.position += move;
  c.look_at += move;
  return c;
}

reference::Camera zoom(const reference::Camera& camera, double factor) {
  reference::Camera c = camera;
  if (!(factor > 0.0) || !std::isfinite(factor)) return c;
  if (c.projection == reference::Camera::Projection::Orthographic) {
    c.view_height *= factor;
  } else {
    c.position = c.look_at + (c.position - c.look_at) * factor;
  }
  return c;
}

glm::dvec3 turnDirection(const reference::Camera& camera, const glm::dvec3& direction, double yaw,
                         double pitch) {
  const Frame f = cameraFrame(camera);
  glm::dvec3 d = glm::normalize(direction);
  d = glm::rotate(d, yaw, f.up);
  d = glm::rotate(d, -pitch, f.right);
  return glm::normalize(d);
}

std::vector<OverlaySegment> overlaySegments(const reference::Camera& camera, const glm::dvec3& lo,
                                            const glm::dvec3& hi, int width, int height) {
  reference::Camera c = camera;
  c.width = width;
  c.height = height;
  const reference::CameraModel model(c);
  std::vector<std::pair<glm::dvec3, glm::dvec3>> ends;
  std::vector<int> kinds;
  for (int axis = 0; axis < 3; ++axis)
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b) {
        glm::dvec3 p0, p1;
        const int u = (axis + 1) % 3, v = (axis + 2) % 3;
        p0[axis] = lo[axis];
        p1[axis] = hi[axis];
        p0[u] = p1[u] = a ? hi[u] : lo[u];
        p0[v] = p1[v] = b ? hi[v] : lo[v];
        ends.emplace_back(p0, p1);
        kinds.push_back(0);
      }
  for (int axis = 0; axis < 3; ++axis) {
    glm::dvec3 e(0.0);
    e[axis] = 1.0;
    ends.emplace_back(glm::dvec3(0.0), e);
    kinds.push_back(axis + 1);
  }
  std::vector<OverlaySegment> out;
  for (size_t k = 0; k < ends.size(); ++k) {
    OverlaySegment s;
    s.kind = kinds[k];
    // project() also says false for points outside the image, whose coordinates it still sets
    // (the painter clips the segment); only an end behind a pinhole camera hides a segment.
    const glm::dvec3 forward = glm::normalize(c.look_at - c.position);
    const bool pinhole = c.projection == reference::Camera::Projection::Pinhole;
    const bool front = !pinhole || (glm::dot(ends[k].first - c.position, forward) > 0.0 &&
                                    glm::dot(ends[k].second - c.position, forward) > 0.0);
    (void)model.project(ends[k].first, s.x0, s.y0);
    (void)model.project(ends[k].second, s.x1, s.y1);
    s.visible = front;
    out.push_back(s);
  }
  return out;
}

}  // namespace translucent::explorer
