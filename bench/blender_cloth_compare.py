# Hangs one cloth in Blender's cloth solver and counts its folds along the centre fibre, for
# the comparison with foldcast's fold model (bench/blender_cloth_compare.sh runs the sweep,
# bench/blender_cloth_table.py compares; docs/benchmarks.md has the table).
#
#   blender -b --factory-startup -P bench/blender_cloth_compare.py -- \
#       NAME WIDTH_M HEIGHT_M INSET_M THICKNESS_MM YOUNG_MPA GSM POISSON NU NV
#
# Prints one line "RESULT,<csv row>" (see FIELDS).  Blender only: never part of the build
# or the tests.
#
# The cloth: an NU x NV quad grid of the flat panel in Blender's XZ plane (x across, z up,
# y out of the cloth), a 0.3 mm random out-of-plane jitter (fixed seed) so it can buckle.  The
# two top corners are pinned and moved in by the inset over the first 1.5 s (a shape key),
# then the cloth settles until it is at rest: its fastest vertex below REST_SPEED_M_S (1 mm/s)
# over a whole second, after at least MIN_SETTLE_FRAMES, at most MAX_SETTLE_FRAMES (the row
# says whether it got there).  A fixed 10 s settle left the soft looks swaying at centimetres
# per second on fine grids, counting waves of their lower half as folds.
#
# Units.  A cloth's rest shape depends only on how stiff it is against its own weight: its
# bending length cubed, D / w (bending rigidity D = E t^3 / (12 (1 - nu^2)) over weight per area
# w), and an in-plane stiffness far above its weight.  Blender's drag (air viscosity x 0.01 per
# vertex) and spring damping do not scale with the vertex mass, so at the cloth's real mass
# (0.06 g per vertex at 25 x 35) they outweigh gravity a thousandfold: the cloth creeps at
# centimetres per second and never reaches rest (this script's first table, in
# docs/benchmarks.md, was made so).  Each vertex therefore gets Blender's own default mass,
# VERTEX_KG = 0.3 kg, and the bending stiffness is set so that Blender's D / w is the fabric's:
# bending = (D / w) / BENDING_PER_UNIT, where BENDING_PER_UNIT, Blender's D / w per unit of
# `bending` for 0.3 kg vertices 2.08 cm apart, comes from Peirce's cantilever test in Blender
# (bench/blender_bending_calibration.py: 1.35e-6 m^3, at Peirce's 41.5 degrees) and scales as
# 0.3 kg / VERTEX_KG.  Tension and compression (80) and shear (5) stay far stiffer than the
# weight: the script prints the top edge's and the centre fibre's lengths to show it.
# BENDING_SCALE multiplies the bending stiffness (sensitivity runs); a grid of another spacing
# scales the calibration by spacing^4 (checked at 1.04 cm).
import math
import os
import random
import sys
import time

import bpy

# Blender's D / w (m^3) per unit of `bending` for REFERENCE_VERTEX_KG vertices
# CALIBRATION_SPACING_M apart (bench/blender_bending_calibration.py -- 200: theta 40 degrees).
BENDING_PER_UNIT = 1.35e-6
REFERENCE_VERTEX_KG = 0.3
CALIBRATION_SPACING_M = 0.0208


def set_cloth_springs(s, vertex_kg):
    """The solver settings and the springs other than bending, shared with the bending
    calibration (its figure holds for cloth set up so)."""
    s.quality = int(os.environ.get("CLOTH_QUALITY", "5"))
    s.mass = vertex_kg
    s.bending_model = "ANGULAR"
    s.tension_stiffness = 80.0
    s.compression_stiffness = float(os.environ.get("COMPRESSION_STIFFNESS", "80.0"))
    s.shear_stiffness = float(os.environ.get("SHEAR_STIFFNESS", "5.0"))

FIELDS = ["name", "width_m", "height_m", "inset_m", "thickness_mm", "young_mpa", "gsm", "poisson",
          "nu", "nv", "sign_changes", "crest_heights_m", "settle_speed_m_s", "blender_s", "centre_fibre", "top_edge_m",
          "centre_fibre_m", "spacing_m", "at_rest", "settle_frames", "fold_depth_m", "hem_width_m", "hem_centre_m",
          "hem_corners_m"]

REST_SPEED_M_S = 1e-3
MIN_SETTLE_FRAMES = int(os.environ.get("MIN_SETTLE_FRAMES", "120"))
MAX_SETTLE_FRAMES = int(os.environ.get("MAX_SETTLE_FRAMES", "2400"))


