// SPDX-License-Identifier: GPL-3.0-or-later
// `.bssrdf` plug-in files on the command line (`profile --model my.bssrdf`, `invert --model ...`):
// recognising a file among model names, a headless GL context made only when one is needed,
// loading with --param overrides, and errors as one line naming `file.bssrdf:LINE`.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "translucent/gpu/bssrdf_kernels.h"
#include "translucent/gpu/context.h"

namespace translucent::cli {

// A --model entry names a .bssrdf file when it ends in ".bssrdf" (any case) or is an existing
// regular file other than a tabulated .csv profile (bssrdf::isPluginFile); otherwise it is a
// registered model name or a tabulated profile.
bool isBssrdfFile(const std::string& entry);

// The headless OpenGL 4.5 context; without one, a ParameterError saying that `what` needs it and
// what the EGL displays offered.
std::unique_ptr<gpu::Context> bssrdfContext(const std::string& what);

// Loads and compiles `path` (a context must be current) and applies the `name=value` overrides
// whose name it declares (float: a number within [min, max]; bool: true/false/1/0; color: r,g,b).
// Parse and GLSL errors become a ParameterError whose message is the first `file.bssrdf:LINE`
// line of the diagnostic.
std::unique_ptr<gpu::BssrdfEvaluator> loadBssrdfModel(const std::string& path,
                                                      const std::vector<std::string>& params);

// Checks that every `name=value` names a parameter of at least one of the files.
void checkParamsUsed(const std::vector<std::string>& params,
                     const std::vector<const gpu::BssrdfEvaluator*>& models);

}  // namespace translucent::cli
