// SPDX-License-Identifier: GPL-3.0-or-later
// The empirical technique on the GPU (techniques/empirical/empirical_technique.h), against closed
// forms and the CPU reference of its per-pixel mathematics (techniques/empirical/shading.h).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

#include "translucent/geometry/icosphere.h"
#include "render_helpers.h"
#include "translucent/techniques/empirical/empirical_technique.h"
#include "translucent/techniques/empirical/shading.h"
#include "translucent/techniques/registry.h"

namespace translucent::empirical {
namespace {

using pointcloud::testing::join;
using pointcloud::testing::TempDir;
using pointcloud::testing::testScene;
using pointcloud::testing::useTestCache;
using pointcloud::testing::writeObj;

class EmpiricalGpu : public gpu::testing::GpuTest {};

double layerAt(const techniques::Frame& f, const std::string& layer, int x, int y) {
  return double(f.layers.at(layer)[(size_t(y) * size_t(f.width) + size_t(x)) * 3]);
}

std::unique_ptr<EmpiricalTechnique> technique() {
  useTestCache();
  auto t = std::make_unique<EmpiricalTechnique>();
  t->setParameter("ao", false);
  return t;
}

// Orthographic view down -z of a unit sphere: at the centre pixel the first solid span is the
// diameter. Pixel centres miss the axis by nothing (odd image size); the icosphere's faces lie
// at most R (1 - cos(θ/2)) inside the sphere, θ ≈ 1.1° the edge angle at 6 subdivisions.
TEST_F(EmpiricalGpu, SphereThicknessAtTheCentreIsTheDiameter) {
  TempDir dir;
  const auto obj = writeObj(geometry::makeIcosphere(6, 1.0), dir.path() / "sphere.obj");
  scene::Scene s = testScene(obj, 65);
  auto t = technique();
  t->setParameter("smoothing", false);
  t->prepare(s, gpu::testing::context());
  const techniques::Frame f = t->render({});
  const double D = t->sceneDiameter();
  EXPECT_NEAR(D, 2.0, 1e-6);
  const double facet = 2.0 * (1.0 - std::cos(0.5 * 1.1 * std::numbers::pi / 180.0));
  EXPECT_NEAR(layerAt(f, "thickness", 32, 32) * D, 2.0, facet + 1e-4);
  EXPECT_NEAR(layerAt(f, "back_depth", 32, 32) - layerAt(f, "front_depth", 32, 32), 2.0,
              facet + 1e-4);
  EXPECT_EQ(layerAt(f, "thickness", 0, 0), 0.0);  // background
}

// The same through a pinhole camera: the linearisation must invert a perspective matrix (the
// near and far planes differ from the orthographic ones). The centre pixel looks along the axis.
TEST_F(EmpiricalGpu, SphereThicknessThroughAPerspectiveCamera) {
  TempDir dir;
  const auto obj = writeObj(geometry::makeIcosphere(6, 1.0), dir.path() / "sphere.obj");
  scene::Scene s = testScene(obj, 65);
  s.camera.projection = reference::Camera::Projection::Pinhole;
  s.camera.fov = 40.0;
  auto t = technique();
  t->setParameter("smoothing", false);
  t->prepare(s, gpu::testing::context());
  const techniques::Frame f = t->render({});
  const double facet = 2.0 * (1.0 - std::cos(0.5 * 1.1 * std::numbers::pi / 180.0));
  // Front at distance 4, back at 6 from the camera at z = 5. A float depth buffer over
  // [near, far] ≈ [2.8, 6.1] resolves eye depth z to about z² / near · 2^-24 < 1e-6.
  EXPECT_NEAR(layerAt(f, "front_depth", 32, 32), 4.0, facet + 1e-5);
  EXPECT_NEAR(layerAt(f, "back_depth", 32, 32), 6.0, facet + 1e-5);
  EXPECT_NEAR(layerAt(f, "thickness", 32, 32) * t->sceneDiameter(), 2.0, facet + 2e-5);
}

// The smoothed thickness of the GPU equals the CPU reference (Eq. C.1) applied to the GPU's own
// unsmoothed layers, on the curved back of a sphere and at its silhouette.
TEST_F(EmpiricalGpu, SmoothedThicknessMatchesTheCpuReference) {
  TempDir dir;
  const auto obj = writeObj(geometry::makeIcosphere(5, 1.0), dir.path() / "sphere.obj");
  scene::Scene s = testScene(obj, 48);
  auto t = technique();
  t->setParameter("smoothing_threshold", 0.02);
  t->setParameter("kernel_size", 5);
  t->setParameter("sigma", 1.5);
  t->prepare(s, gpu::testing::context());
  const techniques::Frame f = t->render({});
  const double D = t->sceneDiameter();
  DepthImage back;
  back.width = f.width;
  back.height = f.height;
  back.background = -1.0f;
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x) {
      const double b = layerAt(f, "back_depth", x, y);
      back.depth.push_back(layerAt(f, "front_depth", x, y) > 0.0 ? float(b / D) : -1.0f);
    }
  SmoothingOptions o;
  o.kernelSize = 5;
  o.sigma = 1.5;
  o.threshold = 0.02;
  int covered = 0;
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x) {
      const double front = layerAt(f, "front_depth", x, y);
      if (front <= 0.0) continue;
      ++covered;
      const double expected = (double(smoothDepth(back, x, y, o)) * D - front) / D;
      ASSERT_NEAR(layerAt(f, "thickness", x, y), expected, 2e-5) << x << "," << y;
    }
  EXPECT_GT(covered, 1000);
}

