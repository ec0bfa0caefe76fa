// SPDX-License-Identifier: GPL-3.0-or-later
// Sharded path tracing and `translucent merge` (shard.h).
#include "shard.h"

#include "translucent/io/input_file.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "commands.h"
#include "translucent/geometry/atomic_file.h"
#include "translucent/io/json.h"
#include "translucent/io/output_guard.h"
#include "translucent/optics/medium.h"  // ParameterError
#include "output_guard.h"
#include "safe_print.h"

namespace translucent::cli {
namespace fs = std::filesystem;
namespace {

std::vector<std::string> gCommandLine;  // argv[1..]
const MergedRun* gMerged = nullptr;

// Options that do not change a complete run's numbers, left out of what a partial file records
// (shards of one run may use other thread counts and time limits; an incomplete shard is refused
// by merge anyway).
bool isShardOnly(const std::string& option) {
  return option == "--shard" || option == "--partial" || option == "--threads" ||
         option == "--time-limit";
}

// The recorded arguments: the command line without the shard-only options and their values
// (`--opt value` and `--opt=value`).
std::vector<std::string> recordedArguments() {
  std::vector<std::string> out;
  for (size_t i = 0; i < gCommandLine.size(); ++i) {
    const std::string& a = gCommandLine[i];
    const std::string name = a.substr(0, a.find('='));
    if (isShardOnly(name)) {
      if (name == a) ++i;  // its value follows
      continue;
    }
    out.push_back(a);
  }
  return out;
}

std::string readBytes(const fs::path& path, const std::string& what) {
  if (const std::string why = io::irregularInput(path); !why.empty())
    throw ParameterError(fmt::format("{} '{}' {}: expected a file", what, path.string(), why));
  std::ifstream f(path, std::ios::binary);
  if (!f) throw ParameterError(fmt::format("{} '{}': cannot read the file", what, path.string()));
  std::ostringstream s;
  s << f.rdbuf();
  if (f.bad()) throw ParameterError(fmt::format("{} '{}': read error", what, path.string()));
  return s.str();
}

// The settings hash: the recorded arguments and the contents of every input file.
std::string settingsHash(const std::vector<std::string>& args, const OutputSet& inputs) {
  nlohmann::json j = {{"version", "translucent 0.1.0"}, {"args", args}};
  nlohmann::json files = nlohmann::json::array();
  for (const auto& [what, path] : inputs.inputs()) {
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) continue;
    files.push_back({{"what", what},
                     {"path", path.string()},
                     {"hash", fmt::format("{:016x}", geometry::contentHash(readBytes(path, what)))}});
  }
  j["inputs"] = files;
  return fmt::format("{:016x}", geometry::contentHash(j.dump()));
}

uint64_t parseIndex(const std::string& text, const std::string& what) {
  if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos || text.size() > 18)
    throw ParameterError(fmt::format("--shard: {} '{}' is not a whole number", what, text));
  return std::stoull(text);
}

}  // namespace

void setCommandLine(int argc, char** argv) {
  gCommandLine.assign(argv + std::min(argc, 1), argv + argc);
}

const MergedRun* mergedRun() { return gMerged; }

void ShardArgs::add(CLI::App& cmd) {
  cmd.add_option("--shard", shard,
                 "Trace only shard I of N (I/N, 0 <= I < N) of this run's photon blocks and write "
                 "it to --partial; `translucent merge` adds the N parts up into exactly this "
                 "run's outputs (see README, \"Path tracing on a Slurm cluster\")");
  outputOption(cmd.add_option("--partial", partial,
                              "With --shard: the partial result to write (binary; e.g. "
                              "part-3.tpart)"));
}

ShardRange ShardArgs::range(uint64_t total) const {
  if (shard.empty()) throw ParameterError("--partial: given without --shard I/N");
  if (partial.empty())
    throw ParameterError(fmt::format("--shard {}: give --partial FILE, where the shard's result "
                                     "goes", shard));
  const size_t slash = shard.find('/');
  if (slash == std::string::npos)
    throw ParameterError(fmt::format("--shard '{}': expected I/N, e.g. 0/4", shard));
  ShardRange r;
  r.index = parseIndex(shard.substr(0, slash), "I");
  r.shards = parseIndex(shard.substr(slash + 1), "N");
  if (r.shards == 0 || r.index >= r.shards)
    throw ParameterError(fmt::format("--shard {}: expected 0 <= I < N", shard));
  r.total = total;
  // ⌊I·K/N⌋ in 128 bits (K and N may each be large).
  auto edge = [&](uint64_t i) {
    return static_cast<uint64_t>(static_cast<reference::UFixed>(i) * total / r.shards);
  };
  r.first = edge(r.index);
  r.blocks = edge(r.index + 1) - r.first;
  return r;
}

