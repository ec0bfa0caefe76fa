// SPDX-License-Identifier: GPL-3.0-or-later
// libFuzzer target for environment images (lights::EnvironmentMap::load through OpenImageIO,
// issue #15).
//
// Input: the first byte picks the format (0: .exr, 1: .hdr, 2: .png, modulo 3), the rest is the
// file. OpenImageIO picks its reader by the extension and reads files by name, so the input is
// written to a temporary file first. A ParameterError is the expected outcome for a malformed
// image; anything else (a crash, a sanitizer report, another exception, a hang) is a finding. A
// map that loads must hold finite, non-negative radiance of the size it says.
#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "translucent/lights/environment_map.h"
#include "translucent/optics/medium.h"  // ParameterError

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  static const char* const kExtensions[] = {".exr", ".hdr", ".png"};
  static const std::string path =
      (std::filesystem::temp_directory_path() /
       ("translucent_fuzz_image_" + std::to_string(::getpid())))
          .string();
  const std::string file = path + kExtensions[data[0] % 3];
  {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data + 1), static_cast<std::streamsize>(size - 1));
  }
  try {
    const auto map = translucent::lights::EnvironmentMap::load(file);
    if (map.rgb.size() != size_t(map.width) * size_t(map.height) * 3) std::abort();
    for (const float v : map.rgb)
      if (!std::isfinite(v) || v < 0.0f) std::abort();
  } catch (const translucent::ParameterError&) {
  }
  std::error_code ec;
  std::filesystem::remove(file, ec);
  return 0;
}
