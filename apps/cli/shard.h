// SPDX-License-Identifier: GPL-3.0-or-later
// Path tracing in shards (issue 17): `translucent pathtrace slab|sphere|mesh … --shard I/N
// --partial FILE` traces shard I of the N shards of the run that the same command without them
// traces, and `translucent merge PART… [outputs]` adds the shards up and writes, bit for bit,
// what the unsharded command writes (timings and thread counts aside).
//
// A run is a sequence of K blocks of kBlockPhotons photons (per channel), block b always the same
// photons (its own random streams); shard I traces blocks [⌊I·K/N⌋, ⌊(I+1)·K/N⌋). Every sum
// across blocks is an exact fixed-point sum (reference/exact_sum.h), so the shards' run states
// add up to the whole run's state, bit for bit. A partial file records the command's arguments
// (without --shard, --partial, --threads and --time-limit, which do not change the numbers), a hash of them and
// of every input file's contents (the settings hash), the shard and its blocks, and the state.
// `merge` checks that the parts are the N shards of one run, each once and complete, adds their
// states and runs the recorded command with its tracing replaced by the merged state, the output
// options given to merge, and the inputs checked against the hash (a scene edited since the
// shards ran is an error).
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "translucent/reference/run_state.h"

namespace translucent::cli {

class OutputSet;

// main() records the command line (what a partial file stores).
void setCommandLine(int argc, char** argv);

struct ShardRange {
  uint64_t index = 0, shards = 1;  // shard I of N
  uint64_t first = 0, blocks = 0;  // its blocks [first, first + blocks)
  uint64_t total = 0;              // blocks of the whole run
};

struct ShardArgs {
  std::string shard, partial;
  void add(CLI::App& cmd);
  bool active() const { return !shard.empty() || !partial.empty(); }
  // Both given and well-formed ("I/N", 0 <= I < N); ParameterError naming the option otherwise.
  // `total`: blocks of the whole run.
  ShardRange range(uint64_t total) const;
  // The device a run of this command traces on (--device cpu|gpu|auto): a shard takes "auto" as
  // "cpu", since auto could pick different devices on different nodes, whose random streams
  // differ (the GPU's are its own), and the shards would not add up to one run.
  std::string device(const std::string& choice) const {
    return active() && choice == "auto" ? "cpu" : choice;
  }
};

// What traced a merged run, for its outputs: the shards' device ("gpu" when --device gpu, else
// "cpu": shards trace auto on the CPU). The renderer of each shard is not recorded.
inline std::string mergedDevice(const std::string& choice) {
  return choice == "gpu" ? "gpu" : "cpu";
}
// "N threads" for the CPU, else what traced ("gpu (<renderer>)"): the stderr summaries.
inline std::string tracedBy(const std::string& device, int threads) {
  return device == "cpu" ? std::to_string(threads) + " threads" : device;
}

// The merged run while `merge` runs the recorded command; null otherwise (the command traces).
struct MergedRun {
  reference::RunState state;
  std::vector<std::string> args;  // the recorded command
  std::string settings_hash;
  std::vector<std::string> files;  // the parts
  uint64_t shards = 0;
  double seconds = 0.0;  // sum over the shards
  int threads = 0;       // the most any shard used
};
const MergedRun* mergedRun();

// Output options cannot be combined with --shard (they belong to `merge`): ParameterError naming
// the first one given.
void refuseOutputsWithShard(const std::vector<std::pair<std::string, std::string>>& outputs);

// Shard: writes the partial file (checked like every output, beside the inputs, before the
// tracing starts: call checkPartialOutput first). Merge: checks that the inputs still hash to
// the parts' settings hash.
void checkPartialOutput(const ShardArgs& s, const OutputSet& inputs);
// `blocks_done`: the shard's blocks [first, first + blocks_done) that `state` holds (all of them
// when complete); a shard stopped early (SIGTERM, --time-limit) writes the blocks it finished,
// which a re-run of the same shard resumes from (readCheckpoint).
void writePartial(const ShardArgs& s, const ShardRange& r, const OutputSet& inputs,
                  const reference::RunState& state, double seconds, int threads, bool complete,
                  uint64_t blocks_done);

// Checkpoint and resume: the --partial file of an earlier run of this very shard (the same
// recorded arguments, inputs, shard and blocks) that stopped early. Its state holds the shard's
// first blocks_done blocks; blocks are deterministic by index and sums exact, so tracing the
// remaining blocks and adding the states gives the uninterrupted shard's state bit for bit.
// None (and the shard traces from its start) when the file is missing, is another run's or
// shard's, or records no finished blocks; a line on stderr says why when a file was there.
struct Checkpoint {
  reference::RunState state;
  uint64_t blocks_done = 0;
  double seconds = 0.0;
};
std::optional<Checkpoint> readCheckpoint(const ShardArgs& s, const ShardRange& r,
                                         const OutputSet& inputs);
void checkMergedInputs(const OutputSet& inputs);

void addMergeCommand(CLI::App& app);

}  // namespace translucent::cli