void refuseOutputsWithShard(const std::vector<std::pair<std::string, std::string>>& outputs) {
  for (const auto& [option, path] : outputs)
    if (!path.empty())
      throw ParameterError(fmt::format(
          "{} {}: a shard writes only its --partial file; give the outputs to `translucent "
          "merge` (which writes what this command would write unsharded)", option, path));
}

void checkPartialOutput(const ShardArgs& s, const OutputSet& inputs) {
  OutputSet outputs = inputs;
  outputs.output("--partial", s.partial);
  outputs.check();
}

void writePartial(const ShardArgs& s, const ShardRange& r, const OutputSet& inputs,
                  const reference::RunState& state, double seconds, int threads, bool complete,
                  uint64_t blocks_done) {
  const std::vector<std::string> args = recordedArguments();
  const nlohmann::json header = {{"args", args},
                                 {"settings_hash", settingsHash(args, inputs)},
                                 {"shard", r.index},
                                 {"shards", r.shards},
                                 {"first_block", r.first},
                                 {"blocks", r.blocks},
                                 {"total_blocks", r.total},
                                 {"complete", complete},
                                 {"blocks_done", complete ? r.blocks : blocks_done},
                                 {"seconds", seconds},
                                 {"threads", threads}};
  writeTextOutput("--partial", s.partial, reference::encodeRunState(header.dump(), state));
  printStderr("{}: shard {}/{} (blocks {}..{} of {}){}; wrote {}\n",
              args.size() >= 2 ? args[0] + " " + args[1] : "pathtrace", r.index, r.shards, r.first,
              r.first + r.blocks, r.total,
              complete ? "" : fmt::format(", stopped early after {} of its {} blocks: INCOMPLETE "
                                          "(merge will refuse it; run the shard again: it resumes "
                                          "from this file)", blocks_done, r.blocks),
              s.partial);
}

std::optional<Checkpoint> readCheckpoint(const ShardArgs& s, const ShardRange& r,
                                         const OutputSet& inputs) {
  std::error_code ec;
  if (s.partial.empty() || isStdoutPath(s.partial) || !fs::is_regular_file(s.partial, ec))
    return std::nullopt;
  const auto notResumed = [&](const std::string& why) {
    printStderr("--partial {}: not resumed ({}); the shard is traced from its start\n", s.partial,
                why);
    return std::nullopt;
  };
  try {
    reference::DecodedRunState d = reference::decodeRunState(readBytes(s.partial, "--partial"));
    const nlohmann::json h = io::parseJson(d.header_json, "its header");
    const std::vector<std::string> args = recordedArguments();
    if (!h.is_object() || !h.contains("args") || h.at("args") != nlohmann::json(args))
      return notResumed("the file is the partial result of another command");
    if (!h.contains("settings_hash") || h.at("settings_hash") != settingsHash(args, inputs))
      return notResumed("the inputs have changed since it was written");
    for (const auto& [key, value] : {std::pair<const char*, uint64_t>{"shard", r.index},
                                     {"shards", r.shards},
                                     {"first_block", r.first},
                                     {"blocks", r.blocks}})
      if (!h.contains(key) || !h.at(key).is_number_unsigned() || h.at(key).get<uint64_t>() != value)
        return notResumed(fmt::format("it is another shard: its \"{}\" differs", key));
    if (!h.contains("blocks_done") || !h.at("blocks_done").is_number_unsigned() ||
        h.at("blocks_done").get<uint64_t>() > r.blocks)
      return notResumed("it records no finished blocks");
    Checkpoint c;
    c.blocks_done = h.at("blocks_done").get<uint64_t>();
    if (c.blocks_done == 0) return notResumed("no block was finished");
    c.state = std::move(d.state);
    if (h.contains("seconds") && h.at("seconds").is_number()) c.seconds = h.at("seconds").get<double>();
    printStderr("--partial {}: resuming shard {}/{} after its {} of {} blocks done\n", s.partial,
                r.index, r.shards, c.blocks_done, r.blocks);
    return c;
  } catch (const std::exception& e) {
    return notResumed(e.what());
  }
}