// Two closed boxes one behind the other along the view (a U seen edge-on): depth peeling stops
// at the back of the first box, 0.4 thick, not at the back of the second (1.2 from the front).
// A back surface with a step larger than the threshold keeps its thickness exactly.
TEST_F(EmpiricalGpu, FirstSolidSpanAndNoBlurAcrossSteps) {
  TempDir dir;
  const geometry::TriangleMesh front = geometry::makeBox({-0.5, -0.5, 0.2}, {0.5, 0.5, 0.6});
  const geometry::TriangleMesh behind = geometry::makeBox({-0.5, -0.5, -0.6}, {0.5, 0.5, -0.1});
  scene::Scene s = testScene(writeObj(join(front, behind), dir.path() / "u.obj"), 40);
  auto t = technique();
  t->prepare(s, gpu::testing::context());
  techniques::Frame f = t->render({});
  const double D = t->sceneDiameter();
  for (int y = 12; y < 28; ++y)
    for (int x = 12; x < 28; ++x) ASSERT_NEAR(layerAt(f, "thickness", x, y) * D, 0.4, 1e-5);

  // Left half 0.5 thick, right half 0.8 thick: a step of 0.3, above the threshold of 0.1 D.
  const geometry::TriangleMesh a = geometry::makeBox({-0.5, -0.5, 0.0}, {0.0, 0.5, 0.5});
  const geometry::TriangleMesh b = geometry::makeBox({0.0, -0.5, -0.3}, {0.5, 0.5, 0.5});
  s = testScene(writeObj(join(a, b), dir.path() / "step.obj"), 40);
  t->prepare(s, gpu::testing::context());
  f = t->render({});
  const double D2 = t->sceneDiameter();
  ASSERT_GT(0.3 / D2, 0.1);
  int checked = 0;
  for (int y = 0; y < 40; ++y)
    for (int x = 0; x < 40; ++x) {
      if (layerAt(f, "front_depth", x, y) <= 0.0) continue;
      const double expected = (x < 20 ? 0.5 : 0.8);
      ASSERT_NEAR(layerAt(f, "thickness", x, y) * D2, expected, 1e-5) << x << "," << y;
      ++checked;
    }
  EXPECT_GT(checked, 300);  // an 18 × 18 pixel square
}

