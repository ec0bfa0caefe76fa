// SPDX-License-Identifier: GPL-3.0-or-later
// Compute dispatch, SSBO upload/download, and GPU pass timing.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <stdexcept>

#include "translucent/gpu/compute.h"
#include "translucent/gpu/pass_timer.h"
#include "gpu_test.h"

namespace translucent::gpu {
namespace {

using testing::GpuTest;
using testing::TempDir;

// Writes f(i) = i * i + Offset (as uint) and 0.5 * i (as float) for i < Count.
constexpr const char* kFill = R"(#version 450 core
layout(local_size_x = LOCAL_SIZE) in;
#include "common/compute.glsl"
layout(std430, binding = 0) writeonly buffer Squares { uint squares[]; };
layout(std430, binding = 1) writeonly buffer Halves { float halves[]; };
uniform uint Count;
uniform uint Offset;
void main() {
  uint i = linearInvocationIndex();
  if (i >= Count) return;
  squares[i] = i * i + Offset;
  halves[i] = 0.5 * float(i);
}
)";

TEST_F(GpuTest, ComputeShaderWritesKnownValues) {
  TempDir dir;
  const auto file = dir.write("fill.comp", kFill);
  auto program = ShaderProgram::compute(file, {{"LOCAL_SIZE", "32"}});
  EXPECT_EQ(program.workGroupSize()[0], 32u);

  const size_t n = 1000;  // not a multiple of the local size: the tail is guarded
  const Buffer squares = makeStorageBuffer((n + 8) * sizeof(std::uint32_t));
  const Buffer halves = makeStorageBuffer((n + 8) * sizeof(float));
  // Sentinels past the end must survive: the shader may not write beyond Count.
  const std::vector<std::uint32_t> sentinel(8, 0xdeadbeefu);
  upload<std::uint32_t>(squares, sentinel, n);
  bindStorage(0, squares);
  bindStorage(1, halves);
  program.set("Count", static_cast<unsigned>(n));
  program.set("Offset", 7u);
  dispatch1D(program, n);

  const auto s = download<std::uint32_t>(squares, n + 8);
  const auto h = download<float>(halves, n);
  for (size_t i = 0; i < n; ++i) {
    ASSERT_EQ(s[i], static_cast<std::uint32_t>(i * i + 7)) << i;
    ASSERT_EQ(h[i], 0.5f * static_cast<float>(i)) << i;
  }
  for (size_t i = n; i < n + 8; ++i) EXPECT_EQ(s[i], 0xdeadbeefu) << i;
}

TEST_F(GpuTest, OneDimensionalDispatchBeyondTheRowLimitUsesMoreRows) {
  // When a batch needs more groups than one row may hold (GL_MAX_COMPUTE_WORK_GROUP_COUNT[0]:
  // 65535 on Mesa, 2^31 - 1 on NVIDIA; forced to 1000 here so that every driver takes this path),
  // dispatch1D lays the groups out in rows; every index must still be written exactly once and
  // the partial last row must not write past the count.
  TempDir dir;
  auto program = ShaderProgram::compute(dir.write("fill.comp", kFill), {{"LOCAL_SIZE", "4"}});
  const size_t n = 4 * 1000 * 4 + 321;  // 4 full rows of 1000 groups of 4, then a partial row
  const Buffer squares = makeStorageBuffer((n + 1) * sizeof(std::uint32_t));
  const Buffer halves = makeStorageBuffer((n + 1) * sizeof(float));
  const std::vector<float> sentinel{-1.0f};
  upload<float>(halves, sentinel, n);
  bindStorage(0, squares);
  bindStorage(1, halves);
  program.set("Count", static_cast<unsigned>(n));
  program.set("Offset", 0u);
  dispatch1D(program, n, GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT, 1000);
  const auto h = download<float>(halves, n + 1);
  size_t wrong = 0;
  for (size_t i = 0; i < n; ++i) wrong += h[i] != 0.5f * static_cast<float>(i) ? 1 : 0;
  EXPECT_EQ(wrong, 0u) << "of " << n;
  EXPECT_EQ(h[n], -1.0f);
}

TEST_F(GpuTest, UploadDownloadRoundTripAndRangeChecks) {
  std::vector<float> data(257);
  std::iota(data.begin(), data.end(), -3.25f);
  const Buffer b = makeStorageBuffer<float>(data);
  EXPECT_EQ(b.size(), static_cast<std::int64_t>(data.size() * sizeof(float)));
  EXPECT_EQ(download<float>(b, data.size()), data);
  const std::vector<float> patch{100.f, 200.f};
  upload<float>(b, patch, 10);
  const auto part = download<float>(b, 4, 9);
  EXPECT_EQ(part, (std::vector<float>{data[9], 100.f, 200.f, data[12]}));
  EXPECT_THROW(download<float>(b, 2, 256), GlError);
  EXPECT_THROW(upload<float>(b, patch, 256), GlError);
  EXPECT_THROW(download<float>(Buffer{}, 1), GlError);
}

TEST_F(GpuTest, PassTimerReportsNestedPassesInMilliseconds) {
  TempDir dir;
  auto program = ShaderProgram::compute(dir.write("fill.comp", kFill), {{"LOCAL_SIZE", "64"}});
  const size_t n = 1 << 16;
  const Buffer squares = makeStorageBuffer(n * sizeof(std::uint32_t));
  const Buffer halves = makeStorageBuffer(n * sizeof(float));
  bindStorage(0, squares);
  bindStorage(1, halves);
  program.set("Count", static_cast<unsigned>(n));
  program.set("Offset", 0u);

  PassTimer timer;
  {
    auto outer = timer.scope("outer");
    { auto first = timer.scope("first"); dispatch1D(program, n); }
    { auto second = timer.scope("second"); dispatch1D(program, n); }
  }
  const auto passes = timer.collect();
  ASSERT_EQ(passes.size(), 3u);
  EXPECT_EQ(passes[0].name, "outer");
  EXPECT_EQ(passes[0].depth, 0);
  EXPECT_EQ(passes[1].name, "first");
  EXPECT_EQ(passes[1].depth, 1);
  EXPECT_EQ(passes[2].name, "second");
  for (const auto& p : passes) {
    EXPECT_TRUE(std::isfinite(p.ms)) << p.name;
    EXPECT_GE(p.ms, 0.0) << p.name;
  }
  // Timestamps are monotonic: the outer pass spans both inner ones.
  EXPECT_GE(passes[0].ms, passes[1].ms + passes[2].ms - 1e-6);
  EXPECT_EQ(timer.lastMs("second"), passes[2].ms);
  EXPECT_LT(timer.lastMs("never"), 0.0);
  EXPECT_TRUE(timer.collect().empty());  // collected passes are not reported twice

  timer.begin("open");
  EXPECT_THROW(timer.collect(), GlError);
  timer.end();
  EXPECT_THROW(timer.end(), GlError);

  // A scope left by an exception ends its pass without throwing from its destructor, and the
  // pass is reported like any other.
  EXPECT_THROW(
      {
        auto unwound = timer.scope("unwound");
        throw std::runtime_error("thrown inside a timed pass");
      },
      std::runtime_error);
  const auto after = timer.collect();
  ASSERT_EQ(after.size(), 2u);  // "open" (ended explicitly above) and "unwound"
  EXPECT_EQ(after[1].name, "unwound");
  EXPECT_GE(after[1].ms, 0.0);
}

}  // namespace
}  // namespace translucent::gpu
