// SPDX-License-Identifier: GPL-3.0-or-later
// The state of a Monte Carlo run that later passes or other shards add to: its order-independent
// sums (exact_sum.h) and its counts, as named arrays. A shard of a run writes it to its partial
// file (run_state_file.h); `translucent merge` adds the shards' states and hands the total to the
// same code that writes the unsharded run's outputs (issue 17). Adding states is exact and
// associative, so any grouping of the same blocks gives the same state, bit for bit.
#pragma once

#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "translucent/reference/exact_sum.h"

namespace translucent::reference {

struct RunState {
  // Sums keep their grid's exponent (exact_sum.h) so that states of different settings never
  // add up silently.
  struct Sums {
    int exponent = 0;
    std::vector<Fixed> values;
    bool operator==(const Sums&) const = default;
  };
  std::map<std::string, Sums> sums;
  std::map<std::string, std::vector<uint64_t>> counts;

  void putSums(const std::string& name, int exponent, std::vector<Fixed> values) {
    sums[name] = {exponent, std::move(values)};
  }
  void putCounts(const std::string& name, std::vector<uint64_t> values) {
    counts[name] = std::move(values);
  }
  // The array `name` with `size` entries on the grid `exponent`; std::runtime_error naming it
  // when it is missing or of another layout.
  const std::vector<Fixed>& getSums(const std::string& name, size_t size, int exponent) const {
    const auto it = sums.find(name);
    if (it == sums.end()) throw std::runtime_error("run state: no array '" + name + "'");
    if (it->second.values.size() != size || it->second.exponent != exponent)
      throw std::runtime_error("run state: array '" + name + "' has " +
                               std::to_string(it->second.values.size()) + " values on grid 2^" +
                               std::to_string(it->second.exponent) + ", expected " +
                               std::to_string(size) + " on 2^" + std::to_string(exponent));
    return it->second.values;
  }
  const std::vector<uint64_t>& getCounts(const std::string& name, size_t size) const {
    const auto it = counts.find(name);
    if (it == counts.end()) throw std::runtime_error("run state: no count '" + name + "'");
    if (it->second.size() != size)
      throw std::runtime_error("run state: count '" + name + "' has " +
                               std::to_string(it->second.size()) + " values, expected " +
                               std::to_string(size));
    return it->second;
  }

  // Adds another state of the same layout (same names, sizes and grids); std::runtime_error
  // naming the first difference otherwise.
  void merge(const RunState& o) {
    if (o.sums.size() != sums.size() || o.counts.size() != counts.size())
      throw std::runtime_error("run state: the states hold different arrays");
    for (auto& [name, a] : sums) {
      const std::vector<Fixed>& b = o.getSums(name, a.values.size(), a.exponent);
      for (size_t i = 0; i < b.size(); ++i) addFixed(a.values[i], b[i]);
    }
    for (auto& [name, a] : counts) {
      const std::vector<uint64_t>& b = o.getCounts(name, a.size());
      for (size_t i = 0; i < b.size(); ++i)
        if (__builtin_add_overflow(a[i], b[i], &a[i]))
          throw std::overflow_error("run state: count '" + name + "' overflowed");
    }
  }
};

// A state with a header (a JSON object: what run it is, which shard) as the bytes of a partial
// file, and back. The file is a first line "translucent-partial 1", a one-line JSON header that
// lists the arrays (name, grid exponent, size) and holds a 64-bit content hash of the payload,
// then the payload: the arrays in that order, little-endian (sums as a bitmap of the non-zero
// entries followed by those entries, 128-bit two's complement; counts as 64-bit words).
// decode throws std::runtime_error saying what is wrong (not a partial file, truncated, hash
// mismatch); the caller names the file.
std::string encodeRunState(const std::string& header_json, const RunState& state);
struct DecodedRunState {
  std::string header_json;  // the caller's header (without the layout this file adds)
  RunState state;
};
DecodedRunState decodeRunState(std::string_view bytes);

}  // namespace translucent::reference
