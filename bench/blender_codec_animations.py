# Makes test animations for the codec with Blender's cloth solver: garments moving with a
# body (docs/benchmarks.md, section "codec"):
#
#   blender -b --factory-startup -P bench/blender_codec_animations.py -- OUT_DIR [SCENE ...]
#
# Scenes (all by default): skirt (a skirt pinned at the waist of a body that walks and turns),
# scarf (a scarf hanging from an arm that swings up and round), drop (a cloth falling over a
# sphere that then rolls away, past a box), flag (a flag on a pole waved from side to side, in
# gusty wind).  Each writes OUT_DIR/NAME.pc2 (world-space positions of every frame) and
# OUT_DIR/NAME.obj (the triangles, frame 0), what `foldcast encode` and bench/codec_bench
# --input read.  Prints "SCENE,vertices,frames,seconds".  CODEC_ANIMATION_FRAMES=K makes K
# frames instead (trial runs).  Blender only: never part of the build or the tests.  No
# random numbers but the wind's fixed seeds; whether Blender's solver gives the same
# positions on another machine or Blender version was not checked.
import math
import os
import struct
import sys
import time

import bmesh
import bpy
import mathutils

FPS = 30


def reset():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.render.fps = FPS
    return scene


def grid(name, nu, nv, size_u, size_v):
    """An nu x nv vertex triangulated grid in the XY plane, centred on the origin."""
    mesh = bpy.data.meshes.new(name)
    bm = bmesh.new()
    bmesh.ops.create_grid(bm, x_segments=nu - 1, y_segments=nv - 1, size=0.5)
    bmesh.ops.scale(bm, vec=(size_u, size_v, 1.0), verts=bm.verts)
    bmesh.ops.triangulate(bm, faces=bm.faces)
    bm.to_mesh(mesh)
    bm.free()
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def tube(name, rings, around, radius_top, radius_bottom, height):
    """An open truncated cone (a skirt): `rings` rings of `around` vertices, top at z = 0."""
    mesh = bpy.data.meshes.new(name)
    verts, faces = [], []
    for r in range(rings):
        s = r / (rings - 1)
        rad = radius_top + (radius_bottom - radius_top) * s
        for a in range(around):
            phi = 2 * math.pi * a / around
            verts.append((rad * math.cos(phi), rad * math.sin(phi), -height * s))
    for r in range(rings - 1):
        for a in range(around):
            i, j = r * around + a, r * around + (a + 1) % around
            faces += [(i, j, j + around), (i, j + around, i + around)]
    mesh.from_pydata(verts, [], faces)
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def pin(obj, predicate):
    group = obj.vertex_groups.new(name="pin")
    group.add([v.index for v in obj.data.vertices if predicate(v.co)], 1.0, "REPLACE")
    return group.name


def cloth(obj, pin_group=None, quality=5, mass=0.3, bending=0.5, self_collision=False):
    mod = obj.modifiers.new("cloth", "CLOTH")
    s = mod.settings
    s.quality = quality
    s.mass = mass
    s.bending_stiffness = bending
    s.tension_stiffness = s.compression_stiffness = 40.0
    s.shear_stiffness = 5.0
    if pin_group:
        s.vertex_group_mass = pin_group
    mod.collision_settings.use_self_collision = self_collision
    mod.collision_settings.distance_min = 0.005
    return mod


def collider(obj):
    obj.modifiers.new("collision", "COLLISION")
    obj.collision.thickness_outer = 0.01


def keys(obj, path, frames_values):
    for frame, value in frames_values:
        setattr(obj, path, value)
        obj.keyframe_insert(data_path=path, frame=frame)


