// SPDX-License-Identifier: GPL-3.0-or-later
// The radial profile R(r) of a scene's BSSRDF model tabulated per RGB channel for the GPU passes
// of the techniques that sum R(|x_i − x_o|) over surface samples (pointcloud, tsis): the same
// table and interpolation as bssrdf::ProfileTable::lookup, read by shaders/pointcloud/
// kernel_table.glsl.
#pragma once

#include <array>
#include <string>
#include <vector>

#include <glm/vec4.hpp>

#include "translucent/bssrdf/profile_table.h"
#include "translucent/gpu/bssrdf_kernels.h"
#include "translucent/scene/scene.h"
#include "translucent/techniques/technique.h"

namespace translucent::techniques {

// The exit-radiance convention L(B) of every technique that turns B into radiance, by default
// (seed Eq. 2.16; docs/radiance-convention.md).
inline constexpr const char* kDefaultRadianceConvention = "normalized";

// The descriptors of the techniques that tabulate the profile and turn B into L, with the same
// names, defaults and ranges: table_size (4096, 64 … 65536) and radiance_convention.
ParameterInfo tableSizeParameter(std::string help = "entries of the tabulated profile (uniform in r up "
                                                    "to the radius holding 99.9% of Rd)");
ParameterInfo radianceConventionParameter();

// Fraction of Rd inside the tabulated radius (bssrdf::tabulate's default).
inline constexpr double kProfileTableFraction = 0.999;

struct RgbProfileTable {
  std::array<bssrdf::ProfileTable, 3> tables;  // R only (r_times_R and cdf are left empty)
  std::vector<glm::vec4> gpu;                  // R(r_i) per channel, for a storage buffer
};

// R(r) per channel on a common grid of n entries over [0, r_max], r_max the radius holding
// kProfileTableFraction of Rd in the widest channel: from the registered C++ model named by
// scene.model, or, when `evaluator` is given (a .bssrdf model), from the file's GPU kernel.
// Throws ParameterError naming the model when an entry is not finite.
RgbProfileTable tabulateRgbProfile(const scene::Scene& scene, size_t n,
                                   gpu::BssrdfEvaluator* evaluator);

}  // namespace translucent::techniques
