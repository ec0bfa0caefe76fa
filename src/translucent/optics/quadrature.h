// SPDX-License-Identifier: GPL-3.0-or-later
// 8-point Gauss-Legendre rule on [-1, 1], shared by every fixed-panel quadrature in the library
// (Fdr, profile cumulatives, closed-form checks).
#pragma once

namespace translucent {

inline constexpr double kGauss8X[8] = {-0.9602898564975363, -0.7966664774136267,
                                       -0.5255324099163290, -0.1834346424956498,
                                       0.1834346424956498,  0.5255324099163290,
                                       0.7966664774136267,  0.9602898564975363};
inline constexpr double kGauss8W[8] = {0.1012285362903763, 0.2223810344533745,
                                       0.3137066458778873, 0.3626837833783620,
                                       0.3626837833783620, 0.3137066458778873,
                                       0.2223810344533745, 0.1012285362903763};

}  // namespace translucent
