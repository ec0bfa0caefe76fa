// SPDX-License-Identifier: GPL-3.0-or-later
// geometry::FlatBvh (flat_bvh.h): Embree 3's generic BVH builder (rtcore_builder.h) behind a flat,
// GPU-ready tree, and the CPU twin of shaders/reference/bvh.glsl's traversal.
//
// This file is compiled with -ffp-contract=off (src/geometry/CMakeLists.txt): the watertight
// triangle test relies on the edge function of a shared edge coming out as the exact negative
// in the two triangles (a*b - c*d against c*d - a*b), which a fused multiply-add breaks; and
// intersect() must round as the shader does.
#include "translucent/geometry/flat_bvh.h"

#include <embree3/rtcore.h>
#include <embree3/rtcore_builder.h>
#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <new>
#include <stdexcept>

#include <glm/geometric.hpp>

namespace translucent::geometry {

namespace {

// ---------------------------------------------------------------------------------------------
// Building

// The builder's nodes, in memory of Embree's thread-local allocator (freed with the RTCBVH).
struct BuildNode {
  BuildNode* children[2] = {nullptr, nullptr};  // inner nodes
  uint32_t count = 0;                            // 0: inner; else a leaf of `count` triangles
  uint32_t* triangles = nullptr;                 // leaves: the mesh's triangle indices
};

struct BuildContext {
  std::atomic<bool> failed{false};  // a callback saw what it cannot handle (no exceptions
                                    // through Embree's task scheduler)
};

void* allocate(RTCThreadLocalAllocator alloc, size_t bytes, size_t align) {
  return rtcThreadLocalAlloc(alloc, bytes, align);
}

void* createNode(RTCThreadLocalAllocator alloc, unsigned childCount, void* user) {
  void* memory = allocate(alloc, sizeof(BuildNode), alignof(BuildNode));
  if (memory == nullptr || childCount != 2) {  // maxBranchingFactor 2: always two
    static_cast<BuildContext*>(user)->failed = true;
    if (memory == nullptr) return nullptr;
  }
  return new (memory) BuildNode;
}

void setNodeChildren(void* node, void** children, unsigned childCount, void* user) {
  auto* n = static_cast<BuildNode*>(node);
  if (n == nullptr || childCount != 2) {
    static_cast<BuildContext*>(user)->failed = true;
    return;
  }
  n->children[0] = static_cast<BuildNode*>(children[0]);
  n->children[1] = static_cast<BuildNode*>(children[1]);
}

// Embree requires the callback; the flat tree's boxes are recomputed from the triangles (the
// exact float bounds, the same values as Embree's merged primitive boxes).
void setNodeBounds(void*, const RTCBounds**, unsigned, void*) {}

void* createLeaf(RTCThreadLocalAllocator alloc, const RTCBuildPrimitive* prims, size_t count,
                 void* user) {
  auto* ctx = static_cast<BuildContext*>(user);
  void* memory = allocate(alloc, sizeof(BuildNode), alignof(BuildNode));
  auto* indices = static_cast<uint32_t*>(allocate(alloc, count * sizeof(uint32_t), alignof(uint32_t)));
  if (memory == nullptr || indices == nullptr || count == 0) {
    ctx->failed = true;
    return memory;
  }
  auto* leaf = new (memory) BuildNode;
  leaf->count = static_cast<uint32_t>(count);
  leaf->triangles = indices;
  for (size_t i = 0; i < count; ++i) indices[i] = prims[i].primID;
  return leaf;
}

struct Device {
  RTCDevice device = nullptr;
  RTCBVH bvh = nullptr;
  std::string message;  // Embree's last error text
  ~Device() {
    if (bvh != nullptr) rtcReleaseBVH(bvh);
    if (device != nullptr) rtcReleaseDevice(device);
  }
};

void onEmbreeError(void* user, RTCError, const char* text) {
  static_cast<Device*>(user)->message = text != nullptr ? text : "";
}

[[noreturn]] void embreeFailure(const Device& d, const std::string& what, const char* step) {
  const RTCError e = d.device != nullptr ? rtcGetDeviceError(d.device) : RTC_ERROR_UNKNOWN;
  throw std::runtime_error(fmt::format("{}: Embree failed to {} (error code {}{}{})", what, step,
                                       static_cast<int>(e), d.message.empty() ? "" : ": ",
                                       d.message));
}

// Depth-first flattening: a node, then its first subtree, then its second (whose index the node
// keeps in `a`).
class Flattener {
 public:
  Flattener(FlatBvh& out, const std::vector<FlatBvhTriangle>& meshTriangles)
      : out_(out), mesh_(meshTriangles) {}

