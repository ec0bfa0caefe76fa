// SPDX-License-Identifier: GPL-3.0-or-later
// The techniques' side of `translucent compare`, shared by the CLI and the Python module's
// `translucent.compare`: rows named by technique specs ("name" or a variant
// "name:key=value:key=value"), and a technique rendered and timed as the report measures it.
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "translucent/compare/compare.h"
#include "translucent/compare/report.h"
#include "translucent/scene/scene.h"
#include "translucent/techniques/registry.h"

namespace translucent::analysis {

// A row of the comparison: a technique, or a variant of one, "name:key=value:key=value" (e.g.
// tsis:mode=hybrid:samples=900), so that one report compares settings of the same technique
// side by side; the spec is the row's name.
struct TechniqueSpec {
  std::string base;
  std::vector<std::pair<std::string, std::string>> settings;
};
// ParameterError naming the spec when a part is not key=value.
TechniqueSpec parseTechniqueSpec(const std::string& spec);
// Makes the technique of a spec and applies its settings (the scene's first when the scene
// names the base technique); errors name the spec, the unknown technique (with the valid names)
// or the setting.
std::unique_ptr<techniques::Technique> makeTechniqueSpec(const std::string& spec,
                                                        const scene::Scene* scene);

// One converged frame read back (the images), then `warmup` + `frames` frames kept on the GPU
// (read-back stalls the pipeline, techniques/technique.h), of which the last `frames` are timed:
// the median frame time and per pass the median, min and max.
struct TimedRender {
  TechniqueImages images;
  std::vector<PassStat> passes;
  double frame_ms = 0.0;
  std::vector<std::string> notes;
};
// `row`: the row's name (the technique's, or a variant's spec). std::runtime_error when the
// technique renders another size than the scene's camera.
TimedRender renderTimed(techniques::Technique& t, const std::string& row, const scene::Scene& s,
                        int warmup, int frames);

// Where a reference came from, for the report's notes: "reused from the cache: FILE (computed in
// S s)" or "computed in S s; cached as FILE" (or why it was not cached).
std::string referenceOrigin(const Reference& ref);

// The time now, ISO 8601 UTC (the report's "created").
std::string utcNow();

}  // namespace translucent::analysis
