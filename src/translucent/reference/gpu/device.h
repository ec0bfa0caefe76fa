// SPDX-License-Identifier: GPL-3.0-or-later
// Where a reference runs (`--device cpu|gpu|auto` of `translucent pathtrace slab|sphere|mesh`,
// `device=` of the Python module, the explorer's device boxes): the CPU tracers of src/reference,
// or the GPU tracers of this folder in a GL context of their own.
#pragma once

#include <memory>
#include <string>

#include "translucent/geometry/mesh.h"
#include "translucent/gpu/context.h"
#include "translucent/reference/camera_paths.h"
#include "translucent/reference/mesh_tracer.h"
#include "translucent/reference/slab_request.h"
#include "translucent/reference/sphere.h"

namespace translucent::reference {

enum class Device { Cpu, Gpu };

struct TraceDevice {
  Device device = Device::Cpu;
  std::unique_ptr<gpu::Context> context;  // current on the opening thread; with Device::Gpu
};

// `choice` is "cpu", "gpu" (whatever GL 4.5 context EGL gives, software renderers included), or
// "auto": the GPU when EGL gives a context on a hardware GPU, the CPU otherwise (on llvmpipe the
// CPU tracer is the faster one: BENCHMARKS.md of commit 91fe617). ParameterError naming `option` for another word,
// and for "gpu" when EGL gives no GL 4.5 context (the message says what it offered).
TraceDevice openTraceDevice(const std::string& choice, const std::string& option = "--device");

// The device's walker on a tracer (nothing on the CPU): what every front end (CLI, Python,
// compare, the explorer) calls after opening the device and before tracing. The context must
// outlive the tracer. A mesh: with `choice` "auto" only where the GPU walk can trace the run
// (meshGpuRefusal), so auto keeps the CPU for the rest; with "gpu" a run it cannot trace is a
// ParameterError "<option> gpu: <why>".
void useDevice(const TraceDevice& device, SpherePathTracer& tracer);
// Why the GPU walk cannot trace this mesh run ("" when it can): a 3D field fields.glsl lacks.
std::string meshGpuRefusal(const MeshPathTracer& tracer);
void useDevice(const TraceDevice& device, const std::string& choice, MeshPathTracer& tracer,
               const geometry::TriangleMesh& mesh, const std::string& what,
               const std::string& option = "--device");

// The camera method (camera_paths.h) on the device: the GPU camera walk (camera_gpu.h) where it
// can trace the scene (a 3D field without a GLSL twin it cannot); with "auto" the CPU for the
// rest, with "gpu" a ParameterError "<option> gpu: <why>".
void useDevice(const TraceDevice& device, const std::string& choice, CameraPathTracer& tracer,
               const geometry::TriangleMesh& mesh, const std::string& what,
               const std::string& option = "--device");

// traceSlab (slab.h) or traceSlabGpu (slab_gpu.h), as the device says.
SlabResult traceSlab(const TraceDevice& device, const SlabSetup& setup, const TraceOptions& options,
                     const ProgressCallback& progress = {}, RunState* state = nullptr);

// traceSlabRun (slab_request.h) on the device (run.device chose it).
SlabResult traceSlabRun(const TraceDevice& device, const SlabRun& run,
                        const ProgressCallback& progress = {}, RunState* state = nullptr);

}  // namespace translucent::reference
