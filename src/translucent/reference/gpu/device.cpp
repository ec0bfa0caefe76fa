// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/reference/gpu/device.h"

#include <fmt/format.h>

#include <filesystem>
#include <system_error>

#include "translucent/material/layers.h"
#include "translucent/optics/medium.h"
#include "translucent/reference/gpu/camera_gpu.h"
#include "translucent/reference/gpu/field_gpu.h"
#include "translucent/reference/gpu/mesh_gpu.h"
#include "translucent/reference/gpu/slab_gpu.h"
#include "translucent/reference/gpu/sphere_gpu.h"

namespace translucent::reference {
namespace {

// Whether this machine has a device node through which a hardware GPU could be reached: a DRM
// render node (/dev/dri/renderD*: Mesa's hardware drivers, NVIDIA's with nvidia-drm) or NVIDIA's
// /dev/nvidia0. Without one, `auto` means the CPU, decided without creating a GL context: a
// context would be Mesa's software rasteriser, and creating it only to drop it again loads llvmpipe
// and LLVM into the process (about 60 MiB resident for the rest of the run).
bool mayHaveHardwareGpu() {
  std::error_code ec;
  if (std::filesystem::exists("/dev/nvidia0", ec)) return true;
  for (std::filesystem::directory_iterator it("/dev/dri", ec), end; !ec && it != end; it.increment(ec))
    if (it->path().filename().string().starts_with("renderD")) return true;
  return false;
}

}  // namespace

TraceDevice openTraceDevice(const std::string& choice, const std::string& option) {
  if (choice != "cpu" && choice != "gpu" && choice != "auto")
    throw ParameterError(fmt::format("{} '{}': expected cpu, gpu or auto", option, choice));
  TraceDevice d;
  if (choice == "cpu" || (choice == "auto" && !mayHaveHardwareGpu())) return d;
  try {
    d.context = std::make_unique<gpu::Context>();
  } catch (const gpu::ContextError& e) {
    if (choice == "gpu") throw ParameterError(fmt::format("{} gpu: {}", option, e.what()));
    return d;  // auto without any GL: the CPU
  }
  if (choice == "auto" && d.context->info().software) {
    d.context.reset();
    return d;
  }
  d.device = Device::Gpu;
  return d;
}

void useDevice(const TraceDevice& device, SpherePathTracer& tracer) {
  if (device.device == Device::Gpu) tracer.setWalker(makeGpuSphereWalker(*device.context));
}

std::string meshGpuRefusal(const MeshPathTracer& tracer) {
  const VolumeMedium* v = tracer.volume();
  if (!v) return "";
  return gpu_field::refusal(*v->field);
}

void useDevice(const TraceDevice& device, const std::string& choice, MeshPathTracer& tracer,
               const geometry::TriangleMesh& mesh, const std::string& what,
               const std::string& option) {
  if (device.device != Device::Gpu) return;
  if (const std::string why = meshGpuRefusal(tracer); !why.empty()) {
    if (choice == "auto") return;
    throw ParameterError(fmt::format("{} gpu: {}", option, why));
  }
  tracer.setWalker(makeGpuMeshWalker(*device.context, mesh, what));
}

void useDevice(const TraceDevice& device, const std::string& choice, CameraPathTracer& tracer,
               const geometry::TriangleMesh& mesh, const std::string& what,
               const std::string& option) {
  if (device.device != Device::Gpu) return;
  if (const std::string why = tracer.volume() ? gpu_field::refusal(*tracer.volume()->field) : "";
      !why.empty()) {
    if (choice == "auto") return;
    throw ParameterError(fmt::format("{} gpu: {}", option, why));
  }
  // The light-traced complement at η ≠ 1 in the light method's GPU walk too.
  tracer.setWalker(makeGpuCameraWalker(*device.context, mesh, what),
                   tracer.hasComplement() ? makeGpuMeshWalker(*device.context, mesh, what) : nullptr);
}

SlabResult traceSlab(const TraceDevice& device, const SlabSetup& setup, const TraceOptions& options,
                     const ProgressCallback& progress, RunState* state) {
  if (device.device == Device::Cpu) return traceSlab(setup, options, progress, state);
  device.context->makeCurrent();
  return traceSlabGpu(setup, options, progress, state);
}

SlabResult traceSlabRun(const TraceDevice& device, const SlabRun& run,
                        const ProgressCallback& progress, RunState* state) {
  if (device.device == Device::Cpu) return traceSlabRun(run, progress, state);
  if (!run.layered) return traceSlab(device, run.setup, run.options, progress, state);
  device.context->makeCurrent();
  return traceLayeredSlabGpu(*run.layered, run.options, progress, state);
}

}  // namespace translucent::reference
