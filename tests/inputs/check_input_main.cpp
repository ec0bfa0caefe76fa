// SPDX-License-Identifier: GPL-3.0-or-later
// Loads one user input the way the renderers do, for the malformed-input corpus
// (tests/data/malformed/<family>/manifest.txt, issue #15):
//
//   translucent_check_input scene FILE           loadScene, then its mesh (camera and lights
//                                                outside it), .bssrdf model and
//                                                environment maps
//   translucent_check_input bssrdf FILE          loadBssrdf (parse only, no GL)
//   translucent_check_input image FILE           EnvironmentMap::load
//   translucent_check_input pointcloud-cache FILE  the file as the point-cloud cache entry of a
//                                                fixed mesh and sampling (loadOrSamplePointCloud)
//   translucent_check_input atlas-cache FILE     the same for the atlas cache (loadOrBuildAtlas)
//   translucent_check_input write-seeds DIR      writes valid cache files, EXRs and a VDB for generate.py
//
// Exit status: 1 with the error on stderr; 3 with "warning: ..." on stderr when the input was
// accepted with a warning (a clamped texel, a cache file regenerated with a note); 0 when it was
// accepted silently (a corpus file must never do that); 2 for a usage error. A crash is a signal.
#include <fmt/format.h>
#include <openvdb/openvdb.h>
#include <unistd.h>

#include <cstdio>
#include <exception>
#include <stdexcept>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "translucent/io/image_io.h"
#include "translucent/bssrdf/bssrdf_file.h"
#include "translucent/geometry/atlas.h"
#include "translucent/geometry/icosphere.h"
#include "translucent/geometry/point_cloud.h"
#include "translucent/lights/environment_map.h"
#include "translucent/scene/scene.h"

namespace fs = std::filesystem;
using namespace translucent;

