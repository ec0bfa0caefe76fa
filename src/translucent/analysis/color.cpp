// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/analysis/color.h"

#include <algorithm>
#include <cmath>

namespace translucent::analysis::color {
namespace {

// Linear sRGB -> XYZ from the Rec. 709 primaries and D65 white, as exact fractions (the matrix
// of IEC 61966-2-1 to nine digits); the inverse is computed from it, so that the round trip is
// exact to rounding rather than to the four digits of the published inverse.
constexpr double kRgbToXyz[3][3] = {
    {10135552.0 / 24577794.0, 8788810.0 / 24577794.0, 4435075.0 / 24577794.0},
    {2613072.0 / 12288897.0, 8788810.0 / 12288897.0, 887015.0 / 12288897.0},
    {1425312.0 / 73733382.0, 8788810.0 / 73733382.0, 70074185.0 / 73733382.0}};

struct Inverse {
  double m[3][3];
  Inverse() {
    const auto& a = kRgbToXyz;
    const double det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
                       a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
                       a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        // Cofactor of a[j][i] (transposed), cyclic indices.
        const int r0 = (j + 1) % 3, r1 = (j + 2) % 3, c0 = (i + 1) % 3, c1 = (i + 2) % 3;
        m[i][j] = (a[r0][c0] * a[r1][c1] - a[r0][c1] * a[r1][c0]) / det;
      }
  }
};
const Inverse& xyzToRgbMatrix() {
  static const Inverse inv;
  return inv;
}

Vec3 apply(const double (&m)[3][3], const Vec3& v) {
  return {m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2],
          m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
          m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2]};
}

// CIE L*a*b* companding with its linear segment below (6/29)³ (CIE 15:2004).
constexpr double kDelta = 6.0 / 29.0;
double labF(double t) {
  return t > kDelta * kDelta * kDelta ? std::cbrt(t) : t / (3.0 * kDelta * kDelta) + 4.0 / 29.0;
}
double labFInverse(double f) {
  return f > kDelta ? f * f * f : 3.0 * kDelta * kDelta * (f - 4.0 / 29.0);
}

}  // namespace

double srgbToLinear(double v) {
  return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
}
double linearToSrgb(double v) {
  return v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055;
}

Vec3 linearRgbToXyz(const Vec3& rgb) {
  return apply(kRgbToXyz, rgb);
}
Vec3 xyzToLinearRgb(const Vec3& xyz) {
  return apply(xyzToRgbMatrix().m, xyz);
}
Vec3 whiteXyz() {
  return linearRgbToXyz({1.0, 1.0, 1.0});
}

Vec3 xyzToLab(const Vec3& xyz) {
  static const Vec3 w = whiteXyz();
  const double fx = labF(xyz[0] / w[0]), fy = labF(xyz[1] / w[1]), fz = labF(xyz[2] / w[2]);
  return {116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)};
}
Vec3 labToXyz(const Vec3& lab) {
  static const Vec3 w = whiteXyz();
  const double fy = (lab[0] + 16.0) / 116.0;
  return {w[0] * labFInverse(fy + lab[1] / 500.0), w[1] * labFInverse(fy),
          w[2] * labFInverse(fy - lab[2] / 200.0)};
}

Vec3 xyzToYCxCz(const Vec3& xyz) {
  static const Vec3 w = whiteXyz();
  const double x = xyz[0] / w[0], y = xyz[1] / w[1], z = xyz[2] / w[2];
  return {116.0 * y - 16.0, 500.0 * (x - y), 200.0 * (y - z)};
}
Vec3 yCxCzToXyz(const Vec3& c) {
  static const Vec3 w = whiteXyz();
  const double y = (c[0] + 16.0) / 116.0;
  return {w[0] * (y + c[1] / 500.0), w[1] * y, w[2] * (y - c[2] / 200.0)};
}

Vec3 srgbToLab(const Vec3& s) {
  return xyzToLab(linearRgbToXyz({srgbToLinear(s[0]), srgbToLinear(s[1]), srgbToLinear(s[2])}));
}
Vec3 labToSrgb(const Vec3& lab) {
  const Vec3 lin = xyzToLinearRgb(labToXyz(lab));
  Vec3 out;
  for (int c = 0; c < 3; ++c) out[c] = linearToSrgb(std::clamp(lin[c], 0.0, 1.0));
  return out;
}

}  // namespace translucent::analysis::color
