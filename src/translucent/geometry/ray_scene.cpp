// SPDX-License-Identifier: GPL-3.0-or-later
// Embree 3 behind geometry::RayScene (ray_scene.h).
#include "translucent/geometry/ray_scene.h"

#include <embree3/rtcore.h>
#include <fmt/format.h>

#include <chrono>
#include <limits>
#include <stdexcept>

#include <glm/geometric.hpp>

namespace translucent::geometry {

struct RayScene::Embree {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  ~Embree() {
    if (scene != nullptr) rtcReleaseScene(scene);
    if (device != nullptr) rtcReleaseDevice(device);
  }
};

namespace {

[[noreturn]] void embreeFailure(RTCDevice device, const std::string& what, const char* step) {
  const RTCError e = device != nullptr ? rtcGetDeviceError(device) : RTC_ERROR_UNKNOWN;
  throw std::runtime_error(fmt::format("{}: Embree failed to {} (error code {})", what, step,
                                       static_cast<int>(e)));
}

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

float farLimit(double t_max) {
  return t_max < std::numeric_limits<double>::max() ? static_cast<float>(t_max)
                                                    : std::numeric_limits<float>::infinity();
}

void setRay(RTCRay& ray, const glm::dvec3& o, const glm::dvec3& d, double t_min, double t_max) {
  ray.org_x = static_cast<float>(o.x);
  ray.org_y = static_cast<float>(o.y);
  ray.org_z = static_cast<float>(o.z);
  ray.dir_x = static_cast<float>(d.x);
  ray.dir_y = static_cast<float>(d.y);
  ray.dir_z = static_cast<float>(d.z);
  ray.tnear = static_cast<float>(t_min);
  ray.tfar = farLimit(t_max);
  ray.mask = 0xFFFFFFFFu;
  ray.flags = 0;
}

RTCIntersectContext context(bool incoherent) {
  RTCIntersectContext c;
  rtcInitIntersectContext(&c);
  if (incoherent) c.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
  return c;
}

}  // namespace

RayScene::RayScene(const TriangleMesh& mesh, const std::string& what, Quality quality)
    : embree_(std::make_unique<Embree>()) {
  auto start = std::chrono::steady_clock::now();
  embree_->device = rtcNewDevice(nullptr);
  if (embree_->device == nullptr) embreeFailure(nullptr, what, "create a device");
  device_seconds_ = secondsSince(start);

  start = std::chrono::steady_clock::now();
  embree_->scene = rtcNewScene(embree_->device);
  if (embree_->scene == nullptr) embreeFailure(embree_->device, what, "create a scene");
  rtcSetSceneFlags(embree_->scene, RTC_SCENE_FLAG_ROBUST);
  if (quality == Quality::High) rtcSetSceneBuildQuality(embree_->scene, RTC_BUILD_QUALITY_HIGH);
  RTCGeometry geom = rtcNewGeometry(embree_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  if (geom == nullptr) embreeFailure(embree_->device, what, "create a triangle geometry");
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
      geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), mesh.vertexCount()));
  auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
      geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned),
      mesh.triangleCount()));
  if (vertices == nullptr || indices == nullptr) {
    rtcReleaseGeometry(geom);
    embreeFailure(embree_->device, what, "allocate the mesh buffers");
  }
  for (size_t i = 0; i < mesh.vertexCount(); ++i)
    for (int k = 0; k < 3; ++k) vertices[3 * i + size_t(k)] = static_cast<float>(mesh.positions[i][k]);
  for (size_t i = 0; i < mesh.triangleCount(); ++i)
    for (int k = 0; k < 3; ++k) indices[3 * i + size_t(k)] = mesh.triangles[i][k];
  rtcCommitGeometry(geom);
  rtcAttachGeometry(embree_->scene, geom);
  rtcReleaseGeometry(geom);
  rtcCommitScene(embree_->scene);
  if (rtcGetDeviceError(embree_->device) != RTC_ERROR_NONE)
    embreeFailure(embree_->device, what, "build the scene");
  build_seconds_ = secondsSince(start);
}

RayScene::~RayScene() = default;

bool RayScene::intersect(const glm::dvec3& o, const glm::dvec3& d, double t_min, double t_max,
                         RayHit& hit, bool incoherent) const {
  RTCIntersectContext c = context(incoherent);
  RTCRayHit rh{};
  setRay(rh.ray, o, d, t_min, t_max);
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(embree_->scene, &c, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
  hit.t = static_cast<double>(rh.ray.tfar);
  hit.normal = glm::normalize(glm::dvec3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z));
  hit.triangle = rh.hit.primID;
  return true;
}

bool RayScene::occluded(const glm::dvec3& o, const glm::dvec3& d, double t_min, double t_max,
                        bool incoherent) const {
  RTCIntersectContext c = context(incoherent);
  RTCRay ray{};
  setRay(ray, o, d, t_min, t_max);
  rtcOccluded1(embree_->scene, &c, &ray);
  return ray.tfar == -std::numeric_limits<float>::infinity();
}

bool insideClosedMesh(const RayScene& rays, const glm::dvec3& p) {
  // Directions with no simple relation to the axes, so that axis-aligned meshes (cubes) do not
  // make every ray run along a face.
  static const glm::dvec3 kDirections[3] = {glm::normalize(glm::dvec3(0.5377, 0.8121, 0.2268)),
                                            glm::normalize(glm::dvec3(-0.6983, 0.1254, 0.7047)),
                                            glm::normalize(glm::dvec3(0.2311, -0.9032, -0.3618))};
  int insideVotes = 0;
  for (const glm::dvec3& d : kDirections) {
    int crossings = 0;
    double t = 0.0;
    RayHit hit;
    // Each hit moves the start a little past it (relative to the distance travelled, as Embree
    // intersects in single precision); 10^5 crossings bounds a pathological mesh.
    while (crossings < 100000 && rays.intersect(p, d, t, std::numeric_limits<double>::infinity(), hit)) {
      ++crossings;
      t = hit.t + 1e-6 * (1.0 + hit.t + glm::length(p));
    }
    if (crossings % 2 == 1) ++insideVotes;
  }
  return insideVotes >= 2;
}

}  // namespace translucent::geometry
