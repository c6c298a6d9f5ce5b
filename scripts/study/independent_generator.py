#!/usr/bin/env python3
"""A second recording generator for the diagnosis study, independent of bolo's simulator.

It shares no code with sim/simulator, sim/scene or sim/effects: the scene model, the sensor and
every effect are written here from ../shared/docs/diagnosis.md (the baseline two-frame model, the
effect catalogue) and the recording is written as ../shared/docs/recording-format.md states.

Scene: a smooth random background (power-law spectrum) seen through a slow pan, soft-edged hot
and cold blobs on oscillating paths, and for some null cases a changing mean level, a hot object
entering or shutter events. Sensor, per pixel and frame i:

    I_i = I_{i-1} exp(-t_r,i-1 / tau_c) + H_i,   H_i = the exposure's heating integral

where H_i integrates the input sampled at `substeps` times within the exposure (the scene moves
during it) with the pixel's response exp(-(t_e - t) / tau_h): for a constant input it is
I_ss (1 - exp(-t_e,i / tau_h)). Each frame's exposure and readout are jittered (a relative
spread of `jitter`) and logged exactly in frames.csv. The output is I scaled to unit gain in
steady state at the nominal timing (so scene.npy, the exposure average of the input, is what a
settled pixel reads), then the effect, white readout noise, the core's processing, rounding.

One catalogue effect (or none, or a pattern outside the catalogue) per recording. Its amplitude
is given in units of the pixel noise sigma: for static maps and offsets the natural size (a
pattern's sigma, a step, the drift's excursion); for effects that depend on the scene, the 99th
percentile of the effect's noise-free contribution over all pixel-frames after a global gain and
offset are taken out (which the baseline fit absorbs), found by running the chain once at a
reference parameter and scaling it (the effects are close to linear at these sizes).

usage: independent_generator.py OUT --case effect:ID|null:KIND|ooc:KIND [--amplitude A]
                                [--seed S] [--size WxH] [--frames N] [--ffc-unknown] [--no-noise]
                                [--jitter J]
Writes OUT/{recording.json,frames.npy,frames.csv,scene.npy,truth/effects.json}.
"""
import argparse
import json
import math
import os
import shutil

import numpy as np

EFFECTS = ["offset_fpn", "column_fpn", "row_fpn", "shading", "gain_fpn", "fpa_drift", "ffc_step",
           "thermal_memory", "tau_temperature", "tau_spread", "rolling_readout", "crosstalk",
           "nonlinearity", "temporal_filter", "dead_pixels", "frame_duplication", "agc"]
NULL_KINDS = ["mean_change", "pan_hot_entry", "shutter"]
OOC_KINDS = ["interference", "telegraph_pixels", "ghost"]
BITS = 14
NOISE_SIGMA = 2.5  # white readout noise, counts
# Effects whose size depends on the scene: their parameter is scaled to the requested amplitude.
SCENE_DEPENDENT = {"thermal_memory", "tau_temperature", "tau_spread", "rolling_readout", "crosstalk",
                   "nonlinearity", "temporal_filter", "agc", "ghost"}


def rng_for(seed, tag):
    """An independent random stream per purpose, so adding one draw changes no other."""
    return np.random.default_rng(np.random.SeedSequence([seed, sum(ord(c) * 131 ** i for i, c in enumerate(tag)) % 2**32]))


