// SPDX-License-Identifier: GPL-3.0-or-later
// The layered slab (reference/layered_slab.h) against an independent computation: MCML's
// multi-layer photon walk written here from its published description (Wang, Jacques & Zheng
// 1995; Wang & Jacques, "Monte Carlo modeling of light transport in multi-layered tissues in
// standard C", 1992, chapters 3-4): a weighted photon, "hop" by a dimensionless step whose
// remainder carries into the next layer at a boundary, "drop" of the fraction μa/μt of the weight
// at each interaction, "spin" by MCML's Henyey-Greenstein formula and direction update,
// all-or-none Fresnel at the outer surfaces, Russian roulette below weight 1e-4 (survive 1/10,
// weight x10). Its own generator (std::mt19937_64). Also: one layer equals the homogeneous slab,
// a change far below the diffusion depth is invisible, determinism, and the layers file.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "translucent/optics/fresnel.h"
#include "translucent/reference/layered_slab.h"
#include "translucent/reference/slab_request.h"

namespace translucent::reference {
namespace {

constexpr double kPi = std::numbers::pi;

void expectAgree(const Estimate& a, const Estimate& b, double k, const std::string& what) {
  EXPECT_NEAR(a.value, b.value, k * std::hypot(a.std_error, b.std_error))
      << what << ": " << a.value << " ± " << a.std_error << " vs " << b.value << " ± "
      << b.std_error;
}

// ---------------------------------------------------------------------------------------------
// MCML, multi-layer, matched layers (all at n_in), air (n = 1) above and below, normal incidence.

struct McmlLayer {
  double z0, z1, mua, mus, g;
};

struct McmlResult {
  Estimate rd, tt, a;
  std::vector<Estimate> rdr;  // per unit area
};

double mcmlFresnel(double n1, double n2, double ca1) {  // MCML's RFresnel, unpolarised
  if (n1 == n2) return 0.0;
  if (ca1 > 1.0 - 1e-12) return ((n2 - n1) / (n2 + n1)) * ((n2 - n1) / (n2 + n1));
  const double sa1 = std::sqrt(1.0 - ca1 * ca1);
  const double sa2 = n1 * sa1 / n2;
  if (sa2 >= 1.0) return 1.0;
  const double ca2 = std::sqrt(1.0 - sa2 * sa2);
  const double cap = ca1 * ca2 - sa1 * sa2, cam = ca1 * ca2 + sa1 * sa2;
  const double sap = sa1 * ca2 + ca1 * sa2, sam = sa1 * ca2 - ca1 * sa2;
  return 0.5 * sam * sam * (cam * cam + cap * cap) / (sap * sap * cam * cam);
}

McmlResult mcml(const std::vector<McmlLayer>& layers, double nIn, uint64_t photons, uint64_t seed,
                int bins, double dr) {
  std::mt19937_64 gen(seed);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  auto xi = [&] {
    double v;
    do v = U(gen);
    while (v <= 0.0);
    return v;
  };
  const double rsp = ((1.0 - nIn) / (1.0 + nIn)) * ((1.0 - nIn) / (1.0 + nIn));
  double sR = 0, sR2 = 0, sT = 0, sT2 = 0, sA = 0, sA2 = 0;
  std::vector<double> bR(static_cast<size_t>(bins)), bR2(static_cast<size_t>(bins));
  for (uint64_t p = 0; p < photons; ++p) {
    double x = 0, y = 0, z = 0, ux = 0, uy = 0, uz = 1, w = 1.0 - rsp, sleft = 0, absorbed = 0;
    size_t l = 0;
    for (;;) {
      const McmlLayer& L = layers[l];
      const double mut = L.mua + L.mus;
      double s = sleft == 0.0 ? -std::log(xi()) / mut : sleft / mut;
      sleft = 0.0;
      const double db = uz > 0 ? (L.z1 - z) / uz : uz < 0 ? (L.z0 - z) / uz : 1e300;
      if (s > db) {  // hits the boundary: move there, keep the dimensionless remainder
        x += db * ux;
        y += db * uy;
        z = uz > 0 ? L.z1 : L.z0;
        sleft = (s - db) * mut;
        const bool up = uz < 0;
        if (up && l > 0) {
          --l;
          continue;
        }
        if (!up && l + 1 < layers.size()) {
          ++l;
          continue;
        }
        // The outer surface: all-or-none Fresnel against air.
        const double r = mcmlFresnel(nIn, 1.0, std::abs(uz));
        if (xi() <= r) {
          uz = -uz;
          continue;
        }
        if (up) {
          sR += w;
          sR2 += w * w;
          const int k = static_cast<int>(std::hypot(x, y) / dr);
          if (k < bins) {
            bR[static_cast<size_t>(k)] += w;
            bR2[static_cast<size_t>(k)] += w * w;
          }
        } else {
          sT += w;
          sT2 += w * w;
        }
        break;
      }
      x += s * ux;
      y += s * uy;
      z += s * uz;
      // Drop.
      const double dw = w * L.mua / mut;
      w -= dw;
      absorbed += dw;
      // Spin.
      double ct;
      if (L.g == 0.0) {
        ct = 2.0 * xi() - 1.0;
      } else {
        const double tmp = (1.0 - L.g * L.g) / (1.0 - L.g + 2.0 * L.g * xi());
        ct = (1.0 + L.g * L.g - tmp * tmp) / (2.0 * L.g);
        ct = std::clamp(ct, -1.0, 1.0);
      }
      const double st = std::sqrt(1.0 - ct * ct);
      const double psi = 2.0 * kPi * xi();
      const double cp = std::cos(psi), sp = std::sin(psi);
      if (std::abs(uz) > 0.99999) {
        ux = st * cp;
        uy = st * sp;
        uz = ct * (uz >= 0 ? 1.0 : -1.0);
      } else {
        const double temp = std::sqrt(1.0 - uz * uz);
        const double nux = st * (ux * uz * cp - uy * sp) / temp + ux * ct;
        const double nuy = st * (uy * uz * cp + ux * sp) / temp + uy * ct;
        const double nuz = -st * cp * temp + uz * ct;
        ux = nux;
        uy = nuy;
        uz = nuz;
      }
      // Roulette.
      if (w < 1e-4) {
        if (xi() <= 0.1)
          w *= 10.0;
        else
          break;
      }
    }
    sA += absorbed;
    sA2 += absorbed * absorbed;
  }
  auto est = [&](double s1, double s2, double measure) {
    const double n = static_cast<double>(photons), m = s1 / n;
    return Estimate{m / measure, std::sqrt(std::max(0.0, s2 / n - m * m) / (n - 1.0)) / measure};
  };
  McmlResult r{est(sR, sR2, 1.0), est(sT, sT2, 1.0), est(sA, sA2, 1.0), {}};
  for (int k = 0; k < bins; ++k)
    r.rdr.push_back(est(bR[static_cast<size_t>(k)], bR2[static_cast<size_t>(k)],
                        kPi * dr * dr * (2.0 * k + 1.0)));
  return r;
}

// ---------------------------------------------------------------------------------------------

TraceOptions radialOptions(uint64_t photons, uint64_t seed) {
  TraceOptions o;
  o.photons = photons;
  o.seed = seed;
  o.threads = 2;
  o.radial_bins = 10;
  o.radial_max = 2.0;
  return o;
}

TEST(LayeredSlab, TwoLayersAgreeWithMcmlsMultiLayerWalk) {
  // A forward-scattering layer 0.5 thick (1.2 transport mean free paths) over a semi-infinite,
  // isotropic, more absorbing one; η = 1.4 under air. Totals and 10 annuli of Rd(r), each with
  // the combined standard error: 13 z-tests at |z| < 3.3 (Bonferroni, ~1%). Run in both
  // absorption modes (analog is the default; weighted is MCML's own).
  LayeredSlabSetup s;
  s.layers = {{0.5, 0.5, 9.5, 0.75}, {std::numeric_limits<double>::infinity(), 0.3, 4.7, 0.0}};
  s.n_inside = 1.4;
  const McmlResult m =
      mcml({{0.0, 0.5, 0.5, 9.5, 0.75}, {0.5, 1e300, 0.3, 4.7, 0.0}}, 1.4, 150'000, 7, 10, 0.2);
  for (Absorption mode : {Absorption::Analog, Absorption::Weighted}) {
    TraceOptions o = radialOptions(mode == Absorption::Analog ? 200'000 : 60'000, 3);
    o.absorption = mode;
    const SlabResult r = traceLayeredSlab(s, o);
    const std::string tag = mode == Absorption::Analog ? "analog: " : "weighted: ";
    EXPECT_NEAR(r.specular_reflectance.value, (0.4 / 2.4) * (0.4 / 2.4), 1e-12);
    expectAgree(r.diffuse_reflectance, m.rd, 3.3, tag + "Rd");
    expectAgree(r.absorbed, m.a, 3.3, tag + "absorbed");
    EXPECT_EQ(r.transmittance.value, 0.0);
    for (size_t k = 0; k < 10; ++k)
      expectAgree({r.radial.rd[k], r.radial.rd_stderr[k]}, m.rdr[k], 3.3,
                  tag + "Rd(r) annulus " + std::to_string(k));
    EXPECT_LT(r.diffuse_reflectance.std_error, 0.01 * r.diffuse_reflectance.value);
  }
}

TEST(LayeredSlab, FiniteTwoLayersAgreeWithMcmlIncludingTransmittance) {
  LayeredSlabSetup s;
  s.layers = {{0.3, 1.0, 9.0, 0.9}, {0.4, 0.5, 19.5, 0.5}};
  s.n_inside = 1.33;
  const McmlResult m =
      mcml({{0.0, 0.3, 1.0, 9.0, 0.9}, {0.3, 0.7, 0.5, 19.5, 0.5}}, 1.33, 60'000, 17, 10, 0.2);
  const SlabResult r = traceLayeredSlab(s, radialOptions(200'000, 13));
  expectAgree(r.diffuse_reflectance, m.rd, 3.3, "Rd");
  expectAgree(r.transmittance, m.tt, 3.3, "T");
  expectAgree(r.absorbed, m.a, 3.3, "absorbed");
  for (size_t k = 0; k < 10; ++k)
    expectAgree({r.radial.rd[k], r.radial.rd_stderr[k]}, m.rdr[k], 3.3,
                "Rd(r) annulus " + std::to_string(k));
  // Every photon is accounted for: Rsp + Rd + T + A = 1 (analog: the tallies of one photon are
  // exclusive).
  EXPECT_NEAR(r.specular_reflectance.value + r.diffuse_reflectance.value + r.transmittance.value +
                  r.absorbed.value,
              1.0, 1e-9);
}

SlabSetup homogeneous(const SlabLayer& L, double eta) {
  SlabSetup h;
  h.sigma_a = L.sigma_a;
  h.sigma_s = L.sigma_s;
  h.g = L.g;
  h.n_inside = eta;
  h.thickness = L.thickness;
  return h;
}

TEST(LayeredSlab, OneLayerIsTheHomogeneousSlab) {
  // Two different walkers (the scalar double walk here, the float lane walker there): totals and
  // the radial profile within combined standard errors, at oblique incidence and finite
  // thickness; 13 z-tests at |z| < 3.3.
  LayeredSlabSetup s;
  s.layers = {{1.5, 0.2, 4.8, 0.6}};
  s.n_inside = 1.45;
  s.theta = 0.5;
  SlabSetup h = homogeneous(s.layers[0], 1.45);
  h.theta = 0.5;
  const SlabResult a = traceLayeredSlab(s, radialOptions(150'000, 1));
  const SlabResult b = traceSlab(h, radialOptions(400'000, 2));
  EXPECT_DOUBLE_EQ(a.specular_reflectance.value, b.specular_reflectance.value);
  expectAgree(a.diffuse_reflectance, b.diffuse_reflectance, 3.3, "Rd");
  expectAgree(a.transmittance, b.transmittance, 3.3, "T");
  expectAgree(a.absorbed, b.absorbed, 3.3, "absorbed");
  for (size_t k = 0; k < 10; ++k)
    expectAgree({a.radial.rd[k], a.radial.rd_stderr[k]}, {b.radial.rd[k], b.radial.rd_stderr[k]},
                3.3, "Rd(r) annulus " + std::to_string(k));
  // Splitting the layer in two identical ones changes nothing either (statistically: the
  // boundary consumes no random number, so it is even the same walk up to rounding).
  LayeredSlabSetup split = s;
  split.layers = {{0.4, 0.2, 4.8, 0.6}, {1.1, 0.2, 4.8, 0.6}};
  const SlabResult c = traceLayeredSlab(split, radialOptions(150'000, 1));
  EXPECT_NEAR(c.diffuse_reflectance.value, a.diffuse_reflectance.value,
              1e-3 * a.diffuse_reflectance.value);
}

TEST(LayeredSlab, ChangeFarBelowTheDiffusionDepthIsInvisible) {
  // Upper medium σa = 1, σs = 9: diffusion length 1/σtr = 0.18; the second medium (clear, weakly
  // absorbing) starts at depth 4, 22 diffusion lengths down: e^-44 of Rd comes from there.
  LayeredSlabSetup s;
  s.layers = {{4.0, 1.0, 9.0, 0.0}, {std::numeric_limits<double>::infinity(), 0.01, 1.0, 0.9}};
  s.n_inside = 1.3;
  SlabSetup h = homogeneous(s.layers[0], 1.3);
  h.thickness = std::numeric_limits<double>::infinity();
  const SlabResult a = traceLayeredSlab(s, radialOptions(150'000, 5));
  const SlabResult b = traceSlab(h, radialOptions(400'000, 6));
  expectAgree(a.diffuse_reflectance, b.diffuse_reflectance, 3.3, "Rd");
  expectAgree(a.absorbed, b.absorbed, 3.3, "absorbed");
  for (size_t k = 0; k < 10; ++k)
    expectAgree({a.radial.rd[k], a.radial.rd_stderr[k]}, {b.radial.rd[k], b.radial.rd_stderr[k]},
                3.3, "Rd(r) annulus " + std::to_string(k));
}

TEST(LayeredSlab, SameSeedSameResultForAnyThreadCount) {
  LayeredSlabSetup s;
  s.layers = {{0.3, 0.5, 9.5, 0.8}, {0.5, 0.1, 20.0, 0.0}, {std::numeric_limits<double>::infinity(), 2.0, 8.0, 0.3}};
  s.n_inside = 1.4;
  TraceOptions o = radialOptions(20'000, 42);
  o.angle_bins = 6;
  o.threads = 1;
  const SlabResult a = traceLayeredSlab(s, o);
  o.threads = 3;
  const SlabResult b = traceLayeredSlab(s, o);
  EXPECT_EQ(a.diffuse_reflectance.value, b.diffuse_reflectance.value);
  EXPECT_EQ(a.diffuse_reflectance.std_error, b.diffuse_reflectance.std_error);
  EXPECT_EQ(a.absorbed.value, b.absorbed.value);
  EXPECT_EQ(a.radial.rd, b.radial.rd);
  EXPECT_EQ(a.angular.rd_r_theta, b.angular.rd_r_theta);
  EXPECT_EQ(a.scattering_events, b.scattering_events);
  EXPECT_EQ(a.photons, 20'000u);
}

TEST(LayeredSlab, StopsOnRequestWithAPartialResult) {
  LayeredSlabSetup s;
  s.layers = {{0.3, 0.5, 9.5, 0.8}, {std::numeric_limits<double>::infinity(), 0.01, 20.0, 0.0}};
  s.n_inside = 1.4;
  TraceOptions o = radialOptions(100'000'000, 1);
  const SlabResult r = traceLayeredSlab(s, o, [](const TraceProgress& p) { return p.seconds < 0.2; });
  EXPECT_TRUE(r.partial);
  EXPECT_LT(r.photons, o.photons);
  EXPECT_EQ(r.photons % kBlockPhotons, 0u);
}

std::string errorOf(const std::string& json) {
  try {
    parseSlabLayers(json, "layers.json");
  } catch (const ParameterError& e) {
    return e.what();
  }
  return "";
}

TEST(LayeredSlab, LayersFileErrorsNameFileIndexAndKey) {
  const auto layers = parseSlabLayers(
      R"([{"thickness": 0.2, "sigma_a": 1, "sigma_s": 10, "g": 0.8},
          {"thickness": null, "sigma_a": 0.5, "sigma_s": 20}])", "x.json");
  ASSERT_EQ(layers.size(), 2u);
  EXPECT_EQ(layers[0].thickness, 0.2);
  EXPECT_EQ(layers[0].g, 0.8);
  EXPECT_TRUE(std::isinf(layers[1].thickness));
  EXPECT_EQ(layers[1].g, 0.0);
  EXPECT_EQ(layers[1].sigma_s, 20.0);

  auto expectError = [](const std::string& json, const std::vector<std::string>& parts) {
    const std::string e = errorOf(json);
    EXPECT_FALSE(e.empty()) << json;
    for (const auto& p : parts) EXPECT_NE(e.find(p), std::string::npos) << e << " lacks " << p;
  };
  expectError("{}", {"layers.json", "array"});
  expectError("[1,", {"layers.json", "JSON"});
  expectError(R"([{"thickness": 1, "sigma_a": 1, "sigma_s": 1, "G": 0}])", {"layers.json", "[0]", "\"G\""});
  expectError(R"([{"thickness": 1, "sigma_a": 1, "sigma_s": 1}, {"thickness": 1, "sigma_s": 1}])",
              {"layers.json", "[1]", "\"sigma_a\"", "missing"});
  expectError(R"([{"thickness": null, "sigma_a": 1, "sigma_s": 1}, {"thickness": 1, "sigma_a": 1, "sigma_s": 1}])",
              {"[0]", "\"thickness\"", "last"});
  expectError(R"([{"thickness": -1, "sigma_a": 1, "sigma_s": 1}])", {"[0]", "\"thickness\"", "-1"});
  expectError(R"([{"thickness": 1, "sigma_a": 1, "sigma_s": "a"}])", {"[0]", "\"sigma_s\"", "number"});
  expectError(R"([{"thickness": 1, "sigma_a": 1, "sigma_s": 1, "g": 1}])", {"[0]", "\"g\"", "(-1, 1)"});
  expectError(R"([{"thickness": 1, "sigma_a": 0, "sigma_s": 0}])", {"[0]", "sigma_s"});

  const std::string missing = (std::filesystem::temp_directory_path() / "no_such_layers_9f3.json").string();
  try {
    loadSlabLayers(missing);
    ADD_FAILURE() << "no error for a missing file";
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find(missing), std::string::npos) << e.what();
  }
  // The setup's own checks name the layer.
  LayeredSlabSetup s;
  s.layers = {{1.0, 0.1, 1.0, 0.0}, {std::numeric_limits<double>::infinity(), 0.0, 1.0, 0.0}};
  s.n_inside = 1.3;
  try {
    traceLayeredSlab(s, radialOptions(1024, 1));
    ADD_FAILURE() << "no error for a conservative semi-infinite layer";
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("layer 2"), std::string::npos) << e.what();
  }
}

// --absorption auto (the default) picks the weighted walk for slabs of reduced optical thickness
// σt'·d <= 2, the analog walk for thicker slabs, half-spaces and layered slabs; an explicit choice
// is kept; both walks give the same Rd within their standard errors on a thin slab.
TEST(SlabRequest, AutoAbsorptionIsWeightedForThinSlabsOnly) {
  auto run = [](std::optional<double> thickness, const std::string& absorption) {
    SlabRequest r;
    r.sigma_a = 1.0;
    r.sigma_s = 10.0;
    r.g = 0.5;
    r.eta = 1.3;
    r.thickness = thickness;  // σt' = 1 + 5 = 6
    r.absorption = absorption;
    return makeSlabRun(r);
  };
  EXPECT_EQ(SlabRequest{}.absorption, "auto");
  EXPECT_EQ(run(0.3, "auto").options.absorption, Absorption::Weighted);   // 1.8
  EXPECT_EQ(run(0.34, "auto").options.absorption, Absorption::Analog);    // 2.04
  EXPECT_EQ(run(std::nullopt, "auto").options.absorption, Absorption::Analog);
  EXPECT_EQ(run(0.3, "analog").options.absorption, Absorption::Analog);
  EXPECT_EQ(run(10.0, "weighted").options.absorption, Absorption::Weighted);
  SlabRequest layered;
  layered.eta = 1.3;
  EXPECT_EQ(makeSlabRun(layered, std::vector<SlabLayer>{{0.1, 1.0, 10.0, 0.5}, {std::numeric_limits<double>::infinity(), 1.0, 10.0, 0.5}}, "l.json")
                .options.absorption,
            Absorption::Analog);
  try {
    (void)run(0.3, "implicit");
    ADD_FAILURE() << "accepted";
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("expected auto, analog or weighted"), std::string::npos)
        << e.what();
  }
  // The two walks estimate the same Rd on the thin slab.
  SlabRun a = run(0.3, "auto"), b = run(0.3, "analog");
  a.options.photons = b.options.photons = 200'000;
  a.options.threads = b.options.threads = 2;
  b.options.seed = 2;
  const SlabResult ra = traceSlabRun(a), rb = traceSlabRun(b);
  EXPECT_NEAR(ra.diffuse_reflectance.value, rb.diffuse_reflectance.value,
              3.5 * std::hypot(ra.diffuse_reflectance.std_error, rb.diffuse_reflectance.std_error));
}

// Layers whose walks would not end are refused before tracing, also where each layer alone
// passes the estimate: without absorption a walk ends only by leaving (fuzz_layers).
TEST(LayeredSlab, EndlessWalksInAStackAreRefusedBeforeTracing) {
  SlabRequest request;
  request.eta = 1.4;
  auto errorOfRun = [&](const std::vector<SlabLayer>& layers) -> std::string {
    try {
      makeSlabRun(request, layers, "l.json");
    } catch (const ParameterError& e) {
      return e.what();
    }
    return "";
  };
  // One thick layer without absorption: ~(σt' L)² = 1e12 scattering events to cross it.
  std::string e = errorOfRun({{1e3, 0.0, 1e3, 0.0}});
  EXPECT_NE(e.find("l.json: layer [0]: sigma_a is 0"), std::string::npos) << e;
  EXPECT_NE(e.find("--long-path-roulette"), std::string::npos) << e;
  // Forty thin ones: each crossed in ~1e5 events, the stack in ~1.6e8 (each of 1e6 photons).
  e = errorOfRun(std::vector<SlabLayer>(40, SlabLayer{1.0, 0.0, 100.0, 0.0}));
  EXPECT_NE(e.find("l.json: layers [0] to [39] together"), std::string::npos) << e;
  // The same stack passes with a time limit (the estimate of the total is what it bounds), and
  // with the long-path roulette; a thin transparent layer on an absorbing half-space passes.
  request.time_limited = true;
  EXPECT_EQ(errorOfRun(std::vector<SlabLayer>(40, SlabLayer{1.0, 0.0, 100.0, 0.0})), "");
  request.time_limited = false;
  request.long_path_roulette = 10000;
  EXPECT_EQ(errorOfRun({{1e3, 0.0, 1e3, 0.0}}), "");
  request.long_path_roulette = 0;
  EXPECT_EQ(errorOfRun({{0.5, 0.0, 1e-3, 0.0}, {std::numeric_limits<double>::infinity(), 1.0, 10.0, 0.5}}),
            "");
}

}  // namespace
}  // namespace translucent::reference
