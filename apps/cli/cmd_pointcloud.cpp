// SPDX-License-Identifier: GPL-3.0-or-later
// translucent pointcloud MESH --points N --out cloud.ply: the area-uniform surface samples of the
// point-cloud technique (geometry/point_cloud.h, seed 2.6.4) written as a PLY point cloud
// (x y z nx ny nz area, the triangle of each point), with the uniformity of the sampling
// (nearest-neighbour distances). Open meshes are sampled too: points need no interior.
#include <fmt/format.h>

#include <chrono>
#include <filesystem>
#include <memory>

#include "commands.h"
#include "translucent/geometry/mesh.h"
#include "translucent/geometry/point_cloud.h"
#include "translucent/optics/medium.h"  // ParameterError
#include "output_guard.h"
#include "safe_print.h"

namespace translucent::cli {
namespace {

struct PointCloudArgs {
  std::string mesh, out, sampling = "elimination";
  size_t points = 100000;
  uint64_t seed = 1;
};

void run(const PointCloudArgs& a) {
  if (std::filesystem::path(a.out).extension() != ".ply")
    throw ParameterError(fmt::format("--out {}: expected a .ply file", a.out));
  geometry::SamplingOptions options;
  options.count = a.points;
  options.seed = a.seed;
  try {
    options.method = geometry::parseSamplingMethod(a.sampling);
  } catch (const geometry::PointCloudError& e) {
    throw ParameterError(fmt::format("--sampling: {}", e.what()));
  }
  {
    OutputSet outputs;
    outputs.output("--out", a.out);
    outputs.input("the mesh", a.mesh);
    outputs.check();
  }
  if (!beginWork()) return;
  geometry::TriangleMesh mesh;
  try {
    mesh = geometry::loadMesh(a.mesh);
    mesh.validate(fmt::format("mesh file '{}'", a.mesh));
  } catch (const geometry::MeshError& e) {
    throw ParameterError(e.what());  // names the file
  }
  const auto start = std::chrono::steady_clock::now();
  geometry::PointCloud cloud;
  try {
    cloud = geometry::samplePointCloud(mesh, options);
  } catch (const geometry::PointCloudError& e) {
    throw ParameterError(fmt::format("--points {}: {}", a.points, e.what()));
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  writeOutput("--out", a.out, [&](const std::string& p) { geometry::writePointCloudPly(cloud, p); });
  const auto nn = geometry::nearestNeighbourStats(cloud);
  const size_t open = mesh.openEdgeCount();
  fmt::print("point cloud of {}: {} points ({}, seed {}) in {:.2f} s\n", a.mesh, cloud.size(),
             geometry::toString(options.method), a.seed, seconds);
  fmt::print("surface area      {:.6g} (per point {:.6g}){}\n", cloud.totalArea(),
             cloud.totalArea() / static_cast<double>(cloud.size()),
             open ? fmt::format("; the mesh is open ({} edges)", open) : "");
  fmt::print("nearest neighbour mean {:.4g}, CV {:.3f} (random sampling: ~0.52)\n", nn.mean, nn.cv);
  fmt::print("wrote {}\n", a.out);
}

}  // namespace

void addPointCloudCommand(CLI::App& app) {
  auto args = std::make_shared<PointCloudArgs>();
  auto* cmd = app.add_subcommand(
      "pointcloud",
      "Sample a mesh's surface as the point-cloud technique does and write the points as a PLY "
      "(x y z nx ny nz area face); open meshes too");
  cmd->add_option("mesh", args->mesh, "Mesh file (OBJ, PLY, OFF)")->required();
  cmd->add_option("--points", args->points, "Number of points")->capture_default_str();
  cmd->add_option("--seed", args->seed, "Random seed (same seed: same points on any thread count)")
      ->capture_default_str();
  cmd->add_option("--sampling", args->sampling,
                  "elimination (Yuksel 2015 sample elimination: blue noise) or random")
      ->capture_default_str();
  outputOption(cmd->add_option("--out", args->out, "Output PLY file"))->required();
  cmd->callback([args] { run(*args); });
}

}  // namespace translucent::cli