namespace {

// The fixed mesh and settings whose cache entries the cache files stand in for.
geometry::TriangleMesh cacheMesh() { return geometry::makeIcosphere(1); }
geometry::SamplingOptions cacheSampling() {
  geometry::SamplingOptions o;
  o.count = 64;
  o.seed = 7;
  return o;
}
geometry::AtlasOptions cacheAtlas() {
  geometry::AtlasOptions o;
  o.size = 64;
  o.method = geometry::AtlasMethod::Triangles;
  return o;
}

// A fresh cache folder holding FILE under `name` (the entry the loader will look for).
fs::path cacheWith(const fs::path& file, const std::string& name) {
  const fs::path dir = fs::temp_directory_path() /
                       fmt::format("translucent_check_input_{}", static_cast<long>(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  fs::copy_file(file, dir / name);
  return dir;
}

// The note names the cache entry (a temporary copy): it is shown with the corpus file's name.
std::string named(std::string note, const fs::path& entry, const fs::path& file) {
  for (size_t at; (at = note.find(entry.string())) != std::string::npos;)
    note.replace(at, entry.string().size(), file.string());
  return note;
}

int warnOrSilent(const std::vector<std::string>& warnings) {
  for (const auto& w : warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  return warnings.empty() ? 0 : 3;
}

int check(const std::string& family, const fs::path& file) {
  std::vector<std::string> warnings;
  if (family == "scene") {
    const scene::Scene s = scene::loadScene(file);
    // The files the scene names fail with their own names; the scene's is added, as a renderer
    // says which scene it was loading.
    try {
      scene::requireOutsideMesh(s, scene::loadSceneMesh(s));
      if (bssrdf::hasBssrdfExtension(s.model)) (void)bssrdf::loadBssrdf(s.model);
      for (const auto& l : s.lights)
        if (const auto* e = std::get_if<scene::EnvironmentLight>(&l.emitter)) {
          const auto map = lights::EnvironmentMap::load(e->file);
          if (map.clamped_negative > 0)
            warnings.push_back(fmt::format("environment map '{}': {} negative values read as 0",
                                           e->file.string(), map.clamped_negative));
        }
    } catch (const std::exception& e) {
      throw std::runtime_error(fmt::format("scene file '{}': {}", file.string(), e.what()));
    }
  } else if (family == "bssrdf") {
    (void)bssrdf::loadBssrdf(file);
  } else if (family == "image") {
    const auto map = lights::EnvironmentMap::load(file);
    if (map.clamped_negative > 0)
      warnings.push_back(fmt::format("environment map '{}': {} negative values read as 0",
                                     file.string(), map.clamped_negative));
  } else if (family == "pointcloud-cache") {
    const auto mesh = cacheMesh();
    const fs::path dir = cacheWith(file, geometry::cacheFileName(mesh, cacheSampling()));
    const auto r = geometry::loadOrSamplePointCloud(mesh, cacheSampling(), dir);
    fs::remove_all(dir);
    if (r.fromCache) return 0;  // used: the check fails
    warnings.push_back(r.note.empty() ? "regenerated without a note" : named(r.note, r.file, file));
  } else if (family == "atlas-cache") {
    const auto mesh = cacheMesh();
    const fs::path dir = cacheWith(file, geometry::atlasCacheFileName(mesh, cacheAtlas()));
    const auto r = geometry::loadOrBuildAtlas(mesh, cacheAtlas(), dir);
    fs::remove_all(dir);
    if (r.fromCache) return 0;
    warnings.push_back(r.note.empty() ? "rebuilt without a note" : named(r.note, r.file, file));
  } else if (family == "write-seeds") {
    fs::create_directories(file);
    const auto mesh = cacheMesh();
    geometry::writePointCloudPly(geometry::samplePointCloud(mesh, cacheSampling()),
                                 file / "valid_pointcloud.ply");
    // loadOrBuildAtlas writes the entry it builds; it is copied out under a plain name.
    const fs::path dir = fs::temp_directory_path() / "translucent_check_input_seeds";
    fs::remove_all(dir);
    const auto a = geometry::loadOrBuildAtlas(mesh, cacheAtlas(), dir);
    fs::copy_file(a.file, file / "valid_atlas.bin", fs::copy_options::overwrite_existing);
    fs::remove_all(dir);
    std::vector<float> rgb(16 * 8 * 3, 0.5f);
    analysis::writeExr((file / "valid.exr").string(), 16, 8, rgb, {}, {});
    rgb[5] = std::numeric_limits<float>::quiet_NaN();
    analysis::writeExr((file / "nan.exr").string(), 16, 8, rgb, {}, {});
    rgb[5] = 0.5f;
    rgb[40] = std::numeric_limits<float>::infinity();
    analysis::writeExr((file / "inf.exr").string(), 16, 8, rgb, {}, {});
    rgb[40] = -0.25f;
    analysis::writeExr((file / "negative.exr").string(), 16, 8, rgb, {}, {});
    std::vector<float> one(3, 1.0f);
    analysis::writeExr((file / "one_pixel.exr").string(), 1, 1, one, {}, {});
    // Voxel grids whose background neither absorbs nor scatters (σa = σs = 0 outside the 2³
    // voxels set): a photon that left them flew on forever before the check.
    openvdb::initialize();
    auto sa = openvdb::FloatGrid::create(0.0f);
    sa->setName("sigma_a");
    auto ss = openvdb::FloatGrid::create(0.0f);
    ss->setName("sigma_s");
    for (int z = 0; z < 2; ++z)
      for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 2; ++x) {
          sa->tree().setValue(openvdb::Coord(x, y, z), 0.1f);
          ss->tree().setValue(openvdb::Coord(x, y, z), 1.0f);
        }
    openvdb::io::File vdb((file / "zero_background.vdb").string());
    vdb.write({sa, ss});
    vdb.close();
    return 0;
  } else {
    std::fprintf(stderr, "unknown family '%s': expected scene, bssrdf, image, pointcloud-cache, "
                         "atlas-cache or write-seeds\n", family.c_str());
    return 2;
  }
  return warnOrSilent(warnings);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: translucent_check_input FAMILY FILE\n");
    return 2;
  }
  try {
    const int rc = check(argv[1], argv[2]);
    if (rc == 0) std::printf("accepted '%s' without an error or a warning\n", argv[2]);
    return rc;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
