// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/geometry/mesh.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <assimp/DefaultIOSystem.h>
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <unordered_map>

#include <glm/geometric.hpp>

#include "translucent/geometry/mesh_file_check.h"

namespace translucent::geometry {

double Bounds::radius() const { return 0.5 * glm::length(upper - lower); }

Bounds TriangleMesh::bounds() const {
  Bounds b;
  if (positions.empty()) return b;
  b.lower = b.upper = positions.front();
  for (const auto& p : positions) {
    b.lower = glm::min(b.lower, p);
    b.upper = glm::max(b.upper, p);
  }
  return b;
}

double TriangleMesh::area() const {
  double a = 0.0;
  for (const auto& t : triangles)
    a += 0.5 * glm::length(glm::cross(positions[t.y] - positions[t.x], positions[t.z] - positions[t.x]));
  return a;
}

void TriangleMesh::transform(double scale, const glm::dvec3& translate) {
  for (auto& p : positions) p = scale * p + translate;
  if (scale < 0.0)
    for (auto& n : normals) n = -n;
}

void TriangleMesh::validate(const std::string& what) const {
  if (triangles.empty())
    throw MeshError(fmt::format("{}: the mesh has no triangles: expected a closed triangle mesh",
                                what));
  for (size_t i = 0; i < positions.size(); ++i) {
    const auto& p = positions[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      throw MeshError(fmt::format("{}: vertex {} is ({}, {}, {}): expected finite coordinates",
                                  what, i, p.x, p.y, p.z));
  }
  if (!normals.empty() && normals.size() != positions.size())
    throw MeshError(fmt::format("{}: {} normals for {} vertices: expected one per vertex", what,
                                normals.size(), positions.size()));
  if (!texcoords.empty() && texcoords.size() != positions.size())
    throw MeshError(fmt::format("{}: {} texture coordinates for {} vertices: expected one per "
                                "vertex", what, texcoords.size(), positions.size()));
  const auto n = static_cast<uint32_t>(positions.size());
  for (size_t i = 0; i < triangles.size(); ++i) {
    const auto& t = triangles[i];
    if (t.x >= n || t.y >= n || t.z >= n)
      throw MeshError(fmt::format(
          "{}: triangle {} has vertex indices ({}, {}, {}): expected indices below {}", what, i,
          t.x, t.y, t.z, n));
    const double a = glm::length(glm::cross(positions[t.y] - positions[t.x],
                                            positions[t.z] - positions[t.x]));
    if (!(a > 0.0))
      throw MeshError(fmt::format("{}: triangle {} has zero area: expected non-degenerate "
                                  "triangles", what, i));
  }
}

bool TriangleMesh::orientOutwards() {
  // 6 × signed volume = Σ p0 · (p1 × p2) over the triangles.
  double volume6 = 0.0;
  for (const glm::uvec3& t : triangles)
    volume6 += glm::dot(positions[t.x], glm::cross(positions[t.y], positions[t.z]));
  if (volume6 >= 0.0) return false;
  for (glm::uvec3& t : triangles) std::swap(t.y, t.z);
  for (glm::dvec3& n : normals) n = -n;
  return true;
}

size_t TriangleMesh::openEdgeCount() const {
  // Weld vertices with identical positions (files often repeat a vertex per face), then count
  // how many triangles use each undirected edge.
  std::map<std::array<double, 3>, uint32_t> ids;
  std::vector<uint32_t> weld(positions.size());
  for (size_t i = 0; i < positions.size(); ++i) {
    const auto& p = positions[i];
    const std::array<double, 3> key{p.x, p.y, p.z};
    weld[i] = ids.try_emplace(key, static_cast<uint32_t>(ids.size())).first->second;
  }
  std::unordered_map<uint64_t, int> uses;
  uses.reserve(3 * triangles.size());
  for (const auto& t : triangles) {
    const uint32_t v[3] = {weld[t.x], weld[t.y], weld[t.z]};
    for (int e = 0; e < 3; ++e) {
      const uint32_t a = std::min(v[e], v[(e + 1) % 3]), b = std::max(v[e], v[(e + 1) % 3]);
      ++uses[(static_cast<uint64_t>(a) << 32) | b];
    }
  }
  size_t open = 0;
  for (const auto& [edge, count] : uses)
    if (count != 2) ++open;
  return open;
}

void TriangleMesh::requireClosed(const std::string& what) const {
  const size_t open = openEdgeCount();
  if (open != 0)
    throw MeshError(fmt::format(
        "{}: {} edge(s) are not shared by exactly two triangles: expected a closed (watertight) "
        "surface, since light transport inside needs a well-defined interior",
        what, open));
}

namespace {

// assimp opens the files a mesh names (an OBJ's mtllib) as well as the mesh itself; a hostile
// file could name /dev/zero or a directory and hang or crash the reader. Only regular files open.
class RegularFilesOnly : public Assimp::DefaultIOSystem {
 public:
  Assimp::IOStream* Open(const char* file, const char* mode) override {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec)) return nullptr;
    return Assimp::DefaultIOSystem::Open(file, mode);
  }
};

}  // namespace

