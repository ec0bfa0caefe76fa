// SPDX-License-Identifier: GPL-3.0-or-later
// One background computation of the lit sphere widgets (seed 3.6.2): either the path-traced
// reference (reference::SpherePathTracer) or a model's sphere integration
// (reference::SphereIntegrator; reference::GpuSphereIntegrator for a directional .bssrdf file), refined by doubling passes (reference::runProgressive) on a
// thread of its own, and cancellable at any time.
//
// The run never touches Qt or the ExplorerState: it works on copies of its inputs and reports
// through callbacks that it calls on its own thread. The dock turns them into queued calls to
// the GUI thread. Destroying a run requests a stop and joins its thread; the estimators poll the
// stop flag about ten times a second and drop the block in hand, so that returns within about a
// tenth of a second plus one block (1024 photons per channel, or one image row of samples).
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <thread>

#include <utility>
#include <vector>

#include "translucent/gpu/bssrdf_kernels.h"
#include "translucent/optics/medium.h"
#include "translucent/reference/mc_image.h"
#include "translucent/reference/sphere.h"

namespace translucent::bssrdf {
class Model;
}

namespace translucent::explorer {

struct SphereRunConfig {
  reference::SphereScene scene;
  Medium medium;
  // nullptr: path-trace the sphere; otherwise integrate this model (registered models live for
  // the whole program, so the pointer stays valid; a radial .bssrdf file tabulated for the
  // medium, gpu::bssrdfTabulatedModel, is kept alive by owned_model).
  const bssrdf::Model* model = nullptr;
  std::shared_ptr<const bssrdf::Model> owned_model;
  // A directional .bssrdf file (no `radial`): integrated on the GPU with the light's direction
  // (reference::GpuSphereIntegrator, uniform sampling) in a GL context of the run's own, from the
  // file and the parameter values it had when the run started. Empty: not that case.
  std::string bssrdf_file;
  std::vector<std::pair<std::string, gpu::ParameterValue>> bssrdf_parameters;
  uint64_t first = 1;   // first pass: photons per channel (tracer) or samples per pixel
  uint64_t budget = 1;  // all passes together
  uint64_t cap = 0;     // largest pass (0: none): keeps refreshes coming
  uint64_t seed = 1;
  int threads = 0;      // 0: all hardware threads
  // The path tracer's device (reference/gpu/device.h): "cpu", "gpu" (a GL 4.5 context of the
  // run's own, made on its thread) or "auto" (the GPU on a hardware GPU, else the CPU).
  std::string device = "auto";
  // The path tracer's images of this scattering order only (seed Eq. 2.13: e.g. the multiple
  // scattering that the diffusion models describe); nullopt: all of the light.
  std::optional<reference::ScatteringOrder> order;
};

// The images after a complete pass.
struct SphereSnapshot {
  int pass = 0;           // index of the pass just completed
  int passes = 0;         // passes in the schedule
  uint64_t done = 0;      // photons per channel or samples per pixel so far
  uint64_t budget = 0;    // the schedule's total
  double seconds = 0.0;   // since the run started (including setup)
  std::string device;     // what traced it: "cpu" or "gpu (<renderer>)"; empty: integration
  reference::McImage exitance, radiance;
};

struct SphereRunCallbacks {
  // All called on the run's thread; `finished` is the last call the run makes.
  std::function<void(std::shared_ptr<const SphereSnapshot>)> pass;
  std::function<void(double fraction)> progress;  // of the whole budget, in [0, 1]
  std::function<void(bool stopped, const std::string& error)> finished;
};

class SphereRun {
 public:
  SphereRun(SphereRunConfig config, SphereRunCallbacks callbacks);  // starts the thread
  ~SphereRun();                                                     // stops and joins
  SphereRun(const SphereRun&) = delete;
  SphereRun& operator=(const SphereRun&) = delete;

  void requestStop() { stop_ = true; }

 private:
  void run();
  SphereRunConfig config_;
  SphereRunCallbacks callbacks_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace translucent::explorer
