// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/reference/progressive.h"

#include <algorithm>
#include <limits>
#include <string>

#include "translucent/optics/medium.h"  // ParameterError

namespace translucent::reference {

std::vector<uint64_t> doublingPasses(uint64_t first, uint64_t budget, uint64_t granularity,
                                     uint64_t cap) {
  if (first == 0) throw ParameterError("progressive passes: first pass is 0: expected >= 1");
  if (budget == 0) throw ParameterError("progressive passes: budget is 0: expected >= 1");
  if (granularity == 0)
    throw ParameterError("progressive passes: granularity is 0: expected >= 1");
  auto roundUp = [&](uint64_t n) { return (n + granularity - 1) / granularity * granularity; };
  if (cap != 0 && cap < first)
    throw ParameterError("progressive passes: cap " + std::to_string(cap) +
                         " is below the first pass " + std::to_string(first) +
                         ": expected 0 (no cap) or >= the first pass");
  const uint64_t total = roundUp(budget);
  const uint64_t largest = cap == 0 ? std::numeric_limits<uint64_t>::max() : roundUp(cap);
  std::vector<uint64_t> passes;
  uint64_t done = 0, next = roundUp(first);
  while (done < total) {
    const uint64_t n = std::min(next, total - done);
    passes.push_back(n);
    done += n;
    // Doubling stops growing where it would overflow; the budget ends the loop long before.
    next = next > largest / 2 ? largest : 2 * next;
  }
  return passes;
}

}  // namespace translucent::reference
