// SPDX-License-Identifier: GPL-3.0-or-later
// libFuzzer target for `.bssrdf` files (bssrdf::parseBssrdf: parse only, no GL; issue #15).
//
// The input is the file's text. A BssrdfFileError is the expected outcome for a malformed file;
// anything else (a crash, a sanitizer report, another exception, a hang) is a finding. A file
// that parses must satisfy what the GPU layer relies on: a shader section, and parameters whose
// defaults lie in their ranges.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>
#include <variant>

#include "translucent/bssrdf/bssrdf_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const auto file = translucent::bssrdf::parseBssrdf(text, "fuzz.bssrdf");
    if (file.shader.first_line <= 1) std::abort();  // line 1 holds the attributes
    for (const auto& p : file.parameters)
      if (const auto* f = std::get_if<translucent::bssrdf::FloatParameter>(&p.spec))
        if (!(f->min <= f->value && f->value <= f->max)) std::abort();
  } catch (const translucent::bssrdf::BssrdfFileError&) {
  }
  return 0;
}
