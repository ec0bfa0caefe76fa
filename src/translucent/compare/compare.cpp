// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/compare/compare.h"

#include "translucent/io/input_file.h"

#include <fmt/format.h>
#include <openssl/evp.h>
#include <tbb/parallel_for.h>
#include <unistd.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "translucent/io/image_io.h"
#include "translucent/io/json.h"
#include "translucent/bssrdf/bssrdf_file.h"
#include "translucent/bssrdf/registry.h"
#include "translucent/geometry/atomic_file.h"  // contentHash
#include "translucent/geometry/point_cloud.h"  // defaultCacheDirectory
#include "translucent/geometry/ray_scene.h"
#include "translucent/material/material_desc.h"
#include "translucent/reference/camera.h"
#include "translucent/reference/camera_paths.h"
#include "translucent/reference/gpu/device.h"
#include "translucent/reference/mesh_tracer.h"
#include "translucent/reference/model_reference.h"

namespace translucent::analysis {
namespace fs = std::filesystem;
using nlohmann::json;

CompareImage CompareImage::scaled(double factor) const {
  CompareImage out = *this;
  for (float& v : out.rgb) v = static_cast<float>(static_cast<double>(v) * factor);
  for (float& v : out.se) v = static_cast<float>(static_cast<double>(v) * std::abs(factor));
  return out;
}

const char* toString(ReferenceKind kind) {
  return kind == ReferenceKind::Physical ? "physical" : "model";
}

ReferenceKind parseReferenceKind(const std::string& name, const std::string& option) {
  if (name == "physical") return ReferenceKind::Physical;
  if (name == "model") return ReferenceKind::Model;
  throw ParameterError(
      fmt::format("{} '{}': expected physical or model (or a list of them)", option, name));
}

CompareImage Reference::radianceFor(bssrdf::ExitConvention convention, double eta) const {
  if (convention == bssrdf::ExitConvention::Jensen) return radiance;
  // Eq. 2.16's normalisation 1/(4C_φ(1/η)), a constant of η (exit_radiance.h).
  return radiance.scaled(bssrdf::exitConventionScale(convention, eta));
}

// ---- Cache keys ----------------------------------------------------------------------------

namespace {

std::string sha256Hex(std::string_view data) {
  unsigned char md[EVP_MAX_MD_SIZE];
  unsigned int len = 0;
  if (EVP_Digest(data.data(), data.size(), md, &len, EVP_sha256(), nullptr) != 1)
    throw std::runtime_error("SHA-256 of a reference key failed (OpenSSL EVP_Digest)");
  std::string hex;
  for (unsigned int i = 0; i < len; ++i) hex += fmt::format("{:02x}", md[i]);
  return hex;
}

std::string readFileBytes(const fs::path& path, const std::string& what) {
  if (const std::string why = io::irregularInput(path); !why.empty())
    throw ParameterError(fmt::format("{} '{}' {}: expected a file", what, path.string(), why));
  std::ifstream f(path, std::ios::binary);
  if (!f) throw ParameterError(fmt::format("{} '{}': cannot read the file", what, path.string()));
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

}  // namespace

std::string referenceMaterialDescription(const scene::Scene& scene) {
  // The homogeneous fields (the scene's medium and model), and for a heterogeneous material its
  // whole description (material/material_desc.h) with every file it reads (maps, voxel grids)
  // named by the SHA-256 of its bytes, so that an edited map never reuses a reference.
  const Medium& m = scene.medium;
  json j = {{"kind", "homogeneous"},
            {"model", scene.model},
            {"sigma_a", {m.sigma_a[0], m.sigma_a[1], m.sigma_a[2]}},
            {"sigma_s", {m.sigma_s[0], m.sigma_s[1], m.sigma_s[2]}},
            {"g", m.g}, {"eta", m.eta}, {"scale", m.scale}};
  if (!scene.material.homogeneous()) {
    json desc;
    material::writeMaterialDesc(scene.material, desc, [](const fs::path& p) {
      return "sha256:" + sha256Hex(readFileBytes(p, "material file"));
    });
    j["kind"] = desc.value("type", "heterogeneous");
    j["description"] = desc;
  }
  return j.dump();
}

std::string referenceKeyText(const scene::Scene& scene, const ReferenceRequest& request) {
  return referenceKeyText(scene, request, referenceMaterialDescription(scene));
}

std::string referenceKeyText(const scene::Scene& scene, const ReferenceRequest& request,
                             const std::string& material_description) {
  json j;
  j["material"] = material_description;
  // The scene as the references see it: the technique and display settings change neither.
  json s = json::parse(scene::toJson(scene));
  s.erase("technique");
  s.erase("display");
  // The same file by any path (relative to another working directory, through links).
  std::error_code ec;
  const fs::path canonical = fs::weakly_canonical(scene.mesh_file, ec);
  if (!ec && s.contains("mesh")) s["mesh"]["file"] = canonical.string();
  j["scene"] = s;
  // The coefficients themselves: toJson writes a preset by name, and a caller may have changed
  // the medium behind it.
  const Medium& m = scene.medium;
  j["medium"] = {{"sigma_a", {m.sigma_a[0], m.sigma_a[1], m.sigma_a[2]}},
                 {"sigma_s", {m.sigma_s[0], m.sigma_s[1], m.sigma_s[2]}},
                 {"g", m.g}, {"eta", m.eta}, {"scale", m.scale}};
  j["mesh_sha256"] = sha256Hex(readFileBytes(scene.mesh_file, "mesh file"));
  // Environment maps by content too (a map replaced under the same name changes the light).
  // Only present for scenes that have one, so other scenes keep their keys.
  for (size_t i = 0; i < scene.lights.size(); ++i)
    if (const auto* e = std::get_if<scene::EnvironmentLight>(&scene.lights[i].emitter))
      j["environment_sha256"][fmt::format("{}", i)] =
          sha256Hex(readFileBytes(e->file, "environment map"));
  if (j.contains("environment_sha256") && request.kind == ReferenceKind::Model)
    j["environment_rays"] = reference::ModelReferenceOptions{}.environment_rays;
  j["kind"] = toString(request.kind);
  j["count"] = request.count;
  j["seed"] = request.seed;
  if (request.kind == ReferenceKind::Model) j["subpixels"] = request.subpixels;
  if (request.kind == ReferenceKind::Physical && request.device != "cpu") j["device"] = request.device;
  if (request.kind == ReferenceKind::Physical && request.method != "light") {
    j["method"] = request.method;
    // The camera method's light-traced complement (its photons per path change the image).
    j["complement_photons"] = reference::CameraPathOptions{}.complement_photons;
  }
  j["stored_convention"] = "jensen";
  j["code_version"] = kReferenceCodeVersion;
  return j.dump();  // objects are ordered by key: canonical
}

std::string referenceKey(const scene::Scene& scene, const ReferenceRequest& request) {
  return sha256Hex(referenceKeyText(scene, request));
}

std::string referenceKey(const scene::Scene& scene, const ReferenceRequest& request,
                         const std::string& material_description) {
  return sha256Hex(referenceKeyText(scene, request, material_description));
}

MaterialReferences materialReferences(const material::Material& material) {
  MaterialReferences r;
  switch (material.kind) {
    case material::Material::Kind::Homogeneous:
      r.kind = "homogeneous";
      r.physical = true;
      r.text = "Homogeneous material: the physical reference is the volumetric path tracer, the "
               "model reference the scene's BSSRDF integrated over the surface.";
      break;
    case material::Material::Kind::Volume:
      r.kind = "volume";
      r.physical = true;  // the mesh tracer delta-tracks the field (reference/majorant_grid.h)
      r.text = "Heterogeneous material (3D field): the physical reference is the volumetric path "
               "tracer through the field; the model reference is brute-force Eq. 8 over the "
               "surface (per-point SubEdit profiles, geometric mean of the two points' profiles), "
               "so technique vs model is the technique's own error and model vs physical that of "
               "Eq. 8 and the local profiles.";
      break;
    case material::Material::Kind::Surface:
      r.kind = "surface";
      r.physical = false;
      r.text = "Heterogeneous material (2D map over the surface atlas): it has no volume, so there "
               "is no physical reference; the reference is the model reference, brute-force Eq. 8 "
               "over the surface (per-point SubEdit profiles of the map's media).";
      break;
  }
  return r;
}

// ---- Cache ---------------------------------------------------------------------------------

fs::path defaultReferenceCacheDirectory() {
  return geometry::defaultCacheDirectory() / "references";
}

fs::path ReferenceCache::fileFor(ReferenceKind kind, const std::string& key) const {
  return dir_ / fmt::format("{}-{}.exr", toString(kind), key);
}

namespace {

// The images of a reference as EXR layers (base RGB: the exitance).
struct Layers {
  std::vector<std::string> names;
  std::vector<const std::vector<float>*> data;
  std::vector<float> coverage_rgb;
};

Layers layersOf(const Reference& r) {
  Layers l;
  auto add = [&](const std::string& name, const std::vector<float>& v) {
    if (v.empty()) return;
    l.names.push_back(name);
    l.data.push_back(&v);
  };
  add("exitance_stderr", r.exitance.se);
  add("radiance", r.radiance.rgb);
  add("radiance_stderr", r.radiance.se);
  add("cone_radiance", r.cone_radiance.rgb);
  add("cone_radiance_stderr", r.cone_radiance.se);
  if (!r.coverage.empty()) {
    for (float c : r.coverage) l.coverage_rgb.insert(l.coverage_rgb.end(), {c, c, c});
    l.names.push_back("coverage");
    l.data.push_back(&l.coverage_rgb);
  }
  return l;
}

}  // namespace

// The whole file (ImageError naming it when it cannot be read).
static std::string readFileBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  if (!in || in.bad()) throw ImageError(fmt::format("cannot read '{}'", path.string()));
  return std::move(ss).str();
}

void writeReferenceExr(const fs::path& path, const Reference& r, const std::string& source) {
  const Layers l = layersOf(r);
  std::vector<ExrLayer> layers;
  for (size_t i = 0; i < l.names.size(); ++i) layers.push_back({l.names[i], *l.data[i]});
  const std::pair<std::string, std::string> attrs[] = {
      {"translucent:quantity", "radiant exitance B (RGB); layers: radiance Ft B / pi (Jensen), "
                               "cone_radiance (physical), <layer>_stderr, coverage (model)"},
      {"translucent:reference", toString(r.kind)},
      {"translucent:source", source},
      {"translucent:key", r.key},
      {"translucent:partial", r.partial ? "true" : "false"}};
  writeExr(path.string(), r.exitance.width, r.exitance.height, r.exitance.rgb, layers, attrs);
}

std::optional<Reference> ReferenceCache::load(ReferenceKind kind, const std::string& key,
                                              int width, int height, std::string* note) const {
  const fs::path exr = fileFor(kind, key);
  fs::path meta = exr;
  meta.replace_extension(".json");
  std::error_code ec;
  if (!fs::exists(meta, ec)) return std::nullopt;
  auto fail = [&](const std::string& why) -> std::optional<Reference> {
    if (note) *note = fmt::format("cache entry '{}' {}; recomputed", exr.string(), why);
    return std::nullopt;
  };
  try {
    const json j = io::readJsonFile(meta);
    if (j.at("key").get<std::string>() != key || j.at("kind").get<std::string>() != toString(kind))
      return fail("does not match its name");
    // The .exr's size and content hash, stored in the .json when it was written: a tampered or
    // truncated .exr is recomputed, never used (an entry without them is from an older version).
    if (!j.contains("exr_bytes") || !j.contains("exr_hash")) return fail("has no content hash");
    const std::string bytes = readFileBytes(exr);
    if (bytes.size() != j.at("exr_bytes").get<uint64_t>())
      return fail(fmt::format("is {} bytes: expected {} (its .json)", bytes.size(),
                              j.at("exr_bytes").get<uint64_t>()));
    if (const std::string h = fmt::format("{:016x}", geometry::contentHash(bytes));
        h != j.at("exr_hash").get<std::string>())
      return fail(fmt::format("has content hash {}: expected {} (its .json): the file was "
                              "changed", h, j.at("exr_hash").get<std::string>()));
    const LayeredImage img = readExrLayers(exr.string());
    if (img.width != width || img.height != height) return fail("has another image size");
    Reference r;
    r.kind = kind;
    r.key = key;
    r.from_cache = true;
    r.cache_file = exr;
    r.count_done = j.at("count_done").get<uint64_t>();
    r.seconds = j.at("seconds").get<double>();
    r.request.kind = kind;
    r.request.count = j.at("count").get<uint64_t>();
    r.request.seed = j.at("seed").get<uint64_t>();
    r.request.subpixels = j.value("subpixels", 2);
    r.request.method = j.value("method", std::string("light"));
    if (r.request.method == "camera") r.cone_angle = 0.0;
    auto image = [&](const std::string& name, const std::string& se) {
      CompareImage c;
      c.width = width;
      c.height = height;
      c.rgb = name.empty() ? img.rgb : img.layers.at(name);
      c.se = img.layers.at(se);
      return c;
    };
    r.exitance = image("", "exitance_stderr");
    r.radiance = image("radiance", "radiance_stderr");
    if (kind == ReferenceKind::Physical) r.cone_radiance = image("cone_radiance", "cone_radiance_stderr");
    if (kind == ReferenceKind::Model) {
      const auto& c = img.layers.at("coverage");
      for (size_t i = 0; i < c.size(); i += 3) r.coverage.push_back(c[i]);
    }
    return r;
  } catch (const std::exception& e) {
    return fail(fmt::format("is unreadable ({})", e.what()));
  }
}

void ReferenceCache::store(Reference& r) const {
  if (r.partial) {
    r.cache_note = "partial (stopped early): not cached";
    return;
  }
  const fs::path exr = fileFor(r.kind, r.key);
  fs::path meta = exr;
  meta.replace_extension(".json");
  // Temporary names keep the extension (OpenImageIO picks the format by it).
  const std::string tag = fmt::format(".tmp{}", static_cast<long>(getpid()));
  const fs::path tmpExr = dir_ / (exr.stem().string() + tag + ".exr");
  const fs::path tmpMeta = dir_ / (meta.stem().string() + tag + ".json");
  std::error_code ec;
  fs::create_directories(dir_, ec);
  try {
    writeReferenceExr(tmpExr, r, "translucent compare (reference cache)");
    const std::string bytes = readFileBytes(tmpExr);
    json j = {{"exr_bytes", bytes.size()},
              {"exr_hash", fmt::format("{:016x}", geometry::contentHash(bytes))},
              {"key", r.key},         {"kind", toString(r.kind)},
              {"count", r.request.count}, {"count_done", r.count_done},
              {"seed", r.request.seed},   {"seconds", r.seconds},
              {"width", r.exitance.width}, {"height", r.exitance.height},
              {"code_version", kReferenceCodeVersion}};
    if (r.kind == ReferenceKind::Model) j["subpixels"] = r.request.subpixels;
    if (r.kind == ReferenceKind::Physical) {
      j["method"] = r.request.method;
    }
    {
      std::ofstream f(tmpMeta);
      f << j.dump(2) << "\n";
      if (!f) throw ImageError(fmt::format("cannot write '{}'", tmpMeta.string()));
    }
    // The .json is renamed last: a reader never sees it beside a missing or partial .exr.
    fs::rename(tmpExr, exr);
    fs::rename(tmpMeta, meta);
    r.cache_file = exr;
  } catch (const std::exception& e) {
    fs::remove(tmpExr, ec);
    fs::remove(tmpMeta, ec);
    r.cache_note = fmt::format("not cached: {}", e.what());
  }
}

// ---- Computing references ------------------------------------------------------------------

CompareImage toCompareImage(const reference::McImage& m) {
  return {m.width(), m.height(), m.rgb(), m.rgbStdError()};
}

Reference computeReference(const scene::Scene& scene, const geometry::TriangleMesh& mesh,
                           const ReferenceRequest& request,
                           const reference::ProgressCallback& progress) {
  if (request.count < 1)
    throw ParameterError(fmt::format("{} reference: count is 0: expected at least 1",
                                     toString(request.kind)));
  Reference r;
  r.kind = request.kind;
  r.request = request;
  r.key = referenceKey(scene, request);
  const std::vector<reference::Light> lights = scene::referenceLights(scene);
  const material::Material material = scene::sceneMaterial(scene, mesh);
  if (request.kind == ReferenceKind::Physical) {
    if (material.heterogeneous()) {
      const MaterialReferences roles = materialReferences(material);
      if (!roles.physical)
        throw ParameterError(fmt::format("--reference physical: {}", roles.text));
    }
    if (request.device != "cpu" && request.device != "gpu")
      throw ParameterError(fmt::format("--reference-device '{}': expected cpu or gpu", request.device));
    if (request.method != "light" && request.method != "camera")
      throw ParameterError(fmt::format("--physical-method '{}': expected light or camera", request.method));
    // On the GPU in a GL context of its own, released before the techniques make theirs;
    // declared before the tracer, whose walker it outlives.
    const reference::TraceDevice device =
        request.device == "gpu" ? reference::openTraceDevice("gpu", "--reference-device")
                                : reference::TraceDevice{};
    if (request.method == "camera") {
      // Paths from the camera (reference/camera_paths.h): the true radiance per pixel.
      reference::CameraPathOptions o;
      o.seed = request.seed;
      o.threads = request.threads;
      reference::CameraPathTracer tracer(mesh, material, lights, scene.camera, o);
      reference::useDevice(device, request.device, tracer, mesh, fs::path(scene.mesh_file).string(),
                           "--reference-device");
      const reference::CameraPathStats st = tracer.addPass(request.count, progress);
      r.exitance = toCompareImage(tracer.images().exitance);
      r.radiance = toCompareImage(tracer.images().radiance);
      r.cone_radiance = toCompareImage(tracer.images().cone_radiance);
      r.cone_angle = 0.0;
      r.count_done = st.samples;
      r.seconds = st.seconds;
      r.partial = st.partial;
      return r;
    }
    // Homogeneous: bit-identical to the tracer of scene.medium; a 3D field: delta tracking.
    reference::MeshPathTracer tracer(mesh, material, lights, scene.camera, scene.cone_angle,
                                     {request.seed, request.threads});
    reference::useDevice(device, request.device, tracer, mesh, fs::path(scene.mesh_file).string(),
                         "--reference-device");
    const reference::TransportStats st = tracer.addPass(request.count, progress);
    r.exitance = toCompareImage(tracer.images().exitance);
    r.radiance = toCompareImage(tracer.images().radiance);
    r.cone_radiance = toCompareImage(tracer.images().cone_radiance);
    r.count_done = st.photons.empty() ? 0 : st.photons[0];
    r.seconds = st.seconds;
    r.partial = st.partial;
    return r;
  }
  if (bssrdf::hasBssrdfExtension(scene.model))
    throw ParameterError(fmt::format(
        "--reference model: the scene's model is the .bssrdf file '{}'; the model reference "
        "integrates a registered model ({})", scene.model, fmt::join(bssrdf::modelNames(), ", ")));
  reference::ModelReferenceOptions o;
  o.samples = request.count;
  o.subpixels = request.subpixels;
  o.seed = request.seed;
  o.threads = request.threads;
  o.convention = bssrdf::ExitConvention::Jensen;  // stored; Reference::radianceFor converts
  // The scene's material: a homogeneous one is bit-identical to renderModelReference(mesh,
  // scene.medium, model, ...); a heterogeneous one is brute-force Eq. 8 (model_reference.h).
  const reference::ModelReferenceImages m =
      reference::renderModelReference(mesh, material, lights, scene.camera, o, progress);
  r.exitance = {m.width, m.height, m.exitance, m.exitance_se};
  r.radiance = {m.width, m.height, m.radiance, m.radiance_se};
  r.coverage = m.coverage;
  r.count_done = m.samples;
  r.seconds = m.seconds;
  r.partial = m.partial;
  return r;
}

Reference cachedReference(const scene::Scene& scene, const geometry::TriangleMesh& mesh,
                          const ReferenceRequest& request, const ReferenceCache* cache,
                          const reference::ProgressCallback& progress) {
  std::string note;
  if (cache) {
    const std::string key = referenceKey(scene, request);
    if (auto hit = cache->load(request.kind, key, scene.camera.width, scene.camera.height, &note)) {
      hit->request.threads = request.threads;
      return std::move(*hit);
    }
  }
  Reference r = computeReference(scene, mesh, request, progress);
  if (cache) cache->store(r);
  if (!note.empty()) r.cache_note = note + (r.cache_note.empty() ? "" : "; " + r.cache_note);
  return r;
}

namespace {

// The run of `json_file` as this scene's reference, or std::nullopt with *mismatch saying what
// differs when it was traced for another scene; every other problem is a ParameterError.
std::optional<Reference> readPathtracedReferenceFrom(const json& j, const std::string& what,
                                                     const fs::path& json_file,
                                                     const scene::Scene& scene,
                                                     std::string* mismatch) {
  if (!j.is_object() || !j.contains("command") || !j["command"].is_string() ||
      j["command"].get<std::string>() != "pathtrace mesh" || !j.contains("reference_key") ||
      !j.contains("exr"))
    throw ParameterError(fmt::format("{}: not the --json of `translucent pathtrace mesh` (or of "
                                     "`translucent merge` of its shards)", what));
  if (j.value("partial", true))
    throw ParameterError(fmt::format("{}: a partial run (stopped early): trace it to the end", what));
  ReferenceRequest req;
  req.kind = ReferenceKind::Physical;
  req.count = j.at("photons_per_channel").get<uint64_t>();
  req.seed = j.at("seed").get<uint64_t>();
  // A GPU-traced reference ("device": "gpu (<renderer>)", or "gpu" from merged shards) is keyed
  // as such (ReferenceRequest::device).
  req.device = j.value("device", std::string("cpu")).rfind("gpu", 0) == 0 ? "gpu" : "cpu";
  const std::string text = referenceKeyText(scene, req);
  if (sha256Hex(text) != j.at("reference_key").get<std::string>()) {
    std::vector<std::string> differ;
    const json mine = json::parse(text);
    const json theirs = j.value("reference_key_text", json::object());
    for (const auto& [k, v] : mine.items())
      if (!theirs.contains(k) || theirs[k] != v) differ.push_back(k);
    *mismatch = fmt::format(
        "{}: traced for another scene than this comparison's (different: {})", what,
        differ.empty() ? std::string("the reference key") : fmt::format("{}", fmt::join(differ, ", ")));
    return std::nullopt;
  }
  fs::path exr = j.at("exr").get<std::string>();
  std::error_code ec;
  if (exr.is_relative() && fs::exists(json_file.parent_path() / exr, ec))
    exr = json_file.parent_path() / exr;
  LayeredImage img;
  try {
    img = readExrLayers(exr.string());
  } catch (const std::exception& e) {
    throw ParameterError(fmt::format("{}: its EXR '{}' cannot be read ({})", what, exr.string(),
                                     e.what()));
  }
  if (img.width != scene.camera.width || img.height != scene.camera.height)
    throw ParameterError(fmt::format("{}: its EXR '{}' is {}x{}: the scene's camera is {}x{}",
                                     what, exr.string(), img.width, img.height,
                                     scene.camera.width, scene.camera.height));
  Reference r;
  r.kind = ReferenceKind::Physical;
  r.request = req;
  r.key = j.at("reference_key").get<std::string>();
  r.count_done = req.count;
  r.seconds = j.value("seconds", 0.0);
  r.cache_file = exr;
  auto image = [&](const std::string& name) {
    if (!img.layers.count(name) || !img.layers.count(name + "_stderr"))
      throw ParameterError(fmt::format("{}: its EXR '{}' has no layer '{}' (and '{}_stderr')",
                                       what, exr.string(), name, name));
    return CompareImage{img.width, img.height, img.layers.at(name), img.layers.at(name + "_stderr")};
  };
  r.exitance = image("exitance");
  r.radiance = image("radiance");
  r.cone_radiance = image("cone_radiance");
  return r;
}

std::optional<Reference> readPathtracedReference(const fs::path& json_file,
                                                 const scene::Scene& scene, std::string* mismatch) {
  const std::string what = fmt::format("--reference-from '{}'", json_file.string());
  json j;
  try {
    j = io::readJsonFile(json_file, what);
  } catch (const io::JsonError& e) {
    throw ParameterError(e.what());
  }
  try {
    return readPathtracedReferenceFrom(j, what, json_file, scene, mismatch);
  } catch (const json::exception& e) {  // a key of the wrong type (another tool's JSON)
    throw ParameterError(fmt::format("{}: not the --json of `translucent pathtrace mesh`: {}", what,
                                     io::jsonErrorText(e)));
  }
}

}  // namespace

Reference loadPathtracedReference(const fs::path& json_file, const scene::Scene& scene) {
  std::string mismatch;
  std::optional<Reference> r = readPathtracedReference(json_file, scene, &mismatch);
  if (!r) throw ParameterError(mismatch);
  return std::move(*r);
}

std::optional<ReferenceFromFile> findPathtracedReference(const std::vector<fs::path>& json_files,
                                                 const scene::Scene& scene, std::string* why) {
  std::vector<std::string> mismatches;
  for (const fs::path& f : json_files) {
    std::string mismatch;
    if (std::optional<Reference> r = readPathtracedReference(f, scene, &mismatch))
      return ReferenceFromFile{std::move(*r), f};
    mismatches.push_back(std::move(mismatch));
  }
  if (why) *why = fmt::format("{}", fmt::join(mismatches, "; "));
  return std::nullopt;
}

// ---- Masks ---------------------------------------------------------------------------------

std::vector<uint8_t> interiorMask(const geometry::TriangleMesh& mesh,
                                  const reference::Camera& camera, int grid, double min_cos) {
  if (grid < 1) throw ParameterError(fmt::format("mask grid is {}: expected >= 1", grid));
  const geometry::RayScene rays(mesh, "compare mask");
  const reference::CameraModel cam(camera);
  const int w = camera.width, h = camera.height;
  std::vector<uint8_t> mask(static_cast<size_t>(w) * static_cast<size_t>(h), 0);
  tbb::parallel_for(0, h, [&](int y) {
    for (int x = 0; x < w; ++x) {
      bool inside = true;
      for (int b = 0; b < grid && inside; ++b)
        for (int a = 0; a < grid && inside; ++a) {
          glm::dvec3 o, d;
          cam.ray(x + (a + 0.5) / grid, y + (b + 0.5) / grid, o, d);
          geometry::RayHit hit;
          inside = rays.intersect(o, d, 0.0, std::numeric_limits<double>::infinity(), hit) &&
                   (min_cos <= 0.0 || std::abs(glm::dot(hit.normal, d)) >= min_cos);
        }
      mask[static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x)] = inside;
    }
  });
  return mask;
}

