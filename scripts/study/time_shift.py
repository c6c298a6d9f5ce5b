#!/usr/bin/env python3
"""The ground truth at another instant: each pose of TRUTH (TUM) keeps its time stamp t but holds
the camera's pose at t - SHIFT_S, interpolated between the truth's poses (position linear,
rotation slerp); stamps whose t - SHIFT_S falls outside the truth are left out. `bolo evaluate RUN
--truth OUT` then scores the run as if its poses stood SHIFT_S earlier than the truth's own
instants (bolo evaluate associates by nearest time, so the stamps must stay).

  time_shift.py TRUTH SHIFT_S OUT"""
import sys

import numpy as np


def slerp(q0, q1, w):
    """Unit quaternions (x, y, z, w) q0 -> q1 at weight w, the short way."""
    d = float(np.dot(q0, q1))
    if d < 0:
        q1, d = -q1, -d
    if d > 0.9995:
        q = q0 + w * (q1 - q0)
        return q / np.linalg.norm(q)
    theta = np.arccos(d)
    return (np.sin((1 - w) * theta) * q0 + np.sin(w * theta) * q1) / np.sin(theta)


def read_tum(path):
    """TUM lines as an (N, 8) array: t, position, quaternion (x, y, z, w)."""
    rows = np.array([[float(v) for v in line.split()] for line in open(path)
                     if line.strip() and not line.startswith("#")])
    if rows.ndim != 2 or rows.shape[1] != 8 or len(rows) < 2:
        sys.exit(f"time_shift: {path}: expected TUM lines of 8 numbers, at least two")
    return rows


def pose_at(rows, at):
    """The interpolated (position, quaternion) at time `at`, None outside the poses' span."""
    t = rows[:, 0]
    if at < t[0] - 1e-9 or at > t[-1] + 1e-9:
        return None
    j = int(np.clip(np.searchsorted(t, at) - 1, 0, len(t) - 2))
    w = float(np.clip((at - t[j]) / (t[j + 1] - t[j]), 0.0, 1.0))
    return (1 - w) * rows[j, 1:4] + w * rows[j + 1, 1:4], slerp(rows[j, 4:8], rows[j + 1, 4:8], w)


def main():
    if len(sys.argv) != 4:
        sys.exit("usage: time_shift.py TRUTH SHIFT_S OUT")
    truth, shift, out = sys.argv[1], float(sys.argv[2]), sys.argv[3]
    rows = read_tum(truth)
    lines = []
    for stamp in rows[:, 0]:
        pose = pose_at(rows, stamp - shift)
        if pose is not None:
            lines.append(f"{stamp:.9f} " + " ".join(f"{v:.9f}" for v in (*pose[0], *pose[1])))
    with open(out, "w") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