void checkMergedInputs(const OutputSet& inputs) {
  if (!gMerged) return;
  const std::string now = settingsHash(gMerged->args, inputs);
  if (now != gMerged->settings_hash) {
    std::string files;
    for (const auto& [what, path] : inputs.inputs()) files += fmt::format(" {} '{}',", what, path.string());
    if (!files.empty()) files.pop_back();
    throw ParameterError(fmt::format(
        "merge: the inputs of the run have changed since the shards were traced (settings hash "
        "{} now, {} in the parts){}: trace the shards again", now, gMerged->settings_hash,
        files.empty() ? "" : "; inputs:" + files));
  }
}

// ---------------------------------------------------------------------------------------------
// translucent merge

namespace {

struct MergeArgs {
  std::vector<std::string> parts;
  // The output options of the recorded command, passed on when given.
  std::string json, csv, exr, png, quantity;
  std::optional<double> exposure, gamma;
};

struct Part {
  std::string file;
  nlohmann::json header;
  reference::RunState state;
};

Part readPart(const std::string& file) {
  Part p;
  p.file = file;
  const std::string bytes = readBytes(file, "merge: part");
  try {
    reference::DecodedRunState d = reference::decodeRunState(bytes);
    p.header = io::parseJson(d.header_json, "its header");
    p.state = std::move(d.state);
    const nlohmann::json& h = p.header;
    auto has = [&](const char* key, bool ok) {
      if (!h.is_object() || !h.contains(key) || !ok)
        throw std::runtime_error(fmt::format("its header has no valid \"{}\"", key));
    };
    has("args", h.is_object() && h.contains("args") && h["args"].is_array() &&
                    std::all_of(h["args"].begin(), h["args"].end(),
                                [](const nlohmann::json& a) { return a.is_string(); }));
    has("settings_hash", h.is_object() && h.contains("settings_hash") && h["settings_hash"].is_string());
    has("shards", h.is_object() && h.contains("shards") && h["shards"].is_number_unsigned() &&
                      h["shards"].get<uint64_t>() > 0);
    has("shard", h.is_object() && h.contains("shard") && h["shard"].is_number_unsigned() &&
                     h.contains("shards") && h["shard"].get<uint64_t>() < h["shards"].get<uint64_t>());
    has("complete", h.is_object() && h.contains("complete") && h["complete"].is_boolean());
    for (const char* key : {"seconds", "threads"})
      if (h.contains(key) && !h[key].is_number()) has(key, false);
  } catch (const std::exception& e) {
    throw ParameterError(fmt::format("merge: part '{}': {}", file, e.what()));
  }
  return p;
}

void runMerge(const MergeArgs& a) {
  if (a.parts.empty()) throw ParameterError("merge: give the partial files of every shard");
  std::vector<Part> parts;
  for (const std::string& f : a.parts) parts.push_back(readPart(f));
  const Part& first = parts.front();
  const uint64_t n = first.header["shards"].get<uint64_t>();
  std::map<uint64_t, std::string> byShard;
  for (const Part& p : parts) {
    if (p.header["settings_hash"] != first.header["settings_hash"] ||
        p.header["args"] != first.header["args"] || p.header["shards"].get<uint64_t>() != n)
      throw ParameterError(fmt::format(
          "merge: '{}' and '{}' are parts of different runs (settings hash {} / {}, {} / {} "
          "shards; arguments `{}` / `{}`)", first.file, p.file,
          first.header["settings_hash"].get<std::string>(),
          p.header["settings_hash"].get<std::string>(), n, p.header["shards"].get<uint64_t>(),
          fmt::join(first.header["args"].get<std::vector<std::string>>(), " "),
          fmt::join(p.header["args"].get<std::vector<std::string>>(), " ")));
    const uint64_t i = p.header["shard"].get<uint64_t>();
    if (const auto it = byShard.find(i); it != byShard.end())
      throw ParameterError(fmt::format("merge: shard {}/{} given twice: '{}' and '{}'", i, n,
                                       it->second, p.file));
    if (!p.header["complete"].get<bool>())
      throw ParameterError(fmt::format(
          "merge: '{}' (shard {}/{}) was stopped before it traced all its blocks: run that shard "
          "again", p.file, i, n));
    byShard[i] = p.file;
  }
  std::vector<uint64_t> missing;
  for (uint64_t i = 0; i < n && missing.size() < 20; ++i)
    if (!byShard.count(i)) missing.push_back(i);
  if (!missing.empty())
    throw ParameterError(fmt::format("merge: {} of {} shards given; missing shard{} {}{}",
                                     byShard.size(), n, missing.size() > 1 ? "s" : "",
                                     fmt::join(missing, ", "),
                                     n - byShard.size() > missing.size() ? ", …" : ""));

  MergedRun merged;
  merged.settings_hash = first.header["settings_hash"].get<std::string>();
  merged.args = first.header["args"].get<std::vector<std::string>>();
  merged.shards = n;
  merged.state = first.state;
  for (size_t k = 0; k < parts.size(); ++k) {
    const Part& p = parts[k];
    if (k > 0) {
      try {
        merged.state.merge(p.state);
      } catch (const std::exception& e) {
        throw ParameterError(fmt::format("merge: '{}' does not fit '{}': {}", p.file, first.file,
                                         e.what()));
      }
    }
    merged.files.push_back(p.file);
    merged.seconds += p.header.value("seconds", 0.0);
    merged.threads = std::max(merged.threads, p.header.value("threads", 0));
  }

  // The recorded command with merge's output options, run with the merged state instead of
  // tracing (the command's own checks, outputs and writers: what the unsharded run writes).
  std::vector<std::string> args = first.header["args"].get<std::vector<std::string>>();
  auto pass = [&](const char* option, const std::string& value) {
    if (value.empty()) return;
    args.push_back(option);
    args.push_back(value);
  };
  pass("--json", a.json);
  pass("--csv", a.csv);
  pass("--exr", a.exr);
  pass("--png", a.png);
  pass("--quantity", a.quantity);
  if (a.exposure) pass("--exposure", fmt::format("{}", *a.exposure));
  if (a.gamma) pass("--gamma", fmt::format("{}", *a.gamma));
  if (args.size() < 2 || args[0] != "pathtrace")
    throw ParameterError(fmt::format("merge: the parts record `{}`, not a `pathtrace` command",
                                     fmt::join(args, " ")));
  printStderr("merge: {} shards of `translucent {}`\n", n,
              fmt::join(first.header["args"].get<std::vector<std::string>>(), " "));
  CLI::App app{"translucent (merge)"};
  addAllCommands(app);
  std::vector<std::string> reversed(args.rbegin(), args.rend());  // CLI11 parses a reversed vector
  // The parts are inputs of this run: no output of the recorded command may replace one (also
  // through a hard or symbolic link), whichever of its output options names it.
  std::vector<std::pair<std::string, std::filesystem::path>> partFiles;
  for (const Part& p : parts) partFiles.emplace_back("a partial file", p.file);
  const io::ScopedRunInputs partsAreInputs(std::move(partFiles));
  gMerged = &merged;
  try {
    app.parse(reversed);
  } catch (const CLI::ParseError& e) {
    gMerged = nullptr;
    throw ParameterError(fmt::format("merge: the recorded command with these outputs does not "
                                     "parse: {}", e.what()));
  } catch (...) {
    gMerged = nullptr;
    throw;
  }
  gMerged = nullptr;
}

}  // namespace

void addMergeCommand(CLI::App& app) {
  auto a = std::make_shared<MergeArgs>();
  auto* cmd = app.add_subcommand(
      "merge", "Add up the partial files of the N shards of one `pathtrace ... --shard I/N` run "
               "and write exactly what the unsharded run writes (give its output options)");
  cmd->add_option("parts", a->parts, "Partial files (--partial) of every shard, once each")
      ->required();
  outputOption(cmd->add_option("--json", a->json, "JSON output of the recorded command"));
  outputOption(cmd->add_option("--csv", a->csv, "CSV output (pathtrace slab: radial profile)"));
  outputOption(cmd->add_option("--exr", a->exr, "EXR output (pathtrace sphere|mesh)"));
  outputOption(cmd->add_option("--png", a->png, "PNG output (pathtrace sphere|mesh)"));
  cmd->add_option("--quantity", a->quantity, "What the EXR/PNG pixels hold (pathtrace sphere|mesh)");
  cmd->add_option("--exposure", a->exposure, "PNG exposure [stops]");
  cmd->add_option("--gamma", a->gamma, "PNG display gamma");
  cmd->callback([a] { runMerge(*a); });
}

}  // namespace translucent::cli
