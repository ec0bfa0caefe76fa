// SPDX-License-Identifier: GPL-3.0-or-later
#include "compare/compare_run.h"

#include <algorithm>
#include <chrono>
#include <exception>
#include <filesystem>
#include <optional>
#include <utility>
#include <vector>

#include "translucent/reference/camera_paths.h"
#include "translucent/reference/gpu/device.h"
#include "translucent/reference/mesh_tracer.h"
#include "translucent/reference/progressive.h"

namespace translucent::explorer {
namespace {
struct Stopped {};  // a stop seen between setup steps
}  // namespace

std::vector<uint64_t> modelPasses(uint64_t first, uint64_t budget) {
  std::vector<uint64_t> passes;
  for (uint64_t n = std::max<uint64_t>(first, 1); n <= budget; n *= 2) passes.push_back(n);
  if (passes.empty()) passes.push_back(std::max<uint64_t>(budget, 1));
  return passes;
}

CompareRun::CompareRun(CompareRunConfig config, CompareRunCallbacks callbacks)
    : config_(std::move(config)), callbacks_(std::move(callbacks)) {
  thread_ = std::thread([this] { run(); });
}

CompareRun::~CompareRun() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
}

void CompareRun::run() {
  const auto start = std::chrono::steady_clock::now();
  auto elapsed = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  bool stopped = false;
  std::string error;
  try {
    const scene::Scene& s = config_.scene;
    // Setup (mesh, masks, BVH) cannot be interrupted: the stop flag is read between its steps.
    const geometry::TriangleMesh mesh = scene::loadSceneMesh(s);
    if (stop_) throw Stopped{};
    auto report = [&](int pass, int passes, uint64_t count, uint64_t computed, uint64_t budget,
                      analysis::Reference reference, analysis::Masks masks) {
      if (!callbacks_.pass) return;
      auto snap = std::make_shared<CompareSnapshot>();
      snap->pass = pass;
      snap->passes = passes;
      snap->count = count;
      snap->computed = computed;
      snap->budget = budget;
      snap->seconds = elapsed();
      snap->eta = s.medium.eta;
      snap->reference = std::move(reference);
      snap->masks = std::move(masks);
      callbacks_.pass(std::move(snap));
    };
    auto progressTo = [&](double fraction) {
      if (callbacks_.progress) callbacks_.progress(std::clamp(fraction, 0.0, 1.0));
    };

    // The physical reference's passes on `tracer` (either method), a snapshot after each.
    auto runPhysical = [&](auto& tracer, const std::vector<uint64_t>& passes,
                           const analysis::Masks& masks, const std::string& method,
                           const std::string& device, std::optional<double> coneAngle) {
      uint64_t total = 0;
      for (uint64_t n : passes) total += n;
      const int count = static_cast<int>(passes.size());
      return reference::runProgressive(
                 tracer, passes, stop_,
                 [&](int k, uint64_t done) {
                   analysis::Reference r;
                   r.kind = analysis::ReferenceKind::Physical;
                   r.request.kind = analysis::ReferenceKind::Physical;
                   r.request.method = method;
                   r.request.count = done;
                   r.request.seed = config_.seed;
                   r.request.threads = config_.threads;
                   r.request.device = device;
                   r.cone_angle = coneAngle;
                   r.exitance = analysis::toCompareImage(tracer.images().exitance);
                   r.radiance = analysis::toCompareImage(tracer.images().radiance);
                   r.cone_radiance = analysis::toCompareImage(tracer.images().cone_radiance);
                   r.count_done = done;
                   r.seconds = tracer.stats().seconds;
                   report(k, count, done, done, total, std::move(r), masks);
                 },
                 [&](int k, uint64_t done, const reference::TraceProgress& p) {
                   if (p.photons_total == 0) return;
                   // photons_done / photons_total is the pass's own fraction (all channels).
                   const double in = static_cast<double>(p.photons_done) /
                                     static_cast<double>(p.photons_total);
                   progressTo((static_cast<double>(done) +
                               in * static_cast<double>(passes[static_cast<size_t>(k)])) /
                              static_cast<double>(total));
                 })
          .stopped;
    };

    if (config_.kind == analysis::ReferenceKind::Physical && config_.method == "camera") {
      // The camera method (reference/camera_paths.h): passes of camera paths per pixel, doubling
      // from `first`; its cone radiance is the true radiance (cone half-angle 0).
      const std::vector<reference::Light> lights = scene::referenceLights(s);
      const auto passes = reference::doublingPasses(config_.first, config_.budget, 1, config_.cap);
      const analysis::Masks masks = analysis::compareMasks(s, mesh, {}, 0.0);
      if (stop_) throw Stopped{};
      reference::CameraPathOptions o;
      o.seed = config_.seed;
      o.threads = config_.threads;
      reference::CameraPathTracer tracer(mesh, s.medium, lights, s.camera, o);
      stopped = runPhysical(tracer, passes, masks, "camera", "cpu", 0.0);
    } else if (config_.kind == analysis::ReferenceKind::Physical) {
      // Lights first: one the tracer cannot handle (filtered, an unreadable map) fails before any
      // work.
      const std::vector<reference::Light> lights = scene::referenceLights(s);
      const auto passes = reference::doublingPasses(config_.first, config_.budget,
                                                    reference::kBlockPhotons, config_.cap);
      const analysis::Masks masks = analysis::compareMasks(s, mesh, {});
      if (stop_) throw Stopped{};
      // Before the tracer: the context outlives the walker the tracer holds.
      const reference::TraceDevice dev = reference::openTraceDevice(config_.device, "reference device");
      reference::MeshPathTracer tracer(mesh, s.medium, lights, s.camera, s.cone_angle,
                                       {config_.seed, config_.threads});
      reference::useDevice(dev, config_.device, tracer, mesh,
                           std::filesystem::path(s.mesh_file).string(), "reference device");
      stopped = runPhysical(tracer, passes, masks, "light", tracer.device() == "cpu" ? "cpu" : "gpu",
                            std::nullopt);
    } else {
      const auto passes = modelPasses(config_.first, config_.budget);
      uint64_t total = 0;
      for (uint64_t n : passes) total += n;
      uint64_t computed = 0;
      for (size_t k = 0; k < passes.size() && !stopped; ++k) {
        if (stop_) {
          stopped = true;
          break;
        }
        // Subpixels: the library's (and the CLI's) default, so that the images are the CLI's.
        analysis::ReferenceRequest request;
        request.kind = analysis::ReferenceKind::Model;
        request.count = passes[k];
        request.seed = config_.seed;
        request.threads = config_.threads;
        const uint64_t before = computed;
        analysis::Reference r = analysis::computeReference(
            s, mesh, request, [&](const reference::TraceProgress& p) {
              if (p.photons_total > 0)
                // The model's progress counts pixels: the pass's share of its samples.
                progressTo((static_cast<double>(before) +
                            static_cast<double>(passes[k]) * static_cast<double>(p.photons_done) /
                                static_cast<double>(p.photons_total)) /
                           static_cast<double>(total));
              return !stop_.load();
            });
        if (r.partial || stop_) {
          stopped = true;
          break;
        }
        computed += passes[k];
        analysis::Masks masks = analysis::compareMasks(s, mesh, r.coverage);
        report(static_cast<int>(k), static_cast<int>(passes.size()), passes[k], computed, total,
               std::move(r), std::move(masks));
      }
    }
  } catch (const Stopped&) {
    stopped = true;
  } catch (const std::exception& e) {
    error = e.what();
  }
  if (callbacks_.finished) callbacks_.finished(stopped, error);
}

}  // namespace translucent::explorer
