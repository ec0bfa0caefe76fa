// SPDX-License-Identifier: GPL-3.0-or-later
// translucent atlas MESH [--size N] [--method authalic|lscm|triangles] [--mesh-uvs] --out a.png:
// builds (or reads from the cache) the surface atlas of texture-space importance sampling
// (geometry/atlas.h, seed 3.2.1), prints its statistics and draws its texels coloured by area
// distortion ln(A_T/A_S) (normalised), blue where texels are shrunk (undersampled, the artefacts
// of seed Fig. 4.7a), red where they are enlarged, chart outlines black, empty texels grey.
#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>

#include "safe_print.h"
#include "translucent/analysis/colormap.h"
#include "translucent/io/image_io.h"
#include "commands.h"
#include "output_guard.h"
#include "translucent/geometry/atlas.h"
#include "translucent/geometry/mesh.h"
#include "translucent/optics/medium.h"  // ParameterError
#include "progress.h"

namespace translucent::cli {
namespace {

struct AtlasArgs {
  std::string mesh, method = "lscm", out;
  uint32_t size = 1024, gutter = 0;
  double range = 1.0;
  bool meshUVs = false, json = false, noCache = false;
};

// The picture: one pixel per texel, v = 0 at the bottom, and the colour bar under it.
void drawAtlas(const std::string& path, const geometry::Atlas& atlas,
               const geometry::AtlasCoverage& cov, double range) {
  const int n = static_cast<int>(atlas.size);
  const std::vector<double> d = geometry::areaDistortion(atlas);
  std::vector<float> values(static_cast<size_t>(n) * static_cast<size_t>(n), NAN);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x)
      if (const int32_t o = cov.at(static_cast<uint32_t>(x), static_cast<uint32_t>(y)); o >= 0)
        values[static_cast<size_t>(n - 1 - y) * static_cast<size_t>(n) + static_cast<size_t>(x)] =
            static_cast<float>(d[static_cast<size_t>(o)]);
  std::vector<uint8_t> rgb =
      analysis::falseColor(values, n, n, analysis::ColorMap::Diverging, -range, range);
  // Chart outlines: owned texels next to a texel of another chart or none.
  const auto chartAt = [&](int x, int y) -> int64_t {
    if (x < 0 || y < 0 || x >= n || y >= n) return -1;
    const int32_t o = cov.at(static_cast<uint32_t>(x), static_cast<uint32_t>(y));
    return o < 0 ? -1 : int64_t{atlas.chart[static_cast<size_t>(o)]};
  };
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const int64_t c = chartAt(x, y);
      if (c < 0) continue;
      if (chartAt(x - 1, y) != c || chartAt(x + 1, y) != c || chartAt(x, y - 1) != c ||
          chartAt(x, y + 1) != c) {
        const size_t i = 3 * (static_cast<size_t>(n - 1 - y) * static_cast<size_t>(n) +
                              static_cast<size_t>(x));
        rgb[i] = rgb[i + 1] = rgb[i + 2] = 0;
      }
    }
  const int barHeight = 40;
  if (n >= 2 * 5) {
    const std::vector<uint8_t> bar =
        analysis::colorBar(n, barHeight, analysis::ColorMap::Diverging, -range, range);
    rgb.insert(rgb.end(), bar.begin(), bar.end());
    analysis::writePng8(path, n, n + barHeight, rgb);
  } else {
    analysis::writePng8(path, n, n, rgb);
  }
}

