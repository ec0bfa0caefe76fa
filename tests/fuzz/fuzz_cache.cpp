// SPDX-License-Identifier: GPL-3.0-or-later
// libFuzzer target for cache files (issue #15): the point-cloud cache (readPointCloudCache) and
// the atlas cache (readAtlasCache, for a fixed icosphere).
//
// Input: the first byte picks the cache (even: point cloud .ply, odd: atlas .bin), the rest is
// the file, written to a temporary file (both readers read by name). A PointCloudError or an
// AtlasError is the expected outcome for a damaged file; anything else (a crash, a sanitizer
// report, another exception, a hang) is a finding. A file that is accepted must hold a valid
// cloud (validate()) or an atlas of the mesh's triangle count.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "translucent/geometry/atlas.h"
#include "translucent/geometry/icosphere.h"
#include "translucent/geometry/point_cloud.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace translucent::geometry;
  if (size == 0) return 0;
  static const TriangleMesh mesh = makeIcosphere(1);
  static const std::string path =
      (std::filesystem::temp_directory_path() /
       ("translucent_fuzz_cache_" + std::to_string(::getpid())))
          .string();
  const bool atlas = (data[0] & 1) != 0;
  const std::string file = path + (atlas ? ".bin" : ".ply");
  {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data + 1), static_cast<std::streamsize>(size - 1));
  }
  try {
    if (atlas) {
      const Atlas a = readAtlasCache(file, mesh);
      if (a.chart.size() != mesh.triangleCount()) std::abort();
    } else {
      readPointCloudCache(file).validate(file);
    }
  } catch (const PointCloudError&) {
  } catch (const AtlasError&) {
  }
  std::error_code ec;
  std::filesystem::remove(file, ec);
  return 0;
}