class Timing:
    """Nominal timing, per-frame jittered exposure and readout, shutter events and their gaps."""

    def __init__(self, seed, frames, events=(), shutter_gap_s=0.3, jitter=0.003):
        r = rng_for(seed, "timing")
        self.fps = float(r.choice([25.0, 30.0]))
        period = 1.0 / self.fps
        self.exposure0 = period * float(r.uniform(0.3, 0.5))
        self.readout0 = period - self.exposure0
        self.tau_h = float(r.uniform(0.009, 0.013))
        self.tau_c = float(r.uniform(0.009, 0.013))
        self.jitter = jitter
        z = np.clip(r.standard_normal((frames, 2)), -3, 3)
        self.exposure = self.exposure0 * (1 + jitter * z[:, 0])
        self.readout = self.readout0 * (1 + jitter * z[:, 1])
        self.events = sorted(events)
        self.t = np.zeros(frames)
        for i in range(1, frames):
            self.t[i] = self.t[i - 1] + self.exposure[i - 1] + self.readout[i - 1]
            if i in self.events:
                self.t[i] += shutter_gap_s
        # The nominal pixel's steady-state gain (heating over cooling): output = I / kappa0.
        self.kappa0 = self.kappa(self.tau_h, self.tau_c)

    def kappa(self, tau_h, tau_c):
        return (1 - np.exp(-self.exposure0 / tau_h)) / (1 - np.exp(-self.readout0 / tau_c))


def smooth_field(r, h, w, slope=3.0, cutoff=0.35):
    """Zero-mean, unit-std random field with a power-law spectrum (1/f^slope), band-limited."""
    fy = np.fft.fftfreq(h)[:, None]
    fx = np.fft.rfftfreq(w)[None, :]
    f = np.sqrt(fx * fx + fy * fy)
    amp = np.where(f > 0, (np.maximum(f, 1.0 / max(h, w))) ** (-slope / 2), 0.0) * np.exp(-(f / cutoff) ** 2)
    spec = (r.standard_normal(f.shape) + 1j * r.standard_normal(f.shape)) * amp
    field = np.fft.irfft2(spec, s=(h, w))
    return (field - field.mean()) / field.std()