namespace {
uint64_t countSet(const std::vector<uint8_t>& m) {
  uint64_t n = 0;
  for (uint8_t v : m) n += v != 0;
  return n;
}
}  // namespace

uint64_t Masks::interiorPixels() const { return countSet(interior); }
uint64_t Masks::conePixels() const { return countSet(cone); }

std::optional<double> physicalConeAngle(std::span<const Reference> references) {
  for (const Reference& r : references)
    if (r.kind == ReferenceKind::Physical) return r.cone_angle;
  return std::nullopt;
}

Masks compareMasks(const scene::Scene& scene, const geometry::TriangleMesh& mesh,
                   std::span<const float> model_coverage, std::optional<double> cone_angle) {
  constexpr int kGrid = 4;
  constexpr double kPi = 3.14159265358979323846;
  Masks m;
  m.interior = interiorMask(mesh, scene.camera, kGrid, 0.0);
  // camera.h: the cone reaches below the horizon where the angle to the silhouette is < θc.
  m.cone = interiorMask(mesh, scene.camera, kGrid,
                        std::sin(cone_angle.value_or(scene.cone_angle) * kPi / 180.0));
  if (!model_coverage.empty()) {
    if (model_coverage.size() != m.interior.size())
      throw ParameterError(fmt::format("model reference coverage has {} pixels: expected {}",
                                       model_coverage.size(), m.interior.size()));
    for (size_t i = 0; i < m.interior.size(); ++i)
      if (!(model_coverage[i] >= 1.0f)) m.interior[i] = m.cone[i] = 0;
  }
  return m;
}

