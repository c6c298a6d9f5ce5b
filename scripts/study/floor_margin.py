#!/usr/bin/env python3
"""How close the candidates the practical floor refused came to it, on the second generator's
recordings of the diagnosis study: for every candidate that passed the held-out dBIC and block
tests but explained less than the floor, its explained share of the floor, and whether it was the
recording's true effect. Then the candidates judged by a signature of their own instead (temporal_filter, rolling_readout, tau_temperature):
the largest z of each on every recording of the study (both generators), with and without the effect.

usage: floor_margin.py [WORKDIR (default out/diagnosis-study)] [--top N]
"""
import argparse
import glob
import json
import os
import re


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("work", nargs="?", default="out/diagnosis-study")
    ap.add_argument("--top", type=int, default=12)
    a = ap.parse_args()
    work, top = a.work, a.top
    rows = []
    for path in sorted(glob.glob(os.path.join(work, "gen2-*.d", "diagnosis.json"))):
        name = os.path.basename(os.path.dirname(path))[:-2]
        truth = name.split("-")[2] if name.startswith("gen2-effect-") else None
        with open(path) as f: d = json.load(f)
        for c in d["candidates"]:
            m = re.search(r"below the practical floor \(explained ([-0-9.e+]+) of ([-0-9.e+]+)\)", c.get("note", ""))
            if m and c["evidence"]["delta_bic"] > 10 and c["evidence"]["block_z"] > 1:
                rows.append((float(m.group(1)) / float(m.group(2)), name, c["effect"], c["effect"] == truth))
    rows.sort(reverse=True)
    print("| share of the floor | recording | candidate | the true effect |\n|---|---|---|---|")
    for share, name, effect, true in rows[:top]:
        print(f"| {share:.3f} | {name} | {effect} | {'yes' if true else 'no'} |")
    signatures = []
    for path in sorted(glob.glob(os.path.join(work, "*.d", "diagnosis.json"))):
        name = os.path.basename(os.path.dirname(path))[:-2]
        with open(path) as f: d = json.load(f)
        for c in d["candidates"]:
            m = re.search(r"signature.*\(z ([-0-9.e+]+)", c.get("note", ""))
            if m:
                synthetic = name.split("-")[0] in ("gen2", "conc", "curve", "null")
                signatures.append((float(m.group(1)), name, c["effect"], c["round"],
                                   ("yes" if c["effect"] in name else "no") if synthetic else "unknown (real)"))
    signatures.sort(reverse=True)
    print("\n| signature z | recording | candidate | round | the effect is in the recording |\n|---|---|---|---|---|")
    shown = [s for s in signatures if s[4] == "yes"] + [s for s in signatures if s[4] != "yes"][:top]
    for z, name, effect, rnd, present in shown:
        print(f"| {z:.2f} | {name} | {effect} | {rnd} | {present} |")


if __name__ == "__main__":
    main()
