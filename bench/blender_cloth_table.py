#!/usr/bin/env python3
# The comparison step: Blender's cached results (bench/blender_cloth_compare.sh) against
# `foldcast drape --json` for the same cloth, as Markdown tables for docs/benchmarks.md.
#   bench/blender_cloth_table.py [CSV] [FOLDCAST]
# Seconds to run: only foldcast runs (the fold model may change; Blender's rows stay).
#
# Blender's reference for a case is its finest grid at rest; a case is converged when the
# grids of at most 1.04 cm and at most 0.7 cm, both at rest, count the same folds.  Rows of
# coarser grids (the first sweep's 2.1 cm) are listed apart and never used as the reference.
import csv
import json
import os
import subprocess
import sys

root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
path = sys.argv[1] if len(sys.argv) > 1 else os.path.join(root, "bench", "blender_cloth.csv")
foldcast = sys.argv[2] if len(sys.argv) > 2 else os.path.join(root, "build", "foldcast")
COARSE_M, FINE_M = 0.0104, 0.0070  # the two spacings' upper bounds


def spacing_class(row):
    s = float(row["spacing_m"])
    return "fine" if s <= FINE_M + 5e-6 else "coarse" if s <= COARSE_M + 5e-6 else "legacy"


def model(row):
    args = [foldcast, "drape", "--json", "-q", "--width-m", row["width_m"], "--height-m", row["height_m"],
            "--inset-m", row["inset_m"], "--thickness-mm", row["thickness_mm"], "--young-mpa", row["young_mpa"],
            "--gsm", row["gsm"], "--poisson", row["poisson"], "--grid", "64x64"]
    return json.loads(subprocess.run(args, check=True, capture_output=True, text=True).stdout)


def direction(values):
    steps = [b - a for a, b in zip(values, values[1:])]
    if all(s == 0 for s in steps):
        return "flat"
    if all(s <= 0 for s in steps):
        return "down"
    if all(s >= 0 for s in steps):
        return "up"
    return "mixed"


def side(centre, corners):
    return "above" if centre > corners + 1e-3 else "below" if centre < corners - 1e-3 else "level"


cases = {}
for r in csv.DictReader(open(path)):
    cases.setdefault((r["name"], float(r["inset_m"])), {})[spacing_class(r)] = r

print("| look | inset (m) | n Blender 1.0 / 0.7 cm (at rest) | n foldcast | within 1 | fold depth Blender / zmax (m) | "
      "hem width Blender / foldcast (m) | hem centre - corners Blender / foldcast (m) |")
print("|---|---|---|---|---|---|---|---|")
stats = {"cases": 0, "within": 0, "converged": 0, "hem_width": 0, "hem_side": 0}
sweeps = {}
for (name, inset), by in cases.items():
    ref = by.get("fine") or by.get("coarse")
    if ref is None:
        continue
    j = model(ref)
    stats["cases"] += 1
    n_b, n_f = int(ref["sign_changes"]), int(j["folds"])
    counts = " / ".join(f"{by[k]['sign_changes']}{'' if by[k]['at_rest'] == '1' else ' (moving)'}" if k in by else "-"
                        for k in ("coarse", "fine"))
    converged = ("coarse" in by and "fine" in by and by["coarse"]["at_rest"] == by["fine"]["at_rest"] == "1" and
                 by["coarse"]["sign_changes"] == by["fine"]["sign_changes"])
    stats["converged"] += converged
    ok = abs(n_b - n_f) <= 1
    stats["within"] += ok
    sweeps.setdefault(name, []).append((inset, n_b, n_f))
    hem_b, hem_f = float(ref["hem_width_m"]), j["hem"]["width_m"]
    stats["hem_width"] += abs(hem_f - hem_b) <= 0.2 * hem_b
    lift_b = float(ref["hem_centre_m"]) - float(ref["hem_corners_m"])
    lift_f = j["hem"]["centre_y_m"] - j["hem"]["corners_y_m"]
    same_side = side(lift_b, 0.0) == side(lift_f, 0.0)
    stats["hem_side"] += same_side
    print(f"| {name} | {inset:g} | {counts}{'' if converged else ' (not converged)'} | {n_f} | {'yes' if ok else 'no'} | "
          f"{float(ref['fold_depth_m']):.3f} / {j['zmax_m']:.3f} | {hem_b:.3f} / {hem_f:.3f} | "
          f"{lift_b:+.3f} / {lift_f:+.3f}{'' if same_side else ' (other side)'} |")

n = max(stats["cases"], 1)
print()
print(f"Cases with a Blender reference at <= 1.04 cm: {stats['cases']}; converged (both spacings at rest, same n): "
      f"{stats['converged']}.")
print(f"n within 1 of Blender's: {stats['within']} of {stats['cases']} ({100 * stats['within'] / n:.0f} %).")
print(f"Hem width within 20 %: {stats['hem_width']} of {stats['cases']}; hem centre on the same side of its corners: "
      f"{stats['hem_side']} of {stats['cases']}.")
print()
print("| look | n along the inset sweep, Blender | foldcast | same direction |")
print("|---|---|---|---|")
same = 0
for name, runs in sweeps.items():
    runs.sort()
    b = direction([r[1] for r in runs])
    f = direction([r[2] for r in runs])
    same += b == f
    print(f"| {name} | {' '.join(str(r[1]) for r in runs)} ({b}) | {' '.join(str(r[2]) for r in runs)} ({f}) | "
          f"{'yes' if b == f else 'no'} |")
print()
print(f"Same direction of n along the inset sweep: {same} of {len(sweeps)} looks.")
