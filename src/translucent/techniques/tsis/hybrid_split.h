// SPDX-License-Identifier: GPL-3.0-or-later
// The local/global split of the diffusion profile of the hybrid method (seed 3.3.1) and the
// sample pattern of its local term, the Local Translucent Shadow Map (seed 3.3.2, Fig. 3.9).
//
// Split:  W_l(r) = 1 − ½ e^{(r − R_p) K}  (r ≤ R_p),   ½ e^{−(r − R_p) K}  (r > R_p),
//         W_g(r) = 1 − W_l(r),
// The seed prints e^{−(r − R_p) K} in the first branch too, which makes W_l negative for
// r < R_p − ln 2 / K (and W_g > 1): a sign slip, since its Fig. 3.4 shows W_l rising to 1 at
// r = 0. The symmetric form above is continuous at R_p (½), in [0, 1], and is what the figure
// shows. So R_d = R_d W_l + R_d W_g exactly and B = B_l + B_g for any estimator linear in R_d.
// R_p per channel is the largest r at which the importance 2πr R_d(r) reaches a lower bound (the
// seed's 0.1 in its experiments, Fig. 3.5). The seed gives K = 1.5 and the bound 0.1 for models
// measured in millimetres (Fig. 3.4: R_p = 2.4141 mm for skimmilk's red channel); here both are
// taken per millimetre and converted to scene units with the medium's scale (the presets'
// coefficients are per mm: one scene unit is `scale` mm), so that the split is the seed's
// whatever the model's size in scene units.
//
// Pattern: L circles of C samples around the centre sample, L×C + 1 in all (Fig. 3.9: 4×4 + 1).
// The seed takes the radii "from the importance sampling strategy on the projection plane" of
// Mertens et al. 2003 (the seed's §3.3.2 swaps this citation with Dachsbacher & Stamminger's
// translucent shadow maps): here the plane is cut into L + 1 zones of equal mass of the local
// profile's radial density 2πr R_d W_l (the channels' normalised densities averaged, so one
// pattern serves all three): the centre sample stands for the central disc, circle k for ring k
// at the ring's median radius, angles uniform (each circle turned by the golden angle).
// The seed weights a sample by "the corresponding area" A of its zone share. We weight it by
// the zone's share of the profile instead, A_c = ∫_zone R_c W_l dA / (C R_c(ρ) W_l(ρ)), the
// stratified importance-sampling weight 1/(N p) (Mertens et al.'s estimator): then a constant
// irradiance on a plane is integrated exactly in every channel, where the geometric area would
// weight the centre sample by the profile's peak over the whole central disc. The zones end at
// the radius holding 99.9% of the local term.
#pragma once

#include <array>
#include <vector>

#include <glm/vec4.hpp>

#include "translucent/bssrdf/profile_table.h"

namespace translucent::tsis {

// Seed 3.3.1's W_l(r) for split radius rp and constant k (same length units).
double localWeight(double r, double rp, double k);
inline double globalWeight(double r, double rp, double k) { return 1.0 - localWeight(r, rp, k); }

// The largest r of the table's grid with 2πr R(r) ≥ bound, or 0 if there is none (the profile
// is everywhere below the bound: everything is global but the ½ at r = 0).
double autoSplitRadius(const bssrdf::ProfileTable& table, double bound);

struct HybridSplit {
  std::array<double, 3> rp{};  // R_p per channel [scene units]
  double k = 0.0;              // K [1/scene unit]
};

// R_p per channel from the tables (in scene units) with K and the bound given per millimetre
// and `mmPerUnit` millimetres per scene unit (the medium's scale).
HybridSplit makeHybridSplit(const std::array<bssrdf::ProfileTable, 3>& tables, double kPerMm,
                            double boundPerMm, double mmPerUnit);

// R(r_i) W(r_i) per channel on the tables' grid (W = W_l if `local`, else W_g), for the GPU.
std::vector<glm::vec4> weightedProfile(const std::array<bssrdf::ProfileTable, 3>& tables,
                                       const HybridSplit& split, bool local);

// The pattern, two vec4 per sample: (x, y, ρ, 0) the offset on the projection plane and its
// radius [scene units], then (A_r, A_g, A_b, 0) the weights [scene units²] (see above).
std::vector<glm::vec4> localPattern(const std::array<bssrdf::ProfileTable, 3>& tables,
                                    const HybridSplit& split, int circles, int perCircle);

}  // namespace translucent::tsis
