// SPDX-License-Identifier: GPL-3.0-or-later
// Structural checks of OBJ, PLY and OFF files before assimp reads them (internal to loadMesh).
//
// Why: assimp trusts what a file declares. A PLY or OFF header that promises more vertices or
// faces than the file holds, an index outside the vertex list, a header without data or without
// end_header make it read past its buffers (segfault), fail an assertion (abort), allocate what
// the header says (std::bad_alloc for 4e9 vertices) or loop forever. These checks walk the file
// the way assimp's readers do (line by line where they are line based) and reject, with the line
// or element and the value, anything that would make assimp index or allocate on a lie.
#pragma once

#include <string>
#include <string_view>

namespace translucent::geometry::detail {

// Throws MeshError naming `path` (and the line, element or byte offset) when `data`, the file's
// bytes, is not a well-formed mesh of the format its extension names. `extension` is lowercase
// with the dot (".obj", ".ply", ".off"); other extensions are not checked.
void checkMeshFile(const std::string& path, std::string_view data, const std::string& extension);

}  // namespace translucent::geometry::detail
