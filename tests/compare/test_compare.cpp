// SPDX-License-Identifier: GPL-3.0-or-later
// `translucent compare`'s library (analysis/compare.h) on the cube scene at a few dozen pixels:
// metrics that must come out of known inputs (a reference scaled by 1.1 is +10% biased; two
// independent estimates of the same image agree within their noise), the reference cache (a
// second request hits and gives the same numbers, a changed input misses), the masks and the
// report folder's safety rules.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "translucent/compare/compare.h"
#include "translucent/compare/diagnosis.h"
#include "translucent/compare/report.h"
#include "translucent/geometry/icosphere.h"
#include "translucent/bssrdf/exit_radiance.h"
#include "translucent/bssrdf/registry.h"
#include "translucent/reference/model_reference.h"

namespace translucent::analysis {
namespace {
namespace fs = std::filesystem;

class TempDir {
 public:
  explicit TempDir(const std::string& tag)
      : path_(fs::temp_directory_path() /
              ("translucent_test_compare_" + tag + "_" + std::to_string(::getpid()))) {
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

scene::Scene cubeScene(int width = 32, int height = 24) {
  scene::Scene s = scene::loadScene(TRANSLUCENT_CUBE_SCENE);
  s.camera.width = width;
  s.camera.height = height;
  return s;
}

ReferenceRequest physical(uint64_t photons, uint64_t seed) {
  ReferenceRequest r;
  r.kind = ReferenceKind::Physical;
  r.count = photons;
  r.seed = seed;
  r.threads = 2;
  return r;
}

ReferenceRequest model(uint64_t samples, uint64_t seed) {
  ReferenceRequest r;
  r.kind = ReferenceKind::Model;
  r.count = samples;
  r.seed = seed;
  r.threads = 2;
  r.subpixels = 2;
  return r;
}

// Both noise-aware statistics of two estimates of the same expected image must be within
// 3.5 standard errors of zero (a two-sided 3.5σ band: a false failure once in ~2000 runs, and the
// seeds are fixed).
void expectAgreeWithinNoise(const Metrics& m, const std::string& what) {
  SCOPED_TRACE(what);
  ASSERT_GT(m.pixels, 100u);
  ASSERT_GT(m.noise_mse_stderr, 0.0);
  EXPECT_LT(std::abs(m.noise_mse), 3.5 * m.noise_mse_stderr)
      << "noise_mse " << m.noise_mse << " ± " << m.noise_mse_stderr;
  ASSERT_GT(m.bias_stderr, 0.0);
  EXPECT_LT(std::abs(m.bias), 3.5 * m.bias_stderr) << "bias " << m.bias << " ± " << m.bias_stderr;
  // The noise-aware error is far below the raw one: the difference is (almost) all noise.
  EXPECT_LT(m.rel_rmse, 0.5 * m.rel_rmse_raw);
}

TEST(CompareMetrics, AReferenceScaledBy1p1HasTenPercentBias) {
  const scene::Scene s = cubeScene();
  const geometry::TriangleMesh mesh = scene::loadSceneMesh(s);
  const Reference ref = computeReference(s, mesh, physical(20000, 1));
  const Masks masks = compareMasks(s, mesh, {});
  ASSERT_GT(masks.interiorPixels(), 50u);
  for (const CompareImage* img : {&ref.exitance, &ref.radiance}) {
    CompareImage t = img->scaled(1.1);
    t.se.clear();  // an exact "technique"
    const Metrics m = compareImages(t, *img, masks.interior);
    EXPECT_NEAR(m.bias, 0.1, 1e-6);
    EXPECT_NEAR(m.mean_test / m.mean_reference, 1.1, 1e-6);
    // The error is 10% of every pixel: between 10% of the mean (uniform image) and far more.
    EXPECT_GT(m.rel_rmse_raw, 0.1 - 1e-6);
    // A 10% error is far outside the noise of most pixels.
    EXPECT_GT(m.mean_abs_z, 1.0);
  }
  // The technique rows: exitance against exitance, the radiance under its convention.
  TechniqueImages t{"scaled", bssrdf::ExitConvention::Jensen, ref.radiance.scaled(1.1),
                    ref.exitance.scaled(1.1)};
  t.radiance.se.clear();
  t.exitance.se.clear();
  const std::vector<Reference> refs = {ref};
  const auto rows = techniqueMetrics(t, refs, s.medium.eta, masks);
  ASSERT_EQ(rows.size(), 3u);  // exitance, radiance, cone_radiance against the physical reference
  EXPECT_EQ(rows[0].quantity, "exitance");
  EXPECT_NEAR(rows[0].metrics.bias, 0.1, 1e-6);
  EXPECT_EQ(rows[1].quantity, "radiance");
  EXPECT_NEAR(rows[1].metrics.bias, 0.1, 1e-6);
  EXPECT_EQ(rows[2].quantity, "cone_radiance");
  EXPECT_EQ(rows[2].mask, "interior_cone");
}

TEST(CompareMetrics, NormalizedRadianceIsJensenOverTheDiffuseTransmittance) {
  const scene::Scene s = cubeScene(16, 12);
  const Reference ref = computeReference(s, scene::loadSceneMesh(s), physical(5000, 3));
  const CompareImage n = ref.radianceFor(bssrdf::ExitConvention::Normalized, s.medium.eta);
  const double scale = 1.0 / bssrdf::diffuseTransmittanceFromOutside(s.medium.eta);
  ASSERT_EQ(n.rgb.size(), ref.radiance.rgb.size());
  for (size_t i = 0; i < n.rgb.size(); ++i) {
    const double l = ref.radiance.rgb[i], se = ref.radiance.se[i];
    EXPECT_NEAR(n.rgb[i], l * scale, 1e-6 * l * scale + 1e-30);
    EXPECT_NEAR(n.se[i], se * scale, 1e-6 * se * scale + 1e-30);
  }
  EXPECT_EQ(ref.radianceFor(bssrdf::ExitConvention::Jensen, s.medium.eta).rgb, ref.radiance.rgb);
}

TEST(CompareMetrics, TwoPhysicalReferencesAgreeWithinTheirErrors) {
  const scene::Scene s = cubeScene();
  const geometry::TriangleMesh mesh = scene::loadSceneMesh(s);
  const Reference a = computeReference(s, mesh, physical(100000, 11));
  const Reference b = computeReference(s, mesh, physical(100000, 12));
  ASSERT_NE(a.exitance.rgb, b.exitance.rgb);  // independent
  const Masks masks = compareMasks(s, mesh, {});
  expectAgreeWithinNoise(compareImages(a.exitance, b.exitance, masks.interior), "exitance");
  expectAgreeWithinNoise(compareImages(a.radiance, b.radiance, masks.interior), "radiance");
  expectAgreeWithinNoise(compareImages(a.cone_radiance, b.cone_radiance, masks.cone), "cone");
}

// The model reference against itself with another seed. Its pixels share the surface samples, so
// their errors are correlated: the metrics' bias_stderr (independent pixels) understates the
// uncertainty of an image mean, and its standard errors include a conservative sub-pixel term
// (model_reference.h), so noise_mse tends below 0. What must hold: per pixel, z is no wider than a
// standard normal deviate; the noise-aware MSE is not above the noise (one-sided); and the bias is
// within 3.5 times the correlation-proof bound sd(Σ t) <= Σ se_t of the mean's standard error.
void expectModelAgreesWithItself(const CompareImage& t, const CompareImage& r,
                                 const std::vector<uint8_t>& mask, const std::string& what) {
  SCOPED_TRACE(what);
  const Metrics m = compareImages(t, r, mask);
  ASSERT_GT(m.pixels, 100u);
  EXPECT_LT(m.noise_mse, 3.5 * m.noise_mse_stderr) << m.noise_mse << " ± " << m.noise_mse_stderr;
  // The channels share the samples too, so the metrics' z (independent channels) is up to √3
  // too wide; per pixel, sd(Σc t) <= Σc se_t bounds it whatever the correlation.
  double st = 0.0, sr = 0.0, sum = 0.0, abs_z = 0.0;
  uint64_t n = 0, above3 = 0;
  for (size_t p = 0; p < mask.size(); ++p) {
    if (!mask[p]) continue;
    double dt = 0.0, pt = 0.0, pr = 0.0;
    for (size_t c = 0; c < 3; ++c) {
      const double se_t = t.se[3 * p + c], se_r = r.se[3 * p + c];
      dt += static_cast<double>(t.rgb[3 * p + c]) - static_cast<double>(r.rgb[3 * p + c]);
      pt += se_t;
      pr += se_r;
      sum += static_cast<double>(r.rgb[3 * p + c]);
    }
    st += pt;
    sr += pr;
    const double z = dt / std::sqrt(pt * pt + pr * pr);
    if (!std::isfinite(z)) continue;
    ++n;
    abs_z += std::abs(z);
    above3 += std::abs(z) > 3.0;
  }
  ASSERT_GT(n, 100u);
  EXPECT_LT(abs_z / n, 0.8) << "a standard normal deviate has mean |z| = 0.80";
  EXPECT_LT(static_cast<double>(above3) / n, 0.01) << above3 << " of " << n;
  const double bound = std::sqrt(st * st + sr * sr) / sum;
  EXPECT_LT(std::abs(m.bias), 3.5 * bound) << "bias " << m.bias << ", bound " << bound;
}

TEST(CompareMetrics, TheModelReferenceAsATechniqueHasNoErrorBeyondNoise) {
  const scene::Scene s = cubeScene();
  const geometry::TriangleMesh mesh = scene::loadSceneMesh(s);
  const Reference ref = computeReference(s, mesh, model(20000, 1));
  const Reference other = computeReference(s, mesh, model(20000, 2));
  ASSERT_NE(ref.exitance.rgb, other.exitance.rgb);  // independent
  const Masks masks = compareMasks(s, mesh, ref.coverage);
  ASSERT_GT(masks.interiorPixels(), 50u);
  expectModelAgreesWithItself(other.exitance, ref.exitance, masks.interior, "exitance");
  expectModelAgreesWithItself(other.radiance, ref.radiance, masks.interior, "radiance");
}

TEST(CompareMasks, InteriorExcludesSilhouettesAndConeExcludesGrazingViews) {
  const scene::Scene s = cubeScene(40, 30);
  const geometry::TriangleMesh mesh = scene::loadSceneMesh(s);
  const Masks m = compareMasks(s, mesh, {});
  const auto at = [&](const std::vector<uint8_t>& v, int x, int y) {
    return v[static_cast<size_t>(y) * 40 + static_cast<size_t>(x)];
  };
  EXPECT_EQ(at(m.interior, 20, 15), 1);  // the camera looks at the cube's centre
  EXPECT_EQ(at(m.interior, 0, 0), 0);    // background
  uint64_t both = 0;
  for (size_t i = 0; i < m.interior.size(); ++i) {
    EXPECT_LE(m.cone[i], m.interior[i]);
    both += m.cone[i];
  }
  EXPECT_GT(both, 0u);
  // A stricter cone (larger θc) masks at least as much; a grid of 1 ray per pixel keeps more
  // interior pixels than 4x4 (the silhouette pixels' centres may hit).
  const auto one = interiorMask(mesh, s.camera, 1, 0.0);
  uint64_t n1 = 0;
  for (uint8_t v : one) n1 += v;
  EXPECT_GE(n1, m.interiorPixels());
  const auto steep = interiorMask(mesh, s.camera, 4, std::sin(60.0 * 3.14159265358979 / 180.0));
  for (size_t i = 0; i < steep.size(); ++i) EXPECT_LE(steep[i], m.interior[i]);
}

// The error regions of a unit sphere seen along −z by an orthographic camera and lit from
// +x: the silhouette (|n·v| < 0.3) is the outer ring ρ > sqrt(1 − 0.3²) of the disc, 9% of it;
// the shadow boundary is the terminator x = 0, a band of 2 × 2 + 1 pixel columns across the
// disc; every chord along −n passes through the centre (thickness 2), so the sphere is all thin
// for a medium with ℓd > 2 and nowhere thin for ℓd < 2.
TEST(CompareDiagnosis, TheRegionsOfALitSphere) {
  const geometry::TriangleMesh mesh = geometry::makeIcosphere(6, 1.0);
  scene::Scene s;
  s.camera.width = 80;
  s.camera.height = 80;
  s.camera.position = {0.0, 0.0, 100.0};
  s.camera.look_at = {0.0, 0.0, 0.0};
  s.camera.up = {0.0, 1.0, 0.0};
  s.camera.projection = reference::Camera::Projection::Orthographic;
  s.camera.view_height = 2.2;  // the disc spans 80 / 1.1 ≈ 73 pixels
  s.lights.push_back({reference::DirectionalLight{{1.0, 0.0, 0.0}, 1.0}, {1.0, 1.0, 1.0}});
  s.medium.sigma_a = {0.01, 0.01, 0.01};  // ℓd = 1/sqrt(3 σa σt') ≈ 5.8 > 2
  s.medium.sigma_s = {1.0, 1.0, 1.0};
  const std::vector<uint8_t> interior = interiorMask(mesh, s.camera, 1, 0.0);
  uint64_t disc = 0;
  for (uint8_t v : interior) disc += v;
  ASSERT_GT(disc, 3500u);  // π (40/1.1)² ≈ 4154
  ErrorRegions r = errorRegions(s, mesh, interior);
  ASSERT_EQ(r.names.size(), 4u);
  auto count = [](const std::vector<uint8_t>& m) {
    uint64_t n = 0;
    for (uint8_t v : m) n += v;
    return n;
  };
  const double silhouette = static_cast<double>(count(r.masks[0])) / static_cast<double>(disc);
  EXPECT_NEAR(silhouette, 0.09, 0.02);  // pixel-centre sampling of a thin ring: ±2 points
  EXPECT_EQ(count(r.masks[1]), disc);   // all thin
  // Boundary: the columns within 2 pixels of the terminator x = 0 (pixel columns 38..41 hold
  // its neighbours), across the disc's diameter (~73 rows).
  const uint64_t boundary = count(r.masks[2]);
  EXPECT_GT(boundary, 4u * 65u);
  EXPECT_LT(boundary, 6u * 75u);
  for (int y = 0; y < 80; ++y)
    for (int x = 0; x < 80; ++x) {
      const size_t i = static_cast<size_t>(y) * 80 + static_cast<size_t>(x);
      if (r.masks[2][i]) {
        EXPECT_LE(std::abs(x + 0.5 - 40.0), 3.5) << x << "," << y;
      }
      EXPECT_EQ(r.masks[3][i], interior[i] && !r.masks[0][i] && !r.masks[1][i] && !r.masks[2][i]);
    }
  s.medium.sigma_a = {1.0, 1.0, 1.0};  // ℓd = 1/sqrt(3 · 1 · 2) ≈ 0.41 < 2
  r = errorRegions(s, mesh, interior);
  EXPECT_EQ(count(r.masks[1]), 0u);
}

// The split: with P = 1, M = 1.1 and T = M + 0.05 in one half and T = M = P in the other, the
// model's part of the first half is 10%, the technique's 5%, T against P 15%; noise given as
// standard errors is taken out (a difference that is all noise measures 0).
TEST(CompareDiagnosis, TheSplitAddsTheTechniquesAndTheModelsParts) {
  const int w = 20, h = 10;
  const size_t n = static_cast<size_t>(w) * h;
  CompareImage p{w, h, std::vector<float>(3 * n, 1.0f), {}};
  CompareImage m = p, t = p;
  ErrorRegions r;
  r.width = w;
  r.height = h;
  r.names = {"left", "right"};
  r.masks.assign(2, std::vector<uint8_t>(n, 0));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = static_cast<size_t>(y) * w + static_cast<size_t>(x);
      r.masks[x < w / 2 ? 0 : 1][i] = 1;
      if (x < w / 2)
        for (size_t c = 0; c < 3; ++c) {
          m.rgb[3 * i + c] = 1.1f;
          t.rgb[3 * i + c] = 1.15f;
        }
    }
  const std::vector<uint8_t> interior(n, 1);
  auto rows = splitError(t, m, p, r, interior);
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[0].region, "interior");
  EXPECT_EQ(rows[1].pixels, n / 2);
  EXPECT_NEAR(rows[1].model_part, 0.10, 1e-6);
  EXPECT_NEAR(rows[1].technique_part, 0.05, 1e-6);
  EXPECT_NEAR(rows[1].vs_physical, 0.15, 1e-6);
  EXPECT_NEAR(rows[2].vs_physical, 0.0, 1e-9);
  // The whole picture: RMS over both halves, sqrt(0.15² / 2).
  EXPECT_NEAR(rows[0].vs_physical, 0.15 / std::sqrt(2.0), 1e-6);
  // The physical reference's noise: an error of 0.05 with a standard error of 0.05 is all noise.
  p.se.assign(3 * n, 0.05f);
  rows = splitError(t, t, p, r, interior);
  EXPECT_NEAR(rows[2].vs_physical, 0.0, 1e-9);
  EXPECT_NEAR(rows[1].vs_physical, std::sqrt(0.15 * 0.15 - 0.05 * 0.05), 1e-5);
  EXPECT_NEAR(rows[1].technique_part, 0.0, 1e-9);
  // The map: black outside, orange where the technique's part dominates, blue the model's.
  const auto map = splitMap(t, m, CompareImage{w, h, std::vector<float>(3 * n, 1.0f), {}}, interior);
  ASSERT_EQ(map.size(), 3 * n);
  EXPECT_GT(map[2], map[0]);  // left: model 0.1 > technique 0.05: bluer
  EXPECT_EQ(map[3 * (n - 1)], 0);  // right: no error, black
  EXPECT_THROW(splitError(t, m, CompareImage{w, h + 1, std::vector<float>(3 * n + 3 * w, 1.0f), {}}, r, interior),
               ParameterError);
}

TEST(CompareCache, ASecondRequestHitsAndAChangedInputMisses) {
  TempDir dir("cache");
  const ReferenceCache cache(dir.path());
  scene::Scene s = cubeScene(16, 12);
  const geometry::TriangleMesh mesh = scene::loadSceneMesh(s);
  const ReferenceRequest req = physical(4000, 5);
  const Reference first = cachedReference(s, mesh, req, &cache);
  EXPECT_FALSE(first.from_cache);
  ASSERT_FALSE(first.cache_file.empty()) << first.cache_note;
  EXPECT_TRUE(fs::exists(first.cache_file));
  const Reference second = cachedReference(s, mesh, req, &cache);
  EXPECT_TRUE(second.from_cache);
  EXPECT_EQ(second.key, first.key);
  EXPECT_EQ(second.exitance.rgb, first.exitance.rgb);  // bit for bit (float EXR)
  EXPECT_EQ(second.exitance.se, first.exitance.se);
  EXPECT_EQ(second.radiance.rgb, first.radiance.rgb);
  EXPECT_EQ(second.cone_radiance.se, first.cone_radiance.se);
  EXPECT_EQ(second.count_done, first.count_done);

  // What the references do not depend on keeps the key: threads, technique and display settings.
  scene::Scene same = s;
  same.technique = "empirical";
  same.settings["kernel_size"] = 3.0;
  same.exposure = 2.0;
  ReferenceRequest threads = req;
  threads.threads = 1;
  EXPECT_EQ(referenceKey(same, threads), first.key);
  // Everything they depend on changes it.
  scene::Scene other = s;
  other.medium.sigma_a[0] *= 1.01;
  EXPECT_NE(referenceKey(other, req), first.key);
  other = s;
  other.camera.position.x += 0.01;
  EXPECT_NE(referenceKey(other, req), first.key);
  other = s;
  other.cone_angle = 3.0;
  EXPECT_NE(referenceKey(other, req), first.key);
  ReferenceRequest more = req;
  more.count = 8000;
  EXPECT_NE(referenceKey(s, more), first.key);
  more = req;
  more.seed = 6;
  EXPECT_NE(referenceKey(s, more), first.key);
  more = req;
  more.kind = ReferenceKind::Model;
  EXPECT_NE(referenceKey(s, more), first.key);
  more = req;
  more.device = "gpu";  // the GPU walk's own streams: another reference of the same scene
  EXPECT_NE(referenceKey(s, more), first.key);
  other = s;
  other.medium.sigma_a[0] *= 1.01;
  const Reference changed = cachedReference(other, mesh, req, &cache);
  EXPECT_FALSE(changed.from_cache);
  EXPECT_NE(changed.exitance.rgb, first.exitance.rgb);

  // A mesh file's bytes are part of the key even when its path stays.
  TempDir meshes("mesh");
  const fs::path copy = meshes.path() / "cube.obj";
  fs::copy_file(s.mesh_file, copy);
  scene::Scene moved = s;
  moved.mesh_file = copy;
  const std::string before = referenceKey(moved, req);
  std::ofstream(copy, std::ios::app) << "# an edit\n";
  EXPECT_NE(referenceKey(moved, req), before);
  moved.mesh_file = meshes.path() / "missing.obj";
  EXPECT_THROW((void)referenceKey(moved, req), ParameterError);
}

TEST(CompareCache, PartialReferencesAreNotStoredAndCorruptEntriesMiss) {
  TempDir dir("partial");
  const ReferenceCache cache(dir.path());
  const scene::Scene s = cubeScene(16, 12);
  const geometry::TriangleMesh mesh = scene::loadSceneMesh(s);
  // Stop at the first progress report (as Ctrl-C does): the tracer returns what it has, partial.
  const Reference part = cachedReference(s, mesh, physical(5000000, 7), &cache,
                                         [](const reference::TraceProgress&) { return false; });
  EXPECT_TRUE(part.partial);
  EXPECT_TRUE(part.cache_file.empty());
  EXPECT_NE(part.cache_note.find("partial"), std::string::npos) << part.cache_note;
  EXPECT_FALSE(fs::exists(cache.fileFor(ReferenceKind::Physical, part.key)));

  const ReferenceRequest req = physical(2000, 8);
  const Reference r = cachedReference(s, mesh, req, &cache);
  ASSERT_FALSE(r.cache_file.empty());
  // A byte changed in place (same size): the content hash stored in the .json catches it.
  std::string bytes;
  {
    std::ifstream in(r.cache_file, std::ios::binary);
    std::ostringstream ss;
    ss << in.rdbuf();
    bytes = ss.str();
  }
  ASSERT_GT(bytes.size(), 100u);
  bytes[bytes.size() - 50] = static_cast<char>(bytes[bytes.size() - 50] ^ 0x01);
  std::ofstream(r.cache_file, std::ios::binary | std::ios::trunc) << bytes;
  std::string note;
  EXPECT_FALSE(cache.load(ReferenceKind::Physical, r.key, 16, 12, &note));
  EXPECT_NE(note.find("the file was changed; recomputed"), std::string::npos) << note;
  // Truncated (another size): caught before the EXR is decoded.
  std::ofstream(r.cache_file, std::ios::trunc) << "not an EXR";
  EXPECT_FALSE(cache.load(ReferenceKind::Physical, r.key, 16, 12, &note));
  EXPECT_NE(note.find("is 10 bytes: expected"), std::string::npos) << note;
  const Reference again = cachedReference(s, mesh, req, &cache);
  EXPECT_FALSE(again.from_cache);
  EXPECT_EQ(again.exitance.rgb, r.exitance.rgb);  // same seed, same image
}

TEST(CompareReportFolder, RefusesForeignFilesAndReplacesPreviousReports) {
  TempDir dir("out");
  const fs::path out = dir.path() / "report";
  prepareReportDirectory(out, false, {}, "--out");  // created
  EXPECT_TRUE(fs::is_directory(out));
  std::ofstream(out / "notes.txt") << "mine";
  try {
    prepareReportDirectory(out, false, {}, "--out");
    FAIL() << "expected an error";
  } catch (const ParameterError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("--out"), std::string::npos) << what;
    EXPECT_NE(what.find("notes.txt"), std::string::npos) << what;
    EXPECT_NE(what.find("--force"), std::string::npos) << what;
  }
  EXPECT_NO_THROW(prepareReportDirectory(out, true, {}, "--out"));
  EXPECT_TRUE(fs::exists(out / "notes.txt"));  // --force writes beside, never deletes, it
  fs::remove(out / "notes.txt");

