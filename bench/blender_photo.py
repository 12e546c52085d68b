# A photograph foldcast has never seen: Blender's cloth solver hangs a panel from two grippers
# (bench/blender_cloth_compare.py's build(): size, weight, bending stiffness from E and t,
# the top corners pinned and moved in by the inset) and Cycles renders it as a camera would
# see it in a workshop: a wall, a table, boxes beside the cloth, the grippers, a printed
# motif (a disc and block letters) unless PRINT is 0.  For checking `foldcast overlay --fit`
# on images that neither foldcast's renderer nor its drape made (docs/compare.md,
# "Blender photos"):
#
#   blender -b --factory-startup -P bench/blender_photo.py -- OUT_DIR NAME WIDTH_M HEIGHT_M \
#       INSET_M THICKNESS_MM YOUNG_MPA GSM POISSON R,G,B PRINT
#
# Writes OUT_DIR/NAME.png (1104 x 621, as the shared photos), OUT_DIR/NAME_mask.png (the
# cloth alone, white on black) and OUT_DIR/NAME.json (the grippers in pixels, the scale
# in px/m between them, the solver's centre-fibre sign changes).  Blender only: never part of
# the build or the tests.
import json
import math
import os
import sys

import bpy
from bpy_extras.object_utils import world_to_camera_view
from mathutils import Vector

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import blender_cloth_compare as cloth_bench  # noqa: E402

WIDTH_PX, HEIGHT_PX = 1104, 621
NU, NV = 31, 43


def settle(scene, obj):
    final, _speed, _at_rest, _frames = cloth_bench.settle(scene, obj, 36)
    return final