def build(width, height, inset, t_mm, e_mpa, gsm, poisson, nu, nv):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.render.fps = 24
    rng = random.Random(1)
    verts = []
    for j in range(nv):
        for i in range(nu):
            x = -0.5 * width + width * i / (nu - 1)
            z = -height * j / (nv - 1)
            verts.append((x, 3e-4 * (2.0 * rng.random() - 1.0) if j > 0 else 0.0, z))
    faces = [(j * nu + i, j * nu + i + 1, (j + 1) * nu + i + 1, (j + 1) * nu + i)
             for j in range(nv - 1) for i in range(nu - 1)]
    mesh = bpy.data.meshes.new("cloth")
    mesh.from_pydata(verts, [], faces)
    mesh.update()
    obj = bpy.data.objects.new("cloth", mesh)
    scene.collection.objects.link(obj)
    corners = [0, nu - 1]
    pin = obj.vertex_groups.new(name="pin")
    pin.add(corners, 1.0, "REPLACE")
    # Corners moved in by the inset with a shape key, animated over the first 2 s.
    obj.shape_key_add(name="Basis")
    key = obj.shape_key_add(name="in")
    key.data[0].co.x += inset
    key.data[nu - 1].co.x -= inset
    move_frames, settle_frames = 36, MAX_SETTLE_FRAMES
    key.value = 0.0
    key.keyframe_insert("value", frame=1)
    key.value = 1.0
    key.keyframe_insert("value", frame=1 + move_frames)
    cloth = obj.modifiers.new("cloth", "CLOTH")
    s = cloth.settings
    vertex_kg = float(os.environ.get("VERTEX_KG", str(REFERENCE_VERTEX_KG)))
    set_cloth_springs(s, vertex_kg)
    s.air_damping = float(os.environ.get("AIR_DAMPING", "1.0"))
    d = e_mpa * 1e6 * (t_mm * 1e-3) ** 3 / (12.0 * (1.0 - poisson ** 2))
    w = gsm * 1e-3 * 9.81
    spacing = 0.5 * (width / (nu - 1) + height / (nv - 1))
    # Blender's D / w per unit scales as spacing^4 / vertex mass (with the vertex mass fixed,
    # the weight per area grows as 1 / spacing^2; measured at 1.04 cm: 7.8e-8 m^3, the rule
    # gives 8.4e-8).
    per_unit = (float(os.environ.get("BENDING_PER_UNIT", str(BENDING_PER_UNIT))) *
                (spacing / CALIBRATION_SPACING_M) ** 4 * REFERENCE_VERTEX_KG / vertex_kg)
    s.bending_stiffness = d / w / per_unit * float(os.environ.get("BENDING_SCALE", "1.0"))
    s.vertex_group_mass = "pin"
    cloth.collision_settings.use_collision = False
    cloth.collision_settings.use_self_collision = False
    cloth.point_cache.frame_start = 1
    cloth.point_cache.frame_end = 1 + move_frames + settle_frames
    scene.frame_start = 1
    scene.frame_end = cloth.point_cache.frame_end
    return scene, obj


