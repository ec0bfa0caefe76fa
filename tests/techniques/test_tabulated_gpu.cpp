// SPDX-License-Identifier: GPL-3.0-or-later
// A tabulated profile (bssrdf/tabulated.h) is a model for every technique: a box of marble
// (scene units of 1 cm, so the table's millimetres are converted) rendered by each registered
// technique with the dipole and with a dense table of the dipole, written to a CSV and named by
// the scene, gives the same image within the table's interpolation error.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "translucent/bssrdf/registry.h"
#include "translucent/bssrdf/tabulated.h"
#include "render_helpers.h"
#include "translucent/techniques/registry.h"

namespace translucent::techniques {
namespace {

using namespace translucent::pointcloud::testing;

class TabulatedGpu : public gpu::testing::GpuTest {};

// The dipole's R(r) for each channel of `medium` at scale 1 (millimetres), on a log grid.
bssrdf::ProfileSamples denseDipole(Medium medium) {
  medium.scale = 1.0;
  const auto ps = bssrdf::profiles(bssrdf::model("dipole"), medium);
  double rMax = 0.0;
  for (const auto& p : ps) rMax = std::max(rMax, p->radiusForFraction(0.999999));
  bssrdf::ProfileSamples t;
  constexpr int n = 3000;
  for (int i = 0; i < n; ++i) {
    const double r = 1e-5 * rMax * std::pow(1e5, double(i) / (n - 1));
    t.r_mm.push_back(r);
    for (size_t c = 0; c < 3; ++c) t.R_mm[c].push_back(ps[c]->R(r));
  }
  return t;
}

Frame renderWith(const std::string& technique, const scene::Scene& s) {
  return renderConverged(*make(technique), s);
}

TEST_F(TabulatedGpu, EveryTechniqueRendersATableOfTheDipoleAsTheDipole) {
  TempDir dir;
  useTestCache();
  const auto box = geometry::makeBox({-0.8, -0.8, -0.5}, {0.8, 0.8, 0.0});
  scene::Scene s = testScene(writeObj(box, dir.path() / "box.obj"), 24);
  ASSERT_EQ(s.medium.scale, 10.0);
  const std::string table = (dir.path() / "dipole.csv").string();
  bssrdf::writeProfileSamples(table, denseDipole(s.medium));
  for (const std::string& name : names()) {
    SCOPED_TRACE(name);
    s.model = "dipole";
    const Frame a = renderWith(name, s);
    s.model = table;
    const Frame b = renderWith(name, s);
    ASSERT_EQ(a.rgb.size(), b.rgb.size());
    double sa = 0.0, sb = 0.0, peak = 0.0;
    for (size_t i = 0; i < a.rgb.size(); ++i) {
      sa += double(a.rgb[i]);
      sb += double(b.rgb[i]);
      peak = std::max(peak, double(a.rgb[i]));
    }
    ASSERT_GT(sa, 0.0);
    // 3000 log-spaced samples interpolate the dipole to ~1e-5; what remains is the techniques'
    // own tables built from R(r) (float32 on the GPU): 0.5% on the image, 2% on a bright pixel.
    std::printf("%s: image sum ratio table/dipole %.6f\n", name.c_str(), sb / sa);
    EXPECT_NEAR(sb / sa, 1.0, 5e-3);
    int bad = 0;
    for (size_t i = 0; i < a.rgb.size(); ++i) {
      const double x = a.rgb[i], y = b.rgb[i];
      if (x > 0.1 * peak && std::abs(y - x) > 0.02 * x) ++bad;
    }
    EXPECT_EQ(bad, 0);
  }
}

}  // namespace
}  // namespace translucent::techniques
