// SPDX-License-Identifier: GPL-3.0-or-later
// Classic MCML for one layer, re-implemented from mcmlgo.c / mcmlmain.c of MCML 1.2 (Wang,
// Jacques & Zheng 1995) so that the reference walker can be timed against it in one binary.
//
// Kept as in MCML, because these are what the speed comparison is about: double precision, one
// photon at a time, the hop / drop / spin loop, the absorbed weight dropped into the A[z][r] grid
// at every interaction (with its sqrt and divisions), Rd[r][a] / Tt[r][a] scored with acos at
// every exit, HG sampling with cos/sin of the azimuth, the direction update dividing by
// sqrt(1 - uz²), RFresnel with its trigonometric identities, roulette at w < 1e-4 with chance
// 0.1, and Knuth's subtractive generator ran3 (Numerical Recipes) as MCML's RandomNum.
// Left out: multiple layers, glass layers, partial reflection, file I/O.
#include "mcml_peer.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace translucent::bench {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kWeight = 1e-4;  // MCML: WEIGHT
constexpr double kChance = 0.1;   // MCML: CHANCE
constexpr double kCosZero = 1.0 - 1.0e-12;
constexpr double kCos90D = 1.0e-6;

// ran3 of Numerical Recipes in C (Knuth's subtractive method), MCML's RandomNum.
class Ran3 {
 public:
  explicit Ran3(int seed) {
    long mj = kMSeed - (seed < 0 ? -seed : seed);
    mj %= kMBig;
    ma_[55] = mj;
    long mk = 1;
    for (int i = 1; i <= 54; i++) {
      const int ii = (21 * i) % 55;
      ma_[ii] = mk;
      mk = mj - mk;
      if (mk < 0) mk += kMBig;
      mj = ma_[ii];
    }
    for (int k = 1; k <= 4; k++)
      for (int i = 1; i <= 55; i++) {
        ma_[i] -= ma_[1 + (i + 30) % 55];
        if (ma_[i] < 0) ma_[i] += kMBig;
      }
    inext_ = 0;
    inextp_ = 31;
  }
  double operator()() {
    if (++inext_ == 56) inext_ = 1;
    if (++inextp_ == 56) inextp_ = 1;
    long mj = ma_[inext_] - ma_[inextp_];
    if (mj < 0) mj += kMBig;
    ma_[inext_] = mj;
    return static_cast<double>(mj) * 1.0e-9;
  }

 private:
  static constexpr long kMBig = 1000000000, kMSeed = 161803398;
  long ma_[56] = {};
  int inext_ = 0, inextp_ = 0;
};

struct Photon {
  double x, y, z, ux, uy, uz, w;
  bool dead;
  double s, sleft;
};

double rFresnel(double n1, double n2, double ca1, double* ca2) {
  if (n1 == n2) {
    *ca2 = ca1;
    return 0.0;
  }
  if (ca1 > kCosZero) {
    *ca2 = ca1;
    const double r = (n2 - n1) / (n2 + n1);
    return r * r;
  }
  if (ca1 < kCos90D) {
    *ca2 = 0.0;
    return 1.0;
  }
  const double sa1 = std::sqrt(1 - ca1 * ca1);
  const double sa2 = n1 * sa1 / n2;
  if (sa2 >= 1.0) {
    *ca2 = 0.0;
    return 1.0;
  }
  const double c2 = std::sqrt(1 - sa2 * sa2);
  *ca2 = c2;
  const double cap = ca1 * c2 - sa1 * sa2, cam = ca1 * c2 + sa1 * sa2;
  const double sap = sa1 * c2 + ca1 * sa2, sam = sa1 * c2 - ca1 * sa2;
  return 0.5 * sam * sam * (cam * cam + cap * cap) / (sap * sap * cam * cam);
}

class Mcml {
 public:
  Mcml(const McmlSetup& s, int seed)
      : in_(s),
        rand_(seed),
        mut_(s.mua + s.mus),
        da_(0.5 * kPi / s.na),
        aRz_(static_cast<size_t>(s.nz * s.nr)),
        rdRa_(static_cast<size_t>(s.nr * s.na)),
        ttRa_(static_cast<size_t>(s.nr * s.na)) {
    // Critical cosines, as MCML's CriticalAngle().
    cosCrit0_ = s.n_layer > s.n_above ? std::sqrt(1.0 - s.n_above * s.n_above / (s.n_layer * s.n_layer)) : 0.0;
    cosCrit1_ = s.n_layer > s.n_below ? std::sqrt(1.0 - s.n_below * s.n_below / (s.n_layer * s.n_layer)) : 0.0;
    const double r = (s.n_above - s.n_layer) / (s.n_above + s.n_layer);
    rsp_ = r * r;
  }

  void run(uint64_t photons) {
    for (uint64_t i = 0; i < photons; ++i) {
      Photon p{0, 0, 0, 0, 0, 1, 1.0 - rsp_, false, 0, 0};  // LaunchPhoton
      do hopDropSpin(p);
      while (!p.dead);
    }
    n_ += photons;
  }

  McmlResult result() const {
    McmlResult r;
    r.photons = n_;
    r.rsp = rsp_;
    for (double v : rdRa_) r.rd += v;
    for (double v : ttRa_) r.tt += v;
    for (double v : aRz_) r.a += v;
    const double n = static_cast<double>(n_);
    r.rd /= n;
    r.tt /= n;
    r.a /= n;
    r.rd_stderr = std::sqrt(std::max(0.0, rdSum2_ / n - r.rd * r.rd) / (n - 1.0));
    r.steps = steps_;
    return r;
  }

