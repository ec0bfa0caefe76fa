#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// Light-view irradiance map (techniques/common/light_view_map.h): world position and normal of
// the surface the light sees first.
layout(location = 0) in vec3 Position;  // world space [scene units]
layout(location = 1) in vec3 Normal;    // unit, outward
uniform mat4 ViewProjection;            // world -> light clip space
out vec3 vPosition;
out vec3 vNormal;
void main() {
  vPosition = Position;
  vNormal = Normal;
  gl_Position = ViewProjection * vec4(Position, 1.0);
}
