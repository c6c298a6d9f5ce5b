#!/usr/bin/env python3
"""Compares two runs of a study grid (index files as scripts/odometry-study.sh and
scripts/study/rerun-grid.sh write them) cell by cell: ATE % of the path per seed, posed frames,
tracked points, keyframes, tau error at 2 s, then the ATE ratios of the IR modes against none and
affine (median ATE in metres over the seeds, as docs/odometry-study.md) and overall medians.
Standard library only. Usage: compare_grid.py BEFORE_INDEX AFTER_INDEX"""
import json
import statistics
import sys
from collections import defaultdict


def load(index):
    runs = defaultdict(dict)  # (traj, Hz, tau, mode) -> seed -> evaluation or None
    for line in open(index):
        traj, fps, tau, seed, mode, path = line.split()
        runs[(traj, int(fps), float(tau), mode)][seed] = None if path == "FAILED" else json.load(open(path))
    return runs


def med(values):
    values = [v for v in values if v is not None]
    return statistics.median(values) if values else None


def fmt(v, pattern="{:.2f}"):
    return "-" if v is None else pattern.format(v)


def column(cell, key, scale=1.0):
    return [None if cell[s] is None or cell[s].get(key) is None else scale * cell[s][key] for s in sorted(cell)]


before, after = load(sys.argv[1]), load(sys.argv[2])
print("cell | ATE % per seed | posed | tracked points | keyframes | tau err 2 s % (before -> after)")
totals = defaultdict(list)
for key in sorted(before):
    a, b = before[key], after.get(key, {})
    parts = []
    for name, scale, pattern in [("ate_relative", 100, "{:.2f}"), ("posed", 1, "{:.0f}"),
                                 ("tracked_points_total", 1, "{:.0f}"), ("keyframes", 1, "{:.0f}"),
                                 ("tau_c_error_2s", 100, "{:.0f}")]:
        if name == "tau_c_error_2s" and not key[3].startswith("ir"):
            parts.append("")
            continue
        ca, cb = column(a, name, scale), column(b, name, scale)
        totals[name + " before"] += ca
        totals[name + " after"] += cb
        parts.append("/".join(fmt(x, pattern) for x in ca) + " -> " + "/".join(fmt(x, pattern) for x in cb))
    print(f"{key[0]} {key[1]} Hz {key[2] * 1e3:.0f} ms {key[3]} | " + " | ".join(parts))

print("\nATE ratios (median ATE over seeds), before -> after")
print("trajectory Hz tau | ir/none | ir/affine | ir-loop/none | ir-loop/affine")
for traj, fps, tau in sorted({k[:3] for k in before}):
    if (traj, fps, tau, "ir") not in before:
        continue
    cells = []
    for num, den in [("ir", "none"), ("ir", "affine"), ("ir-loop", "none"), ("ir-loop", "affine")]:
        ratios = []
        for runs in (before, after):
            n = med([e and e["ate_rmse_m"] for e in runs.get((traj, fps, tau, num), {}).values()])
            d = med([e and e["ate_rmse_m"] for e in runs.get((traj, fps, tau, den), {}).values()])
            ratios.append(None if n is None or not d else n / d)
        cells.append(fmt(ratios[0]) + " -> " + fmt(ratios[1]))
    print(f"{traj} {fps} Hz {tau * 1e3:.0f} ms | " + " | ".join(cells))

print("\noverall medians, before -> after")
for name in ["ate_relative", "posed", "tracked_points_total", "tau_c_error_2s"]:
    print(f"{name}: {fmt(med(totals[name + ' before']), '{:.3f}')} -> {fmt(med(totals[name + ' after']), '{:.3f}')}")
