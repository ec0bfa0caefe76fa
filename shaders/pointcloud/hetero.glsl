// SPDX-License-Identifier: GPL-3.0-or-later
// Heterogeneous materials in the radiance pass of the point-cloud technique (SubEdit Eqs. 8-9;
// techniques/pointcloud/cpu_traversal.h, "Heterogeneous materials", is the CPU oracle of this
// arithmetic, material/point_profiles.h documents the representation): every point, every octree
// node and the shading point carry n + 1 nodes of ln P (RGB) on [0, r_s], and a term is
//     sqrt(P_c(r) P_o(r)) = exp((ln P_c(r) + ln P_o(r)) / 2),
// with ln P piecewise linear in r (Eq. 9), the tail beyond r_s the last segment of ln(r² P)
// extended while it decreases, and P = 0 beyond 3 r_s. The shading point's profile is the
// barycentric interpolation (of ln P) of its triangle's vertex profiles, or with PC_PROFILE_ATLAS
// the profile texture's at its atlas UV; the G-buffer's position w holds 1 + the triangle index
// (gbuffer.frag with PC_HETERO).
// Needs PC_PROFILE_NODES = n + 1 (>= 2).
#pragma once

layout(std430, binding = 9) readonly buffer PcPointProfiles { vec4 pcPointProfile[]; };    // (n+1) per slot
layout(std430, binding = 10) readonly buffer PcNodeProfiles { vec4 pcNodeProfile[]; };     // (n+1) per node
layout(std430, binding = 11) readonly buffer PcVertexProfiles { vec4 pcVertexProfile[]; }; // (n+1) per vertex
layout(std430, binding = 12) readonly buffer PcMeshVertices { vec4 pcVertex[]; };          // xyz: position
layout(std430, binding = 13) readonly buffer PcMeshTriangles { uvec4 pcTriangle[]; };      // xyz: vertices

uniform float HeteroRadius;  // r_s [scene units]

const uint PC_M = uint(PC_PROFILE_NODES);  // n + 1
const uint PC_N = PC_M - 1u;               // n segments
const float PC_LN_ZERO = -1e30;            // ln 0

vec3 pcShading[PC_PROFILE_NODES];  // the shading point's ln P nodes

// Barycentrics (u, v, w) of x's projection on the plane of triangle (a, b, c), clamped to the
// triangle and renormalised (cpu_traversal.h shadingProfile); a degenerate triangle gives its
// centroid. Shared with the splatting technique (splatting/profile.glsl).
vec3 pcClampedBarycentric(vec3 a, vec3 b, vec3 c, vec3 x) {
  vec3 e0 = b - a, e1 = c - a, e2 = x - a;
  float d00 = dot(e0, e0), d01 = dot(e0, e1), d11 = dot(e1, e1), d20 = dot(e2, e0), d21 = dot(e2, e1);
  float den = d00 * d11 - d01 * d01;
  float v = den > 0.0 ? (d11 * d20 - d01 * d21) / den : 1.0 / 3.0;
  float w = den > 0.0 ? (d00 * d21 - d01 * d20) / den : 1.0 / 3.0;
  v = max(v, 0.0);
  w = max(w, 0.0);
  float u = max(1.0 - v - w, 0.0);
  return vec3(u, v, w) / (u + v + w);
}

#ifdef PC_PROFILE_ATLAS
// Profiles at texture resolution (material/profile_atlas.h): layer k of the array holds node k of
// every texel; a point on triangle `tri` at barycentrics b reads them, bilinearly, at the UV
// Σ b_j uv_j of the triangle's corners in the atlas.
layout(binding = 12) uniform sampler2DArray PcProfileAtlas;
layout(std430, binding = 17) readonly buffer PcTriangleUvs { vec2 pcTriangleUv[]; };  // 3 per triangle

vec3 pcSurfaceNode(uint tri, vec3 b, uint k) {
  vec2 uv = b.x * pcTriangleUv[3u * tri] + b.y * pcTriangleUv[3u * tri + 1u] +
            b.z * pcTriangleUv[3u * tri + 2u];
  return texture(PcProfileAtlas, vec3(uv, float(k))).xyz;
}
#else
// Node k of the profile of a point on triangle `tri` at barycentrics b: the interpolation (of
// ln P) of the triangle's vertex profiles.
vec3 pcSurfaceNode(uint tri, vec3 b, uint k) {
  uvec4 t = pcTriangle[tri];
  return b.x * pcVertexProfile[t.x * PC_M + k].xyz + b.y * pcVertexProfile[t.y * PC_M + k].xyz +
         b.z * pcVertexProfile[t.z * PC_M + k].xyz;
}
#endif

// The shading point's profile on triangle `tri` at x.
void pcHeteroShadingInit(vec3 x, uint tri) {
  uvec4 t = pcTriangle[tri];
  vec3 bc = pcClampedBarycentric(pcVertex[t.x].xyz, pcVertex[t.y].xyz, pcVertex[t.z].xyz, x);
  for (uint k = 0u; k < PC_M; ++k) pcShading[k] = pcSurfaceNode(tri, bc, k);
}

struct PcSegment {
  uint k;     // segment [r_k, r_{k+1}] (the last one in the tail)
  float w;    // t − k, t = n r / r_s
  bool tail;  // t > n
  bool cut;   // t > 3 n: P = 0
  float c;    // 2 ln(n / (n − 1)) in the tail (0 for n = 1)
  float l;    // 2 ln(t / n) in the tail
};

PcSegment pcSegmentAt(float r) {
  float t = r / HeteroRadius * float(PC_N);
  PcSegment s;
  s.k = min(uint(t), PC_N - 1u);
  s.w = t - float(s.k);
  s.tail = t > float(PC_N);
  s.cut = t > 3.0 * float(PC_N);
  s.c = (s.tail && PC_N > 1u) ? 2.0 * log(float(PC_N) / float(PC_N - 1u)) : 0.0;
  s.l = (s.tail && PC_N > 1u) ? 2.0 * log(t / float(PC_N)) : 0.0;
  return s;
}

vec3 pcLnOnSegment(vec3 a, vec3 b, PcSegment s) {
  if (!s.tail) return a + s.w * (b - a);
  if (s.cut) return vec3(PC_LN_ZERO);
  vec3 slope = b - a + s.c;
  return mix(vec3(PC_LN_ZERO), b + (s.w - 1.0) * slope - s.l, lessThan(slope, vec3(0.0)));
}

vec3 pcHeteroTerm(vec3 a, vec3 b, PcSegment s) {
  return exp(0.5 * (pcLnOnSegment(a, b, s) + pcLnOnSegment(pcShading[s.k], pcShading[s.k + 1u], s)));
}

// Eq. 8 for point slot `slot` / octree node `node` at distance r from the shading point.
vec3 pcHeteroPoint(float r, uint slot) {
  PcSegment s = pcSegmentAt(r);
  uint i = slot * PC_M + s.k;
  return pcHeteroTerm(pcPointProfile[i].xyz, pcPointProfile[i + 1u].xyz, s);
}
vec3 pcHeteroNode(float r, uint node) {
  PcSegment s = pcSegmentAt(r);
  uint i = node * PC_M + s.k;
  return pcHeteroTerm(pcNodeProfile[i].xyz, pcNodeProfile[i + 1u].xyz, s);
}
