# What Blender's angular bending stiffness means in physical units: Peirce's cantilever test
# (the textile bending-length test, Peirce 1930) run in Blender's cloth solver, for
# bench/blender_cloth_compare.py.
#
#   blender -b --factory-startup -P bench/blender_bending_calibration.py -- [BENDING [VERTEX_KG [SPACING_M]]]
#
# A strip 4 vertices wide and 8 long, SPACING_M apart, lies flat with its first two columns
# held (a clamp); the rest hangs over under gravity.  The chord from the clamp's edge to the tip
# drops by theta below the horizontal; Peirce's bending length c of a strip of overhang L is
#   c^3 = L^3 cos(theta / 2) / (8 tan theta),   and c^3 = D / w
# (bending rigidity over weight per area).  Blender's cloth has no physical units for either:
# its angular springs take k = bending * rest length * 0.1 and its vertices the mass set, so
# the script prints c^3 per unit of `bending` for that vertex mass and spacing, which the
# comparison divides into the fabric's D / w.  The test is meant for theta near Peirce's
# 41.5 degrees (bending 200 at the defaults); the tip keeps trembling by a few millimetres, so
# it is averaged over the last 60 frames.  Blender only: never part of the build or the tests.
import math
import os
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import blender_cloth_compare as cloth_bench  # noqa: E402  the comparison's springs and reference values

WIDTH_VERTICES, LENGTH_VERTICES, FRAMES, AVERAGED = 4, 8, 300, 60


def main():
    args = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    bending = float(args[0]) if len(args) > 0 else 200.0
    vertex_kg = float(args[1]) if len(args) > 1 else cloth_bench.REFERENCE_VERTEX_KG
    spacing = float(args[2]) if len(args) > 2 else cloth_bench.CALIBRATION_SPACING_M
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.render.fps = 24
    n, m = LENGTH_VERTICES, WIDTH_VERTICES
    verts = [(i * spacing, j * spacing, 0.0) for j in range(m) for i in range(n)]
    faces = [(j * n + i, j * n + i + 1, (j + 1) * n + i + 1, (j + 1) * n + i) for j in range(m - 1) for i in range(n - 1)]
    mesh = bpy.data.meshes.new("strip")
    mesh.from_pydata(verts, [], faces)
    mesh.update()
    obj = bpy.data.objects.new("strip", mesh)
    scene.collection.objects.link(obj)
    clamp = obj.vertex_groups.new(name="clamp")
    clamp.add([j * n + i for j in range(m) for i in range(2)], 1.0, "REPLACE")
    s = obj.modifiers.new("cloth", "CLOTH").settings
    cloth_bench.set_cloth_springs(s, vertex_kg)
    s.bending_stiffness = bending
    s.vertex_group_mass = "clamp"
    cloth = obj.modifiers["cloth"]
    cloth.collision_settings.use_collision = False
    cloth.point_cache.frame_start = scene.frame_start = 1
    cloth.point_cache.frame_end = scene.frame_end = FRAMES
    drop = reach = 0.0
    for frame in range(1, FRAMES + 1):
        scene.frame_set(frame)
        if frame > FRAMES - AVERAGED:
            tip = obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).data.vertices
            drop -= sum(tip[j * n + n - 1].co.z for j in range(m)) / (m * AVERAGED)
            reach += (sum(tip[j * n + n - 1].co.x for j in range(m)) / m - spacing) / AVERAGED
    overhang = (n - 2) * spacing
    theta = math.atan2(drop, reach)
    c3 = overhang ** 3 * math.cos(theta / 2) / (8.0 * math.tan(theta))
    print(f"RESULT bending {bending:g} vertex_kg {vertex_kg:g} spacing_m {spacing:g} theta_deg {math.degrees(theta):.1f} "
          f"c3_m3 {c3:.4e} per_unit {c3 / bending:.4e}", flush=True)


if __name__ == "__main__":
    main()
