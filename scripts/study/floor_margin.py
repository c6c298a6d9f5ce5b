#!/usr/bin/env python3
"""How close the candidates the practical floor refused came to it, on the second generator's
recordings of the diagnosis study: for every candidate that passed the held-out dBIC and block
tests but explained less than the floor, its explained share of the floor, and whether it was the
recording's true effect.

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


if __name__ == "__main__":
    main()
