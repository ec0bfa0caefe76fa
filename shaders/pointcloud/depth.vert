#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// Depth-only rendering of the mesh from a light (shadow maps of the irradiance pass).
layout(location = 0) in vec3 Position;  // world space [scene units]
uniform mat4 ViewProjection;            // world -> light clip space
void main() { gl_Position = ViewProjection * vec4(Position, 1.0); }
