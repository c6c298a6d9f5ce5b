#!/usr/bin/env python3
"""Cycles per instruction of a whole program run on a CPU model: qemu-user's translation-block
log (`-d in_asm,exec,nochain`) gives every executed block's instructions and how often it ran;
the blocks that cover `coverage` of the executed instructions go to llvm-mca, one code region
each; CPI = sum(runs x cycles per run) / sum(runs x instructions), over those blocks.

Each block is timed as llvm-mca times a region: repeated back to back, every load hitting the
cache and every branch predicted (misses would add cycles), on its own (an out-of-order core
overlaps neighbouring blocks, which this does not credit). An estimate, not a bound.

  tb_profile.py LOG_OR_FIFO --triple aarch64 --cpu cortex-a53 [--cpu cortex-a72] [--coverage 0.95]
  -> JSON {cpu: {"cpi", "covered", "blocks"}}
"""
import argparse
import json
import re
import subprocess
import sys

# Branches and PC-relative address forms whose operand qemu prints as an absolute address: the
# operand becomes "." (timing does not depend on the target).
TARGET_OPERAND = re.compile(r"^(b|bl|b\.\w+|cbn?z|tbn?z|adrp?)$")


def read_log(source):
    """{pc: [runs, [instructions]]} from a qemu log read as bytes lines."""
    blocks = {}
    pending_pc, pending = None, []
    for line in source:
        if line.startswith(b"Trace "):
            pc = line.split(b"[", 1)[1].split(b"/", 2)[1].lstrip(b"0")
            entry = blocks.get(pc)
            if entry is not None:
                entry[0] += 1
        elif line.startswith(b"0x"):
            text = line.decode(errors="replace").split(":", 1)[1].split(None, 1)[1].strip()
            if pending_pc is None:
                pending_pc = line[2:line.index(b":")].lstrip(b"0")
                pending = []
            pending.append(text)
        elif pending_pc is not None:
            runs = blocks[pending_pc][0] if pending_pc in blocks else 0
            blocks[pending_pc] = [runs, pending]
            pending_pc = None
    return blocks


def for_mc(text):
    parts = text.split(None, 1)
    if TARGET_OPERAND.match(parts[0]) or (parts[0].startswith("ldr") and "[" not in text):
        text = re.sub(r"#0x[0-9a-f]+$", ".", text)
    return text


def difference(after, before):
    """The blocks' runs in `after` beyond those in `before` (two runs of one program)."""
    out = {}
    for pc, (runs, insns) in after.items():
        extra = runs - before.get(pc, [0])[0]
        if extra > 0:
            out[pc] = [extra, insns]
    return out


def cpi(blocks, triple, cpu, coverage):
    ranked = sorted(blocks.values(), key=lambda b: b[0] * len(b[1]), reverse=True)
    total = sum(b[0] * len(b[1]) for b in ranked)
    chosen, covered = [], 0
    for b in ranked:
        if covered >= coverage * total or b[0] == 0:
            break
        chosen.append(b)
        covered += b[0] * len(b[1])
    source = []
    for i, b in enumerate(chosen):
        source.append(f"# LLVM-MCA-BEGIN b{i}")
        source += ["\t" + for_mc(t) for t in b[1]]
        source.append(f"# LLVM-MCA-END b{i}")
    result = subprocess.run(["llvm-mca", f"-mtriple={triple}", f"-mcpu={cpu}", "-iterations=20",
                             "-resource-pressure=false", "-instruction-info=false"],
                            input="\n".join(source) + "\n", capture_output=True, text=True)
    if result.returncode != 0:
        raise SystemExit(f"tb_profile: llvm-mca {cpu}: {result.stderr[:500]}")
    regions = re.findall(r"\[\d+\] Code Region - b(\d+)\n\nIterations:\s+(\d+)\nInstructions:\s+\d+\n"
                         r"Total Cycles:\s+(\d+)", result.stdout)
    if len(regions) != len(chosen):
        raise SystemExit(f"tb_profile: {len(regions)} regions reported for {len(chosen)} blocks")
    cycles = sum(chosen[int(i)][0] * int(c) / int(n) for i, n, c in regions)
    return {"cpi": round(cycles / covered, 3), "covered": round(covered / total, 3),
            "blocks": len(chosen), "instructions": total}


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("log")
    parser.add_argument("--triple", required=True)
    parser.add_argument("--cpu", action="append", required=True)
    parser.add_argument("--coverage", type=float, default=0.95)
    args = parser.parse_args()
    with open(args.log, "rb") as source:
        blocks = read_log(source)
    json.dump({cpu: cpi(blocks, args.triple, cpu, args.coverage) for cpu in args.cpu}, sys.stdout)
    print()


if __name__ == "__main__":
    main()
