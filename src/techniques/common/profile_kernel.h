// The radial profile R(r) of a scene's BSSRDF model tabulated per RGB channel for the GPU passes
// of the techniques that sum R(|x_i − x_o|) over surface samples (pointcloud, tsis): the same
// table and interpolation as bssrdf::ProfileTable::lookup, read by shaders/pointcloud/
// kernel_table.glsl.
#pragma once

#include <array>
#include <vector>

#include <glm/vec4.hpp>

#include "bssrdf/profile_table.h"
#include "gpu/bssrdf_kernels.h"
#include "scene/scene.h"

namespace translucent::techniques {

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
