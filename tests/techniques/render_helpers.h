// SPDX-License-Identifier: GPL-3.0-or-later
// Shared pieces of the GPU technique tests: meshes written to OBJ files, small scenes, and a
// prepared point-cloud technique (on the process-wide headless context of tests/gpu/gpu_test.h).
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "translucent/geometry/mesh.h"
#include "gpu/gpu_test.h"
#include "translucent/scene/scene.h"
#include "translucent/techniques/pointcloud/pointcloud_technique.h"

namespace translucent::pointcloud::testing {

using gpu::testing::TempDir;

// Writes a triangle mesh as OBJ (positions, vertex normals when present, faces).
inline std::filesystem::path writeObj(const geometry::TriangleMesh& m, const std::filesystem::path& path) {
  std::ofstream f(path);
  f.precision(17);
  for (const auto& p : m.positions) f << "v " << p.x << ' ' << p.y << ' ' << p.z << '\n';
  const bool normals = m.normals.size() == m.positions.size();
  if (normals)
    for (const auto& n : m.normals) f << "vn " << n.x << ' ' << n.y << ' ' << n.z << '\n';
  for (const auto& t : m.triangles) {
    if (normals)
      f << "f " << t.x + 1 << "//" << t.x + 1 << ' ' << t.y + 1 << "//" << t.y + 1 << ' ' << t.z + 1
        << "//" << t.z + 1 << '\n';
    else
      f << "f " << t.x + 1 << ' ' << t.y + 1 << ' ' << t.z + 1 << '\n';
  }
  return path;
}

// Two meshes joined into one (indices of the second shifted).
inline geometry::TriangleMesh join(geometry::TriangleMesh a, const geometry::TriangleMesh& b) {
  const auto base = static_cast<uint32_t>(a.positions.size());
  a.positions.insert(a.positions.end(), b.positions.begin(), b.positions.end());
  for (const auto& t : b.triangles) a.triangles.push_back(t + glm::uvec3(base));
  a.normals.clear();
  return a;
}

// A scene around `mesh_file` with no normalisation, one directional light along +z, an
// orthographic camera looking down -z at the origin, and the technique's small test settings.
inline scene::Scene testScene(const std::filesystem::path& mesh_file, int size = 64) {
  scene::Scene s;
  s.mesh_file = mesh_file;
  s.mesh_normalize = false;
  s.preset = "";
  s.medium = Medium::fromReduced({0.0021, 0.0041, 0.0071}, {2.19, 2.62, 3.00}, 0.0, 1.3, 10.0);
  scene::Light l;
  l.emitter = reference::DirectionalLight{{0.0, 0.0, 1.0}, 1.0};
  s.lights = {l};
  s.camera.projection = reference::Camera::Projection::Orthographic;
  s.camera.position = {0.0, 0.0, 5.0};
  s.camera.look_at = {0.0, 0.0, 0.0};
  s.camera.view_height = 2.2;
  s.camera.width = size;
  s.camera.height = size;
  return s;
}

// Point clouds of the tests go to a folder of their own, not the user's cache.
// The folder is removed when the test process ends.
inline void useTestCache() {
  struct Folder {
    std::filesystem::path path = std::filesystem::temp_directory_path() /
                                 ("translucent-test-cache-" + std::to_string(::getpid()));
    Folder() { std::filesystem::create_directories(path); }
    ~Folder() {
      std::error_code ec;
      std::filesystem::remove_all(path, ec);
    }
  };
  static const Folder folder;
  ::setenv("TRANSLUCENT_CACHE_DIR", folder.path.c_str(), 1);
}

inline std::unique_ptr<PointCloudTechnique> technique(int points) {
  useTestCache();
  auto t = std::make_unique<PointCloudTechnique>();
  t->setParameter("points", points);
  return t;
}

// The camera turned by `angle` radians about the vertical (y) axis through its look-at point: an
// orbit step (issue 14 §6), as the explorer's left drag.
inline reference::Camera orbited(reference::Camera c, double angle) {
  const glm::dvec3 d = c.position - c.look_at;
  const double cs = std::cos(angle), sn = std::sin(angle);
  c.position = c.look_at + glm::dvec3(cs * d.x + sn * d.z, d.y, -sn * d.x + cs * d.z);
  return c;
}

// True when the frame timed a pass of that name (at any depth).
inline bool hasPass(const techniques::Frame& f, std::string_view name) {
  return std::any_of(f.passes.begin(), f.passes.end(), [&](const auto& p) { return p.name == name; });
}

// The largest |a_i − b_i| relative to the largest |b_i| (0 when both are zero); sizes must agree.
inline double relativeMaxDifference(const std::vector<float>& a, const std::vector<float>& b) {
  EXPECT_EQ(a.size(), b.size());
  double peak = 0.0, worst = 0.0;
  for (float v : b) peak = std::max(peak, std::abs(double(v)));
  for (size_t i = 0; i < std::min(a.size(), b.size()); ++i)
    worst = std::max(worst, std::abs(double(a[i]) - double(b[i])));
  return peak > 0.0 ? worst / peak : worst;
}

// Prepares `t` for `s` on the test context and renders one converged frame.
inline techniques::Frame renderConverged(techniques::Technique& t, const scene::Scene& s) {
  t.prepare(s, gpu::testing::context());
  techniques::FrameRequest req;
  req.converge = true;
  return t.render(req);
}

}  // namespace translucent::pointcloud::testing
