// SPDX-License-Identifier: GPL-3.0-or-later
// Writing a whole file so that readers (other processes, other threads) see the old file or the
// new one, never a part, and a failed write leaves nothing behind: the bytes go to a unique
// temporary file beside the target, which is renamed over it only when every write succeeded
// (rename is atomic on POSIX file systems). The caches (point clouds, AO, atlases) use it.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace translucent::geometry {

// Writes `bytes` to `path` atomically. Returns "" on success, else why it failed (the temporary
// file is removed then): callers wrap the reason in their own error or note.
std::string writeFileAtomically(const std::filesystem::path& path, std::string_view bytes);

// A 64-bit content hash (FNV-1a) of `bytes`. The caches store it in the file and compare it on
// reading, so that a tampered or truncated cache file is detected and regenerated instead of
// used: a checksum against accidents and edits, not a defence against a forger.
constexpr uint64_t contentHash(std::string_view bytes) {
  uint64_t h = 0xcbf29ce484222325ULL;
  for (const char c : bytes) {
    h ^= static_cast<unsigned char>(c);
    h *= 0x100000001b3ULL;
  }
  return h;
}

}  // namespace translucent::geometry