def positions(scene, obj):
    depsgraph = bpy.context.evaluated_depsgraph_get()
    evaluated = obj.evaluated_get(depsgraph)
    flat = [0.0] * (3 * len(evaluated.data.vertices))
    evaluated.data.vertices.foreach_get("co", flat)
    return [tuple(flat[3 * k:3 * k + 3]) for k in range(len(flat) // 3)]


def settle(scene, obj, move_frames):
    """Steps the solver until the cloth is at rest (the fastest vertex below REST_SPEED_M_S
    for a second of frames) or MAX_SETTLE_FRAMES have passed; returns the final positions,
    the last frame's largest speed, whether it came to rest and the frames it settled."""
    fps = scene.render.fps
    previous, calm, speed = None, 0, float("inf")
    last = scene.frame_start + move_frames + MAX_SETTLE_FRAMES
    for frame in range(scene.frame_start, last + 1):
        scene.frame_set(frame)
        if frame < scene.frame_start + move_frames:
            continue
        current = positions(scene, obj)
        if previous is not None:
            speed = max(math.dist(a, b) for a, b in zip(current, previous)) * fps
            calm = calm + 1 if speed < REST_SPEED_M_S else 0
            settled = frame - scene.frame_start - move_frames
            if calm >= fps and settled >= MIN_SETTLE_FRAMES:
                return current, speed, True, settled
        previous = current
    return previous, speed, False, MAX_SETTLE_FRAMES


def lowest_crest_vertex(height, depth, begin, end):
    """The lowest crest, below which the fibre hangs straight to the hem: the first vertex
    below the segment's steepest flank with |d depth / d height| <= 0.1 (as foldcast's)."""
    def slope(j):
        dh = height[j + 1] - height[j]
        return 0.0 if dh == 0.0 else abs((depth[j + 1] - depth[j]) / dh)
    steepest = max(range(begin, end - 1), key=slope, default=begin)
    for j in range(steepest + 1, end - 1):
        if slope(j) <= 0.1:
            return j
    return max(range(begin, end), key=lambda j: abs(depth[j]))


def centre_fibre_folds(column_y, column_z):
    """Sign changes of the out-of-plane displacement down the fibre and the height of each
    crest (largest |y| between two sign changes, parabola-refined; the top of a plateau within
    0.5 mm of it; the lowest crest where the fibre stops folding): as foldcast's
    centre_fibre_folds, with Blender's y as foldcast's z and Blender's z as foldcast's y."""
    plane = 1e-4
    sign, start, segments, changes = 0, 0, [], 0
    for j, v in enumerate(column_y):
        s = 1 if v > plane else (-1 if v < -plane else 0)
        if s == 0:
            continue
        if sign != 0 and s != sign:
            changes += 1
            segments.append((start, j))
            start = j
        sign = s
    segments.append((start, len(column_y)))
    crests = []
    for begin, end in segments:
        if len(segments) > 1 and end == len(column_y):
            crests.append(column_z[lowest_crest_vertex(column_z, column_y, begin, end)])
            continue
        deepest = max(range(begin, end), key=lambda j: abs(column_y[j]))
        best = begin  # the top of a plateau within 0.5 mm of the deepest point
        while abs(column_y[best]) < abs(column_y[deepest]) - 5e-4:
            best += 1
        height = column_z[best]
        if best == deepest and 0 < best < len(column_y) - 1:
            zm, z0, zp = (abs(column_y[best - 1]), abs(column_y[best]), abs(column_y[best + 1]))
            curvature = zm - 2.0 * z0 + zp
            if curvature < 0.0:
                offset = max(-0.5, min(0.5, 0.5 * (zm - zp) / curvature))
                other = column_z[best - 1 if offset < 0 else best + 1]
                height += abs(offset) * (other - height)
        crests.append(height)
    return changes, crests


def hem_measures(final, nu, nv):
    hem = final[(nv - 1) * nu:]
    xs = [p[0] for p in hem]
    return [f"{max(xs) - min(xs):.4f}", f"{hem[(nu - 1) // 2][2]:.4f}", f"{0.5 * (hem[0][2] + hem[-1][2]):.4f}"]


def main():
    args = sys.argv[sys.argv.index("--") + 1:]
    name = args[0]
    width, height, inset, t_mm, e_mpa, gsm, poisson = map(float, args[1:8])
    nu, nv = int(args[8]), int(args[9])
    scene, obj = build(width, height, inset, t_mm, e_mpa, gsm, poisson, nu, nv)
    started = time.perf_counter()
    final, speed, at_rest, settle_frames = settle(scene, obj, 36)
    elapsed = time.perf_counter() - started
    centre = (nu - 1) // 2
    column = [final[j * nu + centre] for j in range(nv)]
    # Out-of-plane displacement and height; the supports sit at z = 0 in both tools.
    changes, crests = centre_fibre_folds([p[1] for p in column], [p[2] for p in column])
    row = [name, width, height, inset, t_mm, e_mpa, gsm, poisson, nu, nv, changes,
           ";".join(f"{c:.4f}" for c in crests), f"{speed:.4g}", f"{elapsed:.2f}",
           # The whole centre fibre, height:depth per row (m), so that the table can count
           # folds by another rule without running Blender again.
           ";".join(f"{p[2]:.5f}:{p[1]:.5f}" for p in column),
           # Lengths of the top edge and the centre fibre as Blender left them: the cloth's
           # are width and height; much shorter means it compressed instead of buckling.
           f"{sum(math.dist(final[i], final[i + 1]) for i in range(nu - 1)):.4f}",
           f"{sum(math.dist(column[j], column[j + 1]) for j in range(nv - 1)):.4f}",
           f"{0.5 * (width / (nu - 1) + height / (nv - 1)):.5f}", int(at_rest), settle_frames,
           # The deepest out-of-plane excursion of the centre fibre, the hem's extent across and
           # the heights of its centre and (mean of) its two corners, all in metres.
           f"{max(abs(p[1]) for p in column):.4f}"] + hem_measures(final, nu, nv)
    print("RESULT," + ",".join(str(v) for v in row), flush=True)
    if os.environ.get("DUMP_OBJ"):
        # The settled cloth in foldcast's axes (y up, z out of the cloth), to look at or
        # render with foldcast (a scene whose [garment] path is this file).
        with open(os.environ["DUMP_OBJ"], "w") as out:
            for p in final:
                out.write(f"v {p[0]:.6f} {p[2]:.6f} {p[1]:.6f}\n")
            for j in range(nv - 1):
                for i in range(nu - 1):
                    k = j * nu + i + 1
                    out.write(f"f {k} {k + nu} {k + 1}\nf {k + 1} {k + nu} {k + nu + 1}\n")


if __name__ == "__main__":  # bench/blender_photo.py imports build() and centre_fibre_folds()
    main()
