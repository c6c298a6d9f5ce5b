#!/usr/bin/env python3
"""The carry-over pair fit of firmware/vo/src/tau_estimator.cpp against a one-dimensional
generator that shares no code with bolo.

A line camera looks at a band-limited random texture. Each pixel is a first-order lag of the
radiance it sees, either sampled once a period (the paper's model: y_i = a y_(i-1) + (1 - a) u_i)
or integrated over the period in SUBSTEPS steps while the camera moves (a continuous lag).
Points with known positions give the estimator's pairs

    A = y_i(p_i) - y_(i-1)(p_(i-1)),   B = y_(i-1)(p_i) - y_(i-2)(p_(i-1)),   alpha = sum AB / sum BB

read either exactly (each pixel value computed at the point's position) or by Keys' cubic
from the integer pixels. The points' positions are taken at the read time, or at the mean time
of the period weighted by the pixel's response (the time a tracker fitting the corrected frames
places the pose at). --smear-change takes the change of the smear's spread between the frames
out of A, from the true texture and velocities. Prints tau from the fit, the true tau, and the signal's share
B^2 / (A - alpha B)^2 at the true alpha.
"""
import argparse

import numpy as np

from lag_pairs import PairFit, substeps


def keys(t):
    t = np.abs(t)
    return np.where(t < 1, (1.5 * t - 2.5) * t * t + 1, np.where(t < 2, ((-0.5 * t + 2.5) * t - 4) * t + 2, 0))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--motion", choices=["shake", "zoom"], default="shake",
                    help="shake: sideways with a changing speed; zoom: towards a frontal plane")
    ap.add_argument("--substeps", type=int, default=8, help="1: the sampled lag; more: a continuous lag")
    ap.add_argument("--positions", choices=["read", "response"], default="response",
                    help="the points' positions at the read time or at the response-weighted mean time")
    ap.add_argument("--sampling", choices=["exact", "cubic"], default="exact")
    ap.add_argument("--cutoff", type=float, default=0.1, help="texture's Gaussian cut, cycles per pixel")
    ap.add_argument("--speed", type=float, default=60.0, help="shake: px/s of drift; zoom: m/s towards 30 m")
    ap.add_argument("--tau", type=float, default=0.010, help="seconds")
    ap.add_argument("--fps", type=float, default=60.0)
    ap.add_argument("--footprint", type=int, default=1,
                    help="point samples across a pixel's width whose mean is its value (1: a point)")
    ap.add_argument("--smear-change", action="store_true",
                    help="subtract the smear's second-order change between the two frames from A (an oracle: the "
                         "true texture and velocities)")
    ap.add_argument("--seed", type=int, default=3)
    a = ap.parse_args()

    rng = np.random.default_rng(a.seed)
    T, tau, K = 1 / a.fps, a.tau, a.substeps
    f, z0, step = 300.0, 30.0, 0.0005
    xs = np.arange(-60, 60, step)
    spectrum = rng.normal(size=xs.size) + 1j * rng.normal(size=xs.size)
    spectrum *= np.exp(-(np.fft.fftfreq(xs.size, d=step) / (a.cutoff * f / z0)) ** 2)
    texture = np.real(np.fft.ifft(spectrum))
    texture *= 100 / texture.std()

    if a.motion == "zoom":
        def to_scene(x, t): return x * (z0 - a.speed * t) / f
        def to_image(X, t): return f * X / (z0 - a.speed * t)
    else:
        def shift(t): return (a.speed * t + 3 * np.sin(2 * np.pi * 1.3 * t) + 2 * np.sin(2 * np.pi * 0.7 * t + 1)) * z0 / f
        def to_scene(x, t): return x * z0 / f + shift(t)
        def to_image(X, t): return (X - shift(t)) * f / z0

    alpha = np.exp(-T / tau)
    keep, mean_age, spread = substeps(K, T, tau)

    offsets = (np.arange(a.footprint) + 0.5) / a.footprint - 0.5

    def frame(j, x, history=10):
        """Frame j's values at pixel positions x (alpha^history of the start is left)."""
        if a.footprint > 1:
            return np.mean([point_frame(j, x + o, history) for o in offsets], axis=0)
        return point_frame(j, x, history)

    def point_frame(j, x, history):
        v = np.zeros_like(x)
        for m in range(j - history, j + 1):
            if K == 1:
                v = alpha * v + (1 - alpha) * np.interp(to_scene(x, m * T), xs, texture)
            else:
                for k in range(K):
                    v = keep * v + (1 - keep) * np.interp(to_scene(x, m * T - T + (k + 1) * T / K), xs, texture)
        return v

    pixels = np.arange(-170.0, 171.0)
    cache = {}

    def sample(j, p):
        if a.sampling == "exact":
            return frame(j, p)
        if j not in cache:
            cache[j] = frame(j, pixels)
        idx = p + 170.0
        x0 = np.floor(idx).astype(int)
        return sum(keys(idx - (x0 + q)) * cache[j][x0 + q] for q in range(-1, 3))

    delay = mean_age if a.positions == "response" else 0.0
    def smear_change(X, t):
        """The smear's second-order change from frame i - 1 to i at scene points X (the first
        order is gone at the response-weighted time): Var(age) / 2 (v_i^2 u_i'' - v_(i-1)^2 u_(i-1)''), each frame's u'' in its own pixels."""
        h, dx = 1e-4, 0.01

        def velocity(tt):
            return (to_image(X, tt + h) - to_image(X, tt - h)) / (2 * h)

        def curvature(tt):  # u'' in image pixels at time tt
            step = dx * (to_scene(1.0, tt) - to_scene(0.0, tt))
            return (np.interp(X + step, xs, texture) - 2 * np.interp(X, xs, texture) + np.interp(X - step, xs, texture)) / dx ** 2
        return 0.5 * spread * (velocity(t) ** 2 * curvature(t) - velocity(t - T) ** 2 * curvature(t - T))

    pairs = PairFit(alpha)
    for i in range(12, 120):
        t = i * T - delay
        X = to_scene(rng.uniform(-150, 150, 400), t)
        pi, pm = to_image(X, t), to_image(X, t - T)
        A = sample(i, pi) - sample(i - 1, pm)
        B = sample(i - 1, pi) - sample(i - 2, pm)
        if a.smear_change:
            A = A - (1 - alpha) * smear_change(X, t)
        pairs.add(A, B)
    print(f"{a.motion} substeps {K} positions at {a.positions} ({delay * 1e3:.2f} ms before the read) sampling {a.sampling}"
          f"{' footprint %d' % a.footprint if a.footprint > 1 else ''}{' smear change out' if a.smear_change else ''}: "
          f"{pairs.report(T, tau)}")


if __name__ == "__main__":
    main()
