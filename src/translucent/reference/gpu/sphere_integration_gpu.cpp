// SPDX-License-Identifier: GPL-3.0-or-later
// GPU sphere integration of a .bssrdf file (sphere_integration_gpu.h).
#include "translucent/reference/gpu/sphere_integration_gpu.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <memory>

#include "translucent/gpu/compute.h"
#include "translucent/reference/camera.h"
#include "translucent/reference/sampling.h"

namespace translucent::reference {
namespace {

gpu::ShaderProgram build(const bssrdf::BssrdfFile& file) {
  auto snapshot = std::make_shared<const bssrdf::BssrdfFile>(file);
  return gpu::ShaderProgram(
      fmt::format("{} (reference/sphere_integration.comp)", file.path),
      {{GL_COMPUTE_SHADER, [snapshot] {
          return gpu::bssrdfPreprocessor(*snapshot).load("reference/sphere_integration.comp");
        }}});
}

glm::vec3 toFloat(const glm::dvec3& v) { return glm::vec3(v); }

}  // namespace

GpuSphereIntegrator::GpuSphereIntegrator(gpu::BssrdfEvaluator& evaluator, const SphereScene& scene,
                                         const Medium& medium, uint64_t seed)
    : evaluator_(evaluator), scene_((scene.validate(), scene)), seed_(seed),
      program_(build(evaluator.file())) {
  evaluator_.setMedium(medium);
  images_.exitance = McImage(scene.width, scene.height, 3, McImage::Statistics::PerPixel);
  images_.radiance = images_.exitance;
}

IntegrationStats GpuSphereIntegrator::addPass(uint64_t samples, const ProgressCallback& progress) {
  if (samples == 0) throw ParameterError("integration: samples is 0: expected at least 1");
  if (done_ + samples > 0xFFFFFFFFull)
    throw ParameterError(fmt::format(
        "integration: {} samples per pixel in all: the GPU integrator counts at most 2^32 - 1",
        done_ + samples));
  const auto start = std::chrono::steady_clock::now();
  const int w = scene_.width, h = scene_.height;
  const size_t pixels = static_cast<size_t>(w) * static_cast<size_t>(h);

  // The orthographic camera as an affine map of continuous pixel coordinates.
  const CameraModel camera(scene_.camera());
  glm::dvec3 o00, o10, o01, d;
  camera.ray(0.0, 0.0, o00, d);
  camera.ray(1.0, 0.0, o10, d);
  camera.ray(0.0, 1.0, o01, d);
  const glm::dvec3 light = glm::normalize(scene_.light_direction);
  glm::dvec3 t1, t2;
  detail::tangentFrame(light, t1, t2);

  const gpu::ShaderProgram& p = program_;
  evaluator_.applyUniforms(p);
  p.set("Width", static_cast<unsigned>(w));
  p.set("Height", static_cast<unsigned>(h));
  p.set("SeedLo", static_cast<unsigned>(seed_ & 0xFFFFFFFFu));
  p.set("SeedHi", static_cast<unsigned>(seed_ >> 32));
  p.set("Origin00", toFloat(o00));
  p.set("OriginDx", toFloat(o10 - o00));
  p.set("OriginDy", toFloat(o01 - o00));
  p.set("RayDir", toFloat(d));
  p.set("LightDir", toFloat(light));
  p.set("LightT1", toFloat(t1));
  p.set("LightT2", toFloat(t2));
  p.set("ViewDir", toFloat(glm::normalize(scene_.view_direction)));
  p.set("Radius", static_cast<float>(scene_.radius));
  p.set("Irradiance", static_cast<float>(scene_.irradiance));

  const gpu::Buffer sums = gpu::makeStorageBuffer(pixels * 16 * sizeof(float));
  gpu::bindStorage(0, sums);
  std::vector<float> host(pixels * 16);
  uint64_t left = samples;
  bool stopped = false;
  const uint64_t total = samples * pixels * 3;
  while (left > 0) {
    const uint64_t n = std::min(left, kChunk);
    p.set("Samples", static_cast<unsigned>(n));
    p.set("First", static_cast<unsigned>(done_));
    gpu::dispatch1D(p, pixels);
    gpu::downloadBytes(sums, 0, host.size() * sizeof(float), host.data());
    for (size_t px = 0; px < pixels; ++px) {
      const int i = static_cast<int>(px % static_cast<size_t>(w));
      const int j = static_cast<int>(px / static_cast<size_t>(w));
      const float* s = &host[16 * px];
      for (int c = 0; c < 3; ++c) {
        const size_t idx = images_.exitance.index(i, j, c);
        images_.exitance.addSums(idx, static_cast<double>(s[c]), static_cast<double>(s[4 + c]));
        images_.radiance.addSums(idx, static_cast<double>(s[8 + c]), static_cast<double>(s[12 + c]));
      }
      images_.exitance.addPixelCount(px, n);
      images_.radiance.addPixelCount(px, n);
    }
    done_ += n;
    left -= n;
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (progress && !progress(TraceProgress{(samples - left) * pixels * 3, total, seconds}) &&
        left > 0) {
      stopped = true;
      break;
    }
  }
  IntegrationStats pass;
  pass.samples = samples - left;
  pass.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  pass.threads = 1;
  pass.partial = stopped;
  stats_.samples += pass.samples;
  stats_.seconds += pass.seconds;
  stats_.threads = 1;
  stats_.partial = stats_.partial || stopped;
  return pass;
}

}  // namespace translucent::reference
