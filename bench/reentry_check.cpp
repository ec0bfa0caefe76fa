// SPDX-License-Identifier: GPL-3.0-or-later
// Re-entry in the reference mesh tracer, measured on a scene at η = 1 (BENCHMARKS.md, "Mesh
// tracer: light that re-enters the body"). Two modes:
//
//   reentry_check delta SCENE PHOTONS SEED OUT.exr      (PHOTONS per channel, e.g. 2e6)
//       An independent estimate of the exitance image: delta (Woodcock) tracking with majorant
//       σt everywhere and null collisions outside the mesh; inside/outside follows the parity of
//       the surface crossings. It has no exit, re-entry or free-path carry-over logic; every
//       outward crossing is handed to the same ImageTally scoring (projection, shadow ray) as
//       the tracer's exits, so both estimate the same pixel averages. Prints the exited flux.
//
//   reentry_check compare BEFORE1 AFTER1 BEFORE2 AFTER2 DELTA X0 Y0 X1 Y1
//       Ratios of image sums (R+G+B) from `translucent pathtrace mesh --exr` files: before and
//       after re-entry, two seeds each, and the delta-tracking image. "Concave" pixels are those
//       where AFTER1/BEFORE1 > 1.1; their ratio is then taken from the seed-2 pair (selecting and
//       measuring on the same noise would bias it). [X0, X1) x [Y0, Y1) is a region of interest
//       (the bunny's ears and the head below them). Standard errors treat pixels as
//       independent (photons shared by pixels make them weakly anti-correlated).
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <thread>
#include <vector>

#include "translucent/io/image_io.h"
#include "translucent/reference/camera.h"
#include "translucent/reference/mesh_tracer.h"
#include "translucent/reference/transport_impl.h"
#include "translucent/scene/scene.h"

