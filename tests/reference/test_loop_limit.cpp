// SPDX-License-Identifier: GPL-3.0-or-later
// The driver's loop limit that the GPU walks must stay clear of (reference/gpu/walk_program.h:
// LoopLimit; mesh_walk.comp suspends its walks before it). On Mesa's llvmpipe every loop of an
// invocation stops, without an error, once the loops of its SIMD group have iterated 65535 times
// in all, nested loops counted together and a loop that runs no iteration counted once;
// elsewhere loops run to the end.
#include <gtest/gtest.h>

#include <vector>

#include <glm/vec2.hpp>

#include "translucent/gpu/compute.h"
#include "gpu/gpu_test.h"
#include "translucent/gpu/program.h"
#include "translucent/reference/gpu/walk_program.h"

namespace translucent::reference {
namespace {

class LoopLimitGpu : public gpu::testing::GpuTest {};

// What each of 64 invocations ran of Outer x Inner nested iterations.
std::vector<glm::uvec2> run(uint32_t outer, uint32_t inner) {
  const gpu::ShaderProgram p = gpu::ShaderProgram::compute("tests/loop_limit.comp");
  gpu::Buffer out = gpu::makeStorageBuffer(64 * sizeof(glm::uvec2));
  gpu::bindStorage(0, out);
  p.set("Outer", outer);
  p.set("Inner", inner);
  p.set("Count", 64u);
  gpu::dispatch1D(p, 64);
  return gpu::download<glm::uvec2>(out, 64);
}

TEST_F(LoopLimitGpu, LoopsRunToTheEndOrStopWhereLoopLimitSays) {
  const gpu_walk::LoopLimit limit = gpu_walk::loopLimit();
  // Below the limit everything runs, nested or not.
  for (const glm::uvec2& d : run(1000, 20)) EXPECT_EQ(d, glm::uvec2(1000, 20000));
  const std::vector<glm::uvec2> lone = run(1, 70000), nested = run(100, 1000), empty = run(70000, 0);
  for (size_t i = 0; i < lone.size(); ++i) {
    if (!limit.limited) {
      EXPECT_EQ(lone[i], glm::uvec2(1, 70000));
      EXPECT_EQ(nested[i], glm::uvec2(100, 100000));
      EXPECT_EQ(empty[i], glm::uvec2(70000, 0));
      continue;
    }
    // One loop stops at the limit (the outer loop's single pass costs one more); nested loops
    // share it: 1000 inner iterations and one of the outer loop per outer pass; a loop that runs
    // no iteration still costs one, so an outer loop around an empty one gets half the limit.
    // This is what mesh_walk.comp's count must bound: every loop entered costs at least one.
    EXPECT_NEAR(double(lone[i].y), double(limit.iterations), 2.0);
    EXPECT_NEAR(double(nested[i].x * 1001u + nested[i].y % 1000u), double(limit.iterations), 1002.0);
    EXPECT_NEAR(double(empty[i].x), 0.5 * double(limit.iterations), 2.0);
  }
  if (limit.limited) {
    EXPECT_GE(limit.lanes, 4u);
    // The walks' budget keeps a group of `lanes` walks clear of the limit with room for a
    // flight as long as the budget again.
    EXPECT_TRUE(limit.clear(2 * limit.budget() - 1));
    EXPECT_FALSE(limit.clear(limit.iterations));
  }
}

}  // namespace
}  // namespace translucent::reference
