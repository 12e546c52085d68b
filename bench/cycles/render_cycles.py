# Renders a scene exported by bench_cycles_export with Blender's Cycles (CPU, no denoising,
# no adaptive sampling, Standard view transform) to a linear float EXR, and prints the render
# time.  Bench only (never in the build or tests):
#   blender -b --factory-startup -P bench/cycles/render_cycles.py -- SCENE.json OUT.exr SPP THREADS [SEED]
import json
import math
import sys
import time

import bpy
from mathutils import Vector


def P(v):
    """foldcast's y-up world to Blender's z-up one (a quarter turn about x)."""
    return Vector((v[0], -v[2], v[1]))


args = sys.argv[sys.argv.index("--") + 1:]
scene_file, out_exr, spp, threads = args[:4]
seed = int(args[4]) if len(args) > 4 else 1
spec = json.load(open(scene_file))

bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene


def principled(name, p):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    b = mat.node_tree.nodes["Principled BSDF"]
    b.inputs["Base Color"].default_value = (*p["diffuse"], 1.0)
    b.inputs["Roughness"].default_value = p["roughness"]
    if p["f0"] > 0.3:  # the rod: a metal
        b.inputs["Metallic"].default_value = 1.0
        b.inputs["Base Color"].default_value = (p["f0"], p["f0"], p["f0"], 1.0)
    else:
        b.inputs["Specular"].default_value = min(1.0, p["f0"] / 0.08)
    b.inputs["Anisotropic"].default_value = p["anisotropy"]
    sheen = max(p["sheen"])
    if sheen > 0.0:
        b.inputs["Sheen"].default_value = sheen
        b.inputs["Sheen Tint"].default_value = 0.0
    return mat


materials = {name: principled(name, p) for name, p in spec["materials"].items()}
for i, m in enumerate(spec["meshes"]):
    me = bpy.data.meshes.new(f"mesh{i}")
    me.from_pydata([tuple(P(p)) for p in m["positions"]], [], [tuple(t) for t in m["triangles"]])
    me.polygons.foreach_set("use_smooth", [True] * len(me.polygons))
    me.use_auto_smooth = True  # needed for custom normals
    me.normals_split_custom_set_from_vertices([tuple(P(n)) for n in m["normals"]])
    me.materials.append(materials[m["material"]])
    obj = bpy.data.objects.new(f"obj{i}", me)
    scene.collection.objects.link(obj)

for i, l in enumerate(spec["lights"]):
    light = bpy.data.lights.new(f"light{i}", type="AREA")
    light.shape = "RECTANGLE"
    light.size, light.size_y = l["width_m"], l["height_m"]
    peak = max(l["radiance"])
    light.color = tuple(c / peak for c in l["radiance"])
    # Cycles: radiance = power / (pi * area) for a one-sided area light.
    light.energy = peak * math.pi * l["width_m"] * l["height_m"]
    obj = bpy.data.objects.new(f"light{i}", light)
    obj.location = P(l["position"])
    direction = P(l["target"]) - P(l["position"])
    obj.rotation_euler = direction.to_track_quat("-Z", "Y").to_euler()
    scene.collection.objects.link(obj)

world = bpy.data.worlds.new("world")
world.use_nodes = True
world.node_tree.nodes["Background"].inputs["Color"].default_value = (*spec["environment"], 1.0)
scene.world = world

cam = spec["camera"]
cam_data = bpy.data.cameras.new("camera")
cam_data.sensor_fit = "VERTICAL"
cam_data.angle_y = math.radians(cam["fov_deg"])
cam_obj = bpy.data.objects.new("camera", cam_data)
cam_obj.location = P(cam["position"])
cam_obj.rotation_euler = (P(cam["target"]) - P(cam["position"])).to_track_quat("-Z", "Y").to_euler()
scene.collection.objects.link(cam_obj)
scene.camera = cam_obj

scene.render.engine = "CYCLES"
scene.cycles.device = "CPU"
scene.cycles.samples = int(spp)
scene.cycles.use_adaptive_sampling = False
scene.cycles.use_denoising = False
bounces = int(spec["max_depth"]) - 1  # foldcast counts path vertices after the camera
scene.cycles.max_bounces = bounces
scene.cycles.diffuse_bounces = bounces
scene.cycles.glossy_bounces = bounces
scene.cycles.sample_clamp_indirect = 20.0  # foldcast clamps from the second bounce at 20
scene.cycles.seed = seed
scene.render.threads_mode = "FIXED"
scene.render.threads = int(threads)
scene.render.resolution_x, scene.render.resolution_y = spec["width"], spec["height"]
scene.render.resolution_percentage = 100
scene.render.film_transparent = False
scene.view_settings.view_transform = "Standard"
scene.view_settings.look = "None"
scene.render.image_settings.file_format = "OPEN_EXR"
scene.render.image_settings.color_depth = "32"
scene.render.filepath = out_exr

start, cpu_start = time.perf_counter(), time.process_time()  # process_time: every thread's CPU
bpy.ops.render.render(write_still=True)
print(f"CYCLES_SECONDS {time.perf_counter() - start:.3f}")
print(f"CYCLES_CPU_SECONDS {time.process_time() - cpu_start:.3f}")
