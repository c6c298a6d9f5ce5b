#!/usr/bin/env python3
"""How much of the second generator's noise-free tau_spread and tau_temperature the diagnosis
regressors explain (the design behind sim/effects/src/two_frame_derivative.hpp).

For a seed, the generator's output with the effect less its output without (no noise, the true
time constants and timing), fitted by least squares (no intercept); the share of the effect's
variance explained by:
  * tau_spread, a per-pixel slope (the regressor times the pixel's own departure of ln tau):
    d(output)/d(ln tau) on the transients as observed (the input recovered from the output frame
    by frame), along the frame steps (each frame's carry, heating weight and calibration at the
    nominal timing, which the jittered exposure and readout move per frame, driven by the
    exposure's even average), and along the frame steps plus the within-exposure term's slope;
  * tau_temperature, its regressor fitted beside d(output)/d(ln tau) as the candidate refits the
    baseline's tau: beside the transient reading of it, and beside the frame-step reading; and
    d(output)/d(ln tau) alone, the share a uniform tau (the baseline's own) takes before the
    candidate is tried.

usage: tau_regressor_oracle.py [--seed S] [--size WxH] [--frames N]
"""
import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import independent_generator as g  # noqa: E402


def lateness(te, tau):
    x = te / tau
    return te * (1 / -np.expm1(-x) - 1 / x - 0.5)


def explained(effect, regressors):
    """Share of the effect's variance a least-squares fit on the regressors (no intercept) explains."""
    x = np.stack([r.ravel() for r in regressors], axis=1)
    y = effect.ravel()
    beta = np.linalg.lstsq(x, y, rcond=None)[0]
    return 1 - np.var(y - x @ beta) / np.var(y)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--seed", type=int, default=2)
    ap.add_argument("--size", default="160x120")
    ap.add_argument("--frames", type=int, default=300)
    a = ap.parse_args()
    w, h = map(int, a.size.split("x"))
    n = a.frames
    for eid in ("tau_spread", "tau_temperature"):
        tm = g.Timing(a.seed, n, [], jitter=0.003)
        scene = g.Scene(a.seed, w, h, float(tm.t[-1] + tm.exposure[-1]), "base")
        chain = g.Chain(a.seed, w, h, n, "effect:" + eid, tm, scene, 6)
        fpa, _ = g.fpa_trace(a.seed, tm.t, warm=False)
        chain.reference_level = float(np.median(chain.inputs(0)))
        p, _ = g.effect_params(chain, 1.0, fpa)
        base = chain.run(None, noise=False)
        effect = chain.run(p, noise=False) - base
        sub = chain._inputs.copy()
        even_input = sub.mean(axis=1)
        chain._inputs[:] = sub.mean(axis=1, keepdims=True)
        within = base - chain.run(None, noise=False)
        chain._inputs[:] = sub

        # Each frame's coefficients and their slopes per ln tau (both time constants scaled).
        def steps(scale):
            carry = np.exp(-np.r_[tm.readout0, tm.readout[:-1]] / (tm.tau_c * scale))
            heat = -np.expm1(-tm.exposure / (tm.tau_h * scale))
            kappa = -np.expm1(-tm.exposure0 / (tm.tau_h * scale)) / -np.expm1(-tm.readout0 / (tm.tau_c * scale))
            return carry, heat / kappa
        e = 1e-4
        carry, weight = steps(1.0)
        (cu, wu), (cd, wd) = steps(np.exp(e)), steps(np.exp(-e))
        dcarry, dweight = (cu - cd) / (2 * e), (wu - wd) / (2 * e)
        k_within = (np.log(lateness(tm.exposure0, tm.tau_h * np.exp(e))) - np.log(lateness(tm.exposure0, tm.tau_h * np.exp(-e)))) / (2 * e)
        y0 = chain.reference_level

        transient = np.zeros_like(base)   # the effect's regressor, transients only
        steps_only = np.zeros_like(base)  # along the frame steps
        nuisance_t = np.zeros_like(base)  # d(output)/d(ln tau): transients only
        nuisance_s = np.zeros_like(base)  # along the frame steps
        s = even_input[0].copy()
        g_t = np.zeros_like(s); g_s = np.zeros_like(s); n_t = np.zeros_like(s); n_s = np.zeros_like(s)
        for i in range(1, n):
            c = np.exp(-tm.readout[i - 1] / tm.tau_c)
            c_slope = c * tm.readout[i - 1] / tm.tau_c
            u_seen = (base[i] - c * base[i - 1]) / (1 - c)
            q_prev, q = base[i - 1] - y0, base[i] - y0
            n_t = c_slope * (base[i - 1] - u_seen) + c * n_t
            n_s = dcarry[i] * s + carry[i] * n_s + dweight[i] * even_input[i]
            if eid == "tau_spread":
                g_t, g_s = n_t, n_s
            else:
                share = c_slope / (1 - c)
                x_h = tm.exposure[i] / tm.tau_h
                kappa_n = -x_h * np.exp(-x_h) / -np.expm1(-x_h) + share
                g_t = c * g_t + (q_prev - q) * (share * q_prev + kappa_n * q)
            s = carry[i] * s + weight[i] * even_input[i]
            transient[i], steps_only[i], nuisance_t[i], nuisance_s[i] = g_t, g_s, n_t, n_s
        if eid == "tau_spread":
            per_pixel = p["factor"] - 1
            regs = [[per_pixel * transient], [per_pixel * steps_only], [per_pixel * (steps_only + k_within * within)]]
            print(f"| tau_spread (seed {a.seed}) | transients as observed | frame steps | frame steps + within |\n|---|---|---|---|")
        else:
            regs = [[transient, nuisance_t], [transient, nuisance_s], [nuisance_t]]
            print(f"\n| tau_temperature (seed {a.seed}) | beside the transient d/d(ln tau) | beside the frame-step one "
                  f"| the transient d/d(ln tau) alone (a uniform tau's share) |\n|---|---|---|---|")
        print(f"| explained | " + " | ".join(f"{explained(effect, r):.1%}" for r in regs) + " |")
        print(f"\nthe effect's noise-free mean square: {np.mean(effect ** 2):.3g} counts^2 per pixel-frame")


if __name__ == "__main__":
    main()
