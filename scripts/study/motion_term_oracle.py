#!/usr/bin/env python3
"""How well the diagnosis baseline models motion within the exposure, against the second generator's truth.

Writes a null recording with scripts/study/independent_generator.py, runs the study harness
`diagnose_motion_term_experiment` (built with -DBOLO_BUILD_STUDIES=ON) on it, and compares with
the generator's noise-free output and its sub-step inputs:
  * the baseline's miss of the noise-free output, and the miss with the generator's exact
    within-exposure term (output less the output of the exposure's even average) in place of the
    baseline's own term;
  * the exact term's form: the even average moved in time by the exposure's lateness against the
    pixel's weighting of its sub-steps (frames 5-64);
  * the baseline's term against the exact one;
  * the flow at the leading rims of the moving discs: the normal component's error.

usage: motion_term_oracle.py HARNESS WORKDIR [--seed S] [--kind mean_change] [--size WxH] [--frames N]
"""
import argparse
import json
import math
import os
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import independent_generator as g  # noqa: E402


def chain_for(seed, kind, w, h, n, substeps=6, jitter=0.003):
    """The generator's chain for a null, built as its generate() builds it."""
    timing = g.Timing(seed, n, [], jitter=jitter)
    scene = g.Scene(seed, w, h, float(timing.t[-1] + timing.exposure[-1]), kind)
    chain = g.Chain(seed, w, h, n, "null:" + kind, timing, scene, substeps)
    chain.reference_level = float(np.median(chain.inputs(0)))
    return chain


def disc_centre(b, t):
    return (b["c0"][0] + b["amp"][0] * math.sin(b["omega"][0] * t + b["phase"][0]),
            b["c0"][1] + b["amp"][1] * math.sin(b["omega"][1] * t + b["phase"][1]))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("harness")
    ap.add_argument("work")
    ap.add_argument("--seed", type=int, default=3)
    ap.add_argument("--kind", default="mean_change", choices=g.NULL_KINDS)
    ap.add_argument("--size", default="160x120")
    ap.add_argument("--frames", type=int, default=300)
    a = ap.parse_args()
    w, h = map(int, a.size.split("x"))
    rec = os.path.join(a.work, f"null-{a.kind}-s{a.seed}")
    g.generate(rec, "null:" + a.kind, 1.0, a.seed, w, h, a.frames)
    out = rec + ".motion"
    fit = json.loads(subprocess.run([a.harness, rec, out], check=True, capture_output=True, text=True).stdout)
    base = np.load(os.path.join(out, "baseline.npy")).astype(np.float64)
    within = np.load(os.path.join(out, "within_exposure.npy")).astype(np.float64)
    flow_dy = np.load(os.path.join(out, "flow_dy.npy"))
    flow_dx = np.load(os.path.join(out, "flow_dx.npy"))

    chain = chain_for(a.seed, a.kind, w, h, a.frames)
    truth = chain.run(None, noise=False)
    sub = chain._inputs.copy()
    chain._inputs[:] = sub.mean(axis=1, keepdims=True)
    even = chain.run(None, noise=False)
    chain._inputs[:] = sub
    exact = truth - even
    rms = lambda x: float(np.sqrt(np.mean(x * x)))
    corr = lambda x, y: float(np.corrcoef(x.ravel(), y.ravel())[0, 1])
    print(f"recording {rec} (seed {a.seed}, {a.kind}, {a.size}, {a.frames} frames); baseline: "
          f"exposure_motion share {fit['params'].get('exposure_motion', 0):.3f}, "
          f"timing shift {fit['params'].get('timing_shift_frames', 0):.3f} frames")
    print("| measure | value |\n|---|---|")
    print(f"| baseline's miss of the noise-free output, counts RMS | {rms(truth - base):.3f} |")
    print(f"| the same with the exact within-exposure term in place of its own | {rms(truth - (base - within + exact)):.3f} |")
    print(f"| the exact term, counts RMS | {rms(exact):.3f} |")
    print(f"| the baseline's term against the exact one: correlation | {corr(within, exact):.4f} |")

    tm, sc = chain.timing, chain.scene
    K = chain.substeps
    lagged, weighed = [], []
    for i in range(5, min(65, a.frames)):
        d = tm.exposure[i] / K
        times = tm.t[i] + (np.arange(K) + 0.5) * d
        weights = np.exp(-(tm.exposure[i] - (np.arange(K) + 0.5) * d) / tm.tau_h)
        weights /= weights.sum()
        lateness = float((weights * times).sum() - times.mean())
        frames = sub[i]
        weighed.append((weights[:, None, None] * frames).sum(0) - frames.mean(0))
        lagged.append(np.mean([sc.render(t + lateness) for t in times], axis=0) - frames.mean(0))
    weighed, lagged = np.array(weighed), np.array(lagged)
    print(f"| the even average moved by the lateness against the weighted sub-steps: correlation (frames 5-64) | {corr(lagged, weighed):.5f} |")
    print(f"| its miss against the weighted sub-steps' {rms(weighed):.2f} counts RMS | {rms(lagged - weighed):.3f} |")

    print("\n| disc (radius, px) | normal speed at the leading rim, px/frame (median) | flow's normal error (median) | error > 0.5 px |")
    print("|---|---|---|---|")
    for b in sc.blobs:
        speed, err, big = [], [], []
        for i in range(5, min(200, a.frames - 1)):
            t0 = tm.t[i] + tm.exposure[i] / 2
            t1 = tm.t[i + 1] + tm.exposure[i + 1] / 2
            (cx, cy), (nx, ny) = disc_centre(b, t0), disc_centre(b, t1)
            vx, vy = nx - cx, ny - cy
            dist = np.hypot(sc.xx - nx, sc.yy - ny)
            # The flow is read on frame i + 1's pixels: the rim where the disc arrives.
            rim = (np.abs(dist - b["radius"]) < 1.0) & (((sc.xx - nx) * vx + (sc.yy - ny) * vy) > 0.5 * np.hypot(vx, vy) * dist)
            if not rim.any():
                continue
            ux, uy = (sc.xx[rim] - nx) / dist[rim], (sc.yy[rim] - ny) / dist[rim]
            e = np.abs((flow_dx[i][rim] - vx) * ux + (flow_dy[i][rim] - vy) * uy)
            speed.append(np.median(np.abs(vx * ux + vy * uy)))
            err.append(np.median(e))
            big.append(np.mean(e > 0.5))
        if speed:
            print(f"| {b['radius']:.1f} | {np.median(speed):.2f} | {np.median(err):.2f} | {np.mean(big):.0%} |")


if __name__ == "__main__":
    main()
