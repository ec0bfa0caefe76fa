#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// Depth only: the rasteriser writes gl_FragCoord.z.
void main() {}
