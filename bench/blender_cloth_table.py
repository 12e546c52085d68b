#!/usr/bin/env python3
# The comparison step: Blender's cached results (bench/blender_cloth_compare.sh) against
# `foldcast drape --json` for the same cloth, as a Markdown table for docs/benchmarks.md.
#   bench/blender_cloth_table.py [CSV] [FOLDCAST]
# Seconds to run: only foldcast runs (the fold-count rule may change; Blender's rows stay).
import csv
import json
import os
import subprocess
import sys
import time

root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
path = sys.argv[1] if len(sys.argv) > 1 else os.path.join(root, "bench", "blender_cloth.csv")
foldcast = sys.argv[2] if len(sys.argv) > 2 else os.path.join(root, "build", "foldcast")

rows = list(csv.DictReader(open(path)))
print("| look | inset (m) | n Blender | n foldcast | within 1 | crest heights Blender (m) | a_i foldcast (m) | largest crest gap (m) | Blender (s) | foldcast (s) |")
print("|---|---|---|---|---|---|---|---|---|---|")
by_look = {}
within = 0
top_gaps = []  # the first crest (the swag between the supports): Blender's against the model's
for r in rows:
    args = [foldcast, "drape", "--json", "-q", "--width-m", r["width_m"], "--height-m", r["height_m"],
            "--inset-m", r["inset_m"], "--thickness-mm", r["thickness_mm"], "--young-mpa", r["young_mpa"],
            "--gsm", r["gsm"], "--poisson", r["poisson"], "--grid", "64x64"]
    started = time.perf_counter()
    j = json.loads(subprocess.run(args, check=True, capture_output=True, text=True).stdout)
    seconds = time.perf_counter() - started
    n_b, n_f = int(r["sign_changes"]), int(j["folds"])
    crests = [float(c) for c in r["crest_heights_m"].split(";") if c]
    model = [-a for a in reversed(j["amplitudes_m"])]  # top edge first, as the crests
    gaps = [abs(a - b) for a, b in zip(crests, model)]
    if gaps:
        top_gaps.append(gaps[0])
    ok = abs(n_b - n_f) <= 1
    within += ok
    by_look.setdefault(r["name"], []).append((float(r["inset_m"]), n_b, n_f))
    print(f"| {r['name']} | {r['inset_m']} | {n_b} | {n_f} | {'yes' if ok else 'no'} | "
          f"{' '.join(f'{c:.3f}' for c in crests)} | {' '.join(f'{m:.3f}' for m in model)} | "
          f"{max(gaps):.3f} | {float(r['blender_s']):.1f} | {seconds:.2f} |" if gaps else
          f"| {r['name']} | {r['inset_m']} | {n_b} | {n_f} | {'yes' if ok else 'no'} | | | | "
          f"{float(r['blender_s']):.1f} | {seconds:.2f} |")


def direction(values):
    steps = [b - a for a, b in zip(values, values[1:])]
    if all(s == 0 for s in steps):
        return "flat"
    if all(s <= 0 for s in steps):
        return "down"
    if all(s >= 0 for s in steps):
        return "up"
    return "mixed"


print()
print(f"n within 1 of Blender's: {within} of {len(rows)} cases.")
top_gaps.sort()
print(f"The first crest (the swag between the supports) within 2.5 cm of the model's: "
      f"{sum(g <= 0.025 for g in top_gaps)} of {len(top_gaps)} cases (median gap {top_gaps[len(top_gaps) // 2]:.3f} m).")
print()
print("| look | n along the inset sweep, Blender | foldcast | same direction |")
print("|---|---|---|---|")
same = 0
for name, cases in by_look.items():
    cases.sort()
    b = direction([c[1] for c in cases])
    f = direction([c[2] for c in cases])
    same += b == f
    print(f"| {name} | {' '.join(str(c[1]) for c in cases)} ({b}) | {' '.join(str(c[2]) for c in cases)} ({f}) | {'yes' if b == f else 'no'} |")
print()
print(f"Same direction of n along the inset sweep: {same} of {len(by_look)} looks.")