def scene_skirt():
    """A body (hip cylinder and two swinging legs) walks forward, stops and turns round;
    the skirt is pinned at the waist and follows it."""
    frames = 240
    body = bpy.data.objects.new("body", None)
    bpy.context.scene.collection.objects.link(body)
    bpy.ops.mesh.primitive_cylinder_add(radius=0.17, depth=0.25, location=(0, 0, -0.12))
    hips = bpy.context.object
    hips.parent = body
    collider(hips)
    for side in (-1, 1):
        bpy.ops.mesh.primitive_cylinder_add(radius=0.07, depth=0.8, location=(0, 0, -0.4))
        leg = bpy.context.object
        leg.data.transform(mathutils.Matrix.Translation((0, 0, -0.4)))  # pivot at the hip
        leg.location = (0, 0.09 * side, -0.2)
        leg.parent = body
        collider(leg)
        swing = [(f, (0.0, 0.35 * side * math.sin(2 * math.pi * f / 40) * (1 if f < 130 else 0), 0.0))
                 for f in range(1, 131, 5)] + [(150, (0.0, 0.0, 0.0))]
        keys(leg, "rotation_euler", swing)
    # Walk along x for 130 frames (1.1 m/s), then turn 180 degrees on the spot, hips swaying.
    path = []
    for f in range(1, frames + 1, 5):
        x = 1.1 * min(f, 130) / FPS
        yaw = 0.0 if f < 130 else math.pi * min(1.0, (f - 130) / 60.0)
        path.append((f, x, yaw, 0.03 * math.sin(2 * math.pi * f / 40)))
    keys(body, "location", [(f, (x, sway, 1.0)) for f, x, yaw, sway in path])
    keys(body, "rotation_euler", [(f, (0.0, 0.0, yaw)) for f, x, yaw, sway in path])
    skirt = tube("skirt", 44, 96, 0.18, 0.34, 0.55)
    skirt.parent = body
    group = pin(skirt, lambda co: co.z > -0.001)
    cloth(skirt, group, quality=6, mass=0.2, bending=0.3)
    return skirt, frames


def scene_scarf():
    """A scarf hanging from a hand: the arm swings it up, round and down."""
    frames = 200
    arm = bpy.data.objects.new("arm", None)
    bpy.context.scene.collection.objects.link(arm)
    arm.location = (0, 0, 1.5)
    scarf = grid("scarf", 24, 220, 0.2, 1.6)
    scarf.rotation_euler = (math.pi / 2, 0, 0)  # hanging down in the XZ plane
    scarf.location = (0.6, 0, -0.8)
    scarf.parent = arm
    group = pin(scarf, lambda co: co.y > 0.79)
    cloth(scarf, group, quality=5, mass=0.1, bending=0.2)
    rot = []
    for f in range(1, frames + 1, 4):
        s = f / frames
        rot.append((f, (0.0, -1.2 * math.sin(math.pi * s) ** 2, 2.5 * math.sin(2 * math.pi * s))))
    keys(arm, "rotation_euler", rot)
    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.15, location=(0, 0, 1.4))  # the head, in the way
    collider(bpy.context.object)
    return scarf, frames


def scene_drop():
    """A square cloth falls over a sphere, which then rolls away under it and drags it over
    a box."""
    frames = 180
    sheet = grid("drop", 70, 70, 1.4, 1.4)
    sheet.location = (0.05, 0.05, 1.1)
    sheet.rotation_euler = (0.12, 0.08, 0)
    cloth(sheet, None, quality=5, mass=0.3, bending=0.5)
    sheet.modifiers["cloth"].collision_settings.collision_quality = 4
    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.35, location=(0, 0, 0.5))
    ball = bpy.context.object
    collider(ball)
    ball.collision.cloth_friction = 40.0
    keys(ball, "location", [(1, (0.0, 0.0, 0.5)), (50, (0.0, 0.0, 0.5)), (150, (0.9, -0.5, 0.5))])
    bpy.ops.mesh.primitive_cube_add(size=0.4, location=(0.7, 0.3, 0.2))
    collider(bpy.context.object)
    bpy.ops.mesh.primitive_plane_add(size=6, location=(0, 0, 0))
    collider(bpy.context.object)
    return sheet, frames


