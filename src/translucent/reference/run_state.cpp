// SPDX-License-Identifier: GPL-3.0-or-later
// Partial files of sharded runs (run_state.h).
#include "translucent/reference/run_state.h"

#include <fmt/format.h>

#include <cstring>
#include <nlohmann/json.hpp>

#include "translucent/geometry/atomic_file.h"
#include "translucent/io/json.h"

namespace translucent::reference {
namespace {

constexpr std::string_view kMagic = "translucent-partial 1\n";

void put64(std::string& out, uint64_t v) {
  for (int i = 0; i < 8; ++i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xffu));
}

uint64_t get64(std::string_view bytes, size_t at) {
  uint64_t v = 0;
  for (int i = 0; i < 8; ++i)
    v |= static_cast<uint64_t>(static_cast<unsigned char>(bytes[at + static_cast<size_t>(i)]))
         << (8 * i);
  return v;
}

// An array's "size": a whole number (a negative or fractional one would convert silently).
uint64_t arraySize(const nlohmann::json& a) {
  if (!a.at("size").is_number_unsigned())
    throw std::runtime_error(fmt::format("array '{}': its size is not a whole number",
                                         a.at("name").dump()));
  return a.at("size").get<uint64_t>();
}

}  // namespace

std::string encodeRunState(const std::string& header_json, const RunState& state) {
  nlohmann::json layout = {{"sums", nlohmann::json::array()}, {"counts", nlohmann::json::array()}};
  std::string payload;
  for (const auto& [name, a] : state.sums) {
    layout["sums"].push_back({{"name", name}, {"exponent", a.exponent}, {"size", a.values.size()}});
    // A bitmap of the non-zero entries, then those entries: image sums are mostly zero (the
    // background, the cone-radiance of pixels no exit direction reached).
    std::string bitmap((a.values.size() + 7) / 8, '\0');
    for (size_t i = 0; i < a.values.size(); ++i)
      if (a.values[i] != 0) bitmap[i / 8] = static_cast<char>(bitmap[i / 8] | (1 << (i % 8)));
    payload += bitmap;
    for (const Fixed q : a.values) {
      if (q == 0) continue;
      const auto u = static_cast<UFixed>(q);
      put64(payload, static_cast<uint64_t>(u));
      put64(payload, static_cast<uint64_t>(u >> 64));
    }
  }
  for (const auto& [name, a] : state.counts) {
    layout["counts"].push_back({{"name", name}, {"size", a.size()}});
    for (const uint64_t v : a) put64(payload, v);
  }
  nlohmann::json header = {{"run", nlohmann::json::parse(header_json)},
                           {"layout", layout},
                           {"payload_bytes", payload.size()},
                           {"payload_hash", fmt::format("{:016x}", geometry::contentHash(payload))}};
  std::string out(kMagic);
  out += header.dump();
  out += '\n';
  out += payload;
  return out;
}

DecodedRunState decodeRunState(std::string_view bytes) {
  if (bytes.substr(0, kMagic.size()) != kMagic)
    throw std::runtime_error("not a partial file of `translucent pathtrace --shard` (its first "
                             "line is not \"translucent-partial 1\")");
  const size_t eol = bytes.find('\n', kMagic.size());
  if (eol == std::string_view::npos) throw std::runtime_error("truncated: no header line");
  nlohmann::json header;
  try {
    header = io::parseJson(bytes.substr(kMagic.size(), eol - kMagic.size()), "the header");
  } catch (const io::JsonError& e) {
    throw std::runtime_error(e.what());
  }
  const std::string_view payload = bytes.substr(eol + 1);
  DecodedRunState out;
  try {
    if (!header.at("payload_bytes").is_number_unsigned())
      throw std::runtime_error("payload_bytes is not a whole number");
    const uint64_t size = header.at("payload_bytes").get<uint64_t>();
    if (payload.size() != size)
      throw std::runtime_error(fmt::format("truncated or padded: {} payload bytes, the header says {}",
                                           payload.size(), size));
    const std::string hash = fmt::format("{:016x}", geometry::contentHash(payload));
    if (hash != header.at("payload_hash").get<std::string>())
      throw std::runtime_error("the content hash does not match: the file was changed or damaged");
    size_t at = 0;
    auto need = [&](uint64_t n, const std::string& what) {
      if (n > payload.size() - at)
        throw std::runtime_error(fmt::format("array '{}' runs past the end of the payload", what));
    };
    for (const auto& a : header.at("layout").at("sums")) {
      const std::string name = a.at("name").get<std::string>();
      const uint64_t n = arraySize(a);
      if (!a.at("exponent").is_number_integer() || a.at("exponent").get<int64_t>() < -2000 ||
          a.at("exponent").get<int64_t>() > 2000)
        throw std::runtime_error(fmt::format("array '{}': its grid exponent is not an integer in "
                                             "[-2000, 2000]", name));
      if (n > 8 * payload.size()) need(UINT64_MAX, name);
      const uint64_t mapBytes = (n + 7) / 8;
      need(mapBytes, name);
      const std::string_view bitmap = payload.substr(at, mapBytes);
      at += mapBytes;
      RunState::Sums sums;
      sums.exponent = a.at("exponent").get<int>();
      sums.values.assign(n, 0);
      for (uint64_t i = 0; i < n; ++i) {
        if (!(static_cast<unsigned char>(bitmap[i / 8]) & (1u << (i % 8)))) continue;
        need(16, name);
        const UFixed u = (static_cast<UFixed>(get64(payload, at + 8)) << 64) | get64(payload, at);
        sums.values[i] = static_cast<Fixed>(u);
        at += 16;
      }
      out.state.sums[name] = std::move(sums);
    }
    for (const auto& a : header.at("layout").at("counts")) {
      const std::string name = a.at("name").get<std::string>();
      const uint64_t n = arraySize(a);
      if (n > payload.size() / 8) need(UINT64_MAX, name);
      need(8 * n, name);
      std::vector<uint64_t> v(n);
      for (uint64_t i = 0; i < n; ++i, at += 8) v[i] = get64(payload, at);
      out.state.counts[name] = std::move(v);
    }
    if (at != payload.size())
      throw std::runtime_error("the payload is longer than its arrays");
    out.header_json = header.at("run").dump();
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error(
        fmt::format("the header lacks a field or has a wrong type ({})", io::jsonErrorText(e)));
  }
  return out;
}

}  // namespace translucent::reference