void run(const AtlasArgs& a) {
  geometry::AtlasOptions options;
  try {
    options.method = geometry::parseAtlasMethod(a.method);
  } catch (const geometry::AtlasError&) {
    throw ParameterError(
        fmt::format("--method {}: expected authalic, lscm or triangles", a.method));
  }
  if (a.size < 16 || a.size > 16384)
    throw ParameterError(fmt::format("--size {}: expected 16 .. 16384 texels per side", a.size));
  if (a.gutter > 64) throw ParameterError(fmt::format("--gutter {}: expected 0 .. 64", a.gutter));
  if (!(a.range > 0.0) || !std::isfinite(a.range))
    throw ParameterError(fmt::format("--range {}: expected a positive ln ratio", a.range));
  if (!a.out.empty() && std::filesystem::path(a.out).extension() != ".png")
    throw ParameterError(fmt::format("--out {}: expected a .png file", a.out));
  {
    OutputSet outputs;
    outputs.output("--out", a.out);
    outputs.input("the mesh", a.mesh);
    outputs.check();
  }
  if (!beginWork()) return;
  options.size = a.size;
  options.gutter = a.gutter;
  options.useMeshUVs = a.meshUVs;

  geometry::TriangleMesh mesh;
  try {
    mesh = geometry::loadMesh(a.mesh);
  } catch (const geometry::MeshError& e) {
    throw ParameterError(e.what());  // names the file
  }

  // A bar only once the build has taken a second (a cached atlas is read in milliseconds).
  const auto start = std::chrono::steady_clock::now();
  const auto seconds = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  std::optional<ProgressBar> bar;
  // SIGINT/SIGTERM: an atlas is whole or nothing (charts alone are no parameterisation), so a
  // signal abandons the build (an exception out of the progress callback; TBB passes it on) and
  // the command ends with nothing written and the status of the signal (progress.h).
  struct Stopped {};
  InterruptGuard guard;
  const geometry::AtlasProgress progress = [&](uint64_t done, uint64_t total) {
    if (InterruptGuard::interrupted()) throw Stopped{};
    const double s = seconds();
    if (s < 1.0) return;
    if (!bar) bar.emplace("atlas", "charts");
    bar->update(done, total, s);
  };
  geometry::CachedAtlas cached;
  try {
    if (a.noCache) {
      cached.atlas = geometry::buildAtlas(mesh, options, progress);
    } else {
      cached = geometry::loadOrBuildAtlas(mesh, options, progress);
    }
  } catch (const geometry::AtlasError& e) {
    if (bar) bar->end();
    throw ParameterError(fmt::format("mesh file '{}': {}", a.mesh, e.what()));
  } catch (const Stopped&) {
    if (bar) bar->end();
    printStderr("atlas: stopped by {} before the atlas was complete: nothing written\n",
                stopSignalName());
    return;
  }
  if (bar) bar->end();
  const double buildSeconds = seconds();
  const geometry::Atlas& atlas = cached.atlas;
  const geometry::AtlasCoverage cov = geometry::rasterizeCoverage(atlas);
  const geometry::AtlasStatistics st = geometry::atlasStatistics(atlas, cov);
  if (!cached.note.empty()) printStderr("atlas: {}\n", cached.note);
  if (!a.out.empty())
    writeOutput("--out", a.out,
                [&](const std::string& p) { drawAtlas(p, atlas, cov, a.range); });

  if (a.json) {
    nlohmann::json j{
        {"mesh", a.mesh}, {"method", geometry::toString(atlas.method)}, {"size", atlas.size},
        {"gutter", atlas.gutter}, {"mesh_uv_rejection", atlas.meshUVRejection},
        {"charts", st.charts}, {"folded_charts", atlas.foldedCharts},
        {"distorted_charts", atlas.distortedCharts}, {"triangles", st.triangles},
        {"triangles_below_one_texel", st.trianglesBelowOneTexel},
        {"distortion", {{"rms", st.distortionRms}, {"mean", st.distortionMean},
                        {"p05", st.distortionP05}, {"p50", st.distortionP50},
                        {"p95", st.distortionP95}, {"min", st.distortionMin},
                        {"max", st.distortionMax}}},
        {"utilisation", st.utilisation}, {"covered_fraction", st.coveredFraction},
        {"recovered_area_ratio", st.recoveredAreaRatio}, {"conflicts", cov.conflicts},
        {"conservative_texels", cov.conservative}, {"uncovered_triangles", cov.uncovered},
        {"seconds", buildSeconds}, {"from_cache", cached.fromCache},
        {"cache_file", cached.file.string()}};
    fmt::print("{}\n", j.dump(2));
    return;
  }
  fmt::print("atlas of {}: {}, {}² texels, gutter {}\n", a.mesh, geometry::toString(atlas.method),
             atlas.size, atlas.gutter);
  if (!atlas.meshUVRejection.empty())
    fmt::print("mesh UVs rejected: {}\n", atlas.meshUVRejection);
  fmt::print("charts            {} ({} re-mapped or split after folding, {} split for distortion)\n",
             st.charts, atlas.foldedCharts, atlas.distortedCharts);
  fmt::print("triangles         {} ({} below one texel, {} given a texel conservatively, {} "
             "without one)\n", st.triangles, st.trianglesBelowOneTexel, cov.conservative,
             cov.uncovered);
  fmt::print("area distortion   ln((A_T/ΣA_T)/(A_S/ΣA_S)), area-weighted: RMS {:.4f}, mean "
             "{:+.4f}, 5% {:+.3f}, median {:+.3f}, 95% {:+.3f}, min {:+.3f}, max {:+.3f}\n",
             st.distortionRms, st.distortionMean, st.distortionP05, st.distortionP50,
             st.distortionP95, st.distortionMin, st.distortionMax);
  fmt::print("utilisation       {:.1f}% of the atlas inside triangles, {:.1f}% of texels owned\n",
             100.0 * st.utilisation, 100.0 * st.coveredFraction);
  fmt::print("recovered area    Σ over texels of A_S/A_T = {:.5f} ΣA_S\n", st.recoveredAreaRatio);
  fmt::print("overlaps          {} texel centre(s) inside two triangles\n", cov.conflicts);
  fmt::print("time              {:.2f} s{}\n", buildSeconds,
             cached.fromCache ? fmt::format(" (read from {})", cached.file.string()) : "");
  if (!a.out.empty()) fmt::print("wrote {}\n", a.out);
}

}  // namespace

