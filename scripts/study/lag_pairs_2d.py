#!/usr/bin/env python3
"""The carry-over pair fit of firmware/vo/src/tau_estimator.cpp in two dimensions, on a generator
that shares no code with bolo (lag_pairs_1d.py's companion).

A pinhole camera (f = 250 px) looks at a plane 20 m ahead textured with random plane waves, moving
forwards or sideways with a wobble in position and yaw, so that the image velocities change from
frame to frame. Each pixel is a first-order lag of the radiance it sees, sampled once a period or
integrated over the period in SUBSTEPS steps while the camera moves. Every pixel value is computed
exactly at the point's position (no interpolation, no pixel area). The estimator's pairs

    A = y_i(p_i) - y_(i-1)(p_(i-1)),   B = y_(i-1)(p_i) - y_(i-2)(p_(i-1)),   alpha = sum AB / sum BB

are taken with the points at the response-weighted mean time of the period (the instant a pose
fitted to corrected frames stands for) or at the read. --smear-change takes out of A the change of
the smear's spread between the two frames, Var(age) / 2 (v_i' H_i v_i - v_(i-1)' H_(i-1) v_(i-1)),
from the true texture (H: the image's Hessian at the point, v: its image velocity). Prints tau from
the fit and the signal's share B^2 / (A - alpha B)^2 at the true alpha.
"""
import argparse

import numpy as np

from lag_pairs import PairFit, substeps


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--motion", choices=["forward", "side"], default="forward")
    ap.add_argument("--substeps", type=int, default=8, help="1: the sampled lag; more: a continuous lag")
    ap.add_argument("--positions", choices=["read", "response"], default="response")
    ap.add_argument("--smear-change", action="store_true",
                    help="take the change of the smear's spread out of A (an oracle: the true texture)")
    ap.add_argument("--cutoff", type=float, default=0.2, help="texture's highest frequency, cycles per pixel at 10 m")
    ap.add_argument("--tau", type=float, default=0.010, help="seconds")
    ap.add_argument("--fps", type=float, default=60.0)
    ap.add_argument("--frames", type=int, default=60, help="frames whose pairs are fitted")
    ap.add_argument("--seed", type=int, default=5)
    a = ap.parse_args()

    rng = np.random.default_rng(a.seed)
    T, tau, K, f, plane_z = 1 / a.fps, a.tau, a.substeps, 250.0, 20.0
    waves = 300
    direction = rng.normal(size=(waves, 2))
    direction /= np.linalg.norm(direction, axis=1)[:, None]
    wavenumber = 2 * np.pi * direction * (rng.uniform(0.05, 1.0, waves) * a.cutoff * f / 10.0)[:, None]
    phase = rng.uniform(0, 2 * np.pi, waves)
    amplitude = 140 / np.sqrt(waves)

    def texture(u, w):
        return amplitude * np.cos(np.multiply.outer(u, wavenumber[:, 0]) + np.multiply.outer(w, wavenumber[:, 1]) + phase).sum(-1)

    def camera(t):  # position (m) and yaw (rad); the camera looks along +z at the plane z = plane_z
        if a.motion == "forward":
            return np.array([0.3 * np.sin(5.65 * t), 0.2 * np.sin(8.17 * t + 1), 10 * t]), 0.02 * np.sin(4.4 * t)
        return np.array([3 * t + 0.5 * np.sin(6.9 * t), 0.3 * np.sin(5.0 * t), 0.0]), 0.03 * np.sin(3.8 * t)

    def to_plane(x, y, t):
        c, yaw = camera(t)
        cy, sy = np.cos(yaw), np.sin(yaw)
        dx, dy, dz = cy * x / f + sy, y / f, -sy * x / f + cy
        s = (plane_z - c[2]) / dz
        return c[0] + s * dx, c[1] + s * dy

    def to_image(u, w, t):
        c, yaw = camera(t)
        cy, sy = np.cos(yaw), np.sin(yaw)
        px, py, pz = u - c[0], w - c[1], plane_z - c[2]
        xc, zc = cy * px - sy * pz, sy * px + cy * pz
        return f * xc / zc, f * py / zc

    alpha = np.exp(-T / tau)
    keep, mean_age, spread = substeps(K, T, tau)

    def frame(j, x, y, history=8):
        v = np.zeros_like(x)
        for m in range(j - history, j + 1):
            if K == 1:
                v = alpha * v + (1 - alpha) * texture(*to_plane(x, y, m * T))
            else:
                for k in range(K):
                    v = keep * v + (1 - keep) * texture(*to_plane(x, y, m * T - T + (k + 1) * T / K))
        return v

    delay = mean_age if a.positions == "response" else 0.0

    def smear(u, w, t):
        """Var(age) / 2 v' H v at the scene points (u, w) in the frame whose instant is t."""
        h, e = 1e-4, 0.05
        xa, ya = to_image(u, w, t + h)
        xb, yb = to_image(u, w, t - h)
        vx, vy = (xa - xb) / (2 * h), (ya - yb) / (2 * h)
        x0, y0 = to_image(u, w, t)

        def image(dx, dy):
            return texture(*to_plane(x0 + dx, y0 + dy, t))
        centre = image(0, 0)
        hxx = (image(e, 0) - 2 * centre + image(-e, 0)) / e ** 2
        hyy = (image(0, e) - 2 * centre + image(0, -e)) / e ** 2
        hxy = (image(e, e) - image(e, -e) - image(-e, e) + image(-e, -e)) / (4 * e * e)
        return 0.5 * spread * (vx * vx * hxx + 2 * vx * vy * hxy + vy * vy * hyy)

    pairs = PairFit(alpha)
    moved = 0.0
    for i in range(12, 12 + a.frames):
        t = i * T - delay
        u, w = to_plane(rng.uniform(-120, 120, 300), rng.uniform(-100, 100, 300), t)
        xi, yi = to_image(u, w, t)
        xp, yp = to_image(u, w, t - T)
        A = frame(i, xi, yi) - frame(i - 1, xp, yp)
        B = frame(i - 1, xi, yi) - frame(i - 2, xp, yp)
        if a.smear_change:
            A = A - (1 - alpha) * (smear(u, w, t) - smear(u, w, t - T))
        pairs.add(A, B)
        moved += np.hypot(xi - xp, yi - yp).mean()
    print(f"{a.motion} substeps {K} positions at {a.positions} ({delay * 1e3:.2f} ms before the read)"
          f"{' smear change out' if a.smear_change else ''}: {moved / a.frames:.2f} px a frame, "
          f"{pairs.report(T, tau)}")


if __name__ == "__main__":
    main()
