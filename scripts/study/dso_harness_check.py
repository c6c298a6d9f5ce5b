#!/usr/bin/python3
"""Two recordings on which any working direct VO tracks, to check the DSO peer's harness
(dso_io.py, dso-run.sh, the build) apart from how DSO does on the study's renders: a camera
sliding sideways and one moving straight ahead, 30 Hz, 150 frames, over a fronto-parallel plane
with a smooth random texture filling 8 bits (no noise, no lag). Each frame samples the plane
through the pinhole of its camera.json (bilinear); poses.tum is the truth.

  dso_harness_check.py make OUT      writes OUT/sideways and OUT/forward (bolo recordings)
  dso_harness_check.py score RUN     prints the run's posed share and ATE; exit 1 unless the ATE is
                                     within the study's bound (0.5 % of the path) over >= 80 % of
                                     the frames (DSO's initialiser takes 10-20 of these 150)

dso-harness-check.sh makes both, runs scripts/study/dso-run.sh on each and scores them."""
import json
import sys
from pathlib import Path

import numpy as np
from numpy.lib.stride_tricks import sliding_window_view

from study_runs import TRACKED_ATE_SHARE, evaluation

W, H, N, FPS, F = 320, 256, 150, 30.0, 300.0
TEXELS_PER_M = 150.0


def texture(seed, size=1400):
    """Smooth random texture in [0, 1]: white noise through three 7x7 box filters."""
    t = np.random.default_rng(seed).standard_normal((size, size))
    for _ in range(3):
        t = sliding_window_view(np.pad(t, 3, mode="edge"), (7, 7)).mean(axis=(2, 3))
    return (t - t.min()) / (t.max() - t.min())


def render(tex, position, depth):
    """The plane z = depth ahead of a camera at (x, y, 0) looking along +z, bilinear."""
    v, u = np.mgrid[0:H, 0:W].astype(float)
    px = ((u - (W - 1) / 2) / F * depth + position[0]) * TEXELS_PER_M + tex.shape[1] / 2
    py = ((v - (H - 1) / 2) / F * depth + position[1]) * TEXELS_PER_M + tex.shape[0] / 2
    x0, y0 = np.floor(px).astype(int), np.floor(py).astype(int)
    ax, ay = px - x0, py - y0
    value = (tex[y0, x0] * (1 - ax) * (1 - ay) + tex[y0, x0 + 1] * ax * (1 - ay)
             + tex[y0 + 1, x0] * (1 - ax) * ay + tex[y0 + 1, x0 + 1] * ax * ay)
    return np.rint(6000 + 2000 * value).astype("<u2")


def write(out, positions, depths, tex):
    out.mkdir(parents=True, exist_ok=True)
    np.save(out / "frames.npy", np.stack([render(tex, p, d) for p, d in zip(positions, depths)]))
    times = [i / FPS for i in range(N)]
    (out / "frames.csv").write_text("index,t_s,exposure_s,readout_s,ffc,fpa_temp_c,housing_temp_c\n"
                                    + "".join(f"{i},{t!r},0.01,{1 / FPS - 0.01!r},0,,\n" for i, t in enumerate(times)))
    (out / "camera.json").write_text(json.dumps({"model": "pinhole", "fx": F, "fy": F, "cx": (W - 1) / 2, "cy": (H - 1) / 2}))
    (out / "recording.json").write_text(json.dumps({"format": "bolo-recording", "version": 1, "width": W, "height": H,
                                                    "bits": 14, "fps": FPS, "units": "counts",
                                                    "source": "scripts/study/dso_harness_check.py"}))
    # The plane is at +z; the camera moves by -position in the plane's frame, so its centre is at
    # (x, y, 3 - depth) with the axes of the camera (x right, y down, z ahead).
    (out / "poses.tum").write_text("".join(f"{t!r} {p[0]!r} {p[1]!r} {3.0 - d!r} 0 0 0 1\n"
                                           for t, p, d in zip(times, positions, depths)))


def score(run):
    e = evaluation(run)
    if e is None:
        print(f"{run}: not evaluated")
        return 1
    ok = e["coverage"] >= 0.8 and e["ate_relative"] <= TRACKED_ATE_SHARE
    print(f"{run}: {100 * e['coverage']:.0f} % posed, ATE {e['ate_rmse_m']:.4f} m = {100 * e['ate_relative']:.2f} % of the path,"
          f" rotation RPE {e['rpe_rot_rmse_deg']:.2f} deg: {'ok' if ok else 'FAILED'}")
    return 0 if ok else 1


def main():
    if len(sys.argv) != 3 or sys.argv[1] not in ("make", "score"):
        sys.exit(__doc__)
    if sys.argv[1] == "score":
        sys.exit(score(sys.argv[2]))
    out = Path(sys.argv[2])
    tex = texture(1)
    write(out / "sideways", [(0.004 * i, 0.0) for i in range(N)], [3.0] * N, tex)
    write(out / "forward", [(0.0, 0.0)] * N, [3.0 - 0.01 * i for i in range(N)], tex)


if __name__ == "__main__":
    main()