def static_copy(obj, positions):
    """The settled cloth as a mesh of its own (with UVs, smoothed), the solver's object hidden."""
    faces = [(j * NU + i, j * NU + i + 1, (j + 1) * NU + i + 1, (j + 1) * NU + i)
             for j in range(NV - 1) for i in range(NU - 1)]
    mesh = bpy.data.meshes.new("panel")
    mesh.from_pydata(positions, [], faces)
    uv = mesh.uv_layers.new(name="uv")
    for poly in mesh.polygons:
        poly.use_smooth = True
        for loop in poly.loop_indices:
            k = mesh.loops[loop].vertex_index
            uv.data[loop].uv = ((k % NU) / (NU - 1), 1.0 - (k // NU) / (NV - 1))
    mesh.update()
    copy = bpy.data.objects.new("panel", mesh)
    bpy.context.scene.collection.objects.link(copy)
    copy.modifiers.new("smooth", "SUBSURF").levels = 2
    solid = copy.modifiers.new("thickness", "SOLIDIFY")
    solid.thickness = 0.0008
    obj.hide_render = True
    obj.hide_viewport = True
    return copy


def print_image(colour, with_print):
    """The cloth's colour with a yellow disc and white block letters across its upper middle."""
    w, h = 256, 358
    img = bpy.data.images.new("print", w, h)
    px = [0.0] * (w * h * 4)
    for y in range(h):
        for x in range(w):
            c = colour
            if with_print:
                u, v = x / w, y / h  # v = 0 at the hem
                if (u - 0.55) ** 2 + ((v - 0.52) * h / w) ** 2 < 0.16 ** 2:
                    c = (0.85, 0.75, 0.05)
                for k in range(4):  # block letters: a bar and a stem each
                    left = 0.22 + 0.15 * k
                    if 0.72 < v < 0.76 and left < u < left + 0.11 or 0.62 < v < 0.76 and left < u < left + 0.03:
                        c = (0.92, 0.92, 0.9)
            i = 4 * (y * w + x)
            px[i:i + 4] = [c[0], c[1], c[2], 1.0]
    img.pixels = px
    return img


def cloth_material(colour, with_print):
    mat = bpy.data.materials.new("cloth")
    mat.use_nodes = True
    nodes = mat.node_tree.nodes
    bsdf = nodes["Principled BSDF"]
    bsdf.inputs["Roughness"].default_value = 0.75
    bsdf.inputs["Sheen"].default_value = 0.6
    tex = nodes.new("ShaderNodeTexImage")
    tex.image = print_image(colour, with_print)
    mat.node_tree.links.new(tex.outputs["Color"], bsdf.inputs["Base Color"])
    return mat


def plain_material(name, colour, roughness=0.6, metallic=0.0):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    bsdf = mat.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (*colour, 1.0)
    bsdf.inputs["Roughness"].default_value = roughness
    bsdf.inputs["Metallic"].default_value = metallic
    return mat


def box(name, location, size, colour, metallic=0.0):
    bpy.ops.mesh.primitive_cube_add(location=location)
    obj = bpy.context.object
    obj.name = name
    obj.scale = size
    obj.data.materials.append(plain_material(name, colour, 0.5, metallic))
    return obj


def workshop(pins, height):
    """Wall, table, boxes, the two grippers and the lights around the cloth (Blender's x
    across, z up, the camera looking along +y)."""
    wall = box("wall", (0.0, 0.9, -0.2), (3.0, 0.01, 2.0), (0.55, 0.52, 0.47))
    wall.data.materials[0].node_tree.nodes["Principled BSDF"].inputs["Roughness"].default_value = 0.9
    box("table", (0.0, 0.3, -height - 0.25), (1.6, 0.6, 0.02), (0.45, 0.28, 0.13))
    box("crate", (-0.75, 0.4, -height - 0.1), (0.15, 0.15, 0.13), (0.2, 0.35, 0.6))
    box("case", (0.7, 0.5, -height - 0.15), (0.18, 0.12, 0.08), (0.1, 0.1, 0.1))
    box("shelf", (0.0, 0.85, 0.25), (1.5, 0.05, 0.015), (0.6, 0.45, 0.3))
    for i, p in enumerate(pins):
        bpy.ops.mesh.primitive_cylinder_add(radius=0.018, depth=0.12, location=(p[0], p[1] - 0.05, p[2]),
                                            rotation=(math.pi / 2, 0.0, 0.0))
        grip = bpy.context.object
        grip.name = f"gripper{i}"
        grip.data.materials.append(plain_material("gripper", (0.08, 0.08, 0.09), 0.35, 0.6))
        bpy.ops.mesh.primitive_cylinder_add(radius=0.035, depth=0.25, location=(p[0] * 1.6, p[1] - 0.2, p[2] + 0.05),
                                            rotation=(0.0, math.pi / 2, 0.0))
        arm = bpy.context.object
        arm.name = f"arm{i}"
        arm.data.materials.append(plain_material("arm", (0.7, 0.72, 0.75), 0.3, 0.8))
    bpy.ops.object.light_add(type="AREA", location=(-0.9, -1.3, 0.7))
    key = bpy.context.object
    key.data.energy = 220.0
    key.data.size = 1.0
    key.rotation_euler = (math.radians(60), 0.0, math.radians(-35))
    bpy.ops.object.light_add(type="AREA", location=(1.2, -0.9, 0.2))
    fill = bpy.context.object
    fill.data.energy = 70.0
    fill.data.size = 1.5
    fill.rotation_euler = (math.radians(80), 0.0, math.radians(50))
    world = bpy.data.worlds.new("world")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.25, 0.25, 0.25, 1.0)
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.6
    bpy.context.scene.world = world


def camera(scene, height):
    bpy.ops.object.camera_add(location=(0.0, -1.6, -0.32 * height / 0.7), rotation=(math.pi / 2, 0.0, 0.0))
    cam = bpy.context.object
    cam.data.lens = 35.0 * 0.7 / max(height, 0.35)
    scene.camera = cam
    return cam


def render(scene, path, samples):
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = samples
    scene.cycles.use_denoising = False
    scene.cycles.seed = 3
    scene.render.resolution_x, scene.render.resolution_y = WIDTH_PX, HEIGHT_PX
    scene.render.resolution_percentage = 100
    scene.render.image_settings.file_format = "PNG"
    scene.render.image_settings.color_mode = "RGB"
    scene.render.filepath = path
    bpy.ops.render.render(write_still=True)


def main():
    args = sys.argv[sys.argv.index("--") + 1:]
    out_dir, name = args[0], args[1]
    width, height, inset, t_mm, e_mpa, gsm, poisson = map(float, args[2:9])
    colour = tuple(float(c) for c in args[9].split(","))
    with_print = args[10] != "0"
    scene, obj = cloth_bench.build(width, height, inset, t_mm, e_mpa, gsm, poisson, NU, NV)
    final = settle(scene, obj)
    centre = (NU - 1) // 2
    column = [final[j * NU + centre] for j in range(NV)]
    changes, crests = cloth_bench.centre_fibre_folds([p[1] for p in column], [p[2] for p in column])
    panel = static_copy(obj, final)
    panel.data.materials.append(cloth_material(colour, with_print))
    pins = [final[0], final[NU - 1]]
    workshop(pins, height)
    cam = camera(scene, height)
    scene.view_settings.view_transform = "Filmic"
    os.makedirs(out_dir, exist_ok=True)
    render(scene, os.path.join(out_dir, name + ".png"), int(os.environ.get("PHOTO_SPP", "32")))
    supports = []
    for p in pins:
        v = world_to_camera_view(scene, cam, Vector(p))
        supports.append([round(v.x * WIDTH_PX, 1), round((1.0 - v.y) * HEIGHT_PX, 1)])
    # The mask: the cloth alone, as white on black.
    for o in scene.objects:
        if o.type == "MESH" and o is not panel:
            o.hide_render = True
    panel.data.materials[0] = plain_material("white", (1.0, 1.0, 1.0), 1.0)
    world = scene.world.node_tree.nodes["Background"]
    world.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    world.inputs["Strength"].default_value = 1.0
    for o in scene.objects:
        if o.type == "LIGHT":
            o.hide_render = True
    scene.view_settings.view_transform = "Standard"
    scene.world.node_tree.nodes["Background"].inputs["Strength"].default_value = 1.0
    scene.render.film_transparent = True
    scene.render.image_settings.color_mode = "RGBA"
    render(scene, os.path.join(out_dir, name + "_mask.png"), 4)
    spacing_m = math.dist(pins[0], pins[1])
    meta = {"name": name, "width_m": width, "height_m": height, "inset_m": inset, "thickness_mm": t_mm,
            "young_mpa": e_mpa, "gsm": gsm, "print": with_print, "supports_px": supports,
            "scale_px_per_m": math.dist(*supports) / spacing_m if spacing_m > 0 else None,
            "solver_sign_changes": changes, "solver_crest_heights_m": crests}
    with open(os.path.join(out_dir, name + ".json"), "w") as f:
        json.dump(meta, f, indent=1)
    print("PHOTO," + json.dumps(meta), flush=True)


main()