  uint32_t flatten(const BuildNode* n, int level) {
    if (n == nullptr) throw std::logic_error("null BVH node");
    if (level > 64) throw std::length_error("BVH deeper than 64 levels");
    out_.depth = std::max(out_.depth, level);
    const auto index = static_cast<uint32_t>(out_.nodes.size());
    out_.nodes.emplace_back();
    FlatBvhNode node{};
    if (n->count > 0) {
      node.a = static_cast<uint32_t>(out_.triangles.size());
      node.count = n->count;
      initBox(node);
      for (uint32_t i = 0; i < n->count; ++i) {
        const FlatBvhTriangle& t = mesh_.at(n->triangles[i]);
        out_.triangles.push_back(t);
        for (const float* v : {t.v0, t.v1, t.v2}) grow(node, v, v);
      }
    } else {
      const uint32_t left = flatten(n->children[0], level + 1);
      const uint32_t right = flatten(n->children[1], level + 1);
      node.a = right;
      node.count = 0;
      initBox(node);
      grow(node, out_.nodes[left].lower, out_.nodes[left].upper);
      grow(node, out_.nodes[right].lower, out_.nodes[right].upper);
    }
    out_.nodes[index] = node;
    return index;
  }

 private:
  static void initBox(FlatBvhNode& n) {
    for (int k = 0; k < 3; ++k) {
      n.lower[k] = std::numeric_limits<float>::infinity();
      n.upper[k] = -std::numeric_limits<float>::infinity();
    }
  }
  static void grow(FlatBvhNode& n, const float* lower, const float* upper) {
    for (int k = 0; k < 3; ++k) {
      n.lower[k] = std::min(n.lower[k], lower[k]);
      n.upper[k] = std::max(n.upper[k], upper[k]);
    }
  }

