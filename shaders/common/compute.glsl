// SPDX-License-Identifier: GPL-3.0-or-later
// Helpers for compute shaders dispatched with translucent::gpu::dispatch1D (src/gpu/compute.h).
// Include after the `layout(local_size_x = ...) in;` declaration: gl_WorkGroupSize is only
// declared once the local size is.
#pragma once

// Index of this invocation in a 1D batch laid out as a 2D grid of work groups (dispatch1D uses
// a second row of groups only when the batch exceeds GL_MAX_COMPUTE_WORK_GROUP_COUNT[0]).
uint linearInvocationIndex() {
  return gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x;
}
