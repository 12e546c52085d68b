#!/usr/bin/env python3
"""Open-loop model of profile cascade's spatial predictions on a grid-topology PC2 animation.

For midpoint frames at spacing h (cubic temporal prediction from the original frames, as the
hierarchy predicts from decoded ones), the temporal residual of each interior vertex is
predicted from its neighbours' residuals with the closed loop's quantisation noise added
(uniform, one step wide), and the result quantised with that step. Printed: the empirical
entropy in bits per vertex (sum of the three coordinates' entropies) of

  parallelogram   r_L + r_U - r_UL, grid axes (profile default)
  least squares 5 / 10   weights fitted per frame over 5 (the two parallelograms' corners) or
                  10 causal neighbours, grid axes (the weights of profile cascade)
  isometric       the parallelogram's prediction moved onto the circle the vertex's edge
                  lengths (in frame t - h) allow around its decoded corners, quantised along
                  the grid's axes, then along the circle's (profile cascade's isometric modes)

A model, not the codec: no entropy coder, contexts or mode choice; it shows where bits can be
saved. Needs numpy (Debian: python3-numpy). Example, on bench/blender_codec_animations.py's
drop (a 70 x 70 grid):

  python3 bench/codec_prediction_model.py build/codec_animations/drop.pc2 --cols 70
"""
import argparse
import struct
import sys

import numpy as np


def load_pc2(path):
    data = open(path, 'rb').read()
    if data[:12] != b'POINTCACHE2\0':
        sys.exit(f'{path}: not a PC2 file')
    vertices, = struct.unpack('<i', data[16:20])
    frames, = struct.unpack('<i', data[28:32])
    return np.frombuffer(data[32:], dtype='<f4').reshape(frames, vertices, 3).astype(np.float64)


def entropy_bits(values):
    _, counts = np.unique(values, return_counts=True)
    p = counts / counts.sum()
    return -(counts * np.log2(p)).sum()


def bits_per_vertex(error, step):
    return sum(entropy_bits(np.round(error[..., c] / step).ravel()) for c in range(3)) / error[..., 0].size


def least_squares(taps, target):
    a = np.stack(taps, -1).reshape(-1, len(taps))
    w, *_ = np.linalg.lstsq(a, target.ravel(), rcond=None)
    return target - (a @ w).reshape(target.shape)


def isometric(p0, xa, xb, la2, lb2, target, step):
    """Bits of target's residual from the point of the circle nearest p0 (rows of 3-vectors):
    along the grid's axes, and along the circle's."""
    d = xb - xa
    length = np.linalg.norm(d, axis=1, keepdims=True)
    u = d / length
    along = (la2 - lb2 + length ** 2) / (2 * length)
    radius = np.sqrt(np.maximum(la2 - along ** 2, 0))
    centre = xa + along * u
    w = p0 - centre
    w -= (w * u).sum(1, keepdims=True) * u
    w /= np.linalg.norm(w, axis=1, keepdims=True) + 1e-30
    t = np.cross(u, w)
    e = target - (centre + radius * w)
    grid_axes = sum(entropy_bits(np.round(e[:, c] / step)) for c in range(3)) / len(e)
    circle_axes = sum(entropy_bits(np.round((e * axis).sum(1) / step)) for axis in (t, w, u)) / len(e)
    return np.array([grid_axes, circle_axes])


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('pc2')
    parser.add_argument('--cols', type=int, required=True, help='vertices per grid row (row-major grid)')
    parser.add_argument('--max-error', type=float, default=1e-4, help='bound as a fraction of the diagonal')
    parser.add_argument('--frames', type=int, default=1000, help='at most this many midpoint frames per spacing')
    args = parser.parse_args()
    x = load_pc2(args.pc2)
    count, n, _ = x.shape
    if n % args.cols:
        sys.exit(f'{args.pc2}: {n} vertices is not a multiple of --cols {args.cols}')
    rows, cols = n // args.cols, args.cols
    flat = x.reshape(-1, 3)
    diagonal = np.linalg.norm(flat.max(0) - flat.min(0))
    m = 2 * args.max_error * diagonal / np.sqrt(3)  # the grid-axis step the bound allows
    rng = np.random.default_rng(1)
    print(f'{args.pc2}: {n} vertices x {count} frames, step {m * 1e3:.3f} mm')
    print('spacing  parallelogram  least-squares-5  least-squares-10  isometric-grid-axes  isometric  (bits per vertex)')
    for h, scale in ((1, 1.0), (2, 0.75), (4, 0.5), (8, 0.5)):  # cascade's steps per spacing
        step = m * scale
        sums = np.zeros(5)
        picked = [t for t in range(3 * h, count - 3 * h, 2 * h)][:args.frames]
        for t in picked:
            p = (-x[t - 3 * h] + 9 * x[t - h] + 9 * x[t + h] - x[t + 3 * h]) / 16
            r = (x[t] - p).reshape(rows, cols, 3)
            noisy = r + rng.uniform(-step / 2, step / 2, r.shape)
            v = r[2:, 2:-2]

            def tap(dy, dx):
                return noisy[2 - dy:rows - dy, 2 - dx:cols - 2 - dx]

            near = [tap(0, 1), tap(1, 0), tap(1, 1), tap(1, -1), tap(2, -1)]
            far = [tap(0, 2), tap(2, 0), tap(2, 1), tap(1, -2), tap(1, 2)]
            parallelogram = near[0] + near[1] - near[2]
            sums[0] += bits_per_vertex(v - parallelogram, step)
            sums[1] += bits_per_vertex(least_squares(near, v), step)
            sums[2] += bits_per_vertex(least_squares(near + far, v), step)
            # Isometric: corners L and U decoded (with noise), lengths from frame t - h.
            grid, ref = x[t].reshape(rows, cols, 3), x[t - h].reshape(rows, cols, 3)
            decoded = grid + rng.uniform(-step / 2, step / 2, grid.shape)
            sl, sl_l, sl_u = np.s_[2:, 2:-2], np.s_[2:, 1:-3], np.s_[1:-1, 2:-2]
            p0 = (p.reshape(rows, cols, 3)[sl] + parallelogram).reshape(-1, 3)
            la2 = ((ref[sl] - ref[sl_l]) ** 2).sum(-1).reshape(-1, 1)
            lb2 = ((ref[sl] - ref[sl_u]) ** 2).sum(-1).reshape(-1, 1)
            sums[3:] += isometric(p0, decoded[sl_l].reshape(-1, 3), decoded[sl_u].reshape(-1, 3), la2, lb2,
                                 grid[sl].reshape(-1, 3), step)
        k = max(len(picked), 1)
        print(f'{h:7d}  {sums[0] / k:13.2f}  {sums[1] / k:15.2f}  {sums[2] / k:16.2f}  {sums[3] / k:19.2f}  {sums[4] / k:9.2f}')


if __name__ == '__main__':
    main()