namespace {

using namespace translucent;
using namespace translucent::reference;

int delta(const std::string& scenePath, uint64_t photons, uint64_t seed, const std::string& out) {
  const scene::Scene sc = scene::loadScene(scenePath);
  const MeshBody body(scene::loadSceneMesh(sc));
  const std::vector<Light> lights = detail::validatedLights(scene::referenceLights(sc));
  std::vector<ScalarMedium> channels;
  for (int c = 0; c < 3; ++c) channels.push_back(sc.medium.channel(c));
  for (const auto& c : channels)
    if (c.eta != 1.0) throw ParameterError("reentry_check delta: the scene's eta must be 1");
  const BoundingSphere bs = body.bounds();
  const auto walks = detail::channelWalks(bs, channels, lights);
  ImageTally tally(body, sc.camera, {1.0, 1.0, 1.0}, sc.cone_angle);
  const uint64_t blocks = (photons + kBlockPhotons - 1) / kBlockPhotons;
  const double eps = body.epsilon();
  std::vector<std::unique_ptr<ExitTally::Block>> results(blocks * 3);
  std::vector<double> exited(blocks * 3);
  std::atomic<uint64_t> next{0}, lost{0};

  auto worker = [&] {
    for (uint64_t b; (b = next.fetch_add(1)) < blocks;) {
      for (size_t c = 0; c < 3; ++c) {
        const detail::ChannelWalk& W = walks[c];
        auto block = tally.newBlock();
        Rng rng(seed ^ 0xde17aull, b * 3 + c);
        double ex = 0.0;
        for (uint64_t p = 0; p < kBlockPhotons; ++p) {
          size_t li = 0;
          if (lights.size() > 1) {
            const double u = detail::uniform01(rng) * W.lightCdf.back();
            li = std::min<size_t>(static_cast<size_t>(std::upper_bound(W.lightCdf.begin(), W.lightCdf.end(), u) -
                                                      W.lightCdf.begin()),
                                  lights.size() - 1);
          }
          const detail::Emission em = detail::emit(lights[li], bs, static_cast<int>(c), rng);
          glm::dvec3 x = em.origin, d = em.direction;
          bool inside = false;
          for (;;) {
            const double s = -std::log(1.0 - detail::uniform01(rng)) / W.sigmaT;
            // The surface crossings on [0, s] flip the parity; outward ones are exits.
            SurfaceHit h;
            glm::dvec3 y = x;
            double done = 0.0, tmin = 0.0;
            while (body.intersect(y, d, tmin, s - done, h)) {
              y += h.t * d;
              done += h.t;
              tmin = eps;
              if (inside) {
                ExitRecord e;
                e.position = y;
                e.normal = glm::dot(h.normal, d) > 0.0 ? h.normal : -h.normal;
                e.direction = d;
                e.weight = W.totalFlux;
                e.channel = static_cast<int>(c);
                block->record(e);
                ex += W.totalFlux;
              }
              inside = !inside;
            }
            x += s * d;
            const glm::dvec3 r = x - bs.center;
            if (!inside) {
              // Outside the bounding sphere and moving away: no straight line comes back.
              if (glm::dot(r, r) > bs.radius * bs.radius && glm::dot(r, d) > 0.0) break;
              continue;  // a null collision in air
            }
            if (glm::dot(r, r) > 1.01 * bs.radius * bs.radius) {  // parity lost (a missed hit)
              ++lost;
              break;
            }
            if (detail::uniform01(rng) < W.absorbProbability) break;
            const double mu = sampleHgCosine(W.g, rng.uniform());
            const double phi = 2.0 * std::numbers::pi * detail::uniform01(rng);
            const double st = std::sqrt(std::max(0.0, 1.0 - mu * mu));
            glm::dvec3 t1, t2;
            detail::tangentFrame(d, t1, t2);
            d = glm::normalize(st * std::cos(phi) * t1 + st * std::sin(phi) * t2 + mu * d);
          }
          block->endPhoton();
        }
        exited[b * 3 + c] = ex;
        results[b * 3 + c] = std::move(block);
      }
    }
  };
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<std::thread> pool;
  for (unsigned i = 0; i < std::max(1u, std::thread::hardware_concurrency()); ++i) pool.emplace_back(worker);
  for (auto& t : pool) t.join();
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  double ex[3] = {0, 0, 0};
  for (size_t i = 0; i < results.size(); ++i) {  // in block order: deterministic sums
    tally.merge(*results[i]);
    ex[i % 3] += exited[i];
  }
  const uint64_t n = blocks * kBlockPhotons;
  const std::vector<uint64_t> counts(3, n);
  tally.addPhotons(counts);
  const McImage& img = tally.images().exitance;
  const std::vector<float> rgb = img.rgb(), se = img.rgbStdError();
  const analysis::ExrLayer layers[] = {{"stderr", se}};
  analysis::writeExr(out, img.width(), img.height(), rgb, layers,
                     std::vector<std::pair<std::string, std::string>>{
                         {"translucent:source", "reentry_check delta " + scenePath}});
  std::printf("delta tracking: %llu photons per channel in %.1f s, %llu lost parity; exited flux per "
              "photon R %.5f G %.5f B %.5f; wrote %s\n",
              static_cast<unsigned long long>(n), secs, static_cast<unsigned long long>(lost.load()),
              ex[0] / static_cast<double>(n), ex[1] / static_cast<double>(n),
              ex[2] / static_cast<double>(n), out.c_str());
  return 0;
}

// ----- compare -----------------------------------------------------------------------------

struct Image {
  int w = 0, h = 0, nc = 0, r = 0, s = 0;  // first channel of R,G,B and of stderr.R,G,B
  std::vector<double> px;
  double sum(int x, int y) const {
    const size_t o = (static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x)) * static_cast<size_t>(nc);
    return px[o + size_t(r)] + px[o + size_t(r) + 1] + px[o + size_t(r) + 2];
  }
  double var(int x, int y) const {
    const size_t o = (static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x)) * static_cast<size_t>(nc);
    double v = 0.0;
    for (size_t c = 0; c < 3; ++c) v += px[o + size_t(s) + c] * px[o + size_t(s) + c];
    return v;
  }
};

Image load(const std::string& path) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) throw std::runtime_error("cannot read " + path);
  const OIIO::ImageSpec& spec = in->spec();
  Image I;
  I.w = spec.width;
  I.h = spec.height;
  I.nc = spec.nchannels;
  std::vector<float> f(static_cast<size_t>(I.w) * static_cast<size_t>(I.h) * static_cast<size_t>(I.nc));
  auto find = [&](const char* name) {
    for (int i = 0; i < I.nc; ++i)
      if (spec.channelnames[static_cast<size_t>(i)] == name) return i;
    throw std::runtime_error(path + ": no channel " + name);
  };
  I.r = find("R");
  I.s = find("stderr.R");
  in->read_image(0, 0, 0, I.nc, OIIO::TypeDesc::FLOAT, f.data());
  I.px.assign(f.begin(), f.end());
  return I;
}

