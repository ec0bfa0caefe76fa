// SPDX-License-Identifier: GPL-3.0-or-later
// A faithful scalar re-implementation of classic MCML (Wang, Jacques & Zheng 1995) for one layer:
// the baseline that the reference walker's speed is measured against (bench_reference).
#pragma once

#include <cstdint>

namespace translucent::bench {

struct McmlSetup {
  double mua = 10.0, mus = 90.0, g = 0.75;  // [1/cm]
  double n_above = 1.0, n_layer = 1.0, n_below = 1.0;
  double thickness = 0.02;  // [cm]; use a very large value for a semi-infinite medium
  // Scoring grids as in an MCML input file.
  double dz = 0.001, dr = 0.001;
  int nz = 40, nr = 50, na = 30;
};

struct McmlResult {
  double rsp = 0.0, rd = 0.0, tt = 0.0, a = 0.0;  // per incident photon
  // Standard error of rd from per-photon exit weights (not in MCML 1.2; one add per exiting
  // photon, so it does not change the cost).
  double rd_stderr = 0.0;
  uint64_t photons = 0;
  uint64_t steps = 0;  // hop-drop-spin steps
};

// Traces `photons` photons one after another in double precision with MCML's hop-drop-spin loop
// and its ran3 generator.
McmlResult runMcmlPeer(const McmlSetup& setup, uint64_t photons, int seed = 1);

}  // namespace translucent::bench
