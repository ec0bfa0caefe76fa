// SPDX-License-Identifier: GPL-3.0-or-later
// The fields' packing for fields.glsl (field_gpu.h says the layout).
#include "translucent/reference/gpu/field_gpu.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "translucent/geometry/deform.h"
#include "translucent/gpu/compute.h"
#include "translucent/reference/gpu/walk_program.h"
#include "translucent/material/checker.h"
#include "translucent/material/gradient.h"
#include "translucent/material/layers.h"
#include "translucent/material/noise.h"
#include "translucent/material/surface_distance.h"
#include "translucent/material/veins.h"
#include "translucent/material/voxels.h"
#include "translucent/optics/medium.h"

namespace translucent::reference::gpu_field {
namespace {

using material::LocalMedium;

enum Kind : uint32_t {
  kNone = 0, kChecker = 1, kGradient = 2, kVeins = 3, kLayers = 4, kVoxelDensity = 5,
  kVoxelCoefficients = 6,
};
constexpr uint32_t kMediumWords = 8, kGridHeaderWords = 24, kNodeWords = 10, kTriangleWords = 9;
// fields.glsl's traversal stack for the surface distance; pushing both children of each inner
// node visited holds at most (depth + 1) entries.
constexpr size_t kStackDepth = 64;
// Word indices are uint in GLSL and the grid offsets are computed in it.
constexpr size_t kMaxWords = size_t(1) << 31;

size_t treeDepth(const std::vector<material::SurfaceDistance::Node>& nodes) {
  size_t deepest = 0;
  std::vector<std::pair<uint32_t, size_t>> todo{{0u, 1}};
  while (!todo.empty()) {
    const auto [i, level] = todo.back();
    todo.pop_back();
    deepest = std::max(deepest, level);
    const material::SurfaceDistance::Node& n = nodes.at(i);
    if (n.count == 0) {
      todo.push_back({n.left, level + 1});
      todo.push_back({n.right, level + 1});
    }
  }
  return deepest;
}

size_t gridWords(const material::DenseGrid* g) {
  return g ? g->values.size() + kGridHeaderWords : 0;
}

class Packer {
 public:
  void u(uint32_t v) { w_.push_back(v); }
  void i(int v) { w_.push_back(static_cast<uint32_t>(v)); }
  void f(double v) { w_.push_back(std::bit_cast<uint32_t>(static_cast<float>(v))); }
  void d(double v) {
    const auto b = std::bit_cast<uint64_t>(v);
    u(static_cast<uint32_t>(b));
    u(static_cast<uint32_t>(b >> 32));
  }
  void f3(const glm::dvec3& v) {
    for (int k = 0; k < 3; ++k) f(v[k]);
  }
  void rgb(const Rgb& v) {
    for (double c : v) f(c);
  }
  // The float nearest below (above) v: a box rounded outwards holds the float positions of the
  // triangles it bounds, so that the float traversal prunes nothing the double one keeps.
  void down(double v) { f(static_cast<double>(roundDown(v))); }
  void up(double v) { f(-static_cast<double>(roundDown(-v))); }
  void set(size_t at, uint32_t v) { w_.at(at) = v; }
  size_t size() const { return w_.size(); }
  std::vector<uint32_t> take() { return std::move(w_); }

  // The common head: kind, size (patched by finish), the media and P.
  void head(Kind kind, const std::vector<LocalMedium>& media) {
    u(kind);
    u(0);
    u(static_cast<uint32_t>(media.size()));
    u(static_cast<uint32_t>(4 + kMediumWords * media.size()));
    for (const LocalMedium& m : media) {
      rgb(m.sigma_a);
      f(m.g);
      rgb(m.sigma_s);
      u(0);
    }
  }
  std::vector<uint32_t> finish() {
    set(1, static_cast<uint32_t>(size()));
    return take();
  }

  // A grid header whose values follow at `values_at` (appended later by values()).
  void gridHeader(const material::DenseGrid& g, size_t values_at) {
    for (int k = 0; k < 3; ++k) i(g.origin[k]);
    for (int k = 0; k < 3; ++k) i(g.dims[k]);
    u(static_cast<uint32_t>(g.channels));
    u(static_cast<uint32_t>(values_at));
    rgb(g.background);
    f3(g.translation);
    for (int c = 0; c < 3; ++c) f3(g.world_to_index[c]);
    u(0);
  }
  void values(const material::DenseGrid& g) {
    const size_t want = static_cast<size_t>(g.dims.x) * static_cast<size_t>(g.dims.y) *
                        static_cast<size_t>(g.dims.z) * static_cast<size_t>(g.channels);
    if ((g.channels != 1 && g.channels != 3) || g.dims.x <= 0 || g.dims.y <= 0 || g.dims.z <= 0 ||
        g.values.size() != want)
      throw ParameterError(fmt::format(
          "voxels: a grid of {} x {} x {} voxels with {} channels holds {} values", g.dims.x,
          g.dims.y, g.dims.z, g.channels, g.values.size()));
    for (float v : g.values) u(std::bit_cast<uint32_t>(v));
  }

