# Blender's glTF importer on a foldcast .glb (run by bench/gltf_blender.sh):
#   blender -b --factory-startup -P bench/gltf_blender.py -- GARMENT.glb REFERENCE.pc2|.obj
# Prints the vertex count, the shape keys, the largest vertex error against foldcast's own
# positions (every frame of a PC2: shape key k is frame k + 1; an OBJ: the mesh), and the
# material's values as Blender's Principled BSDF holds them.
import struct
import sys

import bpy
import numpy

# Debian 12's Blender 3.4 importer still spells numpy.bool, which numpy 1.24 removed.
if "bool" not in numpy.__dict__:
    numpy.bool = bool

glb, reference = sys.argv[sys.argv.index("--") + 1:][:2]


def read_pc2(path):
    with open(path, "rb") as f:
        data = f.read()
    vertices, _start, _rate, frames = struct.unpack_from("<iffi", data, 16)
    floats = struct.unpack_from(f"<{vertices * frames * 3}f", data, 32)
    return [[floats[(k * vertices + i) * 3:(k * vertices + i) * 3 + 3] for i in range(vertices)] for k in range(frames)]


def read_obj(path):
    with open(path) as f:
        return [[tuple(map(float, line.split()[1:4])) for line in f if line.startswith("v ")]]


bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.import_scene.gltf(filepath=glb)
mesh_objects = [o for o in bpy.context.scene.objects if o.type == "MESH"]
obj = mesh_objects[0]
frames = read_pc2(reference) if reference.endswith(".pc2") else read_obj(reference)
world = obj.matrix_world
keys = obj.data.shape_keys.key_blocks if obj.data.shape_keys else []


def error(coords, frame):
    # Blender is z-up: the importer maps glTF's (x, y, z) to (x, -z, y).
    worst = 0.0
    for co, p in zip(coords, frame):
        w = world @ co
        worst = max(worst, abs(w.x - p[0]), abs(w.y + p[2]), abs(w.z - p[1]))
    return worst


errors = [error([v.co for v in obj.data.vertices], frames[0])]
for k, key in enumerate(keys[1:], start=1):
    errors.append(error([d.co for d in key.data], frames[k]))
print(f"RESULT vertices {len(obj.data.vertices)} (reference {len(frames[0])})")
print(f"RESULT shape keys {max(0, len(keys) - 1)} (reference frames {len(frames)}); "
      f"animation {'yes' if obj.data.shape_keys and obj.data.shape_keys.animation_data else 'no'}")
print(f"RESULT largest vertex error over {len(errors)} frames: {max(errors):.3g} m (per axis)")
material = obj.active_material
print(f"RESULT material {material.name if material else None}")
if material and material.use_nodes:
    for node in material.node_tree.nodes:
        if node.type == "BSDF_PRINCIPLED":
            for name in ("Base Color", "Roughness", "Metallic", "Specular", "Sheen", "Sheen Tint", "Anisotropic",
                         "Anisotropic Rotation"):
                if name in node.inputs:
                    socket = node.inputs[name]
                    linked = socket.is_linked and socket.links[0].from_node.type
                    value = linked or (tuple(round(x, 4) for x in socket.default_value)
                                       if hasattr(socket.default_value, "__len__") else round(socket.default_value, 4))
                    print(f"RESULT   {name}: {value}")
        if node.type in ("TEX_IMAGE", "NORMAL_MAP", "MAPPING"):
            extra = node.image.size[:] if node.type == "TEX_IMAGE" and node.image else ""
            if node.type == "MAPPING":
                extra = tuple(round(x, 3) for x in node.inputs["Scale"].default_value)
            print(f"RESULT   node {node.type} {node.label or node.name} {extra}")
    print(f"RESULT   double-sided (no backface culling): {not material.use_backface_culling}")