def scene_flag():
    """A flag on a pole waved from side to side and tilted, in gusty wind (which moves it
    little: Blender's wind pushes along the faces' normals, so the motion is the pole's)."""
    frames = 240
    pole = bpy.data.objects.new("pole", None)
    bpy.context.scene.collection.objects.link(pole)
    pole.location = (0, 0, 1.2)
    flag = grid("flag", 90, 50, 1.5, 0.9)
    flag.rotation_euler = (math.pi / 2, 0, 0)
    flag.location = (0.75, 0, 0.8)
    flag.parent = pole
    group = pin(flag, lambda co: co.x < -0.749)
    cloth(flag, group, quality=5, mass=0.02, bending=0.05)
    keys(pole, "rotation_euler", [(f, (0.25 * math.sin(2 * math.pi * f / 90), 0.0,
                                       1.2 * math.sin(2 * math.pi * f / 60))) for f in range(1, frames + 1, 3)])
    bpy.ops.object.effector_add(type="WIND", location=(-1.5, 0, 2.0))
    wind = bpy.context.object
    wind.field.noise = 1.0
    wind.field.seed = 7
    for f in range(1, frames + 1, 5):
        wind.field.strength = 150.0 + 60.0 * math.sin(2 * math.pi * f / 70)
        wind.field.keyframe_insert(data_path="strength", frame=f)
    keys(wind, "rotation_euler", [(f, (0.0, 1.2, 0.6 * math.sin(2 * math.pi * f / 110)))
                                  for f in range(1, frames + 1, 5)])
    return flag, frames


SCENES = {"skirt": scene_skirt, "scarf": scene_scarf, "drop": scene_drop, "flag": scene_flag}


def bake_and_write(obj, frames, out_dir, name):
    scene = bpy.context.scene
    scene.frame_start, scene.frame_end = 1, frames
    mod = obj.modifiers["cloth"]
    mod.point_cache.frame_start, mod.point_cache.frame_end = 1, frames
    positions = []
    for f in range(1, frames + 1):
        scene.frame_set(f)
        depsgraph = bpy.context.evaluated_depsgraph_get()
        ev = obj.evaluated_get(depsgraph)
        world = ev.matrix_world
        positions.append([tuple(world @ v.co) for v in ev.data.vertices])
    n = len(positions[0])
    tmp = os.path.join(out_dir, name + ".pc2.part")
    with open(tmp, "wb") as out:
        out.write(b"POINTCACHE2\0" + struct.pack("<iiffi", 1, n, 1.0, 1.0, frames))
        for frame in positions:
            out.write(struct.pack("<%df" % (3 * n), *[c for p in frame for c in p]))
    os.replace(tmp, os.path.join(out_dir, name + ".pc2"))
    tmp = os.path.join(out_dir, name + ".obj.part")
    with open(tmp, "w") as out:
        for p in positions[0]:
            out.write("v %.6f %.6f %.6f\n" % p)
        for poly in obj.data.polygons:
            out.write("f %s\n" % " ".join(str(i + 1) for i in poly.vertices))
    os.replace(tmp, os.path.join(out_dir, name + ".obj"))
    return n


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    if not argv:
        sys.exit("usage: blender -b --factory-startup -P bench/blender_codec_animations.py -- OUT_DIR [SCENE ...]")
    out_dir, names = argv[0], argv[1:] or list(SCENES)
    os.makedirs(out_dir, exist_ok=True)
    for name in names:
        if name not in SCENES:
            sys.exit("unknown scene '%s' (known: %s)" % (name, ", ".join(SCENES)))
        reset()
        t0 = time.time()
        obj, frames = SCENES[name]()
        frames = int(os.environ.get("CODEC_ANIMATION_FRAMES", frames))
        n = bake_and_write(obj, frames, out_dir, name)
        print("%s,%d,%d,%.1f" % (name, n, frames, time.time() - t0), flush=True)


main()
