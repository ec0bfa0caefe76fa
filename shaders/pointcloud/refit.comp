#version 450 core
// SPDX-License-Identifier: GPL-3.0-or-later
// Refit of the octree's node attributes after the irradiance pass (geometry::Octree::refit on the
// GPU): for every node, the power Φ_v = Σ E_i A_i, the area A_v = Σ A_i and the irradiance-
// weighted position P_v = Σ w_i p_i / Σ w_i, w_i = A_i (E_r + E_g + E_b) / 3 (the area-weighted
// position where Σ w_i = 0), bottom-up: one dispatch per tree level, deepest first. A leaf sums
// its points; an interior node sums its children (a child's weight is the mean of its power, and
// its P_v stands for its points: Σ_c w_c P_c = Σ_i w_i p_i). The topology and the bounding boxes
// do not change.
layout(local_size_x = 64) in;
#include "common/compute.glsl"
#include "pointcloud/common.glsl"

layout(std430, binding = 0) readonly buffer PcDescriptors { uint pcDescriptor[]; };
layout(std430, binding = 1) buffer PcNodes { PcNode pcNode[]; };
layout(std430, binding = 2) readonly buffer PcPoints { PcPoint pcPoint[]; };
layout(std430, binding = 3) readonly buffer PcIrradiance { vec4 pcIrradiance[]; };
layout(std430, binding = 6) readonly buffer PcLevels { uint pcLevelNode[]; };  // deepest first
// Directional BSSRDFs: per point the lights' Σ w l, Σ w (irradiance.comp); per node three sums
// over its points, each point weighted by its area A: (Σ A w l, Σ A w), Σ A w n (the lit
// points' normal) and Σ A n (all points' normal). The traversal takes a cluster's light
// direction and normal from them (radiance.comp, PC_DIRECTIONAL).
layout(std430, binding = 14) readonly buffer PcLightDir { vec4 pcLightDir[]; };
layout(std430, binding = 15) buffer PcNodeLight { vec4 pcNodeLight[]; };  // 3 per node

#ifdef PC_HETERO
// Heterogeneous material (cpu_traversal.h refitNodeProfiles): the node's representative profile,
// sqrt(P_v^k) = Σ Φ sqrt(P^k) / Σ Φ per channel over its points or children (area weights where
// Σ Φ = 0), stored as ln P clamped at -80 (material::kLnFloor). PC_PROFILE_NODES = n + 1.
layout(std430, binding = 9) readonly buffer PcPointProfiles { vec4 pcPointProfile[]; };
layout(std430, binding = 10) buffer PcNodeProfiles { vec4 pcNodeProfile[]; };
#endif

uniform uint LevelOffset;  // first entry of this level in pcLevelNode
uniform uint LevelCount;   // nodes on this level

void main() {
  uint i = linearInvocationIndex();
  if (i >= LevelCount) return;
  uint v = pcLevelNode[LevelOffset + i];
  uint d = pcDescriptor[v];
  vec3 power = vec3(0.0), weighted = vec3(0.0), areaPos = vec3(0.0);
  float area = 0.0, weight = 0.0;
  vec4 light = vec4(0.0), litNormal = vec4(0.0), normal = vec4(0.0);
  if (pcChildCount(d) == 0u) {
    for (uint p = pcIndex(d), e = p + pcPointCount(d); p < e; ++p) {
      vec3 pos = pcPoint[p].positionArea.xyz;
      float a = pcPoint[p].positionArea.w;
      vec4 l = pcLightDir[p];
      light += a * l;
      litNormal.xyz += a * l.w * pcPoint[p].normal.xyz;
      normal.xyz += a * pcPoint[p].normal.xyz;
      vec3 phi = pcIrradiance[p].rgb * a;
      float w = (phi.r + phi.g + phi.b) / 3.0;
      power += phi;
      area += a;
      weight += w;
      weighted += w * pos;
      areaPos += a * pos;
    }
  } else {
    for (uint c = pcIndex(d), e = c + pcChildCount(d); c < e; ++c) {
      vec3 phi = pcNode[c].powerArea.xyz;
      float a = pcNode[c].powerArea.w;
      float w = (phi.r + phi.g + phi.b) / 3.0;
      light += pcNodeLight[3u * c];
      litNormal += pcNodeLight[3u * c + 1u];
      normal += pcNodeLight[3u * c + 2u];
      power += phi;
      area += a;
      weight += w;
      weighted += w * pcNode[c].average.xyz;
      areaPos += a * pcNode[c].average.xyz;
    }
  }
  pcNode[v].powerArea = vec4(power, area);
  pcNodeLight[3u * v] = light;
  pcNodeLight[3u * v + 1u] = litNormal;
  pcNodeLight[3u * v + 2u] = normal;
  pcNode[v].average = vec4(weight > 0.0 ? weighted / weight : areaPos / area, 0.0);
#ifdef PC_HETERO
  const uint m = uint(PC_PROFILE_NODES);
  for (uint k = 0u; k < m; ++k) {
    vec3 s = vec3(0.0), sa = vec3(0.0);
    if (pcChildCount(d) == 0u) {
      for (uint p = pcIndex(d), e = p + pcPointCount(d); p < e; ++p) {
        float a = pcPoint[p].positionArea.w;
        vec3 root = exp(0.5 * pcPointProfile[p * m + k].xyz);
        s += pcIrradiance[p].rgb * a * root;
        sa += a * root;
      }
    } else {
      for (uint c = pcIndex(d), e = c + pcChildCount(d); c < e; ++c) {
        vec3 root = exp(0.5 * pcNodeProfile[c * m + k].xyz);
        s += pcNode[c].powerArea.xyz * root;
        sa += pcNode[c].powerArea.w * root;
      }
    }
    vec3 mean;
    for (int ch = 0; ch < 3; ++ch) mean[ch] = power[ch] > 0.0 ? s[ch] / power[ch] : sa[ch] / area;
    vec3 ln = vec3(-80.0);
    for (int ch = 0; ch < 3; ++ch)
      if (mean[ch] > 0.0) ln[ch] = max(2.0 * log(mean[ch]), -80.0);
    pcNodeProfile[v * m + k] = vec4(ln, 0.0);
  }
#endif
}
