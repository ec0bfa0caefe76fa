// SPDX-License-Identifier: GPL-3.0-or-later
#include "translucent/scene/scene.h"

#include "translucent/io/input_file.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <numbers>
#include <set>
#include <sstream>
#include <type_traits>
#include <utility>

#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>
#include <glm/mat3x3.hpp>

#include "translucent/geometry/point_cloud.h"  // defaultCacheDirectory
#include "translucent/bssrdf/tabulated.h"
#include "translucent/geometry/ray_scene.h"
#include "translucent/io/json.h"
#include "translucent/material/json_reader.h"
#include "translucent/material/material_desc.h"
#include "translucent/material/parse_context.h"
#include "translucent/optics/presets.h"
#include "translucent/scene/data_path.h"

namespace translucent::scene {
namespace {

using nlohmann::json;
using reference::BeamLight;
using reference::Camera;
using reference::DirectionalLight;
using reference::PointLight;

using Reader = material::JsonReader;
using material::rgbJson;
using material::vec;

std::filesystem::path resolve(const std::filesystem::path& p, const std::filesystem::path& base) {
  return p.is_absolute() || base.empty() ? p : base / p;
}

// A file key of the scene (data_path.h), remembered by its given name when found on the data
// search path so that toJson can write that name back.
std::filesystem::path resolveFile(const Reader& r, Scene& s, const std::string& name,
                                  const std::filesystem::path& base_dir, const std::string& key) {
  // A "\u0000" in a file name cut it short where the system opened it ("cube.obj\u0000x" read
  // cube.obj).
  if (name.find('\0') != std::string::npos)
    r.fail(key, "holds a NUL character: expected a file name");
  const ResolvedFile f = resolveSceneFile(name, base_dir, r.what, key);
  if (f.on_search_path) s.data_names[f.path] = name;
  return f.path;
}

// How toJson writes a file path: its given name when it came from the data search path.
std::string writtenPath(const Scene& s, const std::filesystem::path& p) {
  const auto it = s.data_names.find(p);
  return it != s.data_names.end() ? it->second : p.string();
}

void requireDirection(const Reader& r, glm::dvec3& d, const std::string& key) {
  const double n = glm::length(d);
  if (!(n > 0.0) || !std::isfinite(n))
    r.fail(key, fmt::format("is [{}, {}, {}]: expected a non-zero finite direction", d.x, d.y, d.z));
  // Unit vectors are kept bit for bit (normalising again could change the last bit, and a
  // written scene must read back to the same scene).
  if (std::abs(n - 1.0) > 1e-12) d /= n;
}

void requirePositive(const Reader& r, double v, const std::string& key) {
  if (!std::isfinite(v) || !(v > 0.0)) r.fail(key, fmt::format("is {}: expected a finite value > 0", v));
}

// One entry of mesh.deform (scene.h lists the keys).
geometry::Deformation parseDeformation(const Reader& r, const json& j, const std::string& key) {
  using Type = geometry::Deformation::Type;
  if (!j.is_object()) r.fail(key, fmt::format("{}: expected an object", Reader::describe(j)));
  const std::string type = r.string(j, "type", key);
  geometry::Deformation d;
  if (type == "twist") {
    d.type = Type::Twist;
    r.onlyKeys(j, key, {"type", "amount", "period", "origin", "axis"});
  } else if (type == "bend") {
    d.type = Type::Bend;
    r.onlyKeys(j, key, {"type", "amount", "period", "origin", "axis", "direction"});
  } else if (type == "wave") {
    d.type = Type::Wave;
    r.onlyKeys(j, key, {"type", "amount", "period", "origin", "axis", "direction", "wavelength"});
  } else {
    r.fail(key + ".type", fmt::format("'{}': expected twist, bend or wave", type));
  }
  d.amount = r.number(j, "amount", key, 0.0);
  d.period = r.number(j, "period", key, 0.0);
  if (d.period < 0.0)
    r.fail(key + ".period", fmt::format("is {}: expected 0 (constant) or a period > 0", d.period));
  d.origin = r.vec3(j, "origin", key, d.origin);
  d.axis = r.vec3(j, "axis", key, d.axis);
  requireDirection(r, d.axis, key + ".axis");
  if (d.type != Type::Twist) {
    d.direction = r.vec3(j, "direction", key, d.direction);
    requireDirection(r, d.direction, key + ".direction");
    // The frame (axis, direction, axis × direction) must be orthonormal: the formulas (and the
    // GPU's) rely on it, and a slanted direction has no obvious meaning.
    if (std::abs(glm::dot(d.axis, d.direction)) > 1e-9)
      r.fail(key + ".direction",
             fmt::format("[{}, {}, {}] is not perpendicular to axis [{}, {}, {}]: expected a "
                         "direction perpendicular to the axis", d.direction.x, d.direction.y,
                         d.direction.z, d.axis.x, d.axis.y, d.axis.z));
  }
  if (d.type == Type::Wave) {
    d.wavelength = r.number(j, "wavelength", key, 1.0);
    requirePositive(r, d.wavelength, key + ".wavelength");
  }
  return d;
}

json deformationJson(const geometry::Deformation& d) {
  json j = {{"type", geometry::toString(d.type)}, {"amount", d.amount}, {"period", d.period},
            {"origin", vec(d.origin)}, {"axis", vec(d.axis)}};
  if (d.type != geometry::Deformation::Type::Twist) j["direction"] = vec(d.direction);
  if (d.type == geometry::Deformation::Type::Wave) j["wavelength"] = d.wavelength;
  return j;
}

Light parseLight(const Reader& r, Scene& s, const json& l, const std::string& key,
                 const std::filesystem::path& base_dir) {
  if (!l.is_object()) r.fail(key, fmt::format("{}: expected an object", Reader::describe(l)));
  const std::string type = r.string(l, "type", key);
  Light light;
  if (type == "directional") {
    r.onlyKeys(l, key, {"type", "direction", "irradiance", "color"});
    DirectionalLight d{r.requiredVec3(l, "direction", key), r.number(l, "irradiance", key, 1.0)};
    requireDirection(r, d.direction, key + ".direction");
    requirePositive(r, d.irradiance, key + ".irradiance");
    light.emitter = d;
  } else if (type == "point") {
    r.onlyKeys(l, key, {"type", "position", "intensity", "color"});
    PointLight p{r.requiredVec3(l, "position", key), r.number(l, "intensity", key, 1.0)};
    requirePositive(r, p.intensity, key + ".intensity");
    light.emitter = p;
  } else if (type == "beam") {
    r.onlyKeys(l, key, {"type", "origin", "direction", "radius", "power", "color"});
    BeamLight b{r.requiredVec3(l, "origin", key), r.requiredVec3(l, "direction", key),
                r.number(l, "radius", key, 0.0), r.number(l, "power", key, 1.0)};
    requireDirection(r, b.direction, key + ".direction");
    if (b.radius < 0.0) r.fail(key + ".radius", fmt::format("is {}: expected >= 0", b.radius));
    requirePositive(r, b.power, key + ".power");
    light.emitter = b;
  } else if (type == "filtered_directional") {
    r.onlyKeys(l, key, {"type", "direction", "irradiance", "texture", "texture_size", "color"});
    FilteredDirectionalLight f;
    f.direction = r.requiredVec3(l, "direction", key);
    requireDirection(r, f.direction, key + ".direction");
    f.irradiance = r.number(l, "irradiance", key, 1.0);
    requirePositive(r, f.irradiance, key + ".irradiance");
    const std::string tex = r.string(l, "texture", key);
    f.texture = tex == "checker" ? std::filesystem::path(tex)
                                 : resolveFile(r, s, tex, base_dir, key + ".texture");
    f.texture_size = r.number(l, "texture_size", key, 1.0);
    requirePositive(r, f.texture_size, key + ".texture_size");
    light.emitter = f;
  } else if (type == "environment") {
    r.onlyKeys(l, key, {"type", "file", "intensity", "rotate", "occlusion", "color"});
    EnvironmentLight e;
    e.file = resolveFile(r, s, r.string(l, "file", key), base_dir, key + ".file");
    e.intensity = r.number(l, "intensity", key, 1.0);
    requirePositive(r, e.intensity, key + ".intensity");
    e.rotate = r.number(l, "rotate", key, 0.0);
    e.occlusion = r.boolean(l, "occlusion", key, false);
    light.emitter = e;
  } else {
    r.fail(key + ".type", fmt::format("'{}': expected directional, point, beam, "
                                      "filtered_directional or environment", type));
  }
  if (l.contains("color")) light.color = r.rgb(l["color"], key + ".color");
  for (size_t c = 0; c < 3; ++c)
    if (light.color[c] < 0.0)
      r.fail(key + ".color", fmt::format("{} is {}: expected a value >= 0", kChannelNames[c],
                                         light.color[c]));
  // What the light emits per channel: its power (irradiance, intensity...) times its colour. A
  // black light renders and traces to black; one fainter than kMinLightPower in a channel writes
  // zeros to 32-bit images (floats flush below ~1e-38 once scattered) and used to leave the
  // tracer's fixed-point sums no range: both are refused here, before any work, for every
  // renderer and tracer alike.
  const auto [powerName, power] = std::visit(
      [](const auto& e) -> std::pair<const char*, double> {
        using E = std::decay_t<decltype(e)>;
        if constexpr (std::is_same_v<E, DirectionalLight> ||
                      std::is_same_v<E, FilteredDirectionalLight>)
          return {"irradiance", e.irradiance};
        else if constexpr (std::is_same_v<E, PointLight>)
          return {"intensity", e.intensity};
        else if constexpr (std::is_same_v<E, BeamLight>)
          return {"power", e.power};
        else
          return {"intensity", e.intensity};
      },
      light.emitter);
  if (!(light.color[0] > 0.0 || light.color[1] > 0.0 || light.color[2] > 0.0))
    r.fail(key + ".color", fmt::format("is [{}, {}, {}]: the light emits nothing: expected a "
                                       "channel > 0 (or remove the light)", light.color[0],
                                       light.color[1], light.color[2]));
  for (size_t c = 0; c < 3; ++c) {
    const double emitted = power * light.color[c];
    if (light.color[c] > 0.0 && !(emitted >= kMinLightPower))
      r.fail(key, fmt::format("{} {} times {} {} is {}: expected at least {} (a fainter light "
                              "renders black); give a colour of 0 to a channel without light",
                              powerName, power, kChannelNames[c], light.color[c], emitted,
                              kMinLightPower));
  }
  return light;
}

json lightJson(const Scene& s, const Light& l) {
  json j;
  if (const auto* d = std::get_if<DirectionalLight>(&l.emitter)) {
    j = {{"type", "directional"}, {"direction", vec(d->direction)}, {"irradiance", d->irradiance}};
  } else if (const auto* p = std::get_if<PointLight>(&l.emitter)) {
    j = {{"type", "point"}, {"position", vec(p->position)}, {"intensity", p->intensity}};
  } else if (const auto* b = std::get_if<BeamLight>(&l.emitter)) {
    j = {{"type", "beam"}, {"origin", vec(b->origin)}, {"direction", vec(b->direction)},
         {"radius", b->radius}, {"power", b->power}};
  } else if (const auto* f = std::get_if<FilteredDirectionalLight>(&l.emitter)) {
    j = {{"type", "filtered_directional"}, {"direction", vec(f->direction)},
         {"irradiance", f->irradiance}, {"texture", writtenPath(s, f->texture)},
         {"texture_size", f->texture_size}};
  } else {
    const auto& e = std::get<EnvironmentLight>(l.emitter);
    j = {{"type", "environment"}, {"file", writtenPath(s, e.file)}, {"intensity", e.intensity},
         {"rotate", e.rotate}, {"occlusion", e.occlusion}};
  }
  j["color"] = rgbJson(l.color);
  return j;
}

// Rotation by `degrees` about x, then y, then z.
glm::dmat3 rotation(const glm::dvec3& degrees) {
  const glm::dvec3 a = degrees * (std::numbers::pi / 180.0);
  const double cx = std::cos(a.x), sx = std::sin(a.x), cy = std::cos(a.y), sy = std::sin(a.y);
  const double cz = std::cos(a.z), sz = std::sin(a.z);
  // Column-major: glm::dmat3(col0, col1, col2).
  const glm::dmat3 rx(1, 0, 0, 0, cx, sx, 0, -sx, cx);
  const glm::dmat3 ry(cy, 0, -sy, 0, 1, 0, sy, 0, cy);
  const glm::dmat3 rz(cz, sz, 0, -sz, cz, 0, 0, 0, 1);
  return rz * ry * rx;
}

}  // namespace

Scene parseScene(const std::string& text, const std::filesystem::path& base_dir,
                 const std::string& what) {
  const Reader r{what};
  json doc;
  try {
    doc = io::parseJson(text, what);  // the depth limit, then syntax errors, numbers out of range
  } catch (const io::JsonError& e) {
    throw ParameterError(e.what());
  }
  r.onlyKeys(doc, "", {"mesh", "material", "lights", "camera", "technique", "display", "cone_angle",
                       "time"});
  Scene s;

  // Mesh.
  if (!doc.contains("mesh")) r.fail("mesh", "required (an object with \"file\")");
  const json& mesh = doc["mesh"];
  r.onlyKeys(mesh, "mesh", {"file", "fill_holes", "wrap", "normalize", "rotate", "scale", "translate",
                            "deform"});
  s.mesh_file = resolveFile(r, s, r.string(mesh, "file", "mesh"), base_dir, "mesh.file");
  s.mesh_fill_holes = r.boolean(mesh, "fill_holes", "mesh", false);
  if (mesh.contains("wrap")) {
    const json& w = mesh["wrap"];
    if (w.is_boolean()) {
      if (w.get<bool>()) s.mesh_wrap = geometry::AlphaWrapOptions{};
    } else if (w.is_object()) {
      r.onlyKeys(w, "mesh.wrap", {"alpha", "offset"});
      geometry::AlphaWrapOptions o;
      o.alpha = r.number(w, "alpha", "mesh.wrap", o.alpha);
      o.offset = r.number(w, "offset", "mesh.wrap", o.offset);
      // Relative to the bounding-box diagonal: below 1e-4 the wrap of a unit mesh has ~10^8
      // triangles (memory and hours), above 1 it is a blob.
      for (const auto& [name, v] : {std::pair{"alpha", o.alpha}, std::pair{"offset", o.offset}})
        if (!(v >= 1e-4 && v <= 1.0))
          r.fail(fmt::format("mesh.wrap.{}", name),
                 fmt::format("{}: expected a fraction of the bounding-box diagonal in [1e-4, 1]", v));
      s.mesh_wrap = o;
    } else {
      r.fail("mesh.wrap", fmt::format("{}: expected true, false or an object with \"alpha\" and "
                                      "\"offset\"", Reader::describe(w)));
    }
    if (s.mesh_wrap && s.mesh_fill_holes)
      r.fail("mesh.wrap", "given with mesh.fill_holes: expected one of them (the wrap is closed)");
  }
  s.mesh_normalize = r.boolean(mesh, "normalize", "mesh", true);
  s.mesh_rotate = r.vec3(mesh, "rotate", "mesh", glm::dvec3(0.0));
  s.mesh_scale = r.number(mesh, "scale", "mesh", 1.0);
  requirePositive(r, s.mesh_scale, "mesh.scale");
  // 1e-320 made every triangle of zero area, an error that blamed the mesh file.
  if (s.mesh_scale < 1e-9 || s.mesh_scale > 1e9)
    r.fail("mesh.scale", fmt::format("is {}: expected a factor in [1e-9, 1e9]", s.mesh_scale));
  s.mesh_translate = r.vec3(mesh, "translate", "mesh", glm::dvec3(0.0));
  if (mesh.contains("deform")) {
    const json& d = mesh["deform"];
    if (d.is_object()) {
      s.mesh_deform.push_back(parseDeformation(r, d, "mesh.deform"));
    } else if (d.is_array()) {
      if (d.size() > geometry::kMaxDeformations)
        r.fail("mesh.deform", fmt::format("{} deformations: expected at most {}", d.size(),
                                          geometry::kMaxDeformations));
      for (size_t i = 0; i < d.size(); ++i)
        s.mesh_deform.push_back(parseDeformation(r, d[i], fmt::format("mesh.deform[{}]", i)));
    } else {
      r.fail("mesh.deform", fmt::format("{}: expected a deformation object or an array of them",
                                        Reader::describe(d)));
    }
  }
  s.time = doc.contains("time") ? r.number(doc["time"], "time") : 0.0;

  // Material: a preset or explicit coefficients (the homogeneous form), or a spatially varying
  // type (material/material_desc.h), and the BSSRDF model.
  if (!doc.contains("material")) r.fail("material", "required");
  const json& mat = doc["material"];
  if (!mat.is_object()) r.fail("material", fmt::format("{}: expected an object", Reader::describe(mat)));
  const std::string materialType =
      mat.contains("type") ? r.string(mat, "type", "material") : "homogeneous";
  if (materialType != "homogeneous") {
    try {
      (void)material::materialKind(materialType);
    } catch (const ParameterError& e) {
      r.fail("material.type", e.what());
    }
  }
  if (materialType == "homogeneous") {
    r.onlyKeys(mat, "material", {"type", "preset", "sigma_a", "sigma_s", "g", "eta", "scale", "model"});
    const bool explicitCoefficients = mat.contains("sigma_a") || mat.contains("sigma_s");
    if (mat.contains("preset") && explicitCoefficients)
      r.fail("material", "give either \"preset\" or \"sigma_a\" and \"sigma_s\", not both");
    if (mat.contains("preset")) {
      s.preset = r.string(mat, "preset", "material");
      const Preset* p = nullptr;
      try {
        p = &preset(s.preset);
      } catch (const ParameterError& e) {
        r.fail("material.preset", e.what());
      }
      const double g = r.number(mat, "g", "material", p->g);
      try {
        s.medium = Medium::fromReduced(p->sigma_a, p->sigma_s_prime, g,
                                       r.number(mat, "eta", "material", p->eta));
      } catch (const ParameterError& e) {
        r.fail("material", e.what());
      }
    } else if (explicitCoefficients) {
      if (!mat.contains("sigma_a") || !mat.contains("sigma_s"))
        r.fail("material", "\"sigma_a\" and \"sigma_s\" must be given together");
      s.medium.sigma_a = r.rgb(mat["sigma_a"], "material.sigma_a");
      s.medium.sigma_s = r.rgb(mat["sigma_s"], "material.sigma_s");
      s.medium.g = r.number(mat, "g", "material", 0.0);
      s.medium.eta = r.number(mat, "eta", "material", 1.3);
    } else {
      r.fail("material", "expected \"preset\" or \"sigma_a\" and \"sigma_s\"");
    }
  }
  s.medium.scale = r.number(mat, "scale", "material", 1.0);
  if (mat.contains("model")) {
    const std::string m = r.string(mat, "model", "material");
    if (m.empty()) r.fail("material.model", "expected a model name or a .bssrdf file");
    // Files (.bssrdf plug-ins, .csv tabulated profiles) are relative to the scene file.
    const bool file = std::filesystem::path(m).extension() == ".bssrdf" || bssrdf::isTabulatedFile(m);
    s.model = file ? resolve(m, base_dir).string() : m;
    if (bssrdf::isTabulatedFile(m) && materialType != "homogeneous")
      r.fail("material.model", fmt::format("'{}' is a tabulated profile, the R(r) of one material: "
                                           "a {} material needs an analytic model whose profile "
                                           "follows the local coefficients", m, materialType));
  }
  if (materialType != "homogeneous") {
    // The field's own keys; the object's η and scale, and the representative medium as
    // Scene::medium (what techniques without heterogeneous support render).
    material::ParseContext c;
    c.reader = r;
    c.resolve = [&](const std::string& name, const std::string& key) {
      return resolveFile(r, s, name, base_dir, key);
    };
    c.eta = r.number(mat, "eta", "material", 1.3);
    c.model = s.model;
    s.material = material::parseMaterialDesc(c, mat, "material");
    const material::LocalMedium rep = s.material.representative();
    s.medium = rep.medium(c.eta, s.medium.scale);
  }
  try {
    s.medium.validate();
  } catch (const ParameterError& e) {
    r.fail("material", e.what());
  }

  // Lights.
  if (!doc.contains("lights")) r.fail("lights", "required (an array of lights)");
  const json& lights = doc["lights"];
  if (!lights.is_array() || lights.empty()) r.fail("lights", fmt::format("{}: expected a non-empty array", Reader::describe(lights)));
  // Each light may cost a technique a shadow map or light-view map of megabytes: 1,000 lights
  // made render allocate without bound (6 GB in 5 s).
  if (lights.size() > kMaxLights)
    r.fail("lights", fmt::format("holds {} lights: expected at most {}", lights.size(), kMaxLights));
  for (size_t i = 0; i < lights.size(); ++i)
    s.lights.push_back(parseLight(r, s, lights[i], fmt::format("lights[{}]", i), base_dir));

  // Camera.
  if (!doc.contains("camera")) r.fail("camera", "required");
  const json& cam = doc["camera"];
  r.onlyKeys(cam, "camera", {"type", "position", "look_at", "up", "fov", "view_height", "width",
                             "height", "near", "far"});
  const std::string type = cam.contains("type") ? r.string(cam, "type", "camera") : "pinhole";
  if (type == "pinhole")
    s.camera.projection = Camera::Projection::Pinhole;
  else if (type == "orthographic")
    s.camera.projection = Camera::Projection::Orthographic;
  else
    r.fail("camera.type", fmt::format("'{}': expected pinhole or orthographic", type));
  s.camera.position = r.requiredVec3(cam, "position", "camera");
  s.camera.look_at = r.vec3(cam, "look_at", "camera", glm::dvec3(0.0));
  s.camera.up = r.vec3(cam, "up", "camera", glm::dvec3(0.0, 1.0, 0.0));
  s.camera.fov = r.number(cam, "fov", "camera", s.camera.fov);
  s.camera.view_height = r.number(cam, "view_height", "camera", s.camera.view_height);
  // The limits of Camera::validate, checked here so that the message names the key.
  s.camera.width = r.integer(cam, "width", "camera", s.camera.width, 1, 16384);
  s.camera.height = r.integer(cam, "height", "camera", s.camera.height, 1, 16384);
  s.clip_near = r.number(cam, "near", "camera", 0.0);
  s.clip_far = r.number(cam, "far", "camera", 0.0);
  if (s.clip_near < 0.0 || s.clip_far < 0.0 || (s.clip_far > 0.0 && s.clip_far <= s.clip_near))
    r.fail("camera", fmt::format("near {} and far {}: expected 0 (automatic) or 0 < near < far",
                                 s.clip_near, s.clip_far));
  try {
    s.camera.validate();
  } catch (const ParameterError& e) {
    throw ParameterError(fmt::format("{}: {}", what, e.what()));
  }

  // Technique and its settings (checked by the technique itself).
  if (doc.contains("technique")) {
    const json& t = doc["technique"];
    if (!t.is_object()) r.fail("technique", "expected an object {\"name\": ..., settings...}");
    if (t.contains("name")) s.technique = r.string(t, "name", "technique");
    for (const auto& [k, v] : t.items()) {
      if (k == "name") continue;
      const std::string key = "technique." + k;
      if (v.is_boolean())
        s.settings[k] = v.get<bool>();
      else if (v.is_number())
        s.settings[k] = r.number(v, key);
      else if (v.is_string())
        s.settings[k] = v.get<std::string>();
      else
        r.fail(key, "expected a number, true/false or a string");
    }
  }

  // Display.
  if (doc.contains("display")) {
    const json& d = doc["display"];
    r.onlyKeys(d, "display", {"exposure", "gamma", "tonemap", "key"});
    s.exposure = r.number(d, "exposure", "display", 0.0);
    s.gamma = r.number(d, "gamma", "display", 2.2);
    if (d.contains("tonemap")) {
      const std::string op = r.string(d, "tonemap", "display");
      if (op != "clamp" && op != "reinhard")
        r.fail("display.tonemap", fmt::format("'{}': expected clamp or reinhard", op));
      s.tonemap = analysis::parseToneOperator(op, "display.tonemap");
    }
    s.tonemap_key = r.number(d, "key", "display", 1.0);
    if (!(s.tonemap_key > 0.0 && s.tonemap_key <= 100.0))
      r.fail("display.key", fmt::format("is {}: expected a tone map key in (0, 100]", s.tonemap_key));
    requirePositive(r, s.gamma, "display.gamma");
    // Legal numbers that map every pixel to black or white (x^(1/1e-300), 2^1000 x).
    if (!(s.gamma >= 0.01 && s.gamma <= 100.0))
      r.fail("display.gamma", fmt::format("is {}: expected a display gamma in [0.01, 100]", s.gamma));
    if (!(std::fabs(s.exposure) <= 64.0))
      r.fail("display.exposure", fmt::format("is {}: expected stops in [-64, 64]", s.exposure));
  }

  s.cone_angle = doc.contains("cone_angle") ? r.number(doc["cone_angle"], "cone_angle") : 5.0;
  if (!(s.cone_angle > 0.0 && s.cone_angle <= 90.0))
    r.fail("cone_angle", fmt::format("is {}: expected degrees in (0, 90]", s.cone_angle));
  return s;
}

std::vector<std::pair<std::string, std::filesystem::path>> inputFiles(const Scene& s) {
  std::vector<std::pair<std::string, std::filesystem::path>> files;
  files.emplace_back("the scene's mesh", s.mesh_file);
  files.emplace_back("the scene's BSSRDF model", s.model);
  for (const Light& l : s.lights) {
    if (const auto* f = std::get_if<FilteredDirectionalLight>(&l.emitter))
      files.emplace_back("a light's filter texture", f->texture);
    if (const auto* e = std::get_if<EnvironmentLight>(&l.emitter))
      files.emplace_back("the environment map", e->file);
  }
  if (!s.material.homogeneous()) {
    json ignored;
    material::writeMaterialDesc(s.material, ignored, [&](const std::filesystem::path& p) {
      files.emplace_back("a file of the scene's material", p);
      return p.string();
    });
  }
  return files;
}

Scene loadScene(const std::filesystem::path& path) {
  // A directory opens as a stream on Linux and reads as nothing, which JSON reports as a parse
  // error at byte 1: say what is wrong instead.
  if (const std::string why = io::irregularInput(path); !why.empty())
    throw ParameterError(fmt::format("scene file '{}' {}: expected a file", path.string(), why));
  std::ifstream f(path, std::ios::binary);
  if (!f)
    throw ParameterError(fmt::format("scene file '{}' cannot be opened: {}", path.string(),
                                     std::strerror(errno)));
  std::stringstream text;
  text << f.rdbuf();
  if (f.bad())
    throw ParameterError(fmt::format("scene file '{}' cannot be read", path.string()));
  const std::string content = text.str();
  if (content.find_first_not_of(" \t\r\n") == std::string::npos)
    throw ParameterError(fmt::format("scene file '{}' is empty: expected a JSON object",
                                     path.string()));
  // NUL bytes: not a text file (a binary picked by mistake); the JSON error would print them.
  if (const size_t nul = content.find('\0'); nul != std::string::npos)
    throw ParameterError(fmt::format("scene file '{}': byte {} is NUL: expected a JSON text file",
                                     path.string(), nul));
  return parseScene(content, path.parent_path(), fmt::format("scene file '{}'", path.string()));
}

std::string toJson(const Scene& s) {
  json doc;
  doc["mesh"] = {{"file", writtenPath(s, s.mesh_file)}, {"fill_holes", s.mesh_fill_holes},
                 {"normalize", s.mesh_normalize},
                 {"rotate", vec(s.mesh_rotate)}, {"scale", s.mesh_scale},
                 {"translate", vec(s.mesh_translate)}};
  if (s.mesh_wrap) doc["mesh"]["wrap"] = {{"alpha", s.mesh_wrap->alpha}, {"offset", s.mesh_wrap->offset}};
  if (!s.mesh_deform.empty()) {
    json d = json::array();
    for (const geometry::Deformation& x : s.mesh_deform) d.push_back(deformationJson(x));
    doc["mesh"]["deform"] = d;
  }
  if (s.time != 0.0) doc["time"] = s.time;
  json mat;
  if (!s.material.homogeneous()) {
    material::writeMaterialDesc(s.material, mat,
                                [&](const std::filesystem::path& p) { return writtenPath(s, p); });
  } else if (!s.preset.empty()) {
    mat["preset"] = s.preset;
  } else {
    mat["sigma_a"] = rgbJson(s.medium.sigma_a);
    mat["sigma_s"] = rgbJson(s.medium.sigma_s);
  }
  if (s.material.homogeneous()) mat["g"] = s.medium.g;
  mat["eta"] = s.medium.eta;
  mat["scale"] = s.medium.scale;
  mat["model"] = s.model;
  doc["material"] = mat;
  json lights = json::array();
  for (const Light& l : s.lights) lights.push_back(lightJson(s, l));
  doc["lights"] = lights;
  const Camera& c = s.camera;
  doc["camera"] = {{"type", c.projection == Camera::Projection::Pinhole ? "pinhole" : "orthographic"},
                   {"position", vec(c.position)}, {"look_at", vec(c.look_at)}, {"up", vec(c.up)},
                   {"fov", c.fov}, {"view_height", c.view_height}, {"width", c.width},
                   {"height", c.height}, {"near", s.clip_near}, {"far", s.clip_far}};
  json t = {{"name", s.technique}};
  for (const auto& [k, v] : s.settings)
    std::visit([&, key = k](const auto& x) { t[key] = x; }, v);
  doc["technique"] = t;
  doc["display"] = {{"exposure", s.exposure}, {"gamma", s.gamma},
                    {"tonemap", analysis::toString(s.tonemap)}, {"key", s.tonemap_key}};
  doc["cone_angle"] = s.cone_angle;
  return doc.dump(2);
}

void saveScene(const Scene& scene, const std::filesystem::path& path) {
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  f << toJson(scene) << '\n';
  if (!f) throw ParameterError(fmt::format("scene file '{}' cannot be written", path.string()));
}

namespace {

// The placement of a mesh or point cloud whose bounding box is `b`: normalise (the explorer
// paper's one basic unit along the longest axis, §3.6.1), then rotate, scale, move.
struct Placement {
  glm::dvec3 centre{0.0};
  double unit = 1.0;
  glm::dmat3 rot{1.0};
  double scale = 1.0;
  glm::dvec3 translate{0.0};
  glm::dvec3 point(const glm::dvec3& p) const { return scale * (rot * ((p - centre) * unit)) + translate; }
  double length() const { return scale * unit; }  // how lengths scale
};

Placement placementFor(const Scene& scene, const geometry::Bounds& b) {
  Placement pl;
  if (scene.mesh_normalize) {
    const glm::dvec3 extent = b.upper - b.lower;
    const double longest = std::max({extent.x, extent.y, extent.z});
    if (!(longest > 0.0) || !std::isfinite(longest))
      throw geometry::MeshError(fmt::format("mesh '{}': its bounding box has no extent: expected "
                                            "a mesh with area", scene.mesh_file.string()));
    pl.centre = b.center();
    pl.unit = 1.0 / longest;
  }
  pl.rot = rotation(scene.mesh_rotate);
  pl.scale = scene.mesh_scale;
  pl.translate = scene.mesh_translate;
  return pl;
}

void apply(const Placement& pl, geometry::TriangleMesh& mesh) {
  for (glm::dvec3& p : mesh.positions) p = pl.point(p);
  for (glm::dvec3& n : mesh.normals) n = pl.rot * n;
}

geometry::Bounds pointBounds(const geometry::PointCloud& cloud) {
  geometry::Bounds b{glm::dvec3(std::numeric_limits<double>::infinity()),
                     glm::dvec3(-std::numeric_limits<double>::infinity())};
  for (const glm::vec3& p : cloud.positions) {
    b.lower = glm::min(b.lower, glm::dvec3(p));
    b.upper = glm::max(b.upper, glm::dvec3(p));
  }
  return b;
}

}  // namespace

void placeMesh(const Scene& scene, geometry::TriangleMesh& mesh) {
  apply(placementFor(scene, mesh.bounds()), mesh);
}

geometry::TriangleMesh loadSceneMesh(const Scene& scene, geometry::HoleFillStats* fill,
                                     geometry::AlphaWrapStats* wrap,
                                     std::optional<ScenePoints>* points) {
  geometry::TriangleMesh mesh = loadRestMesh(scene, fill, wrap, points);
  if (!geometry::isIdentity(scene.mesh_deform, scene.time)) {
    geometry::deformMesh(scene.mesh_deform, scene.time, mesh);
    mesh.validate(fmt::format("{} (deformed by mesh.deform at time {})", scene.mesh_file.string(),
                              scene.time));
    // The points stay in the rest pose: a technique that deforms moves them with their triangles.
  }
  return mesh;
}

geometry::TriangleMesh loadRestMesh(const Scene& scene, geometry::HoleFillStats* fill,
                                    geometry::AlphaWrapStats* wrap,
                                    std::optional<ScenePoints>* points) {
  if (points) points->reset();
  geometry::TriangleMesh mesh;
  std::optional<ScenePoints> cloud;
  std::vector<uint32_t> vertexOfPoint;
  if (geometry::isPointCloudPly(scene.mesh_file)) {
    // A point cloud: the surface through its points, for everything that needs triangles.
    cloud.emplace();
    try {
      cloud->cloud = geometry::readPointCloudPly(scene.mesh_file);
    } catch (const geometry::PointCloudError& e) {
      throw geometry::MeshError(e.what());
    }
    mesh = geometry::reconstructSurface(
        cloud->cloud,
        fmt::format("point cloud '{}' (mesh.file; its surface is reconstructed)",
                    scene.mesh_file.string()),
        &cloud->reconstruction, &vertexOfPoint);
  } else {
    mesh = geometry::loadMesh(scene.mesh_file.string());
  }
  if (scene.mesh_wrap) {
    const std::string what = fmt::format("mesh file '{}' (mesh.wrap)", scene.mesh_file.string());
    mesh = geometry::loadOrAlphaWrap(mesh, *scene.mesh_wrap, what,
                                     geometry::defaultCacheDirectory() / "wraps", wrap);
  }
  if (scene.mesh_fill_holes) {
    const std::string what = fmt::format("mesh file '{}' (mesh.fill_holes)", scene.mesh_file.string());
    const geometry::HoleFillStats st = geometry::fillHoles(mesh, what);
    if (st.unfilled > 0)
      throw geometry::MeshError(fmt::format("{}: {} of {} holes could not be triangulated: "
                                            "expected a mesh whose holes CGAL can fill", what,
                                            st.unfilled, st.holes));
    if (fill) *fill = st;
  }
  // A point cloud is placed by its points' bounding box, so that the mesh and the points move
  // together whatever the reconstruction, a wrap or a fill did to the bounds.
  const Placement pl = placementFor(scene, cloud ? pointBounds(cloud->cloud) : mesh.bounds());
  apply(pl, mesh);
  mesh.validate(scene.mesh_file.string());
  if (cloud && points) {
    geometry::PointCloud& c = cloud->cloud;
    const double areaScale = pl.length() * pl.length();
    for (size_t i = 0; i < c.size(); ++i) {
      c.positions[i] = glm::vec3(pl.point(glm::dvec3(c.positions[i])));
      c.normals[i] = glm::vec3(glm::normalize(pl.rot * glm::dvec3(c.normals[i])));
      c.areas[i] = static_cast<float>(static_cast<double>(c.areas[i]) * areaScale);
    }
    // Each point's triangle: one that has the point as a vertex (the reconstruction's triangles
    // survive unless a wrap or a fill changed them).
    c.faces.clear();
    const bool sameTriangles = !scene.mesh_wrap && !scene.mesh_fill_holes;
    if (sameTriangles && cloud->reconstruction.unused_points == 0) {
      std::vector<uint32_t> triangleOfVertex(mesh.vertexCount(), 0);
      for (size_t t = 0; t < mesh.triangles.size(); ++t)
        for (int k = 0; k < 3; ++k) triangleOfVertex[mesh.triangles[t][k]] = static_cast<uint32_t>(t);
      c.faces.resize(c.size());
      for (size_t i = 0; i < c.size(); ++i) c.faces[i] = triangleOfVertex[vertexOfPoint[i]];
    }
    c.irradiance.clear();
    *points = std::move(cloud);
  }
  return mesh;
}

std::string describeHoleFill(const geometry::HoleFillStats& f) {
  if (f.holes == 0) return "no holes (the mesh is closed)";
  return fmt::format("{} hole{} filled ({} faired, {} refined without fairing{}), {} triangles "
                     "and {} vertices added, {:.3g}% of the area",
                     f.filled(), f.filled() == 1 ? "" : "s", f.faired, f.refined_unfaired,
                     f.unfilled ? fmt::format(", {} unfilled", f.unfilled) : std::string(),
                     f.triangles_added, f.vertices_added,
                     f.area_before > 0.0 ? 100.0 * f.area_added / f.area_before : 0.0);
}

std::string describeAlphaWrap(const geometry::AlphaWrapOptions& o, const geometry::AlphaWrapStats& w) {
  return fmt::format("alpha wrap (alpha {:.3g}, offset {:.3g} of the file's bounding-box diagonal "
                     "{:.4g}): {} -> {} triangles, area x{:.3f}, {}{}{}",
                     o.alpha, o.offset, w.diagonal, w.triangles_in, w.triangles_out,
                     w.area_in > 0.0 ? w.area_out / w.area_in : 0.0,
                     w.from_cache ? "read from " : (w.cache_file.empty() ? "not cached" : "cached in "),
                     w.cache_file.string(), w.note.empty() ? "" : " (" + w.note + ")");
}

std::vector<reference::Light> referenceLights(const Scene& scene) {
  std::vector<reference::Light> out;
  for (size_t i = 0; i < scene.lights.size(); ++i) {
    const Light& l = scene.lights[i];
    reference::Light r;
    r.color = l.color;
    if (const auto* d = std::get_if<DirectionalLight>(&l.emitter))
      r.emitter = *d;
    else if (const auto* p = std::get_if<PointLight>(&l.emitter))
      r.emitter = *p;
    else if (const auto* b = std::get_if<BeamLight>(&l.emitter))
      r.emitter = *b;
    else if (const auto* e = std::get_if<EnvironmentLight>(&l.emitter)) {
      // The references trace every occlusion physically: `occlusion` is the techniques' choice.
      auto map = std::make_shared<const lights::EnvironmentMap>(lights::EnvironmentMap::load(e->file));
      try {
        r.emitter = reference::EnvironmentLight::make(std::move(map), e->rotate, e->intensity);
      } catch (const ParameterError& err) {
        throw ParameterError(fmt::format("lights[{}]: '{}': {}", i, e->file.string(), err.what()));
      }
    } else
      throw ParameterError(fmt::format(
          "lights[{}]: filtered_directional lights are not supported by the references: expected "
          "directional, point, beam or environment", i));
    out.push_back(r);
  }
  return out;
}

Scene defaultScene() {
  Scene s;
  s.mesh_file = kDefaultBunny;
  s.mesh_normalize = true;
  s.preset = "Marble";
  s.medium = Medium::fromReduced(preset("Marble").sigma_a, preset("Marble").sigma_s_prime,
                                 preset("Marble").g, preset("Marble").eta);
  // One scene unit (the bunny's length) = 25 mm: ℓd is 8.5 mm (red) to 4 mm (blue), a third to
  // a sixth of the bunny, so the thin parts (ears, back) glow.
  s.medium.scale = 25.0;
  s.model = "dipole";
  // Key light from behind (away from the camera) and above, warm; a dim cool fill from the front
  // so that the side facing the camera is not black.
  Light key;
  key.emitter = reference::DirectionalLight{glm::normalize(glm::dvec3(-0.3, 0.9, -0.6)), 5.0};
  key.color = {1.0, 0.85, 0.7};
  Light fill;
  fill.emitter = reference::DirectionalLight{glm::normalize(glm::dvec3(0.6, 0.2, 1.0)), 0.12};
  fill.color = {0.7, 0.8, 1.0};
  s.lights = {key, fill};
  s.camera.projection = Camera::Projection::Pinhole;
  s.camera.position = {0.15, 0.2, 2.1};
  s.camera.look_at = {0.0, 0.0, 0.0};
  s.camera.up = {0.0, 1.0, 0.0};
  s.camera.fov = 35.0;
  s.camera.width = 640;
  s.camera.height = 480;
  s.technique = "pointcloud";
  return s;
}

void requireOutsideMesh(const Scene& scene, const geometry::TriangleMesh& placed_mesh) {
  struct Point {
    std::string key;
    glm::dvec3 p;
  };
  std::vector<Point> points{{"camera.position", scene.camera.position}};
  for (size_t i = 0; i < scene.lights.size(); ++i) {
    const auto& e = scene.lights[i].emitter;
    if (const auto* pl = std::get_if<reference::PointLight>(&e))
      points.push_back({fmt::format("lights[{}].position", i), pl->position});
    else if (const auto* bl = std::get_if<reference::BeamLight>(&e))
      points.push_back({fmt::format("lights[{}].origin", i), bl->origin});
  }
  const geometry::Bounds b = placed_mesh.bounds();
  auto inBox = [&](const glm::dvec3& p) {
    return glm::all(glm::greaterThanEqual(p, b.lower)) && glm::all(glm::lessThanEqual(p, b.upper));
  };
  std::unique_ptr<geometry::RayScene> rays;
  bool checkedClosed = false;
  for (const Point& pt : points) {
    if (!inBox(pt.p)) continue;
    if (!checkedClosed) {
      // An open mesh has no inside (the parity says nothing): the references refuse it anyway.
      if (placed_mesh.openEdgeCount() != 0) return;
      checkedClosed = true;
    }
    if (!rays) rays = std::make_unique<geometry::RayScene>(placed_mesh, scene.mesh_file.string());
    if (geometry::insideClosedMesh(*rays, pt.p))
      throw ParameterError(fmt::format(
          "{} [{}, {}, {}] is inside the mesh '{}' (placed, its bounds [{}, {}, {}] .. [{}, {}, {}]): "
          "expected a point outside the object", pt.key, pt.p.x, pt.p.y, pt.p.z,
          scene.mesh_file.string(), b.lower.x, b.lower.y, b.lower.z, b.upper.x, b.upper.y, b.upper.z));
  }
}

material::Material restMaterial(const Scene& scene, const geometry::TriangleMesh& rest_mesh) {
  Scene rest = scene;
  rest.mesh_deform.clear();
  return sceneMaterial(rest, rest_mesh);
}

material::Material sceneMaterial(const Scene& scene, const geometry::TriangleMesh& placed_mesh) {
  material::BuildContext b;
  b.placed_mesh = &placed_mesh;
  b.frame.rotation = rotation(scene.mesh_rotate);
  b.frame.translate = scene.mesh_translate;
  b.frame.scale = scene.medium.scale;
  // Materials live in the rest pose: the frame maps the deformed surface back to it.
  b.frame.deform = scene.mesh_deform;
  b.frame.time = scene.time;
  if (scene.material.homogeneous()) {  // the mesh is not needed
    material::Material m;
    m.medium = scene.medium;
    m.model = scene.model;
    m.frame = b.frame;
    return m;
  }
  return material::buildMaterial(scene.material, scene.medium, scene.model, b);
}

std::string meshKey(const Scene& s) {
  // The deformation at this time: a periodic chain at 0 and at a whole period is the same mesh,
  // but the key need not know that (a cache miss, never a wrong hit).
  if (geometry::isIdentity(s.mesh_deform, s.time)) return restMeshKey(s);
  return fmt::format("{}|deform {}|t{}", restMeshKey(s), geometry::deformKey(s.mesh_deform), s.time);
}

std::string mediumKey(const Scene& s) {
  return fmt::format("{}|{}|{}|{}|{}|{}", s.model, s.medium.sigma_a, s.medium.sigma_s, s.medium.g,
                     s.medium.eta, s.medium.scale);
}

std::string restMeshKey(const Scene& s) {
  const std::string wrap =
      s.mesh_wrap ? fmt::format("wrap{},{}", s.mesh_wrap->alpha, s.mesh_wrap->offset) : "";
  return fmt::format("{}|fill{}|{}|{}|{},{},{}|{}|{},{},{}", s.mesh_file.string(), s.mesh_fill_holes,
                     wrap, s.mesh_normalize,
                     s.mesh_rotate.x, s.mesh_rotate.y, s.mesh_rotate.z, s.mesh_scale,
                     s.mesh_translate.x, s.mesh_translate.y, s.mesh_translate.z);
}

}  // namespace translucent::scene