  FlatBvh& out_;
  const std::vector<FlatBvhTriangle>& mesh_;
};

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// ---------------------------------------------------------------------------------------------
// Traversal: bvh.glsl line for line. GLSL's min(x, y) is `y < x ? y : x`, max(x, y) is
// `x < y ? y : x`.

float glslMin(float x, float y) { return y < x ? y : x; }
float glslMax(float x, float y) { return x < y ? y : x; }

constexpr float kInf = std::numeric_limits<float>::infinity();

struct Ray {
  glm::vec3 o, d, invD;
  int kx, ky, kz;
  glm::vec3 shear;
};

Ray makeRay(const glm::vec3& o, const glm::vec3& d) {
  Ray r{};
  r.o = o;
  r.d = d;
  for (int k = 0; k < 3; ++k)
    r.invD[k] = std::abs(d[k]) > 1e-30f ? 1.0f / d[k] : (d[k] >= 0.0f ? 1e30f : -1e30f);
  const glm::vec3 a(std::abs(d.x), std::abs(d.y), std::abs(d.z));
  r.kz = a.x > a.y ? (a.x > a.z ? 0 : 2) : (a.y > a.z ? 1 : 2);
  r.kx = (r.kz + 1) % 3;
  r.ky = (r.kx + 1) % 3;
  if (d[r.kz] < 0.0f) std::swap(r.kx, r.ky);
  r.shear = glm::vec3(d[r.kx] / d[r.kz], d[r.ky] / d[r.kz], 1.0f / d[r.kz]);
  return r;
}

float boxEntry(const Ray& r, const float* lower, const float* upper, float tMin, float tMax) {
  float lo[3], hi[3];
  for (int k = 0; k < 3; ++k) {
    const float t0 = (lower[k] - r.o[k]) * r.invD[k], t1 = (upper[k] - r.o[k]) * r.invD[k];
    lo[k] = glslMin(t0, t1);
    hi[k] = glslMax(t0, t1);
  }
  const float enter = glslMax(glslMax(lo[0], lo[1]), glslMax(lo[2], tMin));
  const float exit = glslMin(glslMin(hi[0], hi[1]), glslMin(hi[2], tMax)) * 1.00000024f;
  return enter <= exit ? enter : kInf;
}

float triangleHit(const Ray& r, const FlatBvhTriangle& tri, float tMin, float tMax) {
  const glm::vec3 A = glm::vec3(tri.v0[0], tri.v0[1], tri.v0[2]) - r.o;
  const glm::vec3 B = glm::vec3(tri.v1[0], tri.v1[1], tri.v1[2]) - r.o;
  const glm::vec3 C = glm::vec3(tri.v2[0], tri.v2[1], tri.v2[2]) - r.o;
  const float Ax = A[r.kx] - r.shear.x * A[r.kz], Ay = A[r.ky] - r.shear.y * A[r.kz];
  const float Bx = B[r.kx] - r.shear.x * B[r.kz], By = B[r.ky] - r.shear.y * B[r.kz];
  const float Cx = C[r.kx] - r.shear.x * C[r.kz], Cy = C[r.ky] - r.shear.y * C[r.kz];
  float U = Cx * By - Cy * Bx, V = Ax * Cy - Ay * Cx, W = Bx * Ay - By * Ax;
  if (U == 0.0f || V == 0.0f || W == 0.0f) {  // on an edge in float: decide in double
    U = static_cast<float>(double(Cx) * double(By) - double(Cy) * double(Bx));
    V = static_cast<float>(double(Ax) * double(Cy) - double(Ay) * double(Cx));
    W = static_cast<float>(double(Bx) * double(Ay) - double(By) * double(Ax));
  }
  if ((U < 0.0f || V < 0.0f || W < 0.0f) && (U > 0.0f || V > 0.0f || W > 0.0f)) return -1.0f;
  const float det = U + V + W;
  if (det == 0.0f) return -1.0f;
  const float Az = r.shear.z * A[r.kz], Bz = r.shear.z * B[r.kz], Cz = r.shear.z * C[r.kz];
  const float T = U * Az + V * Bz + W * Cz;
  const float t = T / det;
  return t > tMin && t <= tMax ? t : -1.0f;
}

}  // namespace

FlatBvh FlatBvh::build(const TriangleMesh& mesh, const std::string& what) {
  mesh.validate(what);
  const auto start = std::chrono::steady_clock::now();
  if (mesh.triangleCount() > std::numeric_limits<uint32_t>::max() / 2)
    throw std::runtime_error(fmt::format("{}: too many triangles for a BVH ({})", what,
                                         mesh.triangleCount()));

  // The triangles in float (as the GPU reads them), in mesh order, and their boxes.
  std::vector<FlatBvhTriangle> meshTriangles(mesh.triangleCount());
  std::vector<RTCBuildPrimitive> prims(mesh.triangleCount());
  for (size_t i = 0; i < mesh.triangleCount(); ++i) {
    FlatBvhTriangle& t = meshTriangles[i];
    t.index = static_cast<uint32_t>(i);
    t.pad1 = t.pad2 = 0;
    float* corners[3] = {t.v0, t.v1, t.v2};
    RTCBuildPrimitive& p = prims[i];
    p.lower_x = p.lower_y = p.lower_z = kInf;
    p.upper_x = p.upper_y = p.upper_z = -kInf;
    for (int c = 0; c < 3; ++c) {
      const glm::dvec3& v = mesh.positions[mesh.triangles[i][c]];
      for (int k = 0; k < 3; ++k) corners[c][k] = static_cast<float>(v[k]);
      p.lower_x = std::min(p.lower_x, corners[c][0]);
      p.lower_y = std::min(p.lower_y, corners[c][1]);
      p.lower_z = std::min(p.lower_z, corners[c][2]);
      p.upper_x = std::max(p.upper_x, corners[c][0]);
      p.upper_y = std::max(p.upper_y, corners[c][1]);
      p.upper_z = std::max(p.upper_z, corners[c][2]);
    }
    p.geomID = 0;
    p.primID = static_cast<unsigned>(i);
  }

  Device d;
  d.device = rtcNewDevice(nullptr);
  if (d.device == nullptr) embreeFailure(d, what, "create a device");
  rtcSetDeviceErrorFunction(d.device, onEmbreeError, &d);
  d.bvh = rtcNewBVH(d.device);
  if (d.bvh == nullptr) embreeFailure(d, what, "create a BVH");

  BuildContext ctx;
  RTCBuildArguments args = rtcDefaultBuildArguments();
  // High quality without a splitPrimitive callback is Embree's binned SAH builder (spatial
  // splits need the callback and spare array capacity): every triangle lands in one leaf.
  args.buildQuality = RTC_BUILD_QUALITY_HIGH;
  args.maxBranchingFactor = 2;
  args.maxDepth = 32;  // well inside bvh.glsl's stack of 64
  args.sahBlockSize = 1;
  args.minLeafSize = 1;
  args.maxLeafSize = 4;
  args.traversalCost = 1.0f;
  args.intersectionCost = 1.0f;
  args.bvh = d.bvh;
  args.primitives = prims.data();
  args.primitiveCount = prims.size();
  args.primitiveArrayCapacity = prims.size();
  args.createNode = createNode;
  args.setNodeChildren = setNodeChildren;
  args.setNodeBounds = setNodeBounds;
  args.createLeaf = createLeaf;
  args.splitPrimitive = nullptr;
  args.buildProgress = nullptr;
  args.userPtr = &ctx;
  const auto* root = static_cast<const BuildNode*>(rtcBuildBVH(&args));
  if (root == nullptr || rtcGetDeviceError(d.device) != RTC_ERROR_NONE)
    embreeFailure(d, what, "build the BVH");
  if (ctx.failed)
    throw std::runtime_error(fmt::format(
        "{}: Embree's BVH builder made a node this flattening cannot hold (not binary, or an "
        "allocation failed)", what));

  FlatBvh out;
  out.nodes.reserve(2 * mesh.triangleCount());
  out.triangles.reserve(mesh.triangleCount());
  try {
    Flattener(out, meshTriangles).flatten(root, 1);
  } catch (const std::exception& e) {
    throw std::runtime_error(fmt::format("{}: flattening Embree's BVH failed: {}", what, e.what()));
  }
  if (out.triangles.size() != mesh.triangleCount())
    throw std::runtime_error(fmt::format("{}: Embree's BVH holds {} triangles, the mesh {}", what,
                                         out.triangles.size(), mesh.triangleCount()));
  out.nodes.shrink_to_fit();
  out.buildSeconds = secondsSince(start);
  return out;
}

bool FlatBvh::intersect(const glm::vec3& o, const glm::vec3& d, float tMin, float tMax,
                        float& tHit, glm::vec3& normal, uint32_t& triangle) const {
  if (nodes.empty()) return false;
  const Ray r = makeRay(o, d);
  uint32_t stack[64];
  int top = 0;
  uint32_t node = 0;
  float best = tMax;
  int64_t bestTri = -1;
  if (boxEntry(r, nodes[0].lower, nodes[0].upper, tMin, best) == kInf) return false;
  for (;;) {
    const FlatBvhNode& n = nodes[node];
    if (n.count > 0) {
      for (uint32_t k = n.a; k < n.a + n.count; ++k) {
        const float t = triangleHit(r, triangles[k], tMin, best);
        if (t >= 0.0f) {  // a hit in (tMin, best]: tMin >= 0
          best = t;
          bestTri = k;
        }
      }
    } else {
      const uint32_t left = node + 1, right = n.a;
      const float tl = boxEntry(r, nodes[left].lower, nodes[left].upper, tMin, best);
      const float tr = boxEntry(r, nodes[right].lower, nodes[right].upper, tMin, best);
      const bool hitL = tl != kInf, hitR = tr != kInf;
      if (hitL && hitR) {
        const bool leftFirst = tl <= tr;
        stack[top++] = leftFirst ? right : left;
        node = leftFirst ? left : right;
        continue;
      }
      if (hitL || hitR) {
        node = hitL ? left : right;
        continue;
      }
    }
    if (top == 0) break;
    node = stack[--top];
  }
  if (bestTri < 0) return false;
  const FlatBvhTriangle& tri = triangles[size_t(bestTri)];
  const glm::vec3 v0(tri.v0[0], tri.v0[1], tri.v0[2]), v1(tri.v1[0], tri.v1[1], tri.v1[2]),
      v2(tri.v2[0], tri.v2[1], tri.v2[2]);
  tHit = best;
  normal = glm::normalize(glm::cross(v1 - v0, v2 - v0));
  triangle = tri.index;
  return true;
}

}  // namespace translucent::geometry
