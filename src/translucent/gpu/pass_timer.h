// SPDX-License-Identifier: GPL-3.0-or-later
// GPU time of rendering/compute passes, from GL_TIMESTAMP queries (ARB_timer_query, core in 3.3).
//
//   PassTimer timer;
//   { auto t = timer.scope("irradiance"); ... GL work ... }
//   { auto t = timer.scope("radiance"); ... }
//   for (const auto& p : timer.collect()) fmt::print("{}: {:.3f} ms\n", p.name, p.ms);
//
// Each pass records a timestamp before and after its commands (glQueryCounter), so passes may
// nest (unlike GL_TIME_ELAPSED queries). The time is what the GPU spent between the two points,
// measured without stalling the pipeline; collect() waits for the results.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "translucent/gpu/objects.h"

namespace translucent::gpu {

class PassTimer {
 public:
  struct Pass {
    std::string name;
    double ms = 0.0;  // GPU time between begin and end [milliseconds]
    int depth = 0;    // nesting level (0 = outermost)
  };

  // Throws GlError if the implementation has no timestamp counter (GL_QUERY_COUNTER_BITS = 0).
  PassTimer();

  void begin(std::string name);
  // Ends the innermost open pass (throws GlError if none is open).
  void end();

  class Scope {
   public:
    explicit Scope(PassTimer& timer) : timer_(&timer) {}
    // Never throws (a destructor that throws while an exception unwinds the stack terminates
    // the program): a GL error here is kept and thrown by the next collect().
    ~Scope() {
      if (timer_ != nullptr) timer_->endNoThrow();
    }
    Scope(Scope&& o) noexcept : timer_(o.timer_) { o.timer_ = nullptr; }
    Scope(const Scope&) = delete;
    Scope& operator=(const Scope&) = delete;
    Scope& operator=(Scope&&) = delete;

   private:
    PassTimer* timer_;
  };
  // begin(name) now, end() when the returned object goes out of scope.
  [[nodiscard]] Scope scope(std::string name);

  // Waits for the GPU and returns every ended pass since the last collect(), in begin order.
  // Throws GlError if a pass is still open, or for a GL error a Scope's destructor kept.
  std::vector<Pass> collect();
  // Time of the most recent collected pass with this name, or a negative number if none.
  double lastMs(std::string_view name) const;

 private:
  struct Pending {
    std::string name;
    int depth = 0;
    Query start, stop;
  };
  std::vector<Pending> pending_;
  std::vector<size_t> open_;  // indices into pending_
  std::vector<Pass> last_;
  std::string deferred_error_;  // from endNoThrow, thrown by collect()

  void endNoThrow() noexcept;
};

}  // namespace translucent::gpu
