// SPDX-License-Identifier: GPL-3.0-or-later
// The slab tracer of reference/slab.h on the GPU (issue 16): the same setups (semi-infinite and
// finite slabs, mismatched boundaries, oblique beams, layered slabs), the same options (analog or weighted
// absorption, radial / angular tallies, the long-path roulette, shares of blocks for shards),
// the same SlabResult and the same run state, traced by an OpenGL 4.5 compute shader
// (shaders/reference/slab_walk.comp) in the GL context current on the calling thread.
//
// What differs from the CPU tracer, and why:
//   - the random numbers: Philox4x32-10 keyed by the seed and indexed by (photon, event)
//     (reference/philox.h), so the result is a function of (setup, options, seed) on a given
//     device -- the CPU tracer's xoshiro streams per block are not reproduced, and the two tracers
//     agree within their standard errors, not bit for bit;
//   - the scoring: each photon leaves one record (exit point and cosine, weight, deposit), and the
//     CPU scores the records with the CPU walkers' own functions, in double, in photon order.
//     Tallies need no float atomics, lose no precision, and shards of a GPU run merge exactly;
//   - options.kernel and options.threads do not apply (SlabResult::threads is 1: the host thread).
// Progress is reported, and a stop honoured, between batches of blocks (a batch is sized to take
// about a tenth of a second, so Ctrl-C and time limits act within that).
#pragma once

#include "translucent/reference/layered_slab.h"
#include "translucent/reference/slab.h"

namespace translucent::reference {

// Throws ParameterError for bad setup or options, gpu::GlError when no GL context is current
// or a shader fails to build.
SlabResult traceSlabGpu(const SlabSetup& setup, const TraceOptions& options,
                        const ProgressCallback& progress = {}, RunState* state = nullptr);
// The layered slab (layered_slab.h) on the GPU: shaders/reference/layered_walk.comp, the flight
// in optical depth layer by layer, one sequential Philox stream per photon; the same records,
// scoring and result as the homogeneous slab's.
SlabResult traceLayeredSlabGpu(const LayeredSlabSetup& setup, const TraceOptions& options,
                               const ProgressCallback& progress = {}, RunState* state = nullptr);

}  // namespace translucent::reference
