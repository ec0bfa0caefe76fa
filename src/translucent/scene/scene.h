// SPDX-License-Identifier: GPL-3.0-or-later
// Scene files: the one JSON format that every renderer reads (`translucent render`, the real-time
// techniques, and the reference path tracer `translucent pathtrace mesh --scene`). A scene names
// a mesh and its placement, the material (medium and BSSRDF model), the lights, the camera, the
// technique with its settings and the display settings. Parsing is strict (an unknown key is an
// error that lists the valid ones, so a misspelt key never silently falls back to a default),
// and toJson() writes a scene back such that parsing it again gives the same scene (round trip).
//
//   {
//     "mesh":     {"file": "bunny.obj",        // OBJ/PLY/OFF, relative to the scene file, else
//                                               //   on the data search path (scene/data_path.h)
//                  "fill_holes": false,         // close an open mesh (geometry/hole_filling.h)
//                  "wrap": false | true | {"alpha": 1/300, "offset": 1/3000},
//                                               // or replace a non-manifold scan by its
//                                               //   watertight alpha wrap (geometry/alpha_wrap.h)
//                  "normalize": true,           // centre on the bounding box, longest axis 1
//                  "rotate": [0, 0, 0],         // degrees about x, then y, then z
//                  "scale": 1.0,                // then p -> scale R p + translate
//                  "translate": [0, 0, 0],
//                  "deform": [{"type": "twist", "amount": 90, "period": 2}]},  // see below
//     "time":     0.0,                          // of the deformations (`render --time` sets it)
//     "material": {"preset": "Marble",         // Jensen et al. 2001 (1/mm), or
//                  "sigma_a": [r, g, b] | v,    //   coefficients [1/medium unit]
//                  "sigma_s": [r, g, b] | v,
//                  "g": 0.0, "eta": 1.3,        // (preset: its own unless given)
//                  "scale": 1.0,                // medium units per scene unit (seed 3.6.1)
//                  "model": "dipole"},          // registered model name, or a .bssrdf file
//                 or a spatially varying material (material/material_desc.h):
//                 {"type": "layers" | "veins" | "checker" | "gradient" | "voxels" | "map" |
//                          "rd_map" | "surface_checker", ...the type's keys...,
//                  "eta": 1.3, "scale": 1.0, "model": "dipole"},
//     "lights":   [{"type": "directional", "direction": [x, y, z],   // towards the light
//                   "irradiance": 1.0, "color": [1, 1, 1]},
//                  {"type": "point", "position": [x, y, z], "intensity": 1.0},
//                  {"type": "beam", "origin": [x, y, z], "direction": [x, y, z],
//                   "radius": 0.0, "power": 1.0},
//                  {"type": "filtered_directional", "direction": [x, y, z], "irradiance": 1.0,
//                   "texture": "stained.png" | "checker",   // file, or a built-in 8x8 checker
//                   "texture_size": 1.0},       // scene units one texture repeat spans
//                  {"type": "environment", "file": "sky.exr",  // latitude-longitude, EXR/HDR
//                   "intensity": 1.0, "rotate": 0.0,  // degrees about +y
//                   "occlusion": false}],       // true: shadow-mapped self-occlusion
//     "camera":   {"type": "pinhole" | "orthographic",
//                  "position": [x, y, z], "look_at": [x, y, z], "up": [0, 1, 0],
//                  "fov": 40,              // pinhole, vertical, degrees
//                  "view_height": 2.0,     // orthographic, scene units
//                  "width": 256, "height": 256,
//                  "near": 0, "far": 0},   // clip distances [scene units]; 0: from the mesh
//     "technique": {"name": "pointcloud", ...settings...},  // see `translucent render --help`
//     "display":  {"exposure": 0.0, "gamma": 2.2},          // stops; display gamma (PNG output)
//     "cone_angle": 5.0     // path tracer: half-angle [degrees] of the cone-averaged radiance
//   }
// Every light takes "color" (per-channel multiplier of its flux). Units: positions in scene units;
// light fluxes in W (irradiance W/unit², intensity W/sr, environment radiance W/(unit² sr)).
//
// Files ("mesh.file", a light's "texture" and "file", the material's image and .vdb files): a relative name is found beside the scene
// file, else in each folder of $TRANSLUCENT_DATA, else in ~/.cache/translucent/data
// (scene/data_path.h); a file that is nowhere is an error at parse time that lists every place
// tried. toJson writes a file found beside the scene (or by absolute name) as the resolved path,
// one found on the data search path by the name the scene gave ("cgal/head.off"), so that a
// written scene stays portable and reads back to the same file.
//
// "fill_holes": true closes the mesh at load time (loadSceneMesh): every hole is triangulated,
// refined and faired, before the placement. The references need a closed mesh; scanned heads
// (CGAL's cgal/head.off) are open at the neck. It is part of meshKey, so techniques and the
// reference cache see a filled mesh as another mesh.
//
// "deform": time-dependent procedural deformations (geometry/deform.h), one object or an array
// applied in order, after the placement: their origin and axes are in scene coordinates, where the
// normalised mesh is centred on the origin with its longest side 1, and the placed, undeformed
// mesh is the rest pose in which the material is defined (MaterialFrame maps a deformed point
// back to it, so 3D fields and atlas maps follow the surface). Keys:
//   {"type": "twist" | "bend" | "wave",
//    "amount": 0.0,          // twist, bend: degrees per scene unit along the axis; wave: scene units
//    "period": 0.0,          // > 0: the magnitude at time T is amount sin(2π T/period); 0: amount
//    "origin": [0, 0, 0],    // a point of the twist axis, the bend's neutral line, the wave's node
//    "axis": [0, 1, 0],      // twist: the axis; bend: the neutral line; wave: the displacement
//    "direction": [1, 0, 0], // bend: towards the centre of curvature; wave: along which it
//                            //   varies; perpendicular to axis (a twist takes no direction)
//    "wavelength": 1.0}      // wave only [scene units]
// amount 0 (or time 0 with a period) is the identity. The deformation and the time are part of
// meshKey; restMeshKey leaves them out (GPU techniques deform the rest mesh per frame).
//
// Colour: RGB throughout, linear, in the order red, green, blue.
#pragma once

