# SPDX-License-Identifier: GPL-3.0-or-later
"""Runs inside Blender (blender -b -t 1 --python cycles_scene.py -- JSON): builds the benchmark
scene of bench-cycles in Cycles and renders it to an EXR.

The scene is a Translucent scene file's content, given as JSON after "--" together with the
settings: {"scene": {...}, "mesh": PATH, "samples": N, "seed": S, "out": EXR}. What it supports is
what the benchmark needs: a normalised OBJ mesh, a homogeneous index-matched medium (eta 1: no
surface shader, so the boundary neither reflects nor refracts), directional lights, a pinhole
camera. Coordinates are the scene's (y up), imported without axis conversion.

Cycles' volume closures: Volume Scatter of colour (1, 1, 1) and density D has sigma_s = D; Volume
Absorption of colour c and density D has sigma_a = D (1 - c) per channel. bench-cycles checks
the image means against Translucent's camera method, which would catch a wrong mapping.
"""
import json
import math
import sys

import bpy
import mathutils

args = json.loads(sys.argv[sys.argv.index("--") + 1])
scene_json = args["scene"]
bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene

# Mesh: no axis conversion (the scene's coordinates), normalised as Translucent does
# (centred on the bounding box, longest side 1).
bpy.ops.wm.obj_import(filepath=args["mesh"], forward_axis="Y", up_axis="Z")
obj = bpy.context.selected_objects[0]
vs = [v.co for v in obj.data.vertices]
lo = mathutils.Vector((min(v.x for v in vs), min(v.y for v in vs), min(v.z for v in vs)))
hi = mathutils.Vector((max(v.x for v in vs), max(v.y for v in vs), max(v.z for v in vs)))
centre = (lo + hi) / 2
longest = max(hi - lo)
for v in obj.data.vertices:
    v.co = (v.co - centre) / longest
obj.data.update()

# Medium: absorption + scattering, no surface shader (index matched).
m = scene_json["material"]
sa, ss, g = m["sigma_a"], m["sigma_s"], m.get("g", 0.0)
mat = bpy.data.materials.new("medium")
mat.use_nodes = True
nodes, links = mat.node_tree.nodes, mat.node_tree.links
nodes.clear()
out = nodes.new("ShaderNodeOutputMaterial")
density_a = max(sa)
absorb = nodes.new("ShaderNodeVolumeAbsorption")
absorb.inputs["Color"].default_value = [1.0 - s / density_a for s in sa] + [1.0]
absorb.inputs["Density"].default_value = density_a
if len(set(ss)) != 1:
    raise SystemExit("cycles_scene: sigma_s must be the same in every channel")
scatter = nodes.new("ShaderNodeVolumeScatter")
scatter.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
scatter.inputs["Density"].default_value = ss[0]
scatter.inputs["Anisotropy"].default_value = g
add = nodes.new("ShaderNodeAddShader")
links.new(absorb.outputs[0], add.inputs[0])
links.new(scatter.outputs[0], add.inputs[1])
links.new(add.outputs[0], out.inputs["Volume"])
mat.cycles.homogeneous_volume = True
obj.data.materials.append(mat)

# Lights: suns (Cycles' strength is the irradiance on a plane facing the sun, W/m²).
for i, light in enumerate(scene_json["lights"]):
    if light["type"] != "directional":
        raise SystemExit("cycles_scene: directional lights only")
    data = bpy.data.lights.new(f"sun{i}", "SUN")
    data.energy = light.get("irradiance", 1.0)
    data.color = light.get("color", [1.0, 1.0, 1.0])
    data.angle = 0.0
    sun = bpy.data.objects.new(f"sun{i}", data)
    # A sun shines along its local -z: local +z towards the light.
    sun.rotation_euler = mathutils.Vector(light["direction"]).normalized().to_track_quat("Z", "Y").to_euler()
    scene.collection.objects.link(sun)

# Camera: pinhole, vertical field of view.
c = scene_json["camera"]
cam_data = bpy.data.cameras.new("camera")
cam_data.sensor_fit = "VERTICAL"
cam_data.angle = math.radians(c["fov"])
cam = bpy.data.objects.new("camera", cam_data)
p = mathutils.Vector(c["position"])
f = (mathutils.Vector(c["look_at"]) - p).normalized()
r = f.cross(mathutils.Vector(c["up"])).normalized()
u = r.cross(f)
cam.matrix_world = mathutils.Matrix((
    (r.x, u.x, -f.x, p.x), (r.y, u.y, -f.y, p.y), (r.z, u.z, -f.z, p.z), (0, 0, 0, 1)))
scene.collection.objects.link(cam)
scene.camera = cam

world = bpy.data.worlds.new("black")
world.use_nodes = False
world.color = (0.0, 0.0, 0.0)
scene.world = world

# Cycles: unbiased settings (no clamping, denoising, adaptive sampling or bounce limit that the
# medium reaches), a box filter over the pixel (an image-plane average, as Translucent's).
scene.render.engine = "CYCLES"
cy = scene.cycles
cy.device = "CPU"
cy.samples = args["samples"]
cy.seed = args["seed"]
cy.use_adaptive_sampling = False
cy.use_denoising = False
cy.max_bounces = 1024
cy.volume_bounces = 1024
cy.transparent_max_bounces = 1024
cy.transmission_bounces = 1024
cy.sample_clamp_direct = 0.0
cy.sample_clamp_indirect = 0.0
cy.filter_type = "BOX"
cy.filter_width = 1.0
cy.use_auto_tile = False
scene.render.resolution_x = c["width"]
scene.render.resolution_y = c["height"]
scene.render.resolution_percentage = 100
scene.render.film_transparent = False
scene.view_settings.view_transform = "Standard"
scene.render.image_settings.file_format = "OPEN_EXR"
scene.render.image_settings.color_depth = "32"
scene.render.image_settings.color_mode = "RGB"
scene.render.filepath = args["out"]
bpy.ops.render.render(write_still=True)