TriangleMesh loadMesh(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::exists(path, ec))
    throw MeshError(fmt::format("mesh file '{}' does not exist", path));
  if (!fs::is_regular_file(path, ec))
    throw MeshError(fmt::format("mesh file '{}' is not a regular file", path));
  if (fs::file_size(path, ec) == 0)
    throw MeshError(fmt::format("mesh file '{}' is empty: expected an OBJ, PLY or OFF mesh", path));

  // Check the file's structure (counts, indices, numbers) ourselves before assimp reads it:
  // assimp trusts the counts a header declares (mesh_file_check.h).
  std::string bytes;
  {
    std::ifstream in(path, std::ios::binary);
    bytes.resize(static_cast<size_t>(fs::file_size(path, ec)));
    if (ec || !in.read(bytes.data(), static_cast<std::streamsize>(bytes.size())))
      throw MeshError(fmt::format("mesh file '{}' could not be read", path));
  }
  std::string extension = fs::path(path).extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  detail::checkMeshFile(path, bytes, extension);

  Assimp::Importer importer;
  importer.SetIOHandler(new RegularFilesOnly);  // the importer owns and deletes it
  // Keep only what we use; triangulate polygons, drop points and lines, join identical vertices.
  // ValidateDataStructure runs first and rejects a scene with indices out of range.
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  const aiScene* scene = importer.ReadFile(
      path, aiProcess_ValidateDataStructure | aiProcess_Triangulate |
                aiProcess_JoinIdenticalVertices | aiProcess_SortByPType |
                aiProcess_PreTransformVertices);
  if (scene == nullptr) {
    const std::string error = importer.GetErrorString();
    // SortByPType removed every mesh (all points or lines): say so rather than assimp's words.
    if (error.find("No output meshes") != std::string::npos)
      throw MeshError(fmt::format("mesh file '{}' has no faces (only points or lines): expected "
                                  "a triangle mesh", path));
    throw MeshError(fmt::format("mesh file '{}' could not be read: {}", path, error));
  }

  TriangleMesh mesh;
  bool allNormals = true, allTexcoords = true;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* am = scene->mMeshes[m];
    if (am == nullptr || (am->mPrimitiveTypes & aiPrimitiveType_TRIANGLE) == 0) continue;
    // Checked before anything indexes: the arrays exist and every index is in range.
    if (am->mNumVertices > 0 && am->mVertices == nullptr)
      throw MeshError(fmt::format("mesh file '{}': mesh {} has {} vertices but no positions", path,
                                  m, am->mNumVertices));
    if (am->mNumFaces > 0 && am->mFaces == nullptr)
      throw MeshError(fmt::format("mesh file '{}': mesh {} has {} faces but no face data", path, m,
                                  am->mNumFaces));
    for (unsigned f = 0; f < am->mNumFaces; ++f) {
      const aiFace& face = am->mFaces[f];
      if (face.mNumIndices > 0 && face.mIndices == nullptr)
        throw MeshError(fmt::format("mesh file '{}': mesh {} face {} has no indices", path, m, f));
      for (unsigned k = 0; k < face.mNumIndices; ++k)
        if (face.mIndices[k] >= am->mNumVertices)
          throw MeshError(fmt::format("mesh file '{}': mesh {} face {} has vertex index {}: "
                                      "expected 0 to {}", path, m, f, face.mIndices[k],
                                      am->mNumVertices - 1));
    }
    const auto base = static_cast<uint32_t>(mesh.positions.size());
    for (unsigned v = 0; v < am->mNumVertices; ++v) {
      const aiVector3D& p = am->mVertices[v];
      mesh.positions.emplace_back(p.x, p.y, p.z);
      if (am->HasNormals()) {
        const aiVector3D& n = am->mNormals[v];
        mesh.normals.emplace_back(n.x, n.y, n.z);
      }
      if (am->HasTextureCoords(0)) {
        const aiVector3D& uv = am->mTextureCoords[0][v];
        mesh.texcoords.emplace_back(uv.x, uv.y);
      }
    }
    allNormals = allNormals && am->HasNormals();
    allTexcoords = allTexcoords && am->HasTextureCoords(0);
    for (unsigned f = 0; f < am->mNumFaces; ++f) {
      const aiFace& face = am->mFaces[f];
      if (face.mNumIndices != 3) continue;
      mesh.triangles.emplace_back(base + face.mIndices[0], base + face.mIndices[1],
                                  base + face.mIndices[2]);
    }
  }
  if (!allNormals) mesh.normals.clear();
  if (!allTexcoords) mesh.texcoords.clear();
  for (size_t i = 0; i < mesh.positions.size(); ++i) {
    const auto& p = mesh.positions[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      throw MeshError(fmt::format("mesh file '{}': vertex {} is ({}, {}, {}): expected finite "
                                  "coordinates", path, i, p.x, p.y, p.z));
  }
  // assimp keeps degenerate triangles; drop them rather than fail (they carry no area).
  const size_t loaded = mesh.triangles.size();
  std::erase_if(mesh.triangles, [&](const glm::uvec3& t) {
    return !(glm::length(glm::cross(mesh.positions[t.y] - mesh.positions[t.x],
                                    mesh.positions[t.z] - mesh.positions[t.x])) > 0.0);
  });
  if (mesh.triangles.empty() && loaded > 0)
    throw MeshError(fmt::format("mesh file '{}': all {} triangles have zero area: expected a "
                                "triangle mesh with positive area", path, loaded));
  if (mesh.triangles.empty())
    throw MeshError(fmt::format("mesh file '{}' has no triangles: expected a triangle mesh", path));
  mesh.validate(fmt::format("mesh file '{}'", path));
  return mesh;
}

TriangleMesh makeBox(const glm::dvec3& lo, const glm::dvec3& hi) {
  TriangleMesh m;
  for (int i = 0; i < 8; ++i)
    m.positions.emplace_back((i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z);
  // Two triangles per face, counter-clockwise seen from outside.
  const uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    m.triangles.emplace_back(q[0], q[1], q[2]);
    m.triangles.emplace_back(q[0], q[2], q[3]);
  }
  return m;
}

}  // namespace translucent::geometry
