// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/geometry/atomic_file.h"

#include <fmt/format.h>
#include <unistd.h>

#include <atomic>
#include <cstdint>
#include <fstream>
#include <functional>
#include <system_error>
#include <thread>

namespace translucent::geometry {

std::string writeFileAtomically(const std::filesystem::path& path, std::string_view bytes) {
  namespace fs = std::filesystem;
  // Unique per process, thread and call: concurrent writers of the same file never share one.
  static std::atomic<uint64_t> counter{0};
  const fs::path tmp = path.string() + fmt::format(".tmp-{}-{}-{}", ::getpid(),
                                                   std::hash<std::thread::id>{}(std::this_thread::get_id()),
                                                   counter.fetch_add(1));
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) return fmt::format("cannot create '{}'", tmp.string());
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.flush();
    out.close();
    if (!out) {
      std::error_code ec;
      fs::remove(tmp, ec);
      return "writing failed (disk full?)";
    }
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    return ec.message();
  }
  return "";
}

}  // namespace translucent::geometry
