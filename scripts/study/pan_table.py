#!/usr/bin/env python3
"""Table of scripts/study/pans.sh: per configuration and mode, over the seeds, the rotation error
(RPE over 1 s, median and worst), the frames lost, the restarts, the share of frames posed, and
the IR modes' tau at 2 s.

    pan_table.py INDEX OUT_MD

INDEX lines: FPS SIZE RAYS SEED MODE RUN. A run that could not be evaluated counts as a failure."""
import argparse
import statistics
from pathlib import Path

from study_runs import grouped_evaluations


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("index")
    ap.add_argument("out_md")
    a = ap.parse_args()
    # FPS SIZE RAYS SEED MODE RUN: over the seeds.
    groups = grouped_evaluations(a.index, lambda f: (f[0], f[1], f[2], f[4]))
    out = ["| rate | size | rays | mode | runs | RPE rotation, deg / s (median / worst) | frames lost | restarts | "
           "posed | failed | τ at 2 s, \\|error\\| (median) |", "|---|---|---|---|---|---|---|---|---|---|---|"]
    for (fps, size, rays, mode), evals in groups.items():
        ok = [e for e in evals if e]
        failed = len(evals) - len(ok)
        rot = [e["rpe_rot_rmse_deg"] for e in ok]
        frames = sum(e["frames"] for e in ok)
        posed = sum(e["posed"] for e in ok)
        tau = [abs(e["tau_c_at_2s_s"] / e["tau_true_c_s"] - 1) * 100 for e in ok
               if e.get("tau_c_at_2s_s") and e.get("tau_true_c_s") and mode.startswith("ir")]
        rays_label = "3×3" if rays == "3" else ("1" if rays == "1" else f"{rays}×{rays}")
        rot_cell = f"{statistics.median(rot):.2f} / {max(rot):.2f}" if rot else "–"
        out.append(f"| {fps} Hz | {size} | {rays_label} | `{mode}` | {len(evals)} | {rot_cell} | "
                   f"{sum(e['lost'] for e in ok)} | {sum(e['reinitialisations'] for e in ok)} | "
                   f"{100 * posed / frames if frames else 0:.0f} % | {failed} | "
                   + (f"{statistics.median(tau):.0f} %" if tau else "") + " |")
    Path(a.out_md).parent.mkdir(parents=True, exist_ok=True)
    Path(a.out_md).write_text("\n".join(out) + "\n")


if __name__ == "__main__":
    main()