class Scene:
    """The input I_ss as a function of time; `t` may be a scalar or a (H, 1) array (one time per row)."""

    def __init__(self, seed, w, h, duration, kind="base"):
        r = rng_for(seed, "scene")
        self.w, self.h = w, h
        self.level = float(r.uniform(5000, 7000))
        self.bg_std = float(r.uniform(150, 400))
        ang = r.uniform(0, 2 * math.pi)
        speed = r.uniform(2, 6) if kind != "pan_hot_entry" else r.uniform(1, 2.5)  # pixels per second
        self.pan_v = (speed * math.cos(ang), speed * math.sin(ang))
        self.pan_wobble = (r.uniform(0.5, 2.0), r.uniform(0.1, 0.4), r.uniform(0, 2 * math.pi))
        margin = int(math.ceil(speed * duration + 2 * self.pan_wobble[0])) + 4
        self.margin = margin
        self.canvas = self.level + self.bg_std * smooth_field(r, h + 2 * margin, w + 2 * margin)
        self.yy, self.xx = np.mgrid[0:h, 0:w].astype(np.float64)
        self.blobs = []
        for _ in range(int(r.integers(3, 6))):
            self.blobs.append(dict(
                c0=(r.uniform(0.2, 0.8) * w, r.uniform(0.2, 0.8) * h),
                amp=(r.uniform(0.15, 0.4) * w, r.uniform(0.15, 0.4) * h),
                omega=(r.uniform(0.4, 2.0), r.uniform(0.4, 2.0)),
                phase=(r.uniform(0, 2 * math.pi), r.uniform(0, 2 * math.pi)),
                radius=r.uniform(3, 10), edge=r.uniform(0.5, 1.5),
                contrast=float(r.choice([-1, 1]) * r.uniform(300, 2500))))
        self.kind = kind
        self.duration = duration
        self.mean_step = float(r.choice([-1, 1]) * r.uniform(150, 400)) if kind == "mean_change" else 0.0
        self.mean_t0 = float(r.uniform(0.3, 0.6) * duration)
        self.entry = None
        if kind == "pan_hot_entry":
            side = int(r.integers(4))
            t_in = float(r.uniform(0.3, 0.5) * duration)
            self.entry = dict(side=side, t_in=t_in, speed=float(r.uniform(20, 40)), radius=float(r.uniform(6, 10)),
                              contrast=float(r.uniform(2000, 3500)), depth=float(r.uniform(15, 30)),
                              along=float(r.uniform(0.3, 0.7)))

    def mean_offset(self, t):
        if not self.mean_step:
            return 0.0
        return self.mean_step / (1 + np.exp(-(t - self.mean_t0) / (0.12 * self.duration)))

    @staticmethod
    def _disc(d, radius, edge):
        return 1.0 / (1.0 + np.exp(np.clip((d - radius) / edge, -50, 50)))

    def render(self, t):
        t = np.asarray(t, dtype=np.float64)
        a, f, ph = self.pan_wobble
        ox = self.margin + self.pan_v[0] * t + a * np.sin(2 * math.pi * f * t + ph)
        oy = self.margin + self.pan_v[1] * t + a * np.cos(2 * math.pi * f * t + ph)
        x = self.xx + ox
        y = self.yy + oy
        x0 = np.floor(x).astype(np.int64)
        y0 = np.floor(y).astype(np.int64)
        fx, fy = x - x0, y - y0
        c = self.canvas
        img = ((1 - fy) * ((1 - fx) * c[y0, x0] + fx * c[y0, x0 + 1])
               + fy * ((1 - fx) * c[y0 + 1, x0] + fx * c[y0 + 1, x0 + 1]))
        for b in self.blobs:
            cx = b["c0"][0] + b["amp"][0] * np.sin(b["omega"][0] * t + b["phase"][0])
            cy = b["c0"][1] + b["amp"][1] * np.sin(b["omega"][1] * t + b["phase"][1])
            d = np.sqrt((self.xx - cx) ** 2 + (self.yy - cy) ** 2)
            img = img + b["contrast"] * self._disc(d, b["radius"], b["edge"])
        if self.entry is not None:
            e = self.entry
            depth = np.clip((t - e["t_in"]) * e["speed"], -3 * e["radius"], e["depth"])  # pixels inside the frame
            along = e["along"]
            if e["side"] == 0:
                cx, cy = depth - e["radius"], along * self.h
            elif e["side"] == 1:
                cx, cy = self.w - 1 - depth + e["radius"], along * self.h
            elif e["side"] == 2:
                cx, cy = along * self.w, depth - e["radius"]
            else:
                cx, cy = along * self.w, self.h - 1 - depth + e["radius"]
            d = np.sqrt((self.xx - cx) ** 2 + (self.yy - cy) ** 2)
            img = img + e["contrast"] * self._disc(d, e["radius"], 0.8)
        return img + self.mean_offset(t)


def fpa_trace(seed, t, warm):
    """FPA and housing temperatures: a warm-up towards a plateau plus a slow random walk."""
    r = rng_for(seed, "fpa")
    t0 = float(r.uniform(28, 34))
    rise = float(r.uniform(0.3, 0.8)) * (3.0 if warm else 1.0)
    tau = float(r.uniform(20, 60))
    walk = np.cumsum(r.standard_normal(len(t))) * 0.002
    fpa = t0 + rise * (1 - np.exp(-t / tau)) + walk
    housing = t0 - 2.0 + 0.6 * rise * (1 - np.exp(-t / (2 * tau)))
    return fpa, housing


