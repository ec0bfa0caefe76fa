// SPDX-License-Identifier: GPL-3.0-or-later
// The lane walker's vector pass for the baseline instruction set of the build.
#include "translucent/reference/fastmath.h"
#include "translucent/reference/phase.h"
#include "translucent/reference/walk_lanes.h"

namespace translucent::reference::detail::portable {
#include "translucent/reference/walk_lanes_pass.inl"
}  // namespace translucent::reference::detail::portable
