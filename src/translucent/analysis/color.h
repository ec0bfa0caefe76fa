// SPDX-License-Identifier: GPL-3.0-or-later
// Colour spaces shared by the perceptual metric (flip.h) and the false-colour maps
// (colormap.h): sRGB transfer function, linear sRGB <-> CIE XYZ (Rec. 709 primaries, D65 white),
// CIE XYZ <-> CIE L*a*b* and the linearised YCxCz opponent space (Flohr, Kolpatzik,
// Balasubramanian, Carrara, Bouman & Allebach 1993; used by ꟻLIP for its spatial filters).
//
// White is the D65 white of the sRGB matrix itself, the XYZ of linear RGB (1, 1, 1), so that RGB
// white maps to L* = 100, a* = b* = 0 exactly (up to rounding) and to Y = 100 in YCxCz.
#pragma once

#include <array>

namespace translucent::analysis::color {

using Vec3 = std::array<double, 3>;

// sRGB transfer function (IEC 61966-2-1): encoded [0, 1] <-> linear [0, 1].
double srgbToLinear(double v);
double linearToSrgb(double v);

// Linear sRGB <-> CIE XYZ (Y of white = 1).
Vec3 linearRgbToXyz(const Vec3& rgb);
Vec3 xyzToLinearRgb(const Vec3& xyz);
// The XYZ of linear RGB (1, 1, 1): the reference white of the two spaces below.
Vec3 whiteXyz();

// CIE 1976 L*a*b* relative to whiteXyz().
Vec3 xyzToLab(const Vec3& xyz);
Vec3 labToXyz(const Vec3& lab);

// YCxCz: L*a*b* with the cube root left out, Y = 116 Y/Yn - 16, Cx = 500 (X/Xn - Y/Yn),
// Cz = 200 (Y/Yn - Z/Zn); linear in XYZ, so that spatial filters can be applied in it.
Vec3 xyzToYCxCz(const Vec3& xyz);
Vec3 yCxCzToXyz(const Vec3& ycxcz);

// Shorthands: encoded sRGB -> L*a*b*, and the inverse (clamped to the displayable [0, 1]).
Vec3 srgbToLab(const Vec3& srgb);
Vec3 labToSrgb(const Vec3& lab);

}  // namespace translucent::analysis::color
