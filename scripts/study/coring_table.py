#!/usr/bin/env python3
"""Tables of scripts/study/coring-strength.sh: the IR modes' ATE at each --carry-coring K against
the default, paired on the same sequences, and the medians of every mode.

    coring_table.py INDEX OUT_MD --ks "0 0.5 1.5" --control 1.001

INDEX lists one sequence folder a line; its runs are SEQ-vo-MODE (the defaults) and
SEQ-vo-MODE-coreK. A run that could not be evaluated counts as 100 % of the path."""
import argparse
import math
import re
import statistics
import sys
from collections import OrderedDict
from pathlib import Path

from study_runs import evaluation

FAILED = 100.0  # % of the path a failed run counts as


def ate_percent(run):
    e = evaluation(run)
    return 100.0 * e["ate_relative"] if e and e.get("ate_relative") is not None else FAILED


def describe(seq):
    """(set label, rays, trajectory) from a folder name such as seq-drive-60hz-n6-s2-ss3."""
    name = Path(seq).name
    m = re.match(r"(?:seq|switch)-([a-z]+)-(.*?)-s\d+(?:-ss(\d+))?$", name)
    if not m:
        return name, "?", "?"
    traj, rest, rays = m.group(1), m.group(2), m.group(3) or "1"
    rest = rest.replace("hz", " Hz").replace("-n", ", noise ").replace("-tau", ", τ ")
    return rest, ("3×3" if rays == "3" else f"{rays}×{rays}" if rays != "1" else "1"), traj


def geometric_mean(xs):
    return math.exp(sum(math.log(x) for x in xs) / len(xs)) if xs else float("nan")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("index")
    ap.add_argument("out_md")
    ap.add_argument("--ks", default="0 0.5 1.5")
    ap.add_argument("--control", default="1.001")
    a = ap.parse_args()
    ks = a.ks.split() + [a.control]
    seqs = [line.strip() for line in Path(a.index).read_text().splitlines() if line.strip()]
    if not seqs:
        sys.exit(f"coring_table: {a.index}: no sequences")
    by_set, by_traj = OrderedDict(), OrderedDict()
    for seq in seqs:
        label, rays, traj = describe(seq)
        by_set.setdefault((label, rays), []).append(seq)
        by_traj.setdefault((label, rays, traj), []).append(seq)

    out = []
    head = " | ".join(f"`{m}` K = {k}{' (control)' if k == a.control else ''}" for m in ("ir", "ir-loop") for k in ks)
    out.append("Geometric means of the paired ATE ratios, K against the default (`--carry-coring 1`), "
               "over both trajectories and every seed of a set:\n")
    out.append(f"| sequences | rays | runs | {head} |")
    out.append("|---|---|---|" + "---|" * (2 * len(ks)))
    everything = {(m, k): [] for m in ("ir", "ir-loop") for k in ks}
    for (label, rays), group in by_set.items():
        cells = []
        for mode in ("ir", "ir-loop"):
            for k in ks:
                ratios = [ate_percent(f"{s}-vo-{mode}-core{k}") / ate_percent(f"{s}-vo-{mode}") for s in group]
                everything[(mode, k)] += ratios
                cells.append(f"{geometric_mean(ratios):.2f}")
        out.append(f"| {label} | {rays} | {len(group)} | " + " | ".join(cells) + " |")
    out.append(f"| **all** | | {len(seqs)} | " + " | ".join(f"**{geometric_mean(everything[(m, k)]):.2f}**" for m in ("ir", "ir-loop") for k in ks) + " |")

    out.append("\nRuns over 2 % of the path, and τ at 2 s within 10 % of the truth on the 3×3-ray sequences:\n")
    out.append("| mode | K | runs over 2 % | τ within 10 % (3×3) |")
    out.append("|---|---|---|---|")
    n3 = sum(1 for s in seqs if describe(s)[1] == "3×3")
    for mode in ("ir", "ir-loop"):
        for k in ["1 (default)"] + ks:
            suffix = "" if k.startswith("1 (") else f"-core{k}"
            over = sum(ate_percent(f"{s}-vo-{mode}{suffix}") > 2.0 for s in seqs)
            within = 0
            for s in seqs:
                if describe(s)[1] != "3×3":
                    continue
                e = evaluation(f"{s}-vo-{mode}{suffix}")
                if e and e.get("tau_c_at_2s_s") and e.get("tau_true_c_s"):
                    within += abs(e["tau_c_at_2s_s"] / e["tau_true_c_s"] - 1) <= 0.10
            out.append(f"| `{mode}` | {k} | {over} of {len(seqs)} | {within} of {n3} |")

    k0 = ks[0]
    out.append(f"\nMedian ATE, % of the path (the IR modes at the default and at K = {k0}):\n")
    out.append(f"| sequences | rays | trajectory | `none` | `affine` | `ir` 1 / {k0} | `ir-loop` 1 / {k0} |")
    out.append("|---|---|---|---|---|---|---|")
    for (label, rays, traj), group in by_traj.items():
        def med(suffix):
            return statistics.median(ate_percent(f"{s}-vo-{suffix}") for s in group)
        out.append(f"| {label} | {rays} | {traj} | {med('none'):.2f} | {med('affine'):.2f} | "
                   f"{med('ir'):.2f} / {med('ir-core' + k0):.2f} | {med('ir-loop'):.2f} / {med('ir-loop-core' + k0):.2f} |")
    Path(a.out_md).parent.mkdir(parents=True, exist_ok=True)
    Path(a.out_md).write_text("\n".join(out) + "\n")


if __name__ == "__main__":
    main()