// A box with flat shading: every triangle has its own vertices, with the face normal (the shared
// corners of makeBox would get diagonal smooth normals).
geometry::TriangleMesh flatBox(const glm::dvec3& lower, const glm::dvec3& upper) {
  const geometry::TriangleMesh box = geometry::makeBox(lower, upper);
  geometry::TriangleMesh m;
  for (const glm::uvec3& t : box.triangles) {
    const glm::dvec3 n = glm::normalize(glm::cross(box.positions[t.y] - box.positions[t.x],
                                                   box.positions[t.z] - box.positions[t.x]));
    const auto base = static_cast<uint32_t>(m.positions.size());
    for (int k = 0; k < 3; ++k) {
      m.positions.push_back(box.positions[t[k]]);
      m.normals.push_back(n);
    }
    m.triangles.push_back({base, base + 1, base + 2});
  }
  return m;
}

// Each term of Eq. 3.6 alone, on the flat front face of a box (N = +z, seen along -z, lit from
// L = (0.6, 0, 0.8)), against the CPU reference with the GPU's thickness.
// A flat box (its top face at z = 0.2, facing +z) under one coloured directional light along L.
scene::Scene litBox(const TempDir& dir, const glm::dvec3& L) {
  scene::Scene s = testScene(
      writeObj(flatBox({-0.5, -0.5, -0.2}, {0.5, 0.5, 0.2}), dir.path() / "box.obj"), 32);
  s.lights[0].emitter = reference::DirectionalLight{L, 2.0};
  s.lights[0].color = {1.0, 0.5, 0.25};
  return s;
}

TEST_F(EmpiricalGpu, EachLightingTermInIsolation) {
  TempDir dir;
  const glm::dvec3 L = glm::normalize(glm::dvec3(0.6, 0.0, 0.8));
  const scene::Scene s = litBox(dir, L);
  const glm::dvec3 N(0, 0, 1), V(0, 0, 1);
  const glm::dvec3 H = glm::normalize(L + V);
  struct Case {
    const char* parameter;
    double value;
  };
  const Case cases[] = {{"ka", 0.3},
                        {"diffuse_contribution", 0.7},
                        {"specular_contribution", 0.9},
                        {"backlight", 1.2}};
  for (const Case& c : cases) {
    auto t = technique();
    for (const char* zero : {"ka", "diffuse_contribution", "specular_contribution", "backlight",
                             "diffuse_weight"})
      t->setParameter(zero, 0.0);
    t->setParameter("ks", 0.5);
    t->setParameter("shininess", 12.0);
    t->setParameter("thickness_exponent", 3.0);
    t->setParameter("ambient_light", 0.5);
    t->setParameter(c.parameter, c.value);
    if (std::string(c.parameter) == "backlight") t->setParameter("diffuse_weight", 0.2);
    t->prepare(s, gpu::testing::context());
    const techniques::Frame f = t->render({});
    ShadingParameters p;
    p.ka = p.wd = p.ws = p.wb = p.Kb = 0.0;
    p.ks = 0.5;
    p.shininess = 12.0;
    p.r = 3.0;
    p.Ia = glm::dvec3(0.5);
    p.Id = p.Is = 2.0 * glm::dvec3(1.0, 0.5, 0.25);
    const std::string name = c.parameter;
    if (name == "ka") p.ka = c.value;
    if (name == "diffuse_contribution") p.wd = c.value;
    if (name == "specular_contribution") p.ws = c.value;
    if (name == "backlight") {
      p.wb = c.value;
      p.Kb = 0.2;
    }
    const double thick = layerAt(f, "thickness", 16, 16);
    EXPECT_NEAR(thick * t->sceneDiameter(), 0.4, 1e-5);
    const glm::dvec3 expected = shade(p, 1.0, N, L, H, thick).total();
    EXPECT_GT(glm::length(expected), 0.01) << name;
    for (int ch = 0; ch < 3; ++ch)
      EXPECT_NEAR(double(f.rgb[(16 * 32 + 16) * 3 + size_t(ch)]), expected[ch], 1e-5 * (1.0 + expected[ch]))
          << name << " channel " << ch;
  }
}