 private:
  void hopDropSpin(Photon& p) {
    ++steps_;
    stepSize(p);
    if (hitBoundary(p)) {
      hop(p);
      crossOrNot(p);
    } else {
      hop(p);
      drop(p);
      spin(p);
    }
    if (p.w < kWeight && !p.dead) roulette(p);
  }

  void stepSize(Photon& p) {
    if (p.sleft == 0.0) {
      double rnd;
      do rnd = rand_();
      while (rnd <= 0.0);
      p.s = -std::log(rnd) / mut_;
    } else {
      p.s = p.sleft / mut_;
      p.sleft = 0.0;
    }
  }

  bool hitBoundary(Photon& p) {
    double dlb = 0.0;
    if (p.uz > 0.0)
      dlb = (in_.thickness - p.z) / p.uz;
    else if (p.uz < 0.0)
      dlb = (0.0 - p.z) / p.uz;
    if (p.uz != 0.0 && p.s > dlb) {
      p.sleft = (p.s - dlb) * mut_;
      p.s = dlb;
      return true;
    }
    return false;
  }

  static void hop(Photon& p) {
    p.x += p.s * p.ux;
    p.y += p.s * p.uy;
    p.z += p.s * p.uz;
  }

  void drop(Photon& p) {
    const double izd = p.z / in_.dz;
    const size_t iz = izd > in_.nz - 1 ? static_cast<size_t>(in_.nz - 1) : static_cast<size_t>(izd);
    const double ird = std::sqrt(p.x * p.x + p.y * p.y) / in_.dr;
    const size_t ir = ird > in_.nr - 1 ? static_cast<size_t>(in_.nr - 1) : static_cast<size_t>(ird);
    const double dwa = p.w * in_.mua / mut_;
    p.w -= dwa;
    aRz_[iz * static_cast<size_t>(in_.nr) + ir] += dwa;
  }

  double spinTheta(double g) {
    if (g == 0.0) return 2 * rand_() - 1;
    const double temp = (1 - g * g) / (1 - g + 2 * g * rand_());
    double cost = (1 + g * g - temp * temp) / (2 * g);
    if (cost < -1) cost = -1;
    else if (cost > 1) cost = 1;
    return cost;
  }

  void spin(Photon& p) {
    const double ux = p.ux, uy = p.uy, uz = p.uz;
    const double cost = spinTheta(in_.g);
    const double sint = std::sqrt(1.0 - cost * cost);
    const double psi = 2.0 * kPi * rand_();
    const double cosp = std::cos(psi);
    const double sinp = psi < kPi ? std::sqrt(1.0 - cosp * cosp) : -std::sqrt(1.0 - cosp * cosp);
    if (std::fabs(uz) > kCosZero) {
      p.ux = sint * cosp;
      p.uy = sint * sinp;
      p.uz = cost * (uz >= 0 ? 1 : -1);
    } else {
      const double temp = std::sqrt(1.0 - uz * uz);
      p.ux = sint * (ux * uz * cosp - uy * sinp) / temp + ux * cost;
      p.uy = sint * (uy * uz * cosp + ux * sinp) / temp + uy * cost;
      p.uz = -sint * cosp * temp + uz * cost;
    }
  }

  void record(Photon& p, std::vector<double>& grid, double cosExit) {
    size_t ir = static_cast<size_t>(std::sqrt(p.x * p.x + p.y * p.y) / in_.dr);
    if (ir > static_cast<size_t>(in_.nr - 1)) ir = static_cast<size_t>(in_.nr - 1);
    size_t ia = static_cast<size_t>(std::acos(cosExit) / da_);
    if (ia > static_cast<size_t>(in_.na - 1)) ia = static_cast<size_t>(in_.na - 1);
    grid[ir * static_cast<size_t>(in_.na) + ia] += p.w;
    p.w = 0.0;
    p.dead = true;
  }

  void crossOrNot(Photon& p) {
    double uz1 = 0.0, r = 0.0;
    if (p.uz < 0.0) {  // CrossUpOrNot
      if (-p.uz <= cosCrit0_) r = 1.0;
      else r = rFresnel(in_.n_layer, in_.n_above, -p.uz, &uz1);
      if (rand_() > r) {
        p.uz = -uz1;
        rdSum2_ += p.w * p.w;
        record(p, rdRa_, -p.uz);
      } else {
        p.uz = -p.uz;
      }
    } else {  // CrossDnOrNot
      if (p.uz <= cosCrit1_) r = 1.0;
      else r = rFresnel(in_.n_layer, in_.n_below, p.uz, &uz1);
      if (rand_() > r) {
        p.uz = uz1;
        record(p, ttRa_, p.uz);
      } else {
        p.uz = -p.uz;
      }
    }
  }

  void roulette(Photon& p) {
    if (p.w == 0.0) p.dead = true;
    else if (rand_() < kChance) p.w /= kChance;
    else p.dead = true;
  }

  McmlSetup in_;
  Ran3 rand_;
  double mut_, da_, rsp_ = 0.0, cosCrit0_ = 0.0, cosCrit1_ = 0.0;
  std::vector<double> aRz_, rdRa_, ttRa_;
  double rdSum2_ = 0.0;
  uint64_t n_ = 0, steps_ = 0;
};

}  // namespace

McmlResult runMcmlPeer(const McmlSetup& setup, uint64_t photons, int seed) {
  Mcml m(setup, seed);
  m.run(photons);
  return m.result();
}

}  // namespace translucent::bench
