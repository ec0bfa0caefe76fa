// SPDX-License-Identifier: GPL-3.0-or-later
// Statistics helpers for Monte Carlo tests: Pearson χ² and its upper-tail probability.
#pragma once

#include <cmath>
#include <vector>

namespace translucent::test {

// Regularised upper incomplete gamma Q(a, x), by series / continued fraction (Numerical Recipes).
inline double gammaQ(double a, double x) {
  if (x <= 0.0) return 1.0;
  const double gln = std::lgamma(a);
  if (x < a + 1.0) {
    double ap = a, sum = 1.0 / a, del = sum;
    for (int n = 0; n < 10000; ++n) {
      ap += 1.0;
      del *= x / ap;
      sum += del;
      if (std::abs(del) < std::abs(sum) * 1e-15) break;
    }
    return 1.0 - sum * std::exp(-x + a * std::log(x) - gln);
  }
  double b = x + 1.0 - a, c = 1.0 / 1e-300, d = 1.0 / b, h = d;
  for (int i = 1; i < 10000; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < 1e-300) d = 1e-300;
    c = b + an / c;
    if (std::abs(c) < 1e-300) c = 1e-300;
    d = 1.0 / d;
    const double del = d * c;
    h *= del;
    if (std::abs(del - 1.0) < 1e-15) break;
  }
  return std::exp(-x + a * std::log(x) - gln) * h;
}

// p-value of Pearson's χ² for observed counts against expected counts; bins with expected < 5
// are merged into their neighbour so the χ² approximation holds.
inline double chiSquarePValue(const std::vector<double>& observed,
                              const std::vector<double>& expected) {
  double chi2 = 0.0, accObs = 0.0, accExp = 0.0;
  int dof = -1;
  for (size_t i = 0; i < observed.size(); ++i) {
    accObs += observed[i];
    accExp += expected[i];
    if (accExp >= 5.0) {
      chi2 += (accObs - accExp) * (accObs - accExp) / accExp;
      accObs = accExp = 0.0;
      ++dof;
    }
  }
  if (accExp > 0.0) {
    chi2 += (accObs - accExp) * (accObs - accExp) / accExp;
    ++dof;
  }
  return gammaQ(0.5 * dof, 0.5 * chi2);
}

}  // namespace translucent::test
