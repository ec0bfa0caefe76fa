#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// Subgroup votes (ARB_shader_ballot: NVIDIA, AMD, Mesa) make the traversal coherent; without
// them every invocation traverses alone, which gives the same result.
#extension GL_ARB_gpu_shader_int64 : enable
#extension GL_ARB_shader_ballot : enable
// Radiance pass of the point-cloud technique (seed 2.6.4 "Second Pass", 3.3.3, Algorithm 2):
// per pixel of the G-buffer, the radiant exitance due to subsurface transport
//     B(x_o) = Σ_c R(x_o, x_c) Φ_c     [W / scene unit², RGB]
// over single points (x_c = p_i, Φ_c = E_i A_i) and clusters (octree nodes, x_c = P_v,
// Φ_c = Φ_v), by a stack-bounded traversal of the octree; then the radiance
//     L = s Ft(η, n·ω_o) B / π  (the optional specular reflection is added afterwards by
//     shaders/common/specular.comp),
// s = ExitScale, the exit-radiance convention of seed Eq. 2.16 (bssrdf/exit_radiance.h): 1 for
// Jensen et al. 2001, 1/(4Cφ(1/η)) = 1/(1 - 2 C1_ext) for the normalized form. The exitance
// output stays B.
// The traversal is the CPU oracle's (techniques/pointcloud/cpu_traversal.h) step for step:
//   subdivide(node): interior, Φ_v ≠ 0 and A_v >= ε d², with d the distance from x_o to the
//     node's bounding box (Criterion 0, 0 inside the box) or to P_v (Criterion 1);
//   children from the last to the first; a stack entry packs (node << 8 | remaining siblings);
//   PC_STACK_SIZE = octree depth - 1 entries hold the path below the root (the oracle never
//   pushes the root; this shader does, in one extra entry, see below).
// Traversal is by packets: the invocations of a subgroup (8×4 neighbouring pixels on NVIDIA)
// walk one shared path, subdividing a node when any of them needs it; an invocation that
// accepts a node (adds its cluster) rides along inert through the node's subtree. Each
// invocation thus adds exactly the clusters and points of its own cut, in the same depth-first
// order, while loads and branches are the same for the whole subgroup. The root is pushed too
// here, so the stack depth tells the subtree an inert invocation waits out. The result does not
// depend on which invocations a vote sees, as long as it sees the voter: a partial vote (e.g.
// invocations not yet reconverged) only splits the packet.
// The kernel R(x_o, x_i) comes from "pointcloud:kernel": the tabulated radial profile
// (kernel_table.glsl) or a .bssrdf file's Bssrdf() (kernel_bssrdf.glsl).
layout(local_size_x = 8, local_size_y = 8) in;
#include "pointcloud/common.glsl"

#ifndef PC_STACK_SIZE
#define PC_STACK_SIZE 24
#endif

layout(std430, binding = 0) readonly buffer PcDescriptors { uint pcDescriptor[]; };
layout(std430, binding = 1) readonly buffer PcNodes { PcNode pcNode[]; };
layout(std430, binding = 2) readonly buffer PcPoints { PcPoint pcPoint[]; };
layout(std430, binding = 3) readonly buffer PcIrradiance { vec4 pcIrradiance[]; };
layout(std430, binding = 7) writeonly buffer PcRadiance { vec4 pcRadiance[]; };  // rows from the top
layout(std430, binding = 8) writeonly buffer PcExitance { vec4 pcExitance[]; };

#include "pointcloud:kernel"
#ifdef PC_DIRECTIONAL
// A directional .bssrdf file: the light direction and normal of each point and cluster
// (irradiance.comp, refit.comp). A point lit only by environment light has no direction and is
// taken as lit along its normal; a cluster takes the mean direction of its points' lights
// (weighted by their irradiance and area) and the irradiance-weighted normal of its lit points.
layout(std430, binding = 14) readonly buffer PcLightDir { vec4 pcLightDir[]; };
layout(std430, binding = 15) readonly buffer PcNodeLight { vec4 pcNodeLight[]; };

vec3 pcDirectionOr(vec4 sum, vec3 fallback) {
  float len = length(sum.xyz);
  return sum.w > 0.0 && len > 0.0 ? sum.xyz / len : fallback;
}
#endif
#ifdef PC_HETERO
// Heterogeneous material: Eq. 8 with per-point, per-node and shading-point profiles.
#include "pointcloud/hetero.glsl"
#endif

layout(binding = 0) uniform sampler2D GPosition;  // xyz: world position; w: 1 where covered
layout(binding = 1) uniform sampler2D GNormal;    // xyz: unit shading normal

uniform uvec2 Size;            // image size [pixels]
uniform float Epsilon;         // maximum solid angle of a cluster [sr]
uniform int Criterion;         // 0: bounding-box distance, 1: centroid distance
uniform float Eta;             // n_medium / n_outside
uniform vec3 ExitScale;        // L / (Ft B/π) per channel (radiance_convention), dimensionless
uniform vec3 CameraPosition;   // pinhole centre
uniform vec3 CameraForward;    // orthographic viewing direction
uniform bool Orthographic;

// Traversals the driver cut (llvmpipe ends every loop of an invocation after 65535 iterations:
// gpu/compute.h, LoopLimit): one up when a traversal starts, one down where it ends by its own
// rule; more than 0 after the pass means a pixel's B is missing clusters (pointcloud_technique.cpp
// makes that an error).
layout(std430, binding = 16) buffer PcCut { uint pcCut; };