 private:
  static float roundDown(double v) {
    const float r = static_cast<float>(v);
    return static_cast<double>(r) > v ? std::nextafter(r, -std::numeric_limits<float>::infinity())
                                      : r;
  }
  std::vector<uint32_t> w_;
};

std::vector<uint32_t> packLayers(const material::LayersField& l) {
  const material::LayersDesc& d = l.desc();
  const bool surface = d.from == material::LayersDesc::From::Surface;
  Packer p;
  p.head(kLayers, l.media());
  const size_t P = p.size();
  p.u(surface ? 1u : 0u);
  p.u(0);  // nodes and triangles offsets, patched below
  p.u(0);
  p.f3(d.normal);
  p.f(d.offset);
  for (double b : l.bottoms()) p.f(b);
  if (!surface) return p.finish();
  const material::SurfaceDistance& s = *l.surface();
  p.set(P + 1, static_cast<uint32_t>(p.size()));
  for (const material::SurfaceDistance::Node& n : s.nodes()) {
    for (int k = 0; k < 3; ++k) p.down(n.lo[k]);
    for (int k = 0; k < 3; ++k) p.up(n.hi[k]);
    p.u(n.first);
    p.u(n.count);
    p.u(n.left);
    p.u(n.right);
  }
  p.set(P + 2, static_cast<uint32_t>(p.size()));
  for (const material::SurfaceDistance::Tri& t : s.triangles()) {
    p.f3(t.a);
    p.f3(t.b);
    p.f3(t.c);
  }
  return p.finish();
}

std::vector<uint32_t> packVoxels(const material::VoxelsField& v) {
  const material::VoxelsDesc& d = v.desc();
  Packer p;
  if (d.mode == material::VoxelsDesc::Mode::Density) {
    p.head(kVoxelDensity, {d.media.at(0).medium, d.media.at(1).medium});
    p.gridHeader(*d.density_grid, p.size() + kGridHeaderWords);
    p.values(*d.density_grid);
    return p.finish();
  }
  p.head(kVoxelCoefficients, {});
  p.f(d.g);
  p.u(0);
  p.u(0);
  p.u(0);
  const size_t a = p.size() + 2 * kGridHeaderWords;
  p.gridHeader(*d.sigma_a_grid, a);
  p.gridHeader(*d.sigma_s_grid, a + d.sigma_a_grid->values.size());
  p.values(*d.sigma_a_grid);
  p.values(*d.sigma_s_grid);
  return p.finish();
}

}  // namespace

std::string refusal(const material::VolumeField& f) {
  if (dynamic_cast<const material::CheckerField*>(&f) ||
      dynamic_cast<const material::GradientField*>(&f) ||
      dynamic_cast<const material::VeinsField*>(&f))
    return "";
  if (const auto* l = dynamic_cast<const material::LayersField*>(&f)) {
    if (l->desc().from == material::LayersDesc::From::Plane) return "";
    const size_t depth = treeDepth(l->surface()->nodes());
    if (depth >= kStackDepth)
      return fmt::format("layers below the surface: the mesh's distance tree is {} levels deep, "
                         "more than the GPU's {}",
                         depth, kStackDepth - 1);
    const size_t words = 4 * l->media().size() + l->surface()->nodes().size() * kNodeWords +
                         l->surface()->triangleCount() * kTriangleWords;
    if (words >= kMaxWords)
      return "layers below the surface: the mesh is too large for the GPU's field buffer";
    return "";
  }
  if (const auto* v = dynamic_cast<const material::VoxelsField*>(&f)) {
    const material::VoxelsDesc& d = v->desc();
    const size_t words = 64 + gridWords(d.density_grid.get()) + gridWords(d.sigma_a_grid.get()) +
                         gridWords(d.sigma_s_grid.get());
    if (words >= kMaxWords)
      return "voxels: the grids hold too many values for the GPU's field buffer";
    return "";
  }
  return "this kind of heterogeneous material is traced on the CPU only";
}

std::vector<uint32_t> pack(const material::VolumeField& f) {
  if (const std::string why = refusal(f); !why.empty()) throw ParameterError(why);
  if (const auto* c = dynamic_cast<const material::CheckerField*>(&f)) {
    Packer p;
    p.head(kChecker, {c->medium(0), c->medium(1)});
    p.f3(c->cell());
    return p.finish();
  }
  if (const auto* g = dynamic_cast<const material::GradientField*>(&f)) {
    Packer p;
    p.head(kGradient, {g->medium(0), g->medium(1)});
    p.f3(g->from());
    p.f3(g->axis());
    return p.finish();
  }
  if (const auto* v = dynamic_cast<const material::VeinsField*>(&f)) {
    const material::VeinsDesc& d = v->desc();
    Packer p;
    p.head(kVeins, {d.media.at(0).medium, d.media.at(1).medium});
    for (int k = 0; k < 3; ++k) p.d(d.direction[k]);
    p.d(d.period);
    p.d(d.noise_size);
    p.f(d.turbulence);
    p.f(d.sharpness);
    p.u(static_cast<uint32_t>(d.octaves));
    for (int k = 0; k < 3; ++k) p.u(0);
    for (uint8_t e : material::perlinPermutation()) p.u(e);
    return p.finish();
  }
  if (const auto* l = dynamic_cast<const material::LayersField*>(&f)) return packLayers(*l);
  return packVoxels(dynamic_cast<const material::VoxelsField&>(f));
}

namespace {
// Rounded up to float: a bound below σt would bias the tracking.
float roundUp(double b) {
  float f = static_cast<float>(b);
  if (static_cast<double>(f) < b) f = std::nextafter(f, std::numeric_limits<float>::infinity());
  return f;
}
}  // namespace

void VolumeBuffers::set(const gpu::ShaderProgram& p, const VolumeMedium* v, int channel) {
  if (!violations_) violations_ = gpu::makeStorageBuffer(sizeof(uint32_t));
  if (v == nullptr) {
    if (!fieldWords_) fieldWords_ = gpu::makeStorageBuffer(16);  // bound, never read
    for (gpu::Buffer& b : majorants_)
      if (!b) b = gpu::makeStorageBuffer(16);
    return;
  }
  if (v != volume_) {
    const std::vector<uint32_t> words = pack(*v->field);
    fieldWords_ = gpu::makeStorageBuffer(std::span<const uint32_t>(words));
    const MajorantGrid& g = *v->grid;
    const glm::ivec3 n = g.cells();
    for (int c = 0; c < 3; ++c) {
      std::vector<float> bounds;
      bounds.reserve(static_cast<size_t>(n.x) * static_cast<size_t>(n.y) * static_cast<size_t>(n.z));
      for (int k = 0; k < n.z; ++k)
        for (int j = 0; j < n.y; ++j)
          for (int i = 0; i < n.x; ++i) bounds.push_back(roundUp(g.bound(i, j, k, c)));
      majorants_[static_cast<size_t>(c)] = gpu::makeStorageBuffer(std::span<const float>(bounds));
    }
    volume_ = v;
  }
  const MajorantGrid& g = *v->grid;
  const glm::dvec3 cell = (g.upper() - g.lower()) / glm::dvec3(g.cells());
  p.set("GridLower", glm::vec3(g.lower()));
  p.set("GridUpper", glm::vec3(g.upper()));
  p.set("GridCell", glm::vec3(cell));
  p.set("GridCells", g.cells());
  p.set("GridOuterBound", roundUp(g.maxBound(std::min(channel, 2))));
  p.set("CoefficientScale", static_cast<float>(v->coefficient_scale));
  p.set("FrameRotationT", glm::mat3(glm::transpose(v->frame.rotation)));
  gpu_walk::setDvec3(p, "FrameTranslate", v->frame.translate);
  p.set("FrameScale", static_cast<float>(v->frame.scale));
  // The deformations at the frame's time (shaders/common/deform.comp's form).
  const auto& chain = v->frame.deform;
  if (chain.size() > geometry::kMaxDeformations)
    throw gpu::GlError(fmt::format("GPU walk: {} deformations, at most {}", chain.size(),
                                   geometry::kMaxDeformations));
  const bool deformed = v->frame.deformed();
  p.set("DeformCount", deformed ? static_cast<int>(chain.size()) : 0);
  if (deformed) {
    const geometry::DeformUniforms u = geometry::deformUniforms(chain, v->frame.time);
    const auto n = static_cast<GLsizei>(chain.size());
    glProgramUniform4fv(p.id(), p.uniformLocation("DeformA"), n, &u.a[0].x);
    glProgramUniform4fv(p.id(), p.uniformLocation("DeformB"), n, &u.b[0].x);
    glProgramUniform4fv(p.id(), p.uniformLocation("DeformC"), n, &u.c[0].x);
  }
}

void VolumeBuffers::bind(int channel) const {
  gpu::bindStorage(7, fieldWords_);
  gpu::bindStorage(8, majorants_[static_cast<size_t>(std::min(channel, 2))]);
  gpu::bindStorage(9, violations_);
}

void VolumeBuffers::resetViolations() const {
  const uint32_t zero = 0;
  gpu::uploadBytes(violations_, 0, sizeof(zero), &zero);
}

uint32_t VolumeBuffers::violations() const {
  uint32_t n = 0;
  gpu::downloadBytes(violations_, 0, sizeof(n), &n);
  return n;
}

}  // namespace translucent::reference::gpu_field
