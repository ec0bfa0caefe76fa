// Writing a whole file so that readers (other processes, other threads) see the old file or the
// new one, never a part, and a failed write leaves nothing behind: the bytes go to a unique
// temporary file beside the target, which is renamed over it only when every write succeeded
// (rename is atomic on POSIX file systems). The caches (point clouds, AO, atlases) use it.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

namespace translucent::geometry {

// Writes `bytes` to `path` atomically. Returns "" on success, else why it failed (the temporary
// file is removed then): callers wrap the reason in their own error or note.
std::string writeFileAtomically(const std::filesystem::path& path, std::string_view bytes);

}  // namespace translucent::geometry
