// SPDX-License-Identifier: GPL-3.0-or-later
// Triangle meshes: the minimal indexed representation the reference transport and the renderers
// share, and a loader for OBJ, PLY and OFF files (through assimp).
//
// Units: positions are in scene units (whatever the file uses, times the transform applied by
// the caller). Normals are per vertex and unit length; they are for shading only; the reference
// transport uses the geometric (face) normals.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace translucent::geometry {

// Thrown for missing, unreadable, empty or malformed mesh files, and for meshes that fail a
// requested check; the message names the file and what was expected.
class MeshError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct Bounds {
  glm::dvec3 lower{0.0}, upper{0.0};
  glm::dvec3 center() const { return 0.5 * (lower + upper); }
  double radius() const;  // radius of the sphere about center() that holds the box
};

struct TriangleMesh {
  std::vector<glm::dvec3> positions;
  std::vector<glm::uvec3> triangles;  // vertex indices, counter-clockwise seen from outside
                                      // when the file says so (the transport does not rely on it)
  std::vector<glm::dvec3> normals;    // per vertex (empty: none)
  std::vector<glm::dvec2> texcoords;  // per vertex UV, the file's first set (empty: none); the
                                      // atlas (atlas.h) keeps them when they are a valid one

  size_t vertexCount() const { return positions.size(); }
  size_t triangleCount() const { return triangles.size(); }
  Bounds bounds() const;
  double area() const;

  // Applies p -> scale * p + translate to positions (normals unchanged for a uniform scale).
  void transform(double scale, const glm::dvec3& translate);

  // Throws MeshError (naming `what`, e.g. the file) unless the mesh has triangles, every index is
  // in range, every position is finite, and no triangle has zero area.
  void validate(const std::string& what) const;

  // Number of edges not shared by exactly two triangles, after welding vertices with identical
  // positions: 0 for a closed (watertight, manifold) surface.
  size_t openEdgeCount() const;
  // Throws MeshError naming `what` unless openEdgeCount() == 0.
  void requireClosed(const std::string& what) const;

  // For a closed mesh: makes the winding counter-clockwise seen from outside (positive signed
  // volume, divergence theorem), flipping every triangle and vertex normal otherwise. Returns
  // whether it flipped. Techniques rely on this to tell the outside of a surface.
  bool orientOutwards();
};

// Loads every triangle of every mesh in an OBJ, PLY or OFF file (other formats assimp reads work
// too), joined into one mesh; polygons are triangulated and identical vertices joined. Throws
// MeshError for a missing or unreadable file, a file assimp cannot parse, or one without
// triangles; the result is validate()d. OBJ, PLY and OFF files are checked before assimp reads
// them (mesh_file_check.h: declared counts against the data, every index in range, numbers
// finite), so a malformed or hostile file is a MeshError naming the file, the line (or byte) and
// the value, never a crash, an abort or a hang.
TriangleMesh loadMesh(const std::string& path);

// A closed axis-aligned box [lower, upper] (12 triangles, outward counter-clockwise winding).
TriangleMesh makeBox(const glm::dvec3& lower, const glm::dvec3& upper);

}  // namespace translucent::geometry
