// SPDX-License-Identifier: GPL-3.0-or-later
// The translucent-shadow-map technique on the GPU (techniques/tsm/tsm_technique.h) on whatever
// OpenGL 4.5 implementation the machine has (Mesa llvmpipe here), on the flat-slab set-up of
// tests/reference/flat_slab.h (a wide box, a short-range medium, an orthographic camera from
// above), where TSM's assumptions hold:
//   - lit from above along the normal, the exitance of the central pixels is the half-space
//     value Ft(η, 1) E ∫Rd dA (the profile table's total rd), within the pattern's truncation at
//     r_max (0.1%) and the region weights' quadrature;
//   - with point weights (Rd at the true distance times the sample's area) the GPU sum matches
//     the same sum on the CPU at the pattern's nominal radii (this checks the areas and the
//     projection), and its discretisation error against rd is reported;
//   - a thin plate lit from below shows the transmitted light on its top face: B = Ft E Σ W_k(t)
//     with t the thickness (true 3D distances), a fraction of the lit side's that falls with t;
//   - the map's resolution changes the slab's mean by little;
//   - the same under a distant point light (the perspective map's d² cos³α texel areas) and under
//     a directional light at 60° (weights on the tilted surface);
//   - a camera move (setCamera) keeps the light maps and gives a fresh preparation's image;
//   - unsupported lights fail with an error naming lights[i].
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include <glm/geometric.hpp>

#include "translucent/geometry/icosphere.h"
#include "translucent/geometry/mesh.h"
#include "translucent/optics/fresnel.h"
#include "reference/flat_slab.h"
#include "render_helpers.h"
#include "translucent/techniques/tsm/tsm_technique.h"

