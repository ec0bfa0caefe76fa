// SPDX-License-Identifier: GPL-3.0-or-later
// The GLSL twins of the 3D material fields (material/*.h, shaders/reference/fields.glsl): which
// fields the GPU walk can evaluate, and their packing into one buffer of 32-bit words that
// fields.glsl reads (std430 binding 7, `fieldWords`). fieldAt(q) there is the same formula as
// the field's at(q), in float.
//
// Layout (words; "f" a float as its bits, "i" a two's complement int, "u" a uint):
//   [0] u kind: 0 none (fieldAt gives zeros: a zeroed buffer reads as this), 1 checker,
//       2 gradient, 3 veins, 4 layers, 5 voxels (density), 6 voxels (coefficients)
//   [1] u total word count
//   [2] u n: the number of media
//   [3] u P: where the kind's parameters start (4 + 8 n)
//   [4 + 8 m ..] medium m: f σa.rgb, f g, f σs.rgb, 0 (per medium unit)
//   P.. by kind:
//     checker  f cell.xyz
//     gradient f from.xyz, f axis.xyz (axis = (b − a) / |b − a|²)
//     veins    d direction.xyz, d period, d noise_size ("d" a double as two words, low first),
//              then at P + 10 f turbulence, f sharpness, u octaves, 0 x 3; at P + 16 the 256
//              entries of Perlin's permutation (noise.h), one per word; media: base, vein
//     layers   u form (0 plane, 1 surface), u nodes offset, u triangles offset, f normal.xyz,
//              f offset, then at P + 7 the n − 1 layer bottoms (depths, increasing)
//              surface: node k at (nodes offset) + 10 k: f lo.xyz, f hi.xyz (rounded outwards),
//              u first, u count (> 0: a leaf of triangles first .. first + count − 1), u left,
//              u right (inner nodes); triangle k at (triangles offset) + 9 k: f a.xyz, b.xyz,
//              c.xyz. The tree is material::SurfaceDistance's own, root first.
//     voxels (density)      the density grid's header (below); media: 0 and 1 of the blend
//     voxels (coefficients) f g, 0, 0, 0, then σa's grid header at P + 4 and σs's at P + 28;
//                           no media
//   grid header (24 words): i origin.xyz, i dims.xyz, u channels (1 or 3), u values offset,
//     f background.rgb, f translation.xyz, f world_to_index (3 columns of 3), 0; the values as
//     DenseGrid stores them (x fastest, then y, z; channels interleaved).
//
// Coefficients, positions and transforms are rounded to float, but for the veins' phase, which
// their sharpness amplifies; the integers are exact.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "translucent/gpu/objects.h"
#include "translucent/gpu/program.h"
#include "translucent/material/material.h"
#include "translucent/reference/majorant_grid.h"

namespace translucent::reference::gpu_field {

// "" when fieldAt can evaluate `f`, otherwise why not (a sentence without a prefix, e.g. for
// "--device gpu: <reason>").
std::string refusal(const material::VolumeField& f);

// The words of the layout above. Throws ParameterError (with refusal()'s reason) for a field
// that refusal() refuses.
std::vector<uint32_t> pack(const material::VolumeField& f);

// What shaders/reference/delta_tracking.glsl reads of a heterogeneous medium, for one walker: the
// field packed once per medium (binding 7), the majorant grid's bounds per channel rounded up to
// float (binding 8; a bound below σt would bias the tracking), the violation counter (binding 9),
// and the uniforms (grid, frame, deformations).
class VolumeBuffers {
 public:
  // The uniforms of `volume` in `channel` on `p`, its buffers made when the medium changes; null:
  // placeholders (bound, never read).
  void set(const gpu::ShaderProgram& p, const VolumeMedium* volume, int channel);
  // Binds the buffers of the last set() in `channel`.
  void bind(int channel) const;
  void resetViolations() const;
  uint32_t violations() const;  // counted since resetViolations()

 private:
  gpu::Buffer fieldWords_, violations_, majorants_[3];
  const VolumeMedium* volume_ = nullptr;  // the medium fieldWords_ and majorants_ hold
};

}  // namespace translucent::reference::gpu_field