// The seed's interface (appendix A, issue 14 §7): light ambient and specular colours apart from
// the lights' (diffuse) colour, and a direct-light-only switch that skips the back layer (no
// "back" pass) and the translucency term, against the CPU shading with I_a, I_s set so.
TEST_F(EmpiricalGpu, LightColoursAndDirectLightOnly) {
  TempDir dir;
  const glm::dvec3 L = glm::normalize(glm::dvec3(0.6, 0.0, 0.8));
  const scene::Scene s = litBox(dir, L);
  const glm::dvec3 N(0, 0, 1), V(0, 0, 1);
  const glm::dvec3 H = glm::normalize(L + V);
  for (const bool directOnly : {false, true}) {
    auto t = technique();
    t->setParameter("ka", 0.3);
    t->setParameter("diffuse_contribution", 0.7);
    t->setParameter("specular_contribution", 0.9);
    t->setParameter("ks", 0.5);
    t->setParameter("shininess", 12.0);
    t->setParameter("backlight", 1.2);
    t->setParameter("diffuse_weight", 0.2);
    t->setParameter("thickness_exponent", 3.0);
    t->setParameter("ambient_light", 0.5);
    t->setParameter("ambient_red", 0.2);
    t->setParameter("ambient_green", 1.0);
    t->setParameter("ambient_blue", 3.0);
    t->setParameter("specular_red", 0.0);
    t->setParameter("specular_green", 1.0);
    t->setParameter("specular_blue", 2.0);
    t->setParameter("direct_only", directOnly);
    t->prepare(s, gpu::testing::context());
    const techniques::Frame f = t->render({});
    bool back = false;
    for (const auto& pass : f.passes) back = back || pass.name == "back";
    EXPECT_EQ(back, !directOnly);
    ShadingParameters p;
    p.ka = 0.3;
    p.wd = 0.7;
    p.ws = 0.9;
    p.ks = 0.5;
    p.shininess = 12.0;
    p.wb = directOnly ? 0.0 : 1.2;
    p.Kb = 0.2;
    p.r = 3.0;
    p.Ia = 0.5 * glm::dvec3(0.2, 1.0, 3.0);
    p.Id = 2.0 * glm::dvec3(1.0, 0.5, 0.25);
    p.Is = p.Id * glm::dvec3(0.0, 1.0, 2.0);
    const double thick = 0.4 / t->sceneDiameter();
    const glm::dvec3 expected = shade(p, 1.0, N, L, H, thick).total();
    for (int ch = 0; ch < 3; ++ch)
      EXPECT_NEAR(double(f.rgb[(16 * 32 + 16) * 3 + size_t(ch)]), expected[ch], 1e-5 * (1.0 + expected[ch]))
          << "direct only " << directOnly << " channel " << ch;
  }
}

// A point light straight above the centre of a flat face: diffuse = w_d K_d I / d².
TEST_F(EmpiricalGpu, PointLightFallsOffWithTheSquaredDistance) {
  TempDir dir;
  scene::Scene s = testScene(
      writeObj(flatBox({-0.5, -0.5, -0.2}, {0.5, 0.5, 0.2}), dir.path() / "box.obj"), 33);
  auto t = technique();
  for (const char* zero : {"ka", "specular_contribution", "backlight", "diffuse_weight"})
    t->setParameter(zero, 0.0);
  t->setParameter("diffuse_contribution", 1.0);
  for (double d : {1.0, 2.0}) {
    s.lights[0].emitter = reference::PointLight{{0.0, 0.0, 0.2 + d}, 3.0};
    t->prepare(s, gpu::testing::context());
    const techniques::Frame f = t->render({});
    const ShadingParameters p;
    for (int ch = 0; ch < 3; ++ch)
      EXPECT_NEAR(double(f.rgb[(16 * 33 + 16) * 3 + size_t(ch)]), p.Kd[ch] * 3.0 / (d * d), 1e-5)
          << "distance " << d << " channel " << ch;
  }
}