bool subdivide(uint node, vec3 x) {
  uint d = pcDescriptor[node];
  if (pcChildCount(d) == 0u) return false;
  vec4 pa = pcNode[node].powerArea;
  if (pa.x == 0.0 && pa.y == 0.0 && pa.z == 0.0) return false;
  float d2;
  if (Criterion == 0) {
    vec3 g = max(max(pcNode[node].lower.xyz - x, x - pcNode[node].upper.xyz), vec3(0.0));
    d2 = dot(g, g);
  } else {
    vec3 g = pcNode[node].average.xyz - x;
    d2 = dot(g, g);
  }
  return pa.w >= Epsilon * d2;
}

vec3 contribute(uint node, vec3 x, vec3 n) {
  vec4 pa = pcNode[node].powerArea;
  if (pa.x == 0.0 && pa.y == 0.0 && pa.z == 0.0) return vec3(0.0);
  uint d = pcDescriptor[node];
  if (pcChildCount(d) == 0u) {
    vec3 sum = vec3(0.0);
    for (uint p = pcIndex(d), e = p + pcPointCount(d); p < e; ++p) {
      PcPoint q = pcPoint[p];
#ifdef PC_HETERO
      sum += pcHeteroPoint(distance(x, q.positionArea.xyz), p) * (pcIrradiance[p].rgb * q.positionArea.w);
#elif defined(PC_DIRECTIONAL)
      vec3 wi = pcDirectionOr(pcLightDir[p], q.normal.xyz);
      sum += pcKernelDirectional(x, n, q.positionArea.xyz, q.normal.xyz, wi) * (pcIrradiance[p].rgb * q.positionArea.w);
#else
      sum += pcKernel(x, n, q.positionArea.xyz, q.normal.xyz) * (pcIrradiance[p].rgb * q.positionArea.w);
#endif
    }
    return sum;
  }
#ifdef PC_HETERO
  return pcHeteroNode(distance(x, pcNode[node].average.xyz), node) * pa.xyz;
#elif defined(PC_DIRECTIONAL)
  vec3 nodeNormal = pcDirectionOr(vec4(pcNodeLight[3u * node + 1u].xyz, 1.0),
                                  pcDirectionOr(vec4(pcNodeLight[3u * node + 2u].xyz, 1.0), n));
  vec3 wi = pcDirectionOr(pcNodeLight[3u * node], nodeNormal);
  return pcKernelDirectional(x, n, pcNode[node].average.xyz, nodeNormal, wi) * pa.xyz;
#else
  return pcKernel(x, n, pcNode[node].average.xyz, n) * pa.xyz;
#endif
}

// True when any invocation of the subgroup passes true (itself at least).
bool anyInSubgroup(bool value) {
#if defined(GL_ARB_shader_ballot) && defined(GL_ARB_gpu_shader_int64)
  return ballotARB(value) != uint64_t(0);
#else
  return value;
#endif
}

// Algorithm 2, by subgroup packets (see the top).
vec3 radiantExitance(vec3 x, vec3 n) {
  vec3 b = vec3(0.0);
  uint stack[PC_STACK_SIZE + 1];
  int sp = 0;
  // This invocation is inert while sp > inertAbove: it accepted the node at depth inertAbove
  // and the packet is inside that node's subtree.
  const int kActive = 0x7FFFFFFF;
  int inertAbove = kActive;
  uint node = 0u, childnum = 0u;
  atomicAdd(pcCut, 1u);
  for (;;) {
    bool live = sp <= inertAbove;
    if (live) inertAbove = kActive;
    bool want = live && subdivide(node, x);
    if (anyInSubgroup(want)) {
      if (live && !want) {
        b += contribute(node, x, n);
        inertAbove = sp;
      }
      stack[sp++] = (node << 8) | childnum;
      uint d = pcDescriptor[node];
      childnum = pcChildCount(d) - 1u;
      node = pcIndex(d) + childnum;
      continue;
    }
    if (live) b += contribute(node, x, n);
    for (;;) {
      if (childnum > 0u) {
        --node;
        --childnum;
        break;
      }
      if (sp == 0) {
        atomicAdd(pcCut, 0xFFFFFFFFu);  // ended: one down
        return b;
      }
      uint entry = stack[--sp];
      node = entry >> 8;
      childnum = entry & 0xFFu;
    }
  }
  return b;
}

void main() {
  uvec2 px = gl_GlobalInvocationID.xy;
  if (px.x >= Size.x || px.y >= Size.y) return;
  // GL rows start at the bottom; the output rows start at the top.
  uint out_ = (Size.y - 1u - px.y) * Size.x + px.x;
  vec4 g = texelFetch(GPosition, ivec2(px), 0);
  if (g.w == 0.0) {
    pcRadiance[out_] = vec4(0.0);
    pcExitance[out_] = vec4(0.0);
    return;
  }
  vec3 x = g.xyz;
  vec3 n = normalize(texelFetch(GNormal, ivec2(px), 0).xyz);
  pcKernelInit();
#ifdef PC_HETERO
  pcHeteroShadingInit(x, uint(g.w + 0.5) - 1u);  // w = 1 + the triangle index
#endif
  vec3 b = radiantExitance(x, n);
  vec3 v = Orthographic ? -CameraForward : normalize(CameraPosition - x);
  vec3 l = ExitScale * (pcFresnelTransmittance(dot(n, v), Eta) * b / PC_PI);
  pcRadiance[out_] = vec4(l, 1.0);
  pcExitance[out_] = vec4(b, 1.0);
}