int compare(char** argv) {
  const Image b1 = load(argv[0]), a1 = load(argv[1]), b2 = load(argv[2]), a2 = load(argv[3]),
              dt = load(argv[4]);
  const int x0 = std::stoi(argv[5]), y0 = std::stoi(argv[6]), x1 = std::stoi(argv[7]),
            y1 = std::stoi(argv[8]);
  const int W = b1.w;
  std::vector<int> all, concave, region;
  for (int y = 0; y < b1.h; ++y)
    for (int x = 0; x < W; ++x) {
      if (!(b1.sum(x, y) > 0.0 && b2.sum(x, y) > 0.0)) continue;
      all.push_back(y * W + x);
      if (a1.sum(x, y) > 1.1 * b1.sum(x, y)) concave.push_back(y * W + x);
      if (x >= x0 && x < x1 && y >= y0 && y < y1) region.push_back(y * W + x);
    }
  // Ratio of sums and its standard error (delta method).
  auto ratio = [&](const Image& A, const Image& B, const std::vector<int>& set) {
    double sa = 0, sb = 0, va = 0, vb = 0;
    for (int p : set) {
      sa += A.sum(p % W, p / W);
      sb += B.sum(p % W, p / W);
      va += A.var(p % W, p / W);
      vb += B.var(p % W, p / W);
    }
    const double q = sa / sb;
    return std::pair{q, q * std::sqrt(va / (sa * sa) + vb / (sb * sb))};
  };
  auto row = [&](const char* what, const std::vector<int>& set) {
    const auto ab = ratio(a2, b2, set), bd = ratio(b2, dt, set), ad = ratio(a2, dt, set),
               ad1 = ratio(a1, dt, set);
    std::printf("%-34s %5zu px  after/before %.4f ± %.4f  before/delta %.4f ± %.4f  after/delta %.4f ± %.4f (seed 1: %.4f ± %.4f)\n",
                what, set.size(), ab.first, ab.second, bd.first, bd.second, ad.first, ad.second,
                ad1.first, ad1.second);
  };
  std::printf("(ratios of R+G+B sums; after/before and after/delta from the seed-2 runs)\n");
  row("all lit pixels", all);
  row("after1/before1 > 1.1 (concave)", concave);
  row("region of interest", region);
  // Per pixel and channel: z of the two-seed mean of AFTER (or BEFORE) against DELTA, where the
  // delta-tracking pixel has enough samples for a Gaussian z (value > 5 standard errors).
  for (const auto& [name, A1, A2] : {std::tuple{"after", &a1, &a2}, std::tuple{"before", &b1, &b2}}) {
    double z2 = 0;
    int k = 0, big = 0;
    for (int p : all)
      for (int c = 0; c < 3; ++c) {
        auto at = [&](const Image& I, int off) {
          return I.px[static_cast<size_t>(p) * static_cast<size_t>(I.nc) + static_cast<size_t>(off + c)];
        };
        const double m = 0.5 * (at(*A1, A1->r) + at(*A2, A2->r));
        const double vm = 0.25 * (std::pow(at(*A1, A1->s), 2) + std::pow(at(*A2, A2->s), 2));
        const double d = at(dt, dt.r), vd = std::pow(at(dt, dt.s), 2);
        if (!(d > 5.0 * std::sqrt(vd))) continue;
        const double z = (m - d) / std::sqrt(vm + vd);
        z2 += z * z;
        ++k;
        big += std::abs(z) > 4.0;
      }
    std::printf("per-pixel z, %s vs delta: mean z² %.3f over %d pixel-channels, %d with |z| > 4\n", name,
                z2 / k, k, big);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const std::string mode = argc > 1 ? argv[1] : "";
    if (mode == "delta" && argc == 6) return delta(argv[2], static_cast<uint64_t>(std::stod(argv[3])), std::stoull(argv[4]), argv[5]);
    if (mode == "compare" && argc == 11) return compare(argv + 2);
    std::fprintf(stderr,
                 "usage: reentry_check delta SCENE PHOTONS SEED OUT.exr\n"
                 "       reentry_check compare BEFORE1 AFTER1 BEFORE2 AFTER2 DELTA X0 Y0 X1 Y1\n");
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "reentry_check: %s\n", e.what());
    return 1;
  }
}
