#!/usr/bin/env python3
# Turntable flicker split by bands of image rows, over frames that bench_render_quality's
# flicker parts left in their --out folder: where in the default scene the flicker is (at
# 320x320, rows 40-80 hold the rod, the clips and the wires' lower ends).  The measure is the
# bench's: RMS over pixels and frame pairs of the change from frame to frame minus the
# reference's change, with the 1024-spp reference's own share (seed 8 against seed 7) taken out.
#   bench/flicker_by_rows.py OUT SIZE FRAMES_DIR...      (FRAMES_DIR: a folder of frame_NNNN.png)
# Needs Debian's python3-opencv and python3-numpy.
import glob
import os
import sys

import cv2
import numpy as np

BANDS = [(0, 40), (40, 80), (80, 120), (120, 200), (200, 320)]  # in rows of a 320-row frame


def frames(folder):
    paths = sorted(glob.glob(os.path.join(folder, "frame_*.png")))
    if not paths:
        sys.exit(f"flicker_by_rows: no frame_NNNN.png in {folder}")
    return [cv2.imread(p, cv2.IMREAD_COLOR).astype(np.float64) / 255.0 for p in paths]


def squared_flicker(test, ref):
    """Per pixel, the mean over frame pairs and channels of the squared change minus the reference's."""
    acc = np.zeros(ref[0].shape[:2])
    for f in range(len(test) - 1):
        d = (test[f + 1] - test[f]) - (ref[f + 1] - ref[f])
        acc += (d * d).mean(axis=2)
    return acc / (len(test) - 1)


def main():
    if len(sys.argv) < 4:
        sys.exit("usage: bench/flicker_by_rows.py OUT SIZE FRAMES_DIR...")
    out, size = sys.argv[1], int(sys.argv[2])
    tag = "" if size == 96 else f"_{size}"
    ref = frames(os.path.join(out, f"turntable_ref1024_seed7{tag}"))
    between = squared_flicker(frames(os.path.join(out, f"turntable_ref1024_seed8{tag}")), ref)
    bands = [(a * size // 320, b * size // 320) for a, b in BANDS]

    def own(m, rows):  # the row's own flicker: the reference pair's share is twice one reference's
        a, b = rows
        return np.sqrt(max(0.0, m[a:b].mean() - 0.5 * between[a:b].mean()))

    print("| frames | whole | " + " | ".join(f"rows {a}-{b}" for a, b in bands) + " |")
    print("|---" * (len(bands) + 2) + "|")
    print("| the reference (seed 8 against 7) | " + " | ".join(
        f"{np.sqrt(0.5 * between[a:b].mean()):.4f}" for a, b in [(0, size)] + bands) + " |")
    for folder in sys.argv[3:]:
        m = squared_flicker(frames(folder), ref)
        print(f"| {os.path.basename(folder.rstrip('/'))} | " + " | ".join(
            f"{own(m, rows):.4f}" for rows in [(0, size)] + bands) + " |")


main()