// Gascons 2011, A.1.1: a point light as a spotlight aimed at the mesh's centre (OpenGL's
// GL_SPOT_CUTOFF and GL_SPOT_EXPONENT). The box's top face (z = 0.2) under a light 1 above it:
// at distance r from the axis, cos α = 1/sqrt(1 + r²) = n·L, so the diffuse term is
// Kd I cos α · cos^e α / (1 + r²) inside the cone and 0 beyond it.
TEST_F(EmpiricalGpu, SpotlightCutsOffAndFallsOffAsOpenGl) {
  TempDir dir;
  const int n = 33;
  scene::Scene s = testScene(
      writeObj(flatBox({-0.5, -0.5, -0.2}, {0.5, 0.5, 0.2}), dir.path() / "box.obj"), n);
  s.lights[0].emitter = reference::PointLight{{0.0, 0.0, 1.2}, 3.0};
  auto t = technique();
  for (const char* zero : {"ka", "specular_contribution", "backlight", "diffuse_weight"})
    t->setParameter(zero, 0.0);
  t->setParameter("diffuse_contribution", 1.0);
  t->setParameter("spot_cutoff", 20.0);
  t->setParameter("spot_exponent", 4.0);
  t->prepare(s, gpu::testing::context());
  const techniques::Frame f = t->render({});
  const ShadingParameters p;
  const double cosCut = std::cos(20.0 * std::numbers::pi / 180.0);
  int inside = 0, outside = 0;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const double u = ((x + 0.5) / n - 0.5) * 2.2, v = ((y + 0.5) / n - 0.5) * 2.2;
      if (std::abs(u) > 0.45 || std::abs(v) > 0.45) continue;  // the top face only
      const double r2 = u * u + v * v, c = 1.0 / std::sqrt(1.0 + r2);
      if (std::abs(c - cosCut) < 0.01) continue;  // the cutoff's edge falls between pixels
      const double expected = c >= cosCut ? p.Kd[1] * 3.0 * c * std::pow(c, 4.0) / (1.0 + r2) : 0.0;
      (c >= cosCut ? inside : outside) += 1;
      EXPECT_NEAR(double(f.rgb[(size_t(y) * n + size_t(x)) * 3 + 1]), expected, 1e-5 + 1e-4 * expected)
          << "pixel " << x << ", " << y;
    }
  EXPECT_GT(inside, 20);
  EXPECT_GT(outside, 20);
}

// The local viewer (Gascons 2011, A.1.1): with it off, the half vector uses the view axis, so a
// flat face under a directional light has one specular value through a pinhole camera (the
// closed form Ws Ks I (n·H)^shininess); with it on, H follows each point's direction to the
// camera and the highlight varies over the face (equal to the closed form where the pixel looks
// along the axis).
TEST_F(EmpiricalGpu, LocalViewerOffUsesTheViewAxis) {
  TempDir dir;
  const int n = 33;
  scene::Scene s = testScene(
      writeObj(flatBox({-0.5, -0.5, -0.2}, {0.5, 0.5, 0.2}), dir.path() / "box.obj"), n);
  s.camera.projection = reference::Camera::Projection::Pinhole;
  s.camera.position = {0.0, 0.0, 3.0};
  s.camera.fov = 40.0;
  const glm::dvec3 L = glm::normalize(glm::dvec3(0.4, 0.0, 1.0));
  s.lights[0].emitter = reference::DirectionalLight{L, 2.0};
  auto t = technique();
  for (const char* zero : {"ka", "diffuse_contribution", "backlight", "diffuse_weight"})
    t->setParameter(zero, 0.0);
  t->setParameter("specular_contribution", 1.0);
  t->setParameter("shininess", 20.0);
  t->setParameter("ks", 0.5);
  const glm::dvec3 H = glm::normalize(L + glm::dvec3(0.0, 0.0, 1.0));
  const double expected = 1.0 * 0.5 * 2.0 * std::pow(H.z, 20.0);  // Ws Ks I (n·H)^n, white
  for (bool local : {false, true}) {
    t->setParameter("local_viewer", local);
    t->prepare(s, gpu::testing::context());
    const techniques::Frame f = t->render({});
    double lo = 1e300, hi = 0.0;
    for (int y = n / 2 - 5; y <= n / 2 + 5; ++y)
      for (int x = n / 2 - 5; x <= n / 2 + 5; ++x) {
        const double g = double(f.rgb[(size_t(y) * n + size_t(x)) * 3 + 1]);
        lo = std::min(lo, g);
        hi = std::max(hi, g);
        if (!local) {
          EXPECT_NEAR(g, expected, 1e-4 * expected) << "pixel " << x << ", " << y;
        }
      }
    const double centre = double(f.rgb[(size_t(n / 2) * n + size_t(n / 2)) * 3 + 1]);
    EXPECT_NEAR(centre, expected, 1e-4 * expected) << (local ? "local" : "infinite");
    if (local) {
      EXPECT_GT(hi - lo, 0.05 * expected) << "the local viewer's highlight should vary";
    }
  }
}