  // A previous report: its listed files go, and nothing else is touched.
  std::ofstream(out / "report.json")
      << R"({"generator": "translucent compare", "files": ["index.html", "a.png", "report.json"]})";
  std::ofstream(out / "index.html") << "<html></html>";
  std::ofstream(out / "a.png") << "png";
  fs::create_directories(out / "cache");
  prepareReportDirectory(out, false, out / "cache", "--out");
  EXPECT_FALSE(fs::exists(out / "index.html"));
  EXPECT_FALSE(fs::exists(out / "a.png"));
  EXPECT_FALSE(fs::exists(out / "report.json"));
  EXPECT_TRUE(fs::is_directory(out / "cache"));
  // A report.json of someone else is not a report of ours.
  std::ofstream(out / "report.json") << R"({"generator": "something else", "files": []})";
  EXPECT_THROW(prepareReportDirectory(out, false, out / "cache", "--out"), ParameterError);
  // A file in place of the folder.
  std::ofstream(dir.path() / "file") << "x";
  EXPECT_THROW(prepareReportDirectory(dir.path() / "file", true, {}, "--out"), ParameterError);
}

// The material is part of the key (compare.h, referenceMaterialDescription): another description
// (a heterogeneous material's, once scenes have one) never reuses this scene's references, the
// homogeneous one is the default, and the medium's fields change it.
TEST(CompareCache, TheMaterialDescriptionIsPartOfTheKey) {
  const scene::Scene s = cubeScene(16, 12);
  for (const ReferenceRequest& req : {physical(1000, 1), model(1000, 1)}) {
    const std::string homogeneous = referenceMaterialDescription(s);
    EXPECT_EQ(referenceKey(s, req), referenceKey(s, req, homogeneous));
    EXPECT_NE(referenceKey(s, req, R"({"kind":"volume","field":"layers"})"), referenceKey(s, req));
    EXPECT_NE(referenceKey(s, req, R"({"kind":"volume","field":"layers"})"),
              referenceKey(s, req, R"({"kind":"volume","field":"marble"})"));
    EXPECT_NE(referenceKeyText(s, req).find("\"material\""), std::string::npos);
    scene::Scene other = s;
    other.medium.g = 0.5;
    EXPECT_NE(referenceMaterialDescription(other), homogeneous);
    other = s;
    other.model = "better-dipole";
    EXPECT_NE(referenceMaterialDescription(other), homogeneous);
  }
}

// Which reference is physical per material kind, in the report's words.
TEST(CompareMaterial, ThePhysicalReferenceOfEachMaterialKind) {
  material::Material m;
  MaterialReferences r = materialReferences(m);
  EXPECT_EQ(r.kind, "homogeneous");
  EXPECT_TRUE(r.physical);
  m.kind = material::Material::Kind::Surface;
  r = materialReferences(m);
  EXPECT_EQ(r.kind, "surface");
  EXPECT_FALSE(r.physical);  // a 2D map has no volume
  EXPECT_NE(r.text.find("no physical reference"), std::string::npos) << r.text;
  EXPECT_NE(r.text.find("model reference"), std::string::npos) << r.text;
  m.kind = material::Material::Kind::Volume;
  r = materialReferences(m);
  EXPECT_EQ(r.kind, "volume");
  EXPECT_NE(r.text.find("path tracer"), std::string::npos) << r.text;
  // Today's scenes are homogeneous: both references.
  const scene::Scene s = cubeScene(8, 6);
  EXPECT_TRUE(materialReferences(scene::sceneMaterial(s, scene::loadSceneMesh(s))).physical);
}

// compare's model reference integrates scene::sceneMaterial: for a homogeneous scene exactly the
// homogeneous reference of its medium and model.
// The physical reference from the camera method (marble cube, η 1.3, a sun and a point light):
// its exitance, diffusion radiance Ft·B/π and true radiance agree with the light method's within
// their noise (the same expected images; the light method's cone radiance a 5° average), its
// cone angle is 0 (the masks need no margin at silhouettes), and the cache keeps it apart from
// the light method's.
TEST(CompareReferences, TheCameraMethodsReferenceAgreesWithTheLightMethods) {
  TempDir dir("camera");
  const ReferenceCache cache(dir.path());
  const scene::Scene s = cubeScene();
  const geometry::TriangleMesh mesh = scene::loadSceneMesh(s);
  const Reference light = computeReference(s, mesh, physical(200000, 31));
  ReferenceRequest req = physical(128, 32);
  req.method = "camera";
  const Reference camera = cachedReference(s, mesh, req, &cache);
  EXPECT_FALSE(camera.from_cache);
  ASSERT_TRUE(camera.cone_angle.has_value());
  EXPECT_EQ(*camera.cone_angle, 0.0);
  EXPECT_FALSE(light.cone_angle.has_value());  // the scene's (5 degrees)
  EXPECT_EQ(camera.count_done, 128u);
  EXPECT_NE(camera.key, light.key);
  const Masks masks = compareMasks(s, mesh, {}, camera.cone_angle);
  EXPECT_EQ(masks.cone, masks.interior);
  // The camera method's samples are stratified (Sobol positions per pixel), so its per-sample
  // standard errors overstate its error a little (camera_paths.h): the noise-aware MSE is then
  // below the noise, and only its upper side is tested; the bias is tested both ways.
  auto expectConsistent = [](const Metrics& m, const std::string& what) {
    SCOPED_TRACE(what);
    ASSERT_GT(m.pixels, 100u);
    EXPECT_LT(m.noise_mse, 3.5 * m.noise_mse_stderr) << m.noise_mse << " ± " << m.noise_mse_stderr;
    EXPECT_LT(std::abs(m.bias), 3.5 * m.bias_stderr) << m.bias << " ± " << m.bias_stderr;
  };
  expectConsistent(compareImages(camera.exitance, light.exitance, masks.interior), "exitance");
  expectConsistent(compareImages(camera.radiance, light.radiance, masks.interior),
                   "diffusion radiance");
  // The true radiance against the light method's cone average over 5 degrees (the same within
  // noise: the cone's average differs from the radiance at its axis by far less here).
  expectConsistent(compareImages(camera.cone_radiance, light.cone_radiance,
                                 compareMasks(s, mesh, {}).cone),
                   "true radiance");
  // From the cache: the method and the cone angle come back.
  const Reference again = cachedReference(s, mesh, req, &cache);
  EXPECT_TRUE(again.from_cache);
  EXPECT_EQ(again.request.method, "camera");
  ASSERT_TRUE(again.cone_angle.has_value());
  EXPECT_EQ(*again.cone_angle, 0.0);
  EXPECT_EQ(again.cone_radiance.rgb, camera.cone_radiance.rgb);
}

TEST(CompareReferences, TheModelReferenceOfAHomogeneousSceneIsTheMediumsReference) {
  const scene::Scene s = cubeScene(16, 12);
  const geometry::TriangleMesh mesh = scene::loadSceneMesh(s);
  const Reference r = computeReference(s, mesh, model(20000, 4));
  reference::ModelReferenceOptions o;
  o.samples = 20000;
  o.seed = 4;
  o.threads = 2;
  o.subpixels = model(20000, 4).subpixels;
  const auto direct = reference::renderModelReference(mesh, s.medium, bssrdf::model(s.model),
                                                      scene::referenceLights(s), s.camera, o);
  EXPECT_EQ(r.exitance.rgb, direct.exitance);
  EXPECT_EQ(r.exitance.se, direct.exitance_se);
  EXPECT_EQ(r.radiance.rgb, direct.radiance);
}

}  // namespace
}  // namespace translucent::analysis
