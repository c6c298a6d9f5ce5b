#!/usr/bin/env python3
"""The instant a run's orientations stand for, against the truth: for each shift of a grid, the
rms angle between the estimate's rotation over GAP seconds (frame i to the frame GAP later, in the
camera) and the truth's over the same frames' instants (the truth's stamps) taken SHIFT earlier
(time_shift.pose_at). A pose
that stands for t - d turns like the truth taken d earlier, so the rms is least at shift d; the
rotation over a short interval needs neither the world's alignment nor the scale.

  rotation_time.py RUN_TUM TRUTH_TUM [GAP_S [FROM_MS TO_MS STEP_MS]]

Prints the best shift (ms) and the rms angle (deg) there and at 0."""
import sys

import numpy as np

from time_shift import pose_at, read_tum


def rotation(q):
    x, y, z, w = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def angle_deg(R):
    return np.degrees(np.arccos(np.clip((np.trace(R) - 1) / 2, -1.0, 1.0)))


def rms_by_shift(est, truth, gap, shifts):
    """{shift_s: rms angle in degrees} over the estimate's pose pairs GAP apart; shifts are from
    the truth's own instant of each pose's frame (its nearest truth stamp, as bolo evaluate
    associates them)."""
    stamps = truth[:, 0]
    nearest = np.abs(stamps[None, :] - est[:, :1]).argmin(axis=1)
    t = stamps[nearest]
    pairs = []
    for i in range(len(t)):
        j = int(np.searchsorted(t, t[i] + gap - 1e-6))
        if j < len(t) and abs(t[j] - t[i] - gap) < 0.25 * gap:
            pairs.append((i, j))
    out = {}
    for s in shifts:
        errors = []
        for i, j in pairs:
            a, b = pose_at(truth, t[i] - s), pose_at(truth, t[j] - s)
            if a is None or b is None:
                continue
            rel_est = rotation(est[i, 4:8]).T @ rotation(est[j, 4:8])
            rel_true = rotation(a[1]).T @ rotation(b[1])
            errors.append(angle_deg(rel_est.T @ rel_true))
        out[s] = float(np.sqrt(np.mean(np.square(errors)))) if errors else float("inf")
    return out


def best_shift(run_tum, truth_tum, gap=0.1, grid_ms=(-10.0, 20.0, 0.5)):
    """(best shift ms, rms deg there, rms deg at 0)."""
    shifts = list(np.arange(grid_ms[0], grid_ms[1] + 1e-9, grid_ms[2]) * 1e-3)
    rms = rms_by_shift(read_tum(run_tum), read_tum(truth_tum), gap, shifts + [0.0])
    best = min(shifts, key=lambda s: rms[s])
    return 1e3 * best, rms[best], rms[0.0]


if __name__ == "__main__":
    if len(sys.argv) not in (3, 4, 7):
        sys.exit("usage: rotation_time.py RUN_TUM TRUTH_TUM [GAP_S [FROM_MS TO_MS STEP_MS]]")
    gap = float(sys.argv[3]) if len(sys.argv) > 3 else 0.1
    grid = tuple(float(v) for v in sys.argv[4:7]) if len(sys.argv) == 7 else (-10.0, 20.0, 0.5)
    print("best shift %.1f ms: rms %.4f deg (at 0: %.4f deg)" % best_shift(sys.argv[1], sys.argv[2], gap, grid))