namespace translucent::tsm {
namespace {

using namespace translucent::pointcloud::testing;

class TsmGpu : public gpu::testing::GpuTest {};

// A box of the short-range medium whose top face z = 0 is lit (or, `fromBelow`, whose bottom
// face z = −thickness is lit) by a directional light along the normal, seen from above in
// 8 × 8 pixels over 1 × 1 units at its centre: every pixel is more than r_max (≤ 0.8) inside the
// top face's edges (1.8 − 0.5√2 > 1.09).
struct Slab {
  TempDir dir;
  scene::Scene scene;
  TsmTechnique technique;
  explicit Slab(double thickness = 0.5, bool fromBelow = false, int mapSize = 512,
                const std::string& weights = "region", double halfWidth = 1.8) {
    useTestCache();
    auto mesh = geometry::makeBox({-halfWidth, -halfWidth, -thickness}, {halfWidth, halfWidth, 0.0});
    // The top and bottom faces' own normals at their corners (smoothed ones would tilt the
    // interpolated normal over the big faces, and with it E's cos θ).
    for (const auto& p : mesh.positions) mesh.normals.emplace_back(0.0, 0.0, p.z == 0.0 ? 1.0 : -1.0);
    scene = testScene(writeObj(mesh, dir.path() / "slab.obj"), 8);
    scene.medium = reference::testing::shortRangeMedium();
    scene.camera = reference::testing::flatSlabCamera(1.0, 8);
    scene.lights[0].emitter = reference::DirectionalLight{{0.0, 0.0, fromBelow ? -1.0 : 1.0}, 1.0};
    technique.setParameter("map_size", mapSize);
    technique.setParameter("weights", weights);
    technique.prepare(scene, gpu::testing::context());
  }
  // Mean exitance of channel c over the covered pixels (all of them: asserted).
  double mean(const techniques::Frame& f, int c) const {
    const auto& b = f.layers.at("exitance");
    const size_t n = size_t(f.width) * size_t(f.height);
    double sum = 0.0;
    for (size_t p = 0; p < n; ++p) sum += double(b[3 * p + size_t(c)]);
    return sum / double(n);
  }
  double ft() const { return fresnelTransmittance(1.0, scene.medium.eta); }
};

// Σ over the pattern of W_k(h) for every sample (CPU, the tables the GPU reads).
double regionSum(const bssrdf::ProfileTable& table, double radius, double h) {
  double sum = 0.0;
  for (const auto& q : tsm21Pattern()) sum += regionWeight(table, radius, q.region, h);
  return sum;
}

TEST_F(TsmGpu, PatternAreasCoverTheDisc) {
  const auto pattern = tsm21Pattern();
  ASSERT_EQ(pattern.size(), 21u);
  double area = 0.0;
  for (const auto& q : pattern) {
    EXPECT_LE(glm::length(q.offset), 1.0f);
    area += double(q.area);
  }
  EXPECT_NEAR(area, M_PI, 1e-5);
}

// (a) Lit from above: every pixel B = Ft(η, 1) E ∫Rd dA. Tolerance 1.5%: the table stops at
// r_max (the last 0.1% of Rd in the widest channel is missing), the region weights' midpoint rule
// in ρ² over the linearly interpolated table (checked separately below to 0.5%), float sums of
// 21 terms; h = 0 and cos θ_g = 1 exactly on the flat top face, so texel snapping plays no part.
TEST_F(TsmGpu, LitSlabMatchesTheHalfSpaceExitance) {
  Slab s;
  const techniques::Frame f = s.technique.render({});
  const auto& tables = s.technique.profileTables();
  const auto& b = f.layers.at("exitance");
  ASSERT_EQ(b.size(), 8u * 8u * 3u);
  for (int c = 0; c < 3; ++c) {
    const double rd = tables[size_t(c)].rd;
    ASSERT_GT(rd, 0.0);
    const double cpu = regionSum(tables[size_t(c)], s.technique.filterRadius(), 0.0);
    EXPECT_NEAR(cpu, rd, 0.005 * rd) << "channel " << c << ": region weights' quadrature";
    const double want = s.ft() * rd;
    for (size_t p = 0; p < 64; ++p)
      EXPECT_NEAR(double(b[3 * p + size_t(c)]), want, 0.015 * want) << "channel " << c << " pixel " << p;
    std::printf("lit slab channel %d: B %.6g, Ft E rd %.6g (%+.3f%%)\n", c, s.mean(f, c), want,
                100.0 * (s.mean(f, c) / want - 1.0));
  }
  // The radiance is L = s Ft(η, 1) B / π, s > 0: positive where B is.
  for (float v : f.rgb) EXPECT_GT(v, 0.0f);
}

// (a) Lit obliquely (60° from the normal): E = E_l Ft(η, ½) ½ and still B = E ∫Rd dA (a half
// space), although every texel stands for twice its projected area: the region weights are taken
// on the tilted surface (a weight taken on the projection plane would double B). The pattern's
// disc maps to an ellipse of semi-axes R and 2R ≈ 1.6 on the surface, so the slab is widened to
// ±4. Tolerance 2%: the weights' quadrature in φ (16 steps) and ρ² (96), cos θ_g = ½ on the
// table's grid, h = 0.
TEST_F(TsmGpu, ObliquelyLitSlabStillMatchesTheHalfSpaceExitance) {
  Slab s(0.5, false, 512, "region", 4.0);
  const double c = 0.5;
  s.scene.lights[0].emitter = reference::DirectionalLight{{std::sqrt(1.0 - c * c), 0.0, c}, 1.0};
  s.technique.prepare(s.scene, gpu::testing::context());
  const techniques::Frame f = s.technique.render({});
  const auto& tables = s.technique.profileTables();
  for (int ch = 0; ch < 3; ++ch) {
    const double want = fresnelTransmittance(c, s.scene.medium.eta) * c * tables[size_t(ch)].rd;
    EXPECT_NEAR(s.mean(f, ch), want, 0.02 * want) << "channel " << ch;
    std::printf("oblique slab channel %d: B %.6g, E rd %.6g (%+.3f%%)\n", ch, s.mean(f, ch), want,
                100.0 * (s.mean(f, ch) / want - 1.0));
  }
}

// (a) A point light 50 units above the slab's centre, of intensity 2500 (E_l = 1 at the centre):
// the perspective map's texels stand for d² cos³α of solid angle (light_view_map.glsl), and the
// pattern's radius is set on x_o's plane, so B = Ft(η, cos θ) E_l(x_o) cos θ · rd again, with E_l
// and cos θ varying by < 0.05% over the pixels and the pattern (|x − centre| < 1.5 ≪ 50).
// Tolerance 1%.
TEST_F(TsmGpu, PointLitSlabMatchesTheHalfSpaceExitance) {
  Slab s;
  s.scene.lights[0].emitter = reference::PointLight{{0.0, 0.0, 50.0}, 2500.0};
  s.technique.prepare(s.scene, gpu::testing::context());
  const techniques::Frame f = s.technique.render({});
  const auto& tables = s.technique.profileTables();
  for (int ch = 0; ch < 3; ++ch) {
    const double want = s.ft() * tables[size_t(ch)].rd;
    EXPECT_NEAR(s.mean(f, ch), want, 0.01 * want) << "channel " << ch;
    std::printf("point-lit slab channel %d: B %.6g, Ft E rd %.6g (%+.3f%%)\n", ch, s.mean(f, ch), want,
                100.0 * (s.mean(f, ch) / want - 1.0));
  }
}

// (b) Point weights (Eq. 3.8 as written: Rd(|x_i − x_o|) A_i): the GPU sum equals the CPU sum at
// the nominal radii within 2% (at 2048² texels the samples snap by at most 1.3e-3 units, which
// moves Rd of the centre sample, near its peak z_r ≈ 0.02 .. 0.03, by < 1%); its error against
// rd is the 21-sample rule's, reported, not bounded (+40% .. +250% here: why region is the default).
TEST_F(TsmGpu, PointWeightsMatchThePatternSumOnTheCpu) {
  Slab s(0.5, false, 2048, "point");
  const techniques::Frame f = s.technique.render({});
  const auto& tables = s.technique.profileTables();
  const double R = s.technique.filterRadius();
  for (int c = 0; c < 3; ++c) {
    double cpu = 0.0;
    for (const auto& q : tsm21Pattern())
      cpu += tables[size_t(c)].lookup(double(glm::length(q.offset)) * R) * double(q.area) * R * R;
    const double want = s.ft() * cpu;
    EXPECT_NEAR(s.mean(f, c), want, 0.02 * want) << "channel " << c;
    std::printf("point weights channel %d: B %.6g, CPU pattern %.6g, half space %.6g (%+.1f%%)\n", c,
                s.mean(f, c), want, s.ft() * tables[size_t(c)].rd,
                100.0 * (cpu / tables[size_t(c)].rd - 1.0));
  }
}

// (b) A thin plate (thickness 0.06, about one diffusion length in the red) lit from below: the top
// face receives no light, yet B = Ft E Σ_i W_k(i)(t) > 0 through the plate (the samples' surface
// points lie on the bottom face, h = t). Tolerance 1.5% as above. The transmitted exitance must
// fall with the thickness: at 0.12 it is below that at 0.06 in every channel.
TEST_F(TsmGpu, BackLitThinPlateTransmitsThroughItsThickness) {
  const double t = 0.06;
  Slab s(t, true);
  const techniques::Frame f = s.technique.render({});
  const auto& tables = s.technique.profileTables();
  const double R = s.technique.filterRadius();
  Slab thicker(2.0 * t, true);
  const techniques::Frame f2 = thicker.technique.render({});
  for (int c = 0; c < 3; ++c) {
    const double want = s.ft() * regionSum(tables[size_t(c)], R, t);
    ASSERT_GT(want, 0.0) << "channel " << c << ": the plate is too thick for the test";
    EXPECT_NEAR(s.mean(f, c), want, 0.015 * want) << "channel " << c;
    EXPECT_LT(thicker.mean(f2, c), s.mean(f, c)) << "channel " << c;
    EXPECT_GT(thicker.mean(f2, c), 0.0) << "channel " << c;
    std::printf("back-lit plate channel %d: B %.6g (t %.2f), %.6g (t %.2f); lit side %.6g\n", c,
                s.mean(f, c), t, thicker.mean(f2, c), 2.0 * t, s.ft() * tables[size_t(c)].rd);
  }
}

// (b) The map's resolution: on the slab the region weights do not depend on where the samples
// snap (h = 0), so 128² and 1024² maps agree to 0.1% (float); what changes is only where E varies.
TEST_F(TsmGpu, MapResolutionLeavesTheSlabMeanUnchanged) {
  Slab coarse(0.5, false, 128), fine(0.5, false, 1024);
  const auto a = coarse.technique.render({}), b = fine.technique.render({});
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(coarse.mean(a, c), fine.mean(b, c), 1e-3 * fine.mean(b, c));
}

// Orbiting (issue 14 §6): setCamera keeps the light maps (rendered at the first frame only): the
// frames after a move, and a still frame, have no "light maps" pass. The image at the new camera
// equals a fresh technique's prepared there to 1e-6 of the peak exitance and radiance (the same
// maps and the same filter; measured 0), and differs from the image before the move.
TEST_F(TsmGpu, CameraMovesKeepTheLightMaps) {
  useTestCache();
  TempDir dir;
  scene::Scene s = testScene(writeObj(geometry::makeIcosphere(3, 1.0), dir.path() / "sphere.obj"), 32);
  s.lights[0].emitter = reference::DirectionalLight{glm::normalize(glm::dvec3(0.6, 0.3, 0.8)), 1.0};
  const reference::Camera camera = orbited(s.camera, 0.5);
  TsmTechnique moving;
  moving.setParameter("map_size", 256);
  moving.prepare(s, gpu::testing::context());
  const techniques::Frame before = moving.render({});
  EXPECT_TRUE(hasPass(before, "light maps"));
  ASSERT_TRUE(moving.setCamera(camera));
  const techniques::Frame a = moving.render({});
  const techniques::Frame still = moving.render({});
  for (const techniques::Frame* f : {&a, &still}) {
    EXPECT_FALSE(hasPass(*f, "light maps"));
    EXPECT_TRUE(hasPass(*f, "g-buffer"));
    EXPECT_TRUE(hasPass(*f, "filter"));
  }
  EXPECT_EQ(still.rgb, a.rgb);

  scene::Scene moved = s;
  moved.camera = camera;
  TsmTechnique fresh;
  fresh.setParameter("map_size", 256);
  fresh.prepare(moved, gpu::testing::context());
  const techniques::Frame b = fresh.render({});
  const double dB = relativeMaxDifference(a.layers.at("exitance"), b.layers.at("exitance"));
  const double dL = relativeMaxDifference(a.rgb, b.rgb);
  std::printf("after the move: exitance %.2g, radiance %.2g of the peak from a fresh preparation\n", dB, dL);
  EXPECT_LT(dB, 1e-6);
  EXPECT_LT(dL, 1e-6);
  EXPECT_GT(relativeMaxDifference(before.rgb, a.rgb), 0.05);  // the camera did move
}

// (c) Lights the technique cannot map fail at prepare() naming the light; parameters are checked.
TEST_F(TsmGpu, BadInputFailsNamingTheLightOrParameter) {
  auto expectError = [](auto&& f, const std::string& text) {
    try {
      f();
      FAIL() << "expected an error mentioning " << text;
    } catch (const std::exception& e) {
      EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
    }
  };
  TsmTechnique t;
  expectError([&] { t.setParameter("map_size", 16); }, "map_size");
  expectError([&] { t.setParameter("pattern", std::string("tsm17")); }, "pattern");
  expectError([&] { t.setParameter("filter_radius", 0.0); }, "filter_radius");
  expectError([&] { (void)t.render({}); }, "before prepare");

  useTestCache();
  TempDir dir;
  scene::Scene s = testScene(writeObj(geometry::makeBox({-1, -1, -1}, {1, 1, 1}), dir.path() / "box.obj"), 8);
  scene::Light env;
  env.emitter = scene::EnvironmentLight{};
  s.lights.push_back(env);
  expectError([&] { t.prepare(s, gpu::testing::context()); }, "lights[1]: an environment light");
  s.lights[1].emitter = reference::BeamLight{{0.0, 0.0, 10.0}, {0.0, 0.0, -1.0}, 0.5, 1.0};
  expectError([&] { t.prepare(s, gpu::testing::context()); }, "lights[1]: a beam light");
  s.lights[1].emitter = reference::PointLight{{0.0, 0.0, 0.5}, 1.0};
  expectError([&] { t.prepare(s, gpu::testing::context()); }, "lights[1]: the point light lies inside");
  // Directional and point lights are accepted.
  s.lights[1].emitter = reference::PointLight{{0.0, 0.0, 10.0}, 1.0};
  t.prepare(s, gpu::testing::context());
  const techniques::Frame f = t.render({});
  EXPECT_EQ(f.width, 8);
  EXPECT_FALSE(f.passes.empty());
}

}  // namespace
}  // namespace translucent::tsm
