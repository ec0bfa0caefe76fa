// SPDX-License-Identifier: GPL-3.0-or-later
// Internal to src/reference: the deterministic block-parallel loop shared by the photon tracers
// (traceSlab, the closed-body tracers) and the sphere integrator.
//
// Workers claim blocks in increasing order and fill one result object each; finished results are
// merged strictly in block order (results that finish early wait in `pending`), so sums do not
// depend on which thread did what. A stop request (progress returning false) abandons blocks in
// flight; blocks already complete are still merged, in block order.
#pragma once

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <map>
#include <mutex>
#include <thread>
#include <vector>

namespace translucent::reference::detail {

struct BlockRun {
  uint64_t blocks_done = 0;  // blocks merged
  double seconds = 0.0;
  int threads = 0;
  bool stopped = false;
};

inline int resolveThreads(int requested, uint64_t blocks) {
  const int hw = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const int t = requested > 0 ? requested : hw;
  return static_cast<int>(std::max<uint64_t>(1, std::min<uint64_t>(static_cast<uint64_t>(t), blocks)));
}

// work(b, result, stop) fills `result` for block first + b' and returns false if it was cut short
// by `stop`; merge(b, result) runs under a lock, in block order; progress(blocks_done, seconds)
// runs on the calling thread about ten times a second, and returning false stops the run.
template <class Result, class Make, class Work, class Merge>
BlockRun runBlocks(uint64_t first, uint64_t count, int threads, Make&& make, Work&& work,
                   Merge&& merge, const std::function<bool(uint64_t, double)>& progress) {
  BlockRun run;
  run.threads = resolveThreads(threads, count);
  std::atomic<uint64_t> next{0};
  std::atomic<bool> stop{false};
  std::mutex mutex;
  std::condition_variable done;
  int running = run.threads;
  std::map<uint64_t, Result> pending;
  uint64_t nextMerge = 0;
  std::atomic<uint64_t> merged{0};

  auto worker = [&] {
    for (;;) {
      const uint64_t i = next.fetch_add(1);
      if (i >= count || stop.load()) break;
      Result r = make();
      const bool complete = work(first + i, r, stop);
      std::lock_guard lock(mutex);
      if (!complete) continue;  // a block cut short by a stop is dropped whole
      pending.emplace(i, std::move(r));
      while (!pending.empty() && pending.begin()->first == nextMerge) {
        merge(first + nextMerge, pending.begin()->second);
        pending.erase(pending.begin());
        ++nextMerge;
        ++merged;
      }
    }
    std::lock_guard lock(mutex);
    if (--running == 0) done.notify_all();
  };

  const auto start = std::chrono::steady_clock::now();
  auto elapsed = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  std::vector<std::thread> pool;
  pool.reserve(static_cast<size_t>(run.threads));
  for (int i = 0; i < run.threads; ++i) pool.emplace_back(worker);
  {
    std::unique_lock lock(mutex);
    while (running > 0) {
      done.wait_for(lock, std::chrono::milliseconds(100), [&] { return running == 0; });
      if (running == 0 || !progress || stop.load()) continue;
      const uint64_t m = merged.load() + pending.size();
      lock.unlock();
      const bool go_on = progress(m, elapsed());
      lock.lock();
      if (!go_on) stop = true;
    }
  }
  for (auto& t : pool) t.join();
  run.blocks_done = merged.load();
  for (auto& [i, r] : pending) {
    merge(first + i, r);
    ++run.blocks_done;
  }
  run.stopped = stop.load() && run.blocks_done < count;
  run.seconds = elapsed();
  return run;
}

}  // namespace translucent::reference::detail
