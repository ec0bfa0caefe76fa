// SPDX-License-Identifier: GPL-3.0-or-later
#include "spheres/sphere_run.h"

#include <algorithm>
#include <chrono>
#include <exception>
#include <utility>

#include "translucent/gpu/context.h"
#include "translucent/reference/gpu/device.h"
#include "translucent/reference/progressive.h"
#include "translucent/reference/gpu/sphere_integration_gpu.h"
#include "translucent/reference/sphere_integration.h"

namespace translucent::explorer {

SphereRun::SphereRun(SphereRunConfig config, SphereRunCallbacks callbacks)
    : config_(std::move(config)), callbacks_(std::move(callbacks)) {
  thread_ = std::thread([this] { run(); });
}

SphereRun::~SphereRun() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
}

void SphereRun::run() {
  const auto start = std::chrono::steady_clock::now();
  auto elapsed = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  bool stopped = false;
  std::string error;
  try {
    // The path tracer's passes are whole blocks, so the progressive images equal one run of
    // the same photons (progressive.h).
    const bool integrating = config_.model || !config_.bssrdf_file.empty();
    const uint64_t granularity = integrating ? 1 : reference::kBlockPhotons;
    const auto passes = reference::doublingPasses(config_.first, config_.budget, granularity, config_.cap);
    uint64_t total = 0;
    for (uint64_t n : passes) total += n;
    auto progress = [&](int pass, uint64_t done, const reference::TraceProgress& p) {
      if (!callbacks_.progress || p.photons_total == 0) return;
      // photons_done / photons_total is the pass's own fraction, whatever its unit.
      const double inPass =
          static_cast<double>(p.photons_done) / static_cast<double>(p.photons_total);
      const double size = static_cast<double>(passes[static_cast<size_t>(pass)]);
      callbacks_.progress(
          std::clamp((static_cast<double>(done) + inPass * size) / static_cast<double>(total), 0.0, 1.0));
    };
    std::string device;
    auto publish = [&](const auto& images, int k, uint64_t done) {
      if (!callbacks_.pass) return;
      auto s = std::make_shared<SphereSnapshot>();
      s->pass = k;
      s->passes = static_cast<int>(passes.size());
      s->done = done;
      s->budget = total;
      s->seconds = elapsed();
      s->device = device;
      s->exitance = images.exitance;
      s->radiance = images.radiance;
      callbacks_.pass(std::move(s));
    };
    if (!config_.bssrdf_file.empty()) {
      // The context first: the evaluator and the integrator's program live in it.
      gpu::Context context;
      const auto evaluator = gpu::openBssrdf(config_.bssrdf_file);
      for (const auto& [name, value] : config_.bssrdf_parameters) evaluator->setParameter(name, value);
      reference::GpuSphereIntegrator integrator(*evaluator, config_.scene, config_.medium, config_.seed);
      device = "gpu (" + context.info().renderer + ")";
      stopped = reference::runProgressive(
                    integrator, passes, stop_,
                    [&](int k, uint64_t done) { publish(integrator.images(), k, done); }, progress)
                    .stopped;
    } else if (config_.model) {
      reference::IntegrationOptions o;
      o.seed = config_.seed;
      o.threads = config_.threads;
      reference::SphereIntegrator integrator(*config_.model, config_.scene, config_.medium, o);
      stopped = reference::runProgressive(
                    integrator, passes, stop_,
                    [&](int k, uint64_t done) { publish(integrator.images(), k, done); }, progress)
                    .stopped;
    } else {
      // Before the tracer: the context outlives the walker the tracer holds.
      const reference::TraceDevice dev = reference::openTraceDevice(config_.device, "tracer device");
      reference::TracerOptions options{config_.seed, config_.threads};
      options.split_orders = config_.order.has_value();
      reference::SpherePathTracer tracer(config_.scene, config_.medium, options);
      reference::useDevice(dev, tracer);
      device = tracer.device();
      auto shown = [&]() -> const reference::CameraImages& {
        return config_.order ? tracer.orderImages(*config_.order) : tracer.images();
      };
      stopped = reference::runProgressive(
                    tracer, passes, stop_,
                    [&](int k, uint64_t done) { publish(shown(), k, done); }, progress)
                    .stopped;
    }
  } catch (const std::exception& e) {
    error = e.what();
  }
  if (callbacks_.finished) callbacks_.finished(stopped, error);
}

}  // namespace translucent::explorer
