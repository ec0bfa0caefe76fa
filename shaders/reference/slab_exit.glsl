// SPDX-License-Identifier: GPL-3.0-or-later
// One photon's record of the slab walks (slab_walk.comp, layered_walk.comp), scored on the CPU
// (src/reference/gpu/slab_gpu.cpp: ExitRecord, the same std430 layout, 40 bytes).
#pragma once

struct Exit {
  vec2 xy;        // where it left through the top
  float cosOut;   // cosine of its direction outside (top) -- used for the exit-angle tally
  uint kind;      // 0: top, 1: bottom, 2: absorbed or ended by a roulette
  double weight;  // weight it left with
  double absorbed;
  uint scatters;  // scattering events
  uint pad;
};
layout(std430, binding = 0) writeonly buffer Exits { Exit exits[]; };