#include <filesystem>
#include <optional>
#include <map>
#include <string>
#include <variant>
#include <utility>
#include <vector>

#include <glm/vec3.hpp>

#include "translucent/geometry/alpha_wrap.h"
#include "translucent/geometry/deform.h"
#include "translucent/geometry/hole_filling.h"
#include "translucent/geometry/mesh.h"
#include "translucent/geometry/point_cloud.h"
#include "translucent/geometry/surface_reconstruction.h"
#include "translucent/io/image_io.h"
#include "translucent/material/material.h"
#include "translucent/material/material_desc.h"
#include "translucent/optics/medium.h"
#include "translucent/reference/camera.h"
#include "translucent/reference/transport.h"

namespace translucent::scene {

// A directional light whose irradiance is multiplied by a texture projected along the light
// (seed 3.1.2, "akin to light falling through stained glass"). The texture's u axis is the
// component of +x (or +z when the light is along x) perpendicular to the light, v = direction ×
// u; one repeat spans `texture_size` scene units and the texture is centred on the origin.
struct FilteredDirectionalLight {
  glm::dvec3 direction{0.0, 0.0, 1.0};  // towards the light
  double irradiance = 1.0;              // before the texture [W/unit²]
  std::filesystem::path texture;        // image file (resolved), or "checker"
  double texture_size = 1.0;            // [scene units]
};

// Distant illumination from a latitude-longitude radiance map (+y up, the centre column looks
// along -z, as in most HDR panoramas), optionally rotated about +y.
struct EnvironmentLight {
  std::filesystem::path file;  // EXR/HDR (resolved)
  double intensity = 1.0;      // multiplier of the map's radiance
  double rotate = 0.0;         // degrees about +y
  bool occlusion = false;      // self-occlusion by shadow-mapped samples (seed 3.3.2)
};

// The least a light may emit in a channel it lights (its irradiance, intensity or power times
// that channel's colour; a channel of colour 0 emits nothing and is fine): a fainter light
// renders black in 32-bit images. parseScene refuses such a light, and a light of colour 0.
inline constexpr double kMinLightPower = 1e-30;
// The most lights a scene may hold (parseScene refuses more).
inline constexpr size_t kMaxLights = 64;

struct Light {
  std::variant<reference::DirectionalLight, reference::PointLight, reference::BeamLight,
               FilteredDirectionalLight, EnvironmentLight>
      emitter;
  Rgb color{1.0, 1.0, 1.0};  // per-channel multiplier of the emitted flux
};

// A technique setting as written in the scene (integers are numbers too).
using Setting = std::variant<bool, double, std::string>;

struct Scene {
  // Mesh and placement: normalise (optional), rotate, scale, translate.
  std::filesystem::path mesh_file;  // as resolved (absolute or relative to the working directory)
  bool mesh_fill_holes = false;     // geometry::fillHoles before the placement
  // geometry::loadOrAlphaWrap before the placement (exclusive with mesh_fill_holes).
  std::optional<geometry::AlphaWrapOptions> mesh_wrap;
  bool mesh_normalize = true;
  glm::dvec3 mesh_rotate{0.0};      // degrees
  double mesh_scale = 1.0;
  glm::dvec3 mesh_translate{0.0};
  // Deformations after the placement, in order (geometry/deform.h), at `time`.
  std::vector<geometry::Deformation> mesh_deform;
  double time = 0.0;

