#!/usr/bin/env python3
"""Table of scripts/study/frame-rates.sh: per frame rate, trajectory and mode, over the seeds, the
median ATE (whole run and per tracking segment, % of the path), the restarts, the share of frames
posed and the runs that could not be evaluated.

    rates_table.py INDEX OUT_MD

INDEX lines: FPS TRAJECTORY SEED MODE RUN."""
import argparse
import statistics
from pathlib import Path

from study_runs import grouped_evaluations


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("index")
    ap.add_argument("out_md")
    a = ap.parse_args()
    # FPS TRAJECTORY SEED MODE RUN: over the seeds.
    groups = grouped_evaluations(a.index, lambda f: (f[0], f[1], f[3]))
    out = ["| rate | trajectory | mode | runs | median ATE, % of the path | per segment | restarts | posed | failed |",
           "|---|---|---|---|---|---|---|---|---|"]
    for (fps, traj, mode), evals in groups.items():
        ok = [e for e in evals if e]
        frames = sum(e["frames"] for e in ok)
        posed = sum(e["posed"] for e in ok)

        def median(key):
            values = [100 * e[key] for e in ok if e.get(key) is not None]
            return f"{statistics.median(values):.2f}" if values else "–"

        out.append(f"| {fps} Hz | {traj} | `{mode}` | {len(evals)} | {median('ate_relative')} | "
                   f"{median('segments_ate_relative')} | {sum(e['reinitialisations'] for e in ok)} | "
                   f"{100 * posed / frames if frames else 0:.0f} % | {len(evals) - len(ok)} |")
    Path(a.out_md).parent.mkdir(parents=True, exist_ok=True)
    Path(a.out_md).write_text("\n".join(out) + "\n")


if __name__ == "__main__":
    main()
