// SPDX-License-Identifier: GPL-3.0-or-later
// libFuzzer target for the partial files of sharded runs (issue 17: `pathtrace --shard`,
// `translucent merge`): reference::decodeRunState on arbitrary bytes.
//
// A std::runtime_error is the expected outcome for a damaged file; anything else (a crash, a
// sanitizer report, another exception, a hang, an allocation the file's size does not justify)
// is a finding. A file that is accepted must round-trip: encoded again and decoded, it gives the
// same state.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <stdexcept>
#include <string_view>

#include "translucent/reference/run_state.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace translucent::reference;
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  try {
    const DecodedRunState d = decodeRunState(bytes);
    const DecodedRunState again = decodeRunState(encodeRunState(d.header_json, d.state));
    if (!(again.state.sums == d.state.sums) || again.state.counts != d.state.counts ||
        again.header_json != d.header_json)
      std::abort();
  } catch (const std::runtime_error&) {
  }
  return 0;
}
