// SPDX-License-Identifier: GPL-3.0-or-later
// The techniques' side of compare (compare_run.h).
#include "translucent/compare/compare_run.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <ctime>
#include <map>

#include "translucent/optics/medium.h"  // ParameterError

namespace translucent::analysis {
namespace {

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace

TechniqueSpec parseTechniqueSpec(const std::string& spec) {
  TechniqueSpec out;
  std::vector<std::string> parts;
  size_t start = 0;
  for (;;) {
    const size_t colon = spec.find(':', start);
    parts.push_back(spec.substr(start, colon == std::string::npos ? std::string::npos : colon - start));
    if (colon == std::string::npos) break;
    start = colon + 1;
  }
  out.base = parts[0];
  for (size_t i = 1; i < parts.size(); ++i) {
    const size_t eq = parts[i].find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == parts[i].size())
      throw ParameterError(fmt::format("--techniques: '{}': '{}' is not key=value (a variant is "
                                       "name:key=value:key=value)", spec, parts[i]));
    out.settings.emplace_back(parts[i].substr(0, eq), parts[i].substr(eq + 1));
  }
  return out;
}

std::unique_ptr<techniques::Technique> makeTechniqueSpec(const std::string& spec,
                                                        const scene::Scene* scene) {
  const TechniqueSpec ts = parseTechniqueSpec(spec);
  const std::vector<std::string> all = techniques::names();
  if (std::find(all.begin(), all.end(), ts.base) == all.end())
    throw ParameterError(fmt::format("--techniques '{}': unknown technique '{}': valid techniques "
                                     "are {} (or all)", spec, ts.base, fmt::join(all, ", ")));
  std::unique_ptr<techniques::Technique> t = techniques::make(ts.base);
  if (scene && ts.base == scene->technique) techniques::applySettings(*t, *scene);
  for (const auto& [key, value] : ts.settings) {
    try {
      t->setParameter(key, value);
    } catch (const std::exception& e) {
      throw ParameterError(fmt::format("--techniques '{}': {}", spec, e.what()));
    }
  }
  return t;
}

TimedRender renderTimed(techniques::Technique& t, const std::string& row, const scene::Scene& s,
                        int warmup, int frames) {
  TimedRender r;
  techniques::FrameRequest request;
  request.converge = true;
  techniques::Frame f = t.render(request);
  r.notes = f.notes;
  if (f.width != s.camera.width || f.height != s.camera.height)
    throw std::runtime_error(fmt::format("technique {} rendered {}x{}: expected the camera's {}x{}",
                                         t.name(), f.width, f.height, s.camera.width,
                                         s.camera.height));
  r.images.name = row;
  r.images.convention = techniques::radianceConvention(t);
  r.images.radiance = {f.width, f.height, std::move(f.rgb), {}};
  if (auto it = f.layers.find("exitance"); it != f.layers.end())
    r.images.exitance = {f.width, f.height, std::move(it->second), {}};
  request.readback = false;
  std::vector<double> totals;
  std::vector<std::pair<std::string, int>> order;  // passes in frame order
  std::map<std::pair<std::string, int>, std::vector<double>> times;
  for (int k = 0; k < warmup + frames; ++k) {
    const techniques::Frame g = t.render(request);
    if (k < warmup) continue;
    totals.push_back(g.totalMs());
    for (const auto& p : g.passes) {
      const auto key = std::make_pair(p.name, p.depth);
      if (!times.contains(key)) order.push_back(key);
      times[key].push_back(p.ms);
    }
  }
  r.frame_ms = median(totals);
  for (const auto& key : order) {
    const auto& v = times[key];
    r.passes.push_back({key.first, key.second, median(v), *std::min_element(v.begin(), v.end()),
                        *std::max_element(v.begin(), v.end())});
  }
  return r;
}

std::string referenceOrigin(const Reference& ref) {
  if (ref.from_cache)
    return fmt::format("reused from the cache: {} (computed in {:.2f} s)", ref.cache_file.string(),
                       ref.seconds);
  return fmt::format("computed{} in {:.2f} s{}; {}",
                     ref.kind == ReferenceKind::Physical && ref.request.device == "gpu" ? " on the GPU" : "",
                     ref.seconds,
                     ref.partial ? " (stopped early: partial)" : "",
                     ref.cache_file.empty()
                         ? (ref.cache_note.empty() ? std::string("not cached") : ref.cache_note)
                         : "cached as " + ref.cache_file.string());
}

std::string utcNow() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

}  // namespace translucent::analysis
