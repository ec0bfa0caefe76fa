// SPDX-License-Identifier: GPL-3.0-or-later
// Shared pieces of the point-cloud technique's shaders (src/techniques/pointcloud/): the octree's
// std430 records (geometry/octree.h) and the exact Fresnel transmittance.
// Prefix: pc (point cloud). Units: scene units for positions and areas, W for powers.
#pragma once

// One octree node (geometry::OctreeNode, 64 bytes).
struct PcNode {
  vec4 powerArea;  // xyz: power Φ_v = Σ E_i A_i (RGB) [W]; w: area A_v [scene units²]
  vec4 average;    // xyz: irradiance-weighted average position P_v (GLSL reserves "centroid")
  vec4 lower;      // xyz: bounding box minimum
  vec4 upper;      // xyz: bounding box maximum
};

// One surface sample (geometry::OctreePoint, 32 bytes), in leaf order.
struct PcPoint {
  vec4 positionArea;  // xyz: position; w: area A_i [scene units²]
  vec4 normal;        // xyz: unit outward normal
};

// The 32-bit child descriptor (seed Fig. 3.5): bits 0..3 child count, 4..7 point count,
// 8..31 index of the first child (interior) or first point (leaf).
uint pcChildCount(uint d) { return d & 0xFu; }
uint pcPointCount(uint d) { return (d >> 4) & 0xFu; }
uint pcIndex(uint d) { return d >> 8; }

// Exact unpolarised Fresnel transmittance into the medium for light arriving from outside at
// cos_i = n·ω (clamped to [0, 1]); eta = n_medium / n_outside (optics/fresnel.h).
float pcFresnelTransmittance(float cosI, float eta) {
  cosI = clamp(cosI, 0.0, 1.0);
  float sin2T = (1.0 - cosI * cosI) / (eta * eta);
  if (sin2T >= 1.0) return 0.0;
  float cosT = sqrt(1.0 - sin2T);
  float rs = (cosI - eta * cosT) / (cosI + eta * cosT);
  float rp = (eta * cosI - cosT) / (eta * cosI + cosT);
  return 1.0 - 0.5 * (rs * rs + rp * rp);
}

const float PC_PI = 3.14159265358979323846;
