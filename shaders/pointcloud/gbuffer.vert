#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// G-buffer of the radiance pass: world position and shading normal of the visible surface.
layout(location = 0) in vec3 Position;  // world space [scene units]
layout(location = 1) in vec3 Normal;    // unit, outward
uniform mat4 ViewProjection;            // world -> camera clip space
out vec3 vPosition;
out vec3 vNormal;
void main() {
  vPosition = Position;
  vNormal = Normal;
  gl_Position = ViewProjection * vec4(Position, 1.0);
}
