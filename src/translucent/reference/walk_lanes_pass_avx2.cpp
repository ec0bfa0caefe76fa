// SPDX-License-Identifier: GPL-3.0-or-later
// The lane walker's vector pass for x86-64 with AVX2 and FMA (8 floats per register); this file
// alone is compiled with -mavx2 -mfma, and walk_lanes.cpp calls it only when the CPU has both.
#include "translucent/reference/fastmath.h"
#include "translucent/reference/phase.h"
#include "translucent/reference/walk_lanes.h"

namespace translucent::reference::detail::avx2 {
#if defined(__AVX2__) && defined(__FMA__)
#include "translucent/reference/walk_lanes_pass.inl"
#else
VectorPass vectorPass(Absorption, bool, bool) { return nullptr; }
#endif
}  // namespace translucent::reference::detail::avx2
