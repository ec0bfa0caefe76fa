// SPDX-License-Identifier: GPL-3.0-or-later
// Per-point profiles at the texels of a surface atlas (material/profile_atlas.h): every texel a
// triangle owns holds the profile of the local medium at its surface point (the same nodes as a
// profile built for that point alone), texels beside the charts take their owned neighbours'
// mean, the rest the floor; the layout and the triangles' corner UVs are the atlas'.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "translucent/geometry/atlas.h"
#include "translucent/geometry/icosphere.h"
#include "translucent/material/profile_atlas.h"
#include "translucent/optics/presets.h"

namespace translucent::material {
namespace {

// σa grows with material-space x: every texel its own medium.
class Ramp final : public VolumeField {
 public:
  explicit Ramp(const Medium& m) : m_(LocalMedium::of(m)) {}
  LocalMedium at(const glm::dvec3& q) const override {
    LocalMedium l = m_;
    for (size_t c = 0; c < 3; ++c) l.sigma_a[c] *= 1.0 + 2.0 * (q.x + 1.0);
    return l;
  }
  Rgb majorant(const glm::dvec3&, const glm::dvec3&) const override {
    Rgb m = m_.sigmaT();
    for (size_t c = 0; c < 3; ++c) m[c] += 4.0 * m_.sigma_a[c];
    return m;
  }

 private:
  LocalMedium m_;
};

geometry::Atlas atlasOf(const geometry::TriangleMesh& mesh, uint32_t size) {
  geometry::AtlasOptions ao;
  ao.size = size;
  return geometry::buildAtlas(mesh, ao);
}

TEST(ProfileAtlas, TexelsHoldTheProfilesOfTheirSurfacePoints) {
  const geometry::TriangleMesh mesh = geometry::makeIcosphere(2, 1.0);
  const geometry::Atlas atlas = atlasOf(mesh, 64);
  Material mat;
  mat.kind = Material::Kind::Volume;
  mat.medium = preset("Skin1").medium(10.0);
  mat.model = "dipole";
  mat.volume = std::make_shared<Ramp>(preset("Skin1").medium());
  mat.surface_depth = 0.0;
  const ProfileAtlas pa = buildProfileAtlas(mesh, atlas, mat, {8, 0.0});
  ASSERT_EQ(pa.size, 64u);
  ASSERT_EQ(pa.segments, 8);
  EXPECT_EQ(pa.triangle_uvs, atlas.uvs);
  const geometry::AtlasCoverage coverage = geometry::rasterizeCoverage(atlas);
  EXPECT_EQ(pa.owned, coverage.ownedTexels);
  ASSERT_EQ(pa.texel_triangle.size(), pa.owned);

  const size_t plane = 64 * 64, m = 9;
  size_t owned = 0, filled = 0, empty = 0, checked = 0;
  for (uint32_t y = 0; y < 64; ++y)
    for (uint32_t x = 0; x < 64; ++x) {
      const size_t t = size_t(y) * 64 + x;
      const float flag = pa.nodes[t * 4 + 3];
      const auto sp = geometry::texelSurfacePoint(mesh, atlas, coverage, x, y);
      ASSERT_EQ(flag == 1.0f, sp.has_value()) << "texel " << x << ", " << y;
      if (sp) {
        ++owned;
        if (owned % 37 != 0) continue;  // every 37th: a profile of its own, built alone
        const glm::vec3 p(sp->position), n(sp->normal);
        const PointProfiles alone = PointProfiles::build(
            mat, PointProfiles::surfaceMedia(mat, std::span(&p, 1), std::span(&n, 1)),
            {pa.segments, pa.radius});
        for (size_t k = 0; k < m; ++k)
          for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(pa.nodes[(k * plane + t) * 4 + size_t(c)], alone.node(0, c, int(k)),
                        1e-5 * std::abs(alone.node(0, c, int(k))) + 1e-6);
        ++checked;
        continue;
      }
      // Unowned: a dilated texel lies within the dilation's rings of an owned one and holds
      // values between the profiles' extremes; the others the floor.
      bool nearOwned = false;
      for (int dy = -kProfileAtlasDilation; dy <= kProfileAtlasDilation && !nearOwned; ++dy)
        for (int dx = -kProfileAtlasDilation; dx <= kProfileAtlasDilation; ++dx) {
          const int xx = int(x) + dx, yy = int(y) + dy;
          if (std::abs(dx) + std::abs(dy) > kProfileAtlasDilation || xx < 0 || yy < 0 || xx >= 64 ||
              yy >= 64)
            continue;
          if (pa.nodes[(size_t(yy) * 64 + size_t(xx)) * 4 + 3] == 1.0f) nearOwned = true;
        }
      const float v = pa.nodes[t * 4];
      if (nearOwned) {
        ++filled;
        EXPECT_GT(v, float(kLnFloor)) << "texel " << x << ", " << y << " was not filled";
      } else {
        ++empty;
        EXPECT_EQ(v, float(kLnFloor));
      }
    }
  EXPECT_EQ(owned, pa.owned);
  EXPECT_GT(checked, 20u);
  EXPECT_GT(filled, 0u);
  EXPECT_GT(empty, 0u);
}

TEST(ProfileAtlas, RefusesASurfaceMapWithoutItsAtlasAndAMismatchedAtlas) {
  const geometry::TriangleMesh mesh = geometry::makeIcosphere(1, 1.0);
  const geometry::Atlas atlas = atlasOf(mesh, 32);
  Material mat;
  mat.medium = preset("Marble").medium(10.0);
  mat.model = "dipole";
  EXPECT_THROW((void)buildProfileAtlas(geometry::makeIcosphere(2, 1.0), atlas, mat), ParameterError);
  mat.kind = Material::Kind::Surface;
  EXPECT_THROW((void)buildProfileAtlas(mesh, atlas, mat), ParameterError);
}

}  // namespace
}  // namespace translucent::material