TEST_F(EmpiricalGpu, RunsThroughTheRegistryWithPresetsAndAo) {
  TempDir dir;
  useTestCache();
  auto t = techniques::make("empirical");
  EXPECT_EQ(t->name(), "empirical");
  t->setParameter("preset", std::string("survey6"));
  EXPECT_EQ(std::get<double>(t->parameter("backlight")), 1.6);
  EXPECT_EQ(std::get<double>(t->parameter("thickness_exponent")), 25.0);
  t->setParameter("ao_rays", 16);
  scene::Scene s = testScene(
      writeObj(geometry::makeIcosphere(2, 1.0), dir.path() / "s.obj"), 24);
  t->prepare(s, gpu::testing::context());
  const techniques::Frame f = t->render({});
  EXPECT_EQ(f.width, 24);
  ASSERT_EQ(f.rgb.size(), 24u * 24u * 3u);
  // A convex mesh: every vertex sees the whole hemisphere.
  EXPECT_FLOAT_EQ(f.layers.at("ao")[(12 * 24 + 12) * 3], 1.0f);
  EXPECT_GT(f.rgb[(12 * 24 + 12) * 3], 0.0f);
  ASSERT_EQ(f.passes.size(), 3u);
  EXPECT_THROW(t->setParameter("kernel_size", 40), ParameterError);
  s.lights[0].emitter = reference::BeamLight{};
  EXPECT_THROW(t->prepare(s, gpu::testing::context()), ParameterError);
}

// Random lighting moves the light each frame along randomLightDirection(seed, frame): frame k
// equals a still render with the light set to that direction (1e-6, float shading), and two
// consecutive frames differ.
TEST_F(EmpiricalGpu, RandomLightingMovesTheLightEachFrame) {
  TempDir dir;
  scene::Scene s = testScene(
      writeObj(geometry::makeIcosphere(2, 1.0), dir.path() / "s.obj"), 24);
  auto moving = technique();
  moving->setParameter("random_lighting", true);
  moving->setParameter("random_seed", 11);
  moving->prepare(s, gpu::testing::context());
  std::vector<techniques::Frame> frames;
  for (int k = 0; k < 3; ++k) frames.push_back(moving->render({}));
  ASSERT_FALSE(frames[2].notes.empty());
  EXPECT_NE(frames[2].notes.back().find("frame 2"), std::string::npos) << frames[2].notes.back();
  double change = 0.0;
  for (size_t i = 0; i < frames[1].rgb.size(); ++i)
    change = std::max(change, double(std::abs(frames[1].rgb[i] - frames[2].rgb[i])));
  EXPECT_GT(change, 1e-3);

  auto still = technique();
  for (int k : {0, 2}) {
    s.lights[0].emitter = reference::DirectionalLight{randomLightDirection(11, k), 1.0};
    still->prepare(s, gpu::testing::context());
    const techniques::Frame expected = still->render({});
    ASSERT_EQ(expected.rgb.size(), frames[size_t(k)].rgb.size());
    for (size_t i = 0; i < expected.rgb.size(); ++i)
      ASSERT_NEAR(frames[size_t(k)].rgb[i], expected.rgb[i], 1e-6) << "frame " << k << " value " << i;
  }
}

}  // namespace
}  // namespace translucent::empirical