class Chain:
    """The sensor and the one effect; `run` gives the output frames (float, before rounding)."""

    def __init__(self, seed, w, h, n, case, timing, scene, substeps):
        self.seed, self.w, self.h, self.n = seed, w, h, n
        self.case = case
        self.timing, self.scene, self.substeps = timing, scene, substeps
        self.kind, self.name = case.split(":", 1)
        self._inputs = None
        self.reference_level = None

    def inputs(self, i, row_delay=None):
        """The input at the frame's sub-steps, shape (K, H, W); rows later by `row_delay` seconds."""
        tm = self.timing
        d = tm.exposure[i] / self.substeps
        times = tm.t[i] + (np.arange(self.substeps) + 0.5) * d
        if row_delay is None:
            if self._inputs is None:
                self._inputs = np.empty((self.n, self.substeps, self.h, self.w), np.float32)
                self._done = np.zeros(self.n, bool)
            if not self._done[i]:
                for k, tk in enumerate(times):
                    self._inputs[i, k] = self.scene.render(tk)
                self._done[i] = True
            return self._inputs[i].astype(np.float64)
        rows = (np.arange(self.h, dtype=np.float64) * row_delay)[:, None]
        return np.stack([self.scene.render(tk + rows) for tk in times])

    def scene_frames(self):
        return np.stack([self.inputs(i).mean(axis=0) for i in range(self.n)]).astype(np.float32)

    def run(self, p, noise=True):
        """Output frames for effect parameters `p` (None: no effect)."""
        tm, sc = self.timing, self.scene
        h, w, n = self.h, self.w, self.n
        eid = self.name if p is not None else None
        nr = rng_for(self.seed, "noise")
        out = np.empty((n, h, w), np.float64)
        if self.reference_level is None:
            self.reference_level = float(np.median(self.inputs(0)))
        y0 = self.reference_level
        tau_h = np.full((h, w), tm.tau_h)
        tau_c = np.full((h, w), tm.tau_c)
        if eid == "tau_spread":
            tau_h = tau_h * p["factor"]
            tau_c = tau_c * p["factor"]
        kappa = tm.kappa(tau_h, tau_c)
        state = None
        x2 = None
        filt = None
        agc_state = None
        ffc_ref_temp = p["fpa"][0] if p is not None and "fpa" in p else None
        for i in range(n):
            u = self.inputs(i, p["line_time_s"] if eid == "rolling_readout" else None)
            ubar = u.mean(axis=0)
            if eid == "tau_temperature" and state is not None:
                level = state / tm.kappa0
                factor = np.maximum(0.2, 1 + p["gamma"] * (level - y0))
                tau_h, tau_c = tm.tau_h * factor, tm.tau_c * factor
            if state is None or i in tm.events:
                # Settled on the first frame's input (the camera ran before it), or on the closed
                # shutter, which sits at the background's level, for a shutter event.
                level = ubar if state is None else np.full((h, w), float(np.median(u)))
                if eid == "tau_temperature":
                    factor = np.maximum(0.2, 1 + p["gamma"] * (level - y0))
                    tau_h, tau_c = tm.tau_h * factor, tm.tau_c * factor
                state = level * tm.kappa(tau_h, tau_c)
                carry = state * np.exp(-tm.readout0 / tau_c)
            else:
                carry = state * np.exp(-tm.readout[i - 1] / tau_c)
            keep = np.exp(-(tm.exposure[i] / self.substeps) / tau_h)
            heat = np.zeros((h, w))
            for k in range(self.substeps):
                heat = heat * keep + u[k] * (1 - keep)
            state = carry + heat
            # The camera's calibration makes every pixel read its input in steady state at the
            # nominal timing: per pixel for a spread of tau, per level for a level-dependent tau.
            if eid == "tau_temperature":
                level = state / tm.kappa0
                factor = np.maximum(0.2, 1 + p["gamma"] * (level - y0))
                y = state / tm.kappa(tm.tau_h * factor, tm.tau_c * factor)
            else:
                y = state / kappa
            if eid == "thermal_memory":
                if x2 is None:
                    x2 = p["weight"] * ubar
                else:
                    a2 = math.exp(-(tm.t[i] - tm.t[i - 1]) / p["tau2_s"])
                    x2 = a2 * x2 + (1 - a2) * p["weight"] * ubar
                y = y + x2
            if eid == "crosstalk":
                q = np.pad(y, 1, mode="edge")
                y = (1 - p["epsilon"]) * y + p["epsilon"] * 0.25 * (q[:-2, 1:-1] + q[2:, 1:-1] + q[1:-1, :-2] + q[1:-1, 2:])
            if eid == "nonlinearity":
                y = y - p["c"] * (y - y0) ** 2
            if eid == "gain_fpn":
                y = y * (1 + p["map"])
            if eid in ("offset_fpn", "column_fpn", "row_fpn", "shading"):
                y = y + p["map"]
            if eid == "fpa_drift":
                y = y + p["k"] * (p["fpa"][i] - ffc_ref_temp)
            if eid == "ffc_step":
                y = y + p["offsets"][i]
            if self.kind == "ooc" and p is not None:
                y = y + self.out_of_catalogue(p, i, y)
            if noise:
                y = y + NOISE_SIGMA * nr.standard_normal((h, w))
            if eid == "dead_pixels":
                if i == 0:
                    p["stuck"] = y[p["rows"], p["cols"]].copy()
                y[p["rows"], p["cols"]] = p["stuck"]
            if eid == "temporal_filter":
                filt = y if filt is None else p["alpha"] * filt + (1 - p["alpha"]) * y
                y = filt
            if eid == "agc":
                y, agc_state = self.agc(p, y, agc_state)
            out[i] = y
        if eid == "frame_duplication":
            for i in p["frames"]:
                out[i] = out[i - 1]
        return out

    def agc(self, p, y, st):
        """A linear stretch per frame: the p_lo..p_hi percentiles onto a fixed range, followed at `damping`."""
        lo, hi = np.percentile(y, [p["p_lo"], p["p_hi"]])
        target_gain = p["range"] / max(hi - lo, 1.0)
        if st is None:
            st = (target_gain, lo)
        else:
            st = (st[0] + p["damping"] * (target_gain - st[0]), st[1] + p["damping"] * (lo - st[1]))
        return p["floor"] + st[0] * (y - st[1]), st

    def out_of_catalogue(self, p, i, y):
        tm = self.timing
        if self.name == "interference":
            phase = 2 * math.pi * (p["kx"] * self.scene.xx + p["ky"] * self.scene.yy - p["hz"] * tm.t[i])
            return p["amplitude"] * np.sin(phase)
        if self.name == "telegraph_pixels":
            add = np.zeros((self.h, self.w))
            add[p["rows"], p["cols"]] = p["step"] * p["states"][i]
            return add
        if self.name == "ghost":
            # A faint, blurred, point-mirrored copy of the scene's departure from its mean level.
            img = y - y.mean()
            img = img[::-1, ::-1]
            k = np.exp(-0.5 * (np.arange(-6, 7) / 2.5) ** 2)
            k /= k.sum()
            img = np.apply_along_axis(lambda v: np.convolve(v, k, mode="same"), 0, img)
            img = np.apply_along_axis(lambda v: np.convolve(v, k, mode="same"), 1, img)
            return p["gain"] * img
        raise ValueError(self.name)