void addAtlasCommand(CLI::App& app) {
  auto args = std::make_shared<AtlasArgs>();
  auto* cmd = app.add_subcommand(
      "atlas",
      "Build the surface atlas of a mesh (texture-space importance sampling): disk charts mapped "
      "to the plane, scaled so texel area follows surface area, packed with gutters; print its "
      "statistics and draw it coloured by area distortion");
  cmd->add_option("mesh", args->mesh, "Mesh file (OBJ, PLY, OFF)")->required();
  cmd->add_option("--size", args->size, "Texels per side of the atlas")->capture_default_str();
  cmd->add_option("--method", args->method,
                  "authalic (charts, CGAL's discrete authalic map on a circle), lscm (charts, "
                  "least squares conformal maps, free boundary: less area distortion and better "
                  "utilisation on the bunny, armadillo and cow), or triangles (one chart per "
                  "triangle, no distortion, low utilisation)")
      ->capture_default_str();
  cmd->add_flag("--mesh-uvs", args->meshUVs,
                "Keep the mesh's own UVs when they are valid (positive area, no overlaps, inside "
                "[0,1]²); otherwise say why and build --method");
  cmd->add_option("--gutter", args->gutter,
                  "Texels between charts (0: 2 for charts, 1 for triangles)")
      ->capture_default_str();
  outputOption(cmd->add_option("--out", args->out, "PNG of the texels coloured by area distortion"));
  cmd->add_option("--range", args->range,
                  "Colour range of the distortion picture: ±RANGE in ln(A_T/A_S)")
      ->capture_default_str();
  cmd->add_flag("--json", args->json, "Print the statistics as JSON");
  cmd->add_flag("--no-cache", args->noCache,
                "Build even when the cache has the atlas, and do not store it");
  cmd->callback([args] { run(*args); });
}

}  // namespace translucent::cli
