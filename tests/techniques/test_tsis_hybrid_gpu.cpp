// SPDX-License-Identifier: GPL-3.0-or-later
// The hybrid local/global method of the tsis technique (seed 3.3; techniques/tsis/hybrid_split.h,
// issue #11 §3 and §5):
//   - the split: W_l in [0, 1], ½ at R_p from both sides, W_l + W_g = 1 on the tables, and R_p of
//     the seed's skimmilk red channel against the value its Fig. 3.4 prints;
//   - the LTSM pattern integrates the local profile exactly on a plane;
//   - B_l + B_g = B for the same TSIS samples;
//   - on a flat slab lit along the normal, each term and their sum agree with the half-space
//     values Ft(η, 1) E ∫ R W dA of the profile table;
//   - on the local-dominated setting of seed Fig. 4.8 (skin1, a 30 mm head), the hybrid at
//     900 + 401 samples has a lower error against the model reference than TSIS at 1301;
//   - a light the local term cannot take fails naming it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include <glm/geometric.hpp>

#include "translucent/bssrdf/profile.h"
#include "translucent/bssrdf/registry.h"
#include "translucent/geometry/mesh.h"
#include "translucent/optics/fresnel.h"
#include "reference/flat_slab.h"
#include "translucent/reference/model_reference.h"
#include "translucent/reference/transport.h"
#include "render_helpers.h"
#include "translucent/scene/scene.h"
#include "translucent/techniques/tsis/hybrid_split.h"
#include "translucent/techniques/tsis/tsis_technique.h"