// ---- Metrics -------------------------------------------------------------------------------

Metrics compareImages(const CompareImage& test, const CompareImage& reference,
                      std::span<const uint8_t> mask, const MetricOptions& display) {
  if (test.width != reference.width || test.height != reference.height ||
      test.rgb.size() != reference.rgb.size())
    throw ParameterError(fmt::format("compare: test image {}x{} and reference {}x{} differ in size",
                                     test.width, test.height, reference.width, reference.height));
  if (!mask.empty() && mask.size() * 3 != reference.rgb.size())
    throw ParameterError(fmt::format("compare: mask of {} pixels for a {}x{} image", mask.size(),
                                     reference.width, reference.height));
  MetricOptions o = display;
  o.mask = mask;
  return computeMetrics(test.ref(), reference.ref(), o);
}

namespace {

void addRow(std::vector<PairMetrics>& rows, const std::string& test, const std::string& ref,
            const std::string& quantity, const std::string& convention, const std::string& mask_name,
            const CompareImage& t, const CompareImage& r, const std::vector<uint8_t>& mask,
            const MetricOptions& display) {
  rows.push_back({test, ref, quantity, convention, mask_name, compareImages(t, r, mask, display)});
}

}  // namespace

std::vector<PairMetrics> techniqueMetrics(const TechniqueImages& t,
                                          std::span<const Reference> references, double eta,
                                          const Masks& masks, const MetricOptions& display) {
  std::vector<PairMetrics> rows;
  const std::string conv = bssrdf::toString(t.convention);
  for (const Reference& r : references) {
    const std::string ref = toString(r.kind);
    if (!t.exitance.empty())
      addRow(rows, t.name, ref, "exitance", "", "interior", t.exitance, r.exitance, masks.interior,
             display);
    addRow(rows, t.name, ref, "radiance", conv, "interior", t.radiance,
           r.radianceFor(t.convention, eta), masks.interior, display);
    if (r.kind == ReferenceKind::Physical)
      addRow(rows, t.name, ref, "cone_radiance", conv, "interior_cone", t.radiance,
             r.cone_radiance, masks.cone, display);
  }
  return rows;
}

std::vector<PairMetrics> modelMetrics(std::span<const Reference> references,
                                      bssrdf::ExitConvention convention, double eta,
                                      const Masks& masks, const MetricOptions& display) {
  const Reference *model = nullptr, *physical = nullptr;
  for (const Reference& r : references) (r.kind == ReferenceKind::Model ? model : physical) = &r;
  if (!model || !physical) return {};
  std::vector<PairMetrics> rows;
  const std::string conv = bssrdf::toString(convention);
  const CompareImage l = model->radianceFor(convention, eta);
  addRow(rows, "model", "physical", "exitance", "", "interior", model->exitance, physical->exitance,
         masks.interior, display);
  addRow(rows, "model", "physical", "radiance", conv, "interior", l,
         physical->radianceFor(convention, eta), masks.interior, display);
  addRow(rows, "model", "physical", "cone_radiance", conv, "interior_cone", l,
         physical->cone_radiance, masks.cone, display);
  return rows;
}

}  // namespace translucent::analysis