  // Material.
  std::string preset;  // material preset name, empty for explicit coefficients
  // Homogeneous: the medium. Heterogeneous: η, scale and the representative medium (the top
  // layer, the first of "media", or the mean of a map or coefficient grid), what techniques
  // without heterogeneous support render.
  Medium medium;
  std::string model = "dipole";  // registered model name or a .bssrdf file (resolved path)
  // The spatially varying part ("type" other than "homogeneous", material/material_desc.h);
  // HomogeneousDesc for today's form. sceneMaterial builds it against the placed mesh.
  material::MaterialDesc material;

  std::vector<Light> lights;
  reference::Camera camera;
  double clip_near = 0.0, clip_far = 0.0;  // 0: automatic (from the mesh's bounds)

  std::string technique = "pointcloud";
  std::map<std::string, Setting> settings;  // technique settings, validated by the technique

  double exposure = 0.0;  // stops
  double gamma = 2.2;
  analysis::ToneOperator tonemap = analysis::ToneOperator::Clamp;  // display.tonemap
  double tonemap_key = 1.0;                                          // display.key

  double cone_angle = 5.0;  // path tracer only

  // Files found on the data search path, by resolved path: the name the scene gave. toJson
  // writes that name for a path listed here (a path changed since parsing is not, and is
  // written as it is).
  std::map<std::filesystem::path, std::string> data_names;
};

// Reads and checks a scene file; throws ParameterError naming the file and the offending key.
// (The mesh itself is loaded with loadSceneMesh.)
Scene loadScene(const std::filesystem::path& path);
// The same from JSON text; relative paths are taken relative to `base_dir`. `what` names the
// source in messages.
Scene parseScene(const std::string& text, const std::filesystem::path& base_dir,
                 const std::string& what);
// The scene as JSON text (paths as stored). parseScene(toJson(s)) == s.
// The scene's display settings as a tone map (PNG output, the explorer's view).
inline analysis::ToneMap displayToneMap(const Scene& s) {
  return {s.exposure, s.gamma, s.tonemap, s.tonemap_key, 0.0};
}

std::string toJson(const Scene& scene);
// Every file the scene reads besides its own, with what it is (for messages): the mesh, the
// .bssrdf model, the lights' filter textures and environment maps, the material's maps and
// grids. Names that are not files ("checker", a registered model) are included as given; the
// writers' output check (io/output_guard.h) skips those that do not exist.
std::vector<std::pair<std::string, std::filesystem::path>> inputFiles(const Scene& scene);
// Writes toJson(scene) to `path` (ParameterError naming the file when it cannot).
void saveScene(const Scene& scene, const std::filesystem::path& path);

// Loads the scene's mesh (geometry::loadMesh: MeshError for missing, empty or malformed files),
// fills its holes when mesh_fill_holes (MeshError naming the file when one cannot be filled;
// `fill`, when given, receives what was done) and places it: normalised (centred on its bounding
// box, longest axis 1), rotated, scaled, translated, then deformed by mesh_deform at `time`
// (geometry::deformMesh: a deformed mesh always has vertex normals, the rest pose's smooth ones
// transformed by the deformation). Vertex normals follow the rotation. With mesh_wrap the file's
// triangles are replaced by their alpha wrap first (cached in geometry::defaultCacheDirectory();
// `wrap`, when given, receives the statistics and notes).
//
// A PLY point cloud as mesh.file (geometry::isPointCloudPly: x y z, nx ny nz and area or radius
// per point, no faces; what `translucent pointcloud` writes) is rendered from its points: the
// mesh is the surface reconstructed through them (geometry/surface_reconstruction.h), placed by
// the points' bounding box, and `points`, when given, receives the points placed the same way
// (ScenePoints), which the point-cloud technique uses as its samples instead of sampling the
// reconstructed surface. For a triangle mesh `points` is left empty.
struct ScenePoints {
  // Positions and normals placed like the mesh (normals rotated), areas scaled by the square of
  // the placement's scale; faces: per point the reconstructed mesh's triangle it is a vertex of
  // (empty where a point is not a vertex, or mesh.wrap or mesh.fill_holes changed the triangles).
  geometry::PointCloud cloud;
  geometry::ReconstructionStats reconstruction;
};
geometry::TriangleMesh loadSceneMesh(const Scene& scene, geometry::HoleFillStats* fill = nullptr,
                                     geometry::AlphaWrapStats* wrap = nullptr,
                                     std::optional<ScenePoints>* points = nullptr);
// The same without the deformation: the rest pose (what GPU deformation starts from).
geometry::TriangleMesh loadRestMesh(const Scene& scene, geometry::HoleFillStats* fill = nullptr,
                                    geometry::AlphaWrapStats* wrap = nullptr,
                                    std::optional<ScenePoints>* points = nullptr);
// One line on what fillHoles did ("3 holes filled (2 faired, 1 refined without fairing), 120
// triangles added, 0.12% of the area"), for logs and reports.
std::string describeHoleFill(const geometry::HoleFillStats& fill);
// One line on the alpha wrap ("alpha wrap (alpha 0.00333, offset 0.000333 of the 0.00123 m
// diagonal): 202520 -> 159702 triangles, area x1.02, from the cache ..."), for logs and reports.
std::string describeAlphaWrap(const geometry::AlphaWrapOptions& options,
                              const geometry::AlphaWrapStats& wrap);
// The placement alone, applied to a mesh in place.
void placeMesh(const Scene& scene, geometry::TriangleMesh& mesh);
// A text that changes exactly when loadSceneMesh's result would (file and placement): techniques
// keep their meshes, point clouds and AO while it stays the same.
std::string meshKey(const Scene& scene);
// The same without the deformation and time: changes exactly when loadRestMesh's result would.
std::string restMeshKey(const Scene& scene);
// The material's model and representative medium (model, σa, σs, g, η, scale) as text: with the
// mesh key and the material description, what techniques key their profiles and kernels by.
std::string mediumKey(const Scene& scene);

// The scene's material as renderers and tracers read it (material/material.h): its medium, model,
// the scene → material-space frame of the placement, and (for a heterogeneous material) its field
// or surface map, built against `placed_mesh` (loadSceneMesh's result: layers by depth below the
// surface need it). Throws ParameterError naming the file or key that cannot be used.
material::Material sceneMaterial(const Scene& scene, const geometry::TriangleMesh& placed_mesh);
// The same for a renderer that reads the material at rest-pose points (techniques that keep the
// rest mesh and deform it on the GPU per frame: their per-vertex media are rest-pose quantities):
// built against the rest mesh, its frame without the deformation. sceneMaterial's frame would
// undo the deformation at scene.time on points that are already at rest.
material::Material restMaterial(const Scene& scene, const geometry::TriangleMesh& rest_mesh);

// The camera and every point light and beam origin must lie outside the object (issue 15: inside
// it, a reference renders a black image and a technique a meaningless one). Throws
// ParameterError naming the key, the position and the mesh ("camera.position [0, 0, 0.1] is
// inside the mesh 'bunny.obj' ..."). Points outside the mesh's bounding box cost nothing; for
// the others a ray-parity test (geometry::insideClosedMesh) builds a BVH once. An open mesh has
// no inside: nothing is checked.
void requireOutsideMesh(const Scene& scene, const geometry::TriangleMesh& placed_mesh);

// The lights the references handle (directional, point, beam, environment: its map loaded);
// throws ParameterError naming the first light of another type or an unreadable map.
std::vector<reference::Light> referenceLights(const Scene& scene);

// The built-in scene used when none is given: the closed bunny of Debian's glmark2-data
// (/usr/share/glmark2/models/bunny.obj), Marble, lit from behind and above so that the thin parts
// (the ears) glow, with a camera framing it.
Scene defaultScene();
inline constexpr const char* kDefaultBunny = "/usr/share/glmark2/models/bunny.obj";

}  // namespace translucent::scene
