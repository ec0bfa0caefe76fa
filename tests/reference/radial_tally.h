// SPDX-License-Identifier: GPL-3.0-or-later
// A test tally shared by the mesh-tracer tests: annuli about the origin of a top face (z = 0,
// normal +z) and the flux leaving anywhere else, per-photon scores kept for the second moments.
#pragma once

#include <algorithm>
#include <cmath>
#include <memory>
#include <utility>
#include <vector>

#include "translucent/reference/transport.h"

namespace translucent::reference::test_support {

class RadialTally final : public ExitTally {
 public:
  RadialTally(int bins, double dr) : bins_(bins), dr_(dr), annuli(static_cast<size_t>(bins) + 1) {}
  class Exits final : public Block {
   public:
    explicit Exits(const RadialTally& t) : t_(t) {}
    void record(const ExitRecord& e) override {
      if (e.normal.z > 0.5) {
        const double r = std::hypot(e.position.x, e.position.y);
        const int k = std::min(static_cast<int>(r / t_.dr_), t_.bins_);
        exits.push_back({k, e.weight});
      } else {
        exits.push_back({-1, e.weight});
      }
    }
    std::vector<std::pair<int, double>> exits;

   private:
    const RadialTally& t_;
  };
  std::unique_ptr<Block> newBlock() const override { return std::make_unique<Exits>(*this); }
  void merge(Block& b) override {
    for (const auto& [k, w] : static_cast<Exits&>(b).exits) {
      if (k < 0) {
        elsewhere.add(w);
      } else {
        top.add(w);
        annuli[static_cast<size_t>(k)].add(w);
      }
    }
  }
  int bins_;
  double dr_;
  std::vector<Moments> annuli;
  Moments top, elsewhere;
};

}  // namespace translucent::reference::test_support