def radial(w, h):
    yy, xx = np.mgrid[0:h, 0:w].astype(np.float64)
    xc, yc = (w - 1) / 2, (h - 1) / 2
    rho2 = ((xx - xc) ** 2 + (yy - yc) ** 2) / (xc * xc + yc * yc)
    return 0.7 * rho2 + 0.3 * rho2 * rho2  # 1 at the corners


def unabsorbed_p99(diff, base):
    """99th percentile of |diff| after the least-squares global gain and offset on `base` is taken out."""
    b = base.ravel()
    d = diff.ravel()
    bm = b.mean()
    slope = float(np.dot(b - bm, d - d.mean()) / max(np.dot(b - bm, b - bm), 1e-30))
    rest = d - d.mean() - slope * (b - bm)
    return float(np.percentile(np.abs(rest), 99.0))


def effect_params(chain, a, fpa):
    """The effect's parameters for amplitude `a` (noise sigmas) and its truth record."""
    eid, seed, w, h, n = chain.name, chain.seed, chain.w, chain.h, chain.n
    r = rng_for(seed, "effect-" + eid)
    s = a * NOISE_SIGMA
    if eid == "offset_fpn":
        m = r.standard_normal((h, w)) * s
        return {"map": m}, {"sigma": s}
    if eid == "column_fpn":
        return {"map": np.broadcast_to(r.standard_normal(w) * s, (h, w)).copy()}, {"sigma": s}
    if eid == "row_fpn":
        return {"map": np.broadcast_to((r.standard_normal(h) * s)[:, None], (h, w)).copy()}, {"sigma": s}
    if eid == "shading":
        amp = float(r.choice([-1, 1])) * s
        return {"map": amp * radial(w, h)}, {"amplitude": amp, "profile": "0.7 rho^2 + 0.3 rho^4, rho = 1 at the corners, offset"}
    if eid == "gain_fpn":
        sigma = s / chain.reference_level
        return {"map": r.standard_normal((h, w)) * sigma}, {"sigma": sigma}
    if eid == "fpa_drift":
        k = s / max(float(np.max(np.abs(fpa - fpa[0]))), 1e-6)
        span = chain.timing.t[-1] - chain.timing.t[0]
        return {"k": k, "fpa": fpa}, {"k": k, "rate": float((fpa[-1] - fpa[0]) / span), "regressor": "fpa_temp_c"}
    if eid == "ffc_step":
        offsets = np.zeros(n)
        steps = []
        level = 0.0
        for e in chain.timing.events:
            step = float(r.choice([-1, 1])) * s
            level += step
            offsets[e:] = level
            steps.append(step)
        return {"offsets": offsets}, {"frames": list(chain.timing.events), "steps": steps}
    if eid == "dead_pixels":
        count = max(1, int(round(4 * a)))
        idx = r.choice(h * w, size=count, replace=False)
        rows, cols = idx // w, idx % w
        return {"rows": rows, "cols": cols}, {"count": count, "pixels": [[int(a_), int(b_)] for a_, b_ in zip(rows, cols)],
                                              "model": "stuck at the first frame's reading"}
    if eid == "frame_duplication":
        every = max(2, int(round(20 / max(a, 0.05))))
        start = int(r.integers(2, every + 2))
        frames = list(range(start, n, every))
        return {"frames": frames}, {"every": every, "frames": frames}
    if eid == "thermal_memory":
        tau2 = float(r.uniform(0.1, 0.5))
        return scaled(chain, a, {"tau2_s": tau2, "weight": 1e-3}, "weight", {"tau2_s": tau2})
    if eid == "tau_temperature":
        sign = float(r.choice([-1, 1]))
        return scaled(chain, a, {"gamma": sign * 2e-6}, "gamma", {"y0": chain.reference_level})
    if eid == "tau_spread":
        z = r.standard_normal((h, w))
        p, t = scaled(chain, a, {"factor": 1 + 1e-2 * z, "sigma": 1e-2}, "sigma", {},
                      rebuild=lambda v: {"factor": np.maximum(0.05, 1 + v * z), "sigma": v})
        return p, t
    if eid == "rolling_readout":
        return scaled(chain, a, {"line_time_s": 1e-6}, "line_time_s", {})
    if eid == "crosstalk":
        return scaled(chain, a, {"epsilon": 1e-2}, "epsilon", {})
    if eid == "nonlinearity":
        return scaled(chain, a, {"c": 1e-6}, "c", {"y0": chain.reference_level})
    if eid == "temporal_filter":
        return scaled(chain, a, {"alpha": 0.01}, "alpha", {})
    if eid == "agc":
        extra = {"range": 8000.0, "floor": 4000.0, "p_lo": 0.5, "p_hi": 99.5}
        p, t = scaled(chain, a, dict(extra, damping=1e-3), "damping", dict(extra), noise_gain=True)
        return p, t
    raise ValueError(eid)