namespace translucent::tsis {
namespace {

using namespace translucent::pointcloud::testing;
constexpr double kPi = std::numbers::pi;

class TsisHybrid : public gpu::testing::GpuTest {};

// ∫ 2πr R(r) W(r) dr over the table (midpoint rule, the table's interpolation).
double tableIntegral(const bssrdf::ProfileTable& t, double rp, double k, int part /* 0 full, 1 local, 2 global */) {
  const int n = 200000;
  const double h = t.r_max / n;
  double sum = 0.0;
  for (int i = 0; i < n; ++i) {
    const double r = (i + 0.5) * h;
    const double wl = localWeight(r, rp, k);
    sum += 2.0 * kPi * r * t.lookup(r) * (part == 0 ? 1.0 : part == 1 ? wl : 1.0 - wl);
  }
  return sum * h;
}

std::array<bssrdf::ProfileTable, 3> dipoleTables(const Medium& m, size_t n = 4096) {
  std::array<bssrdf::ProfileTable, 3> out;
  const bssrdf::RgbProfiles prof = bssrdf::profiles(bssrdf::model("dipole"), m);
  double rMax = 0.0;
  for (const auto& p : prof) rMax = std::max(rMax, p->radiusForFraction(0.999));
  for (size_t c = 0; c < 3; ++c) {
    out[c].r_max = rMax;
    out[c].R.resize(n);
    for (size_t i = 0; i < n; ++i) out[c].R[i] = float(prof[c]->R(std::max(rMax * double(i) / double(n - 1), 0.25 * rMax / double(n - 1))));
  }
  return out;
}

TEST(HybridSplit, WeightsAreAPartitionOfUnityContinuousAtRp) {
  for (const double k : {0.5, 1.5, 6.0})
    for (const double rp : {0.0, 0.3, 2.4}) {
      EXPECT_NEAR(localWeight(rp, rp, k), 0.5, 1e-12);
      EXPECT_NEAR(localWeight(rp + 1e-9, rp, k), 0.5, 1e-8);
      double prev = 1.0;
      for (double r = 0.0; r < rp + 10.0; r += 0.01) {
        const double w = localWeight(r, rp, k);
        EXPECT_GE(w, 0.0);
        EXPECT_LE(w, 1.0);
        EXPECT_LE(w, prev + 1e-12) << "W_l falls monotonically";
        prev = w;
        EXPECT_NEAR(w + globalWeight(r, rp, k), 1.0, 1e-15);
      }
    }
  // The weighted tables add up to the table (float rounding).
  const auto tables = dipoleTables(Medium::fromReduced({0.0024, 0.0090, 0.0200}, {0.70, 1.22, 1.90}, 0.0, 1.3, 1.0));
  const HybridSplit split = makeHybridSplit(tables, 1.5, 0.1, 1.0);
  const auto l = weightedProfile(tables, split, true), g = weightedProfile(tables, split, false);
  for (size_t i = 0; i < l.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      const double r = tables[size_t(c)].R[i];
      EXPECT_NEAR(double(l[i][c]) + double(g[i][c]), r, 2e-7 * r + 1e-30);
    }
}

TEST(HybridSplit, SkimmilkSplitRadiusMatchesTheSeed) {
  // Seed Fig. 3.4/3.5: skimmilk's red channel (σa = 0.0024, σs' = 0.70 /mm, η = 1.3), bound 0.1:
  // R_p = 2.4141 mm. Our dipole gives 2.374 (−1.7%): the seed's dipole constants are not
  // printed (A, z_v); a 3% band holds both and fails for any other reading of the bound (e.g.
  // without the 2π, R_p = 1.6; per cm, 0.4).
  const auto tables = dipoleTables(Medium::fromReduced({0.0024, 0.0024, 0.0024}, {0.70, 0.70, 0.70}, 0.0, 1.3, 1.0), 16384);
  const HybridSplit split = makeHybridSplit(tables, 1.5, 0.1, 1.0);
  EXPECT_NEAR(split.rp[0], 2.4141, 0.03 * 2.4141);
  std::printf("skimmilk red R_p = %.4f mm (seed: 2.4141)\n", split.rp[0]);
  // Units: the same medium at 10 mm per scene unit has R_p ten times smaller in scene units.
  Medium m10 = Medium::fromReduced({0.0024, 0.0024, 0.0024}, {0.70, 0.70, 0.70}, 0.0, 1.3, 10.0);
  const HybridSplit s10 = makeHybridSplit(dipoleTables(m10, 16384), 1.5, 0.1, 10.0);
  EXPECT_NEAR(s10.rp[0] * 10.0, split.rp[0], 2e-3 * split.rp[0]);
  EXPECT_NEAR(s10.k, 15.0, 1e-12);
}

TEST(HybridSplit, PatternIntegratesTheLocalProfileOnAPlane) {
  const auto tables = dipoleTables(Medium::fromReduced({0.032, 0.17, 0.48}, {0.74, 0.88, 1.01}, 0.0, 1.3, 1.0));
  const HybridSplit split = makeHybridSplit(tables, 1.5, 0.1, 1.0);
  for (const auto& [circles, per] : {std::pair{4, 4}, std::pair{20, 20}}) {
    const auto pat = localPattern(tables, split, circles, per);
    ASSERT_EQ(pat.size(), size_t(2 * (circles * per + 1)));
    for (size_t c = 0; c < 3; ++c) {
      double sum = 0.0;
      for (size_t k = 0; k < pat.size() / 2; ++k) {
        const double rho = pat[2 * k].z, x = pat[2 * k].x, y = pat[2 * k].y;
        EXPECT_NEAR(std::hypot(x, y), rho, 1e-5 * (rho + 1e-3));
        sum += double(pat[2 * k + 1][int(c)]) * tables[c].lookup(rho) * localWeight(rho, split.rp[c], split.k);
      }
      const double want = 0.999 * tableIntegral(tables[c], split.rp[c], split.k, 1);
      // Exact by construction up to the rings' 64-step midpoint rule against the fine one here
      // and the pattern's 0.999 cut of the averaged density (not of each channel): 1%.
      EXPECT_NEAR(sum, want, 0.01 * want) << circles << "x" << per << " channel " << c;
    }
  }
}

// A flat slab (tests/reference/flat_slab.h) lit along the normal, seen from above.
struct Slab {
  TempDir dir;
  scene::Scene scene;
  std::unique_ptr<TsisTechnique> technique = std::make_unique<TsisTechnique>();
  Slab() {
    useTestCache();
    scene = testScene(writeObj(reference::testing::flatSlab(), dir.path() / "slab.obj"), 8);
    scene.medium = reference::testing::shortRangeMedium();
    scene.camera.view_height = 1.2;
    technique->setParameter("atlas_size", 256);
    technique->setParameter("shadow_map_size", 512);
    technique->setParameter("ltsm_map_size", 1024);
  }
  std::vector<float> exitance(const std::string& mode, const std::string& term, bool converge) {
    technique->setParameter("mode", mode);
    technique->setParameter("term", term);
    technique->prepare(scene, gpu::testing::context());
    techniques::FrameRequest r;
    r.converge = converge;
    return technique->render(r).layers.at("exitance");
  }
};

TEST_F(TsisHybrid, LocalPlusGlobalIsTheWholeForTheSameSamples) {
  Slab slab;
  slab.technique->setParameter("samples", 256);
  // One accumulated frame: each render restarts at frame 0 (a parameter changed), so all three
  // use the same stratified samples.
  slab.technique->setParameter("accumulate_samples", 256);
  const auto full = slab.exitance("global", "full", true);
  const auto local = slab.exitance("global", "local", true);
  const auto global = slab.exitance("global", "global", true);
  double lsum = 0.0, gsum = 0.0;
  for (size_t i = 0; i < full.size(); ++i) {
    const double l = local[i], g = global[i], f = full[i];
    EXPECT_NEAR(l + g, f, 1e-5 * f + 1e-9) << "value " << i;
    lsum += l;
    gsum += g;
  }
  EXPECT_GT(lsum, 0.05 * gsum);  // both terms carry energy
  EXPECT_GT(gsum, 0.05 * lsum);
}

TEST_F(TsisHybrid, FlatSlabTermsMatchTheHalfSpace) {
  Slab slab;
  slab.technique->setParameter("samples", 1024);
  slab.technique->setParameter("accumulate_samples", 1 << 18);
  const auto& m = slab.scene.medium;
  const double ft = fresnelTransmittance(1.0, m.eta);
  // LTSM (local term, deterministic), TSIS of R W_g (converged), and the hybrid's sum.
  const auto local = slab.exitance("hybrid", "local", true);
  const auto global = slab.exitance("hybrid", "global", true);
  const auto both = slab.exitance("hybrid", "full", true);
  const auto& tables = slab.technique->profileTables();
  const HybridSplit split = makeHybridSplit(tables, 1.5, 0.1, m.scale);
  for (size_t c = 0; c < 3; ++c) {
    // E = Ft(η, 1) · 1 on the top face; B = E ∫ R W dA over the plane.
    const double wantLocal = ft * 0.999 * tableIntegral(tables[c], split.rp[c], split.k, 1);
    const double wantGlobal = ft * tableIntegral(tables[c], split.rp[c], split.k, 2);
    double l = 0.0, g = 0.0, b = 0.0;
    const size_t n = local.size() / 3;
    for (size_t p = 0; p < n; ++p) {
      const double lp = local[3 * p + c];
      l += lp / double(n);
      g += double(global[3 * p + c]) / double(n);
      b += double(both[3 * p + c]) / double(n);
      // Local per pixel: the map's texel positions stand in for the pattern's exact offsets
      // (texel 5e-3 units against a reduced mean free path of 0.02–0.03): 3%.
      EXPECT_NEAR(lp, wantLocal, 0.03 * wantLocal) << "pixel " << p << " channel " << c;
    }
    // Global: 256 frames of 1024 samples, ~2% of which fall within the global kernel of a pixel
    // (its support ~0.3 units of the 13 unit² face): ~5·10³ samples per pixel, ~1.5% noise; 3%.
    EXPECT_NEAR(g, wantGlobal, 0.03 * wantGlobal) << "channel " << c;
    EXPECT_NEAR(b, wantLocal + wantGlobal, 0.03 * (wantLocal + wantGlobal)) << "channel " << c;
    std::printf("channel %zu: local %.5g (want %.5g), global %.5g (want %.5g), hybrid %.5g\n", c, l,
                wantLocal, g, wantGlobal, b);
  }
}

// Seed Fig. 4.8: skin1 on a 30 mm model is local-dominated (ℓ ≪ model size), where TSIS needs
// ~14 400 samples; the hybrid at 900 + 401 samples beats TSIS alone at 1301 (the same count).
// Error: relative RMSE of the exitance B over the pixels the model reference covers fully,
// against the model reference (reference/model_reference.h: the dipole integrated over the same
// mesh on the CPU), the mean square over 4 independent frames (real-time images:
// accumulate false), minus the reference's own noise (its standard errors).
TEST_F(TsisHybrid, HybridBeatsTsisWhereLocalScatteringDominates) {
  useTestCache();
  scene::Scene s = scene::loadScene(std::filesystem::path(TRANSLUCENT_DATA_DIR) / "compare" / "head-10mm-skin1.json");
  s.medium.scale = 30.0;  // the head 30 mm long
  s.technique = "tsis";
  s.settings.clear();
  s.camera.width = 48;
  s.camera.height = 36;
  const geometry::TriangleMesh mesh = scene::loadSceneMesh(s);
  reference::ModelReferenceOptions o;
  o.samples = 400000;
  o.subpixels = 1;  // the pixel centres, where the techniques shade
  const reference::ModelReferenceImages ref = reference::renderModelReference(
      mesh, s.medium, bssrdf::model(s.model), scene::referenceLights(s), s.camera, o);

  auto meanSquareError = [&](const std::string& mode, int samples) {
    TsisTechnique t;
    t.setParameter("mode", mode);
    t.setParameter("samples", samples);
    t.setParameter("accumulate", false);
    t.setParameter("shadow_map_size", 1024);
    t.prepare(s, gpu::testing::context());
    double se2 = 0.0, refMean = 0.0, noise = 0.0;
    size_t pixels = 0;
    const int frames = 4;
    for (int f = 0; f < frames; ++f) {
      const auto b = t.render({}).layers.at("exitance");
      for (size_t p = 0; p < ref.coverage.size(); ++p) {
        if (ref.coverage[p] < 1.0f) continue;
        for (size_t c = 0; c < 3; ++c) {
          const double d = double(b[3 * p + c]) - double(ref.exitance[3 * p + c]);
          se2 += d * d;
          if (f == 0) {
            refMean += double(ref.exitance[3 * p + c]);
            noise += double(ref.exitance_se[3 * p + c]) * double(ref.exitance_se[3 * p + c]);
            ++pixels;
          }
        }
      }
    }
    refMean /= double(pixels);
    const double mse = se2 / double(pixels * frames) - noise / double(pixels);
    return std::sqrt(std::max(mse, 0.0)) / refMean;
  };
  const double hybrid = meanSquareError("hybrid", 900);
  const double tsis = meanSquareError("global", 1301);
  std::printf("skin1 30 mm head, relative RMSE of B vs the model reference: hybrid 900+401 %.2f%%, "
              "tsis 1301 %.2f%%\n", 100.0 * hybrid, 100.0 * tsis);
  EXPECT_LT(hybrid, tsis);
}

// Several lights (Chang 2007 lights its scenes with several): each has a light-view map of its
// own, and the local terms add up exactly (one frame, the same pattern); the converged hybrid
// agrees with TSIS of the whole profile under both lights, within the 3% of the one-light slab
// test above.
TEST_F(TsisHybrid, TwoLightsAddUpAndAgreeWithTsis) {
  Slab slab;
  slab.technique->setParameter("samples", 256);
  slab.technique->setParameter("accumulate_samples", 256);  // one frame: the same pattern
  scene::Light a, b;
  a.emitter = reference::DirectionalLight{{0.0, 0.0, 1.0}, 1.0};
  b.emitter = reference::DirectionalLight{glm::normalize(glm::dvec3(0.5, 0.2, 1.0)), 0.6};
  b.color = {1.0, 0.7, 0.4};
  slab.scene.lights = {a};
  const auto localA = slab.exitance("hybrid", "local", true);
  slab.scene.lights = {b};
  const auto localB = slab.exitance("hybrid", "local", true);
  slab.scene.lights = {a, b};
  const auto localAB = slab.exitance("hybrid", "local", true);
  double sum = 0.0;
  for (size_t i = 0; i < localAB.size(); ++i) {
    const double want = double(localA[i]) + double(localB[i]);
    EXPECT_NEAR(localAB[i], want, 1e-5 * want + 1e-9) << "value " << i;
    sum += want;
  }
  EXPECT_GT(sum, 0.0);
  // Converged: the hybrid (both terms) against TSIS of the whole profile, both lights.
  slab.technique->setParameter("samples", 1024);
  slab.technique->setParameter("accumulate_samples", 1 << 18);
  const auto hybrid = slab.exitance("hybrid", "full", true);
  const auto tsis = slab.exitance("global", "full", true);
  for (size_t c = 0; c < 3; ++c) {
    double h = 0.0, g = 0.0;
    for (size_t p = c; p < hybrid.size(); p += 3) {
      h += double(hybrid[p]);
      g += double(tsis[p]);
    }
    std::printf("two lights, channel %zu: hybrid / tsis %.4f\n", c, h / g);
    EXPECT_NEAR(h, g, 0.03 * g) << "channel " << c;
  }
}

// With the inspection views, the hybrid shows its split (Chang 2007, Figs. 3.4-3.5): the local
// and global parts add up to the whole profile at every r, and the local part dominates inside
// R_p (W_l > 1/2) and the global part outside it.
TEST_F(TsisHybrid, ViewsCarryTheSplitPlot) {
  Slab slab;
  slab.technique->setParameter("mode", std::string("hybrid"));
  slab.technique->setParameter("samples", 64);
  slab.technique->prepare(slab.scene, gpu::testing::context());
  techniques::FrameRequest request;
  request.views = true;
  const techniques::Frame f = slab.technique->render(request);
  ASSERT_TRUE(f.plots.contains("hybrid_split"));
  const auto& series = f.plots.at("hybrid_split").series;
  ASSERT_EQ(series.size(), 3u);
  const auto &whole = series[0], &local = series[1], &global = series[2];
  ASSERT_GT(whole.y.size(), 100u);
  const HybridSplit split = makeHybridSplit(slab.technique->profileTables(), 1.5, 0.1, slab.scene.medium.scale);
  const double rp = std::max({split.rp[0], split.rp[1], split.rp[2]});
  int below = 0, beyond = 0, wrong = 0;
  for (size_t i = 0; i < whole.y.size(); ++i) {
    EXPECT_NEAR(local.y[i] + global.y[i], whole.y[i], 1e-12 * whole.y[i] + 1e-300);
    if (whole.y[i] <= 0.0) continue;
    if (whole.x[i] < 0.95 * rp) (local.y[i] > global.y[i] ? below : wrong) += 1;
    if (whole.x[i] > 1.05 * rp) (global.y[i] > local.y[i] ? beyond : wrong) += 1;
  }
  EXPECT_GT(below, 10);
  EXPECT_GT(beyond, 10);
  EXPECT_EQ(wrong, 0);
  slab.technique->setParameter("mode", std::string("global"));
  EXPECT_FALSE(slab.technique->render(request).plots.contains("hybrid_split"));
}

TEST_F(TsisHybrid, RefusesLightsWithoutALightViewMap) {
  Slab slab;
  slab.technique->setParameter("mode", std::string("hybrid"));
  scene::Light beam;
  beam.emitter = reference::BeamLight{{0.0, 0.0, 3.0}, {0.0, 0.0, -1.0}, 0.5, 1.0};
  slab.scene.lights = {beam};
  slab.technique->prepare(slab.scene, gpu::testing::context());
  try {
    (void)slab.technique->render({});
    FAIL() << "expected an error naming lights[0]";
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("lights[0]: mode 'hybrid'"), std::string::npos) << e.what();
  }
  slab.technique->setParameter("term", std::string("global"));  // TSIS only: any light
  EXPECT_NO_THROW((void)slab.technique->render({}));
}

}  // namespace
}  // namespace translucent::tsis
