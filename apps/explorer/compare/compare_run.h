// SPDX-License-Identifier: GPL-3.0-or-later
// One background reference of the Compare dock: the scene at the dock's camera, computed on a
// thread of its own in passes, each reported as a complete analysis::Reference with its masks.
//
//   physical  reference::MeshPathTracer refined by doubling passes (reference/progressive.h) of
//             whole blocks: the image after N photons per channel is bit for bit the one
//             `translucent compare --photons N` computes (same seed, any thread count).
//   model     the model reference cannot add samples to an image it has made (its near-field
//             radius depends on the sample count, model_reference.h), so each pass is a fresh
//             analysis::computeReference with twice the samples of the one before: the image
//             after N samples is the CLI's `--samples N` one, and the run costs twice its last
//             pass.
// Masks: analysis::compareMasks of the scene (with the model's coverage), as the CLI.
//
// The run never touches Qt or the ExplorerState; it calls its callbacks on its own thread.
// Destroying it requests a stop and joins: the estimators poll the stop flag about ten times a
// second and drop the block in hand, so that returns within about a tenth of a second plus one
// block (1024 photons per channel, or a share of the model's pixels) once the passes run; during
// the setup (mesh loading, masks, the tracer's BVH: a second for the bunny on a loaded 2-core
// machine) the flag is read between the steps only.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <thread>

#include "translucent/compare/compare.h"
#include "translucent/scene/scene.h"

namespace translucent::explorer {

struct CompareRunConfig {
  scene::Scene scene;  // camera at the size of the images
  analysis::ReferenceKind kind = analysis::ReferenceKind::Physical;
  // physical: photons per channel (first pass, all passes, largest pass; 0: no cap)
  // model: samples of the first pass; `budget` the largest (passes double up to it)
  uint64_t first = 1, budget = 1, cap = 0;
  uint64_t seed = 1;
  int threads = 0;  // 0: all hardware threads
  // The physical reference's device (reference/gpu/device.h): "cpu", "gpu" (a GL context of the
  // run's own) or "auto" (the GPU on a hardware GPU where the GPU walk can trace the scene).
  std::string device = "auto";
  // The physical reference's method: "light" (photons, MeshPathTracer) or "camera" (camera paths
  // per pixel, CameraPathTracer: first, budget and cap count paths per pixel and channel).
  std::string method = "light";
};

struct CompareSnapshot {
  int pass = 0;            // index of the pass just completed
  int passes = 0;          // passes in the schedule
  uint64_t count = 0;      // photons per channel / samples of the image
  uint64_t computed = 0;   // all photons per channel / samples computed so far
  uint64_t budget = 0;     // of `computed` at the end of the schedule
  double seconds = 0.0;    // since the run started (mesh loading and masks included)
  double eta = 1.0;        // the medium's (for Reference::radianceFor)
  analysis::Reference reference;
  analysis::Masks masks;
};

struct CompareRunCallbacks {
  // All called on the run's thread; `finished` is the last call the run makes.
  std::function<void(std::shared_ptr<const CompareSnapshot>)> pass;
  std::function<void(double fraction)> progress;  // of the whole schedule, in [0, 1]
  std::function<void(bool stopped, const std::string& error)> finished;
};

// The model's pass sizes: first, 2 first, ... while <= budget (at least one pass).
std::vector<uint64_t> modelPasses(uint64_t first, uint64_t budget);

class CompareRun {
 public:
  CompareRun(CompareRunConfig config, CompareRunCallbacks callbacks);  // starts the thread
  ~CompareRun();                                                       // stops and joins
  CompareRun(const CompareRun&) = delete;
  CompareRun& operator=(const CompareRun&) = delete;

  void requestStop() { stop_ = true; }

 private:
  void run();
  CompareRunConfig config_;
  CompareRunCallbacks callbacks_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace translucent::explorer