def scaled(chain, a, ref, key, truth_extra, rebuild=None, noise_gain=False):
    """Scales parameter `key` so the effect's unabsorbed 99th percentile is `a` noise sigmas."""
    rebuild = rebuild or (lambda v: dict(ref, **{key: v}))
    base = chain.run(None, noise=False)
    with_ref = chain.run(dict(rebuild(ref[key])), noise=False)
    size = unabsorbed_p99(with_ref - base, base)
    target = a * NOISE_SIGMA
    if noise_gain:  # the AGC stretches the noise too: amplitude in the recording's own noise
        lo, hi = np.percentile(base[0], [ref["p_lo"], ref["p_hi"]])
        target *= ref["range"] / max(hi - lo, 1.0)
    value = ref[key] * target / max(size, 1e-12)
    p = rebuild(value)
    truth = dict(truth_extra, **{key: value})
    truth["reference_p99"] = size
    return p, truth


def ooc_params(chain, a):
    r = rng_for(chain.seed, "ooc-" + chain.name)
    s = a * NOISE_SIGMA
    h, w, n = chain.h, chain.w, chain.n
    if chain.name == "interference":
        ang = math.radians(float(r.uniform(20, 70)))
        wavelength = float(r.uniform(8, 20))
        p = {"amplitude": s, "kx": math.cos(ang) / wavelength, "ky": math.sin(ang) / wavelength,
             "hz": float(r.uniform(0.5, 3.0))}
        return p, {k: v for k, v in p.items()}
    if chain.name == "telegraph_pixels":
        count = 40
        idx = r.choice(h * w, size=count, replace=False)
        states = np.zeros((n, count))
        cur = r.integers(0, 2, count).astype(float)
        for i in range(n):
            flip = r.random(count) < 1 / 15.0
            cur = np.where(flip, 1 - cur, cur)
            states[i] = cur
        p = {"rows": idx // w, "cols": idx % w, "states": states, "step": 4 * s}
        return p, {"count": count, "step": 4 * s, "mean_dwell_frames": 15}
    if chain.name == "ghost":
        base = chain.run(None, noise=False)
        probe = {"gain": 1e-2}
        with_ref = chain.run(probe, noise=False)
        size = unabsorbed_p99(with_ref - base, base)
        g = 1e-2 * s / max(size, 1e-12)
        return {"gain": g}, {"gain": g, "reference_p99": size}
    raise ValueError(chain.name)


def jsonable(v):
    if isinstance(v, dict):
        return {k: jsonable(x) for k, x in v.items()}
    if isinstance(v, (list, tuple)):
        return [jsonable(x) for x in v]
    if isinstance(v, np.generic):
        return v.item()
    if isinstance(v, np.ndarray):
        return jsonable(v.tolist())
    return v


def write_recording(out, frames, scene, timing, fpa, housing, ffc_flags, info, truth):
    if os.path.exists(out):
        shutil.rmtree(out)
    os.makedirs(os.path.join(out, "truth"))
    n, h, w = frames.shape
    np.save(os.path.join(out, "frames.npy"), np.ascontiguousarray(frames, dtype="<u2"))
    np.save(os.path.join(out, "scene.npy"), np.ascontiguousarray(scene, dtype="<f4"))
    meta = {"format": "bolo-recording", "version": 1, "sensor": "independent generator (synthetic microbolometer)",
            "width": w, "height": h, "bits": BITS, "fps": timing.fps, "units": "counts",
            "source": "scripts/study/independent_generator.py", "notes": info}
    with open(os.path.join(out, "recording.json"), "w") as f:
        json.dump(meta, f, indent=1)
    with open(os.path.join(out, "frames.csv"), "w") as f:
        f.write("index,t_s,exposure_s,readout_s,ffc,fpa_temp_c,housing_temp_c\n")
        for i in range(n):
            f.write(f"{i},{timing.t[i]:.9f},{timing.exposure[i]:.12g},{timing.readout[i]:.12g},{ffc_flags[i]},"
                    f"{fpa[i]:.6f},{housing[i]:.4f}\n")
    with open(os.path.join(out, "truth", "effects.json"), "w") as f:
        json.dump(jsonable(truth), f, indent=1)


def generate(out, case, a, seed, w, h, n, substeps=6, ffc_unknown=False, noise=True, jitter=0.003):
    kind, name = case.split(":", 1)
    if kind == "effect" and name not in EFFECTS or kind == "null" and name not in NULL_KINDS \
            or kind == "ooc" and name not in OOC_KINDS or kind not in ("effect", "null", "ooc"):
        raise SystemExit(f"unknown case {case}")
    r = rng_for(seed, "events")
    events = []
    if (kind, name) in (("effect", "ffc_step"), ("null", "shutter")):
        first = int(r.integers(n // 5, n // 3))
        events = [first, first + int(r.integers(n // 4, n // 3))]
    timing = Timing(seed, n, events, jitter=jitter)
    duration = float(timing.t[-1] + timing.exposure[-1])
    scene = Scene(seed, w, h, duration, name if kind == "null" else "base")
    chain = Chain(seed, w, h, n, case, timing, scene, substeps)
    fpa, housing = fpa_trace(seed, timing.t, warm=(kind == "null" and name == "mean_change"))
    fpa = np.round(fpa, 6)  # the effect uses exactly what frames.csv logs
    chain.reference_level = float(np.median(chain.inputs(0)))
    truth = {"generator": "scripts/study/independent_generator.py", "case": case, "amplitude_sigma": a,
             "seed": seed, "effects": {}, "noise": {"white_counts": NOISE_SIGMA},
             "baseline": {"tau_h_s": timing.tau_h, "tau_c_s": timing.tau_c, "exposure_s": timing.exposure0,
                          "readout_s": timing.readout0, "timing_jitter": timing.jitter, "substeps": substeps,
                          "shutter_events": events}}
    params = None
    if kind == "effect":
        params, t = effect_params(chain, a, fpa)
        truth["effects"][name] = t
    elif kind == "ooc":
        params, t = ooc_params(chain, a)
        truth["out_of_catalogue"] = dict(t, pattern=name)
    else:
        truth["decoys"] = {"mean_change": "the scene's mean level changes by a few hundred counts while the FPA warms",
                           "pan_hot_entry": "a slow pan and a hot object entering the frame",
                           "shutter": "flagged shutter events with the offset correction exact (no step)"}[name]
    frames = chain.run(params, noise=noise)
    frames = np.clip(np.round(frames), 0, 2 ** BITS - 1).astype(np.uint16)
    flags = ["" if ffc_unknown else ("1" if i in events else "0") for i in range(n)]
    if ffc_unknown:
        truth["ffc_column"] = "empty (unknown) in every frame"
    size = "" if kind == "null" else f", amplitude {a:g} noise sigma"
    info = (f"case {case}{size}, seed {seed}; exposure and readout jittered by "
            f"{timing.jitter:.1%} (logged), {substeps} sub-steps per exposure")
    write_recording(out, frames, chain.scene_frames(), timing, fpa, housing, flags, info, truth)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("out")
    ap.add_argument("--case", required=True, help="effect:ID, null:KIND or ooc:KIND")
    ap.add_argument("--amplitude", type=float, default=1.0, help="in units of the pixel noise sigma")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--size", default="160x120")
    ap.add_argument("--frames", type=int, default=300)
    ap.add_argument("--substeps", type=int, default=6)
    ap.add_argument("--ffc-unknown", action="store_true", help="leave the ffc column empty (unknown) in every frame")
    ap.add_argument("--no-noise", action="store_true", help="no white readout noise (the effect keeps its size)")
    ap.add_argument("--jitter", type=float, default=0.003,
                    help="relative spread of each frame's exposure and readout (0: the nominal timing throughout)")
    args = ap.parse_args()
    w, h = (int(v) for v in args.size.split("x"))
    generate(args.out, args.case, args.amplitude, args.seed, w, h, args.frames, args.substeps, args.ffc_unknown,
             not args.no_noise, args.jitter)


if __name__ == "__main__":
    main()
