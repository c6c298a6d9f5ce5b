#!/usr/bin/env python3
"""What a frame costs on the boards (called by scripts/board-cost.sh, which builds what it needs).

1. Cycles per pixel of the hot loops: the firmware sources compiled to assembly with each board
   build's own compile command, each loop fed to llvm-mca with a CPU's scheduling model
   (mca_loops.py).
2. Instructions executed per pixel (pipeline, corrector) and per VO frame, counted under qemu-user
   by a TCG plugin (insn_count_plugin.c; --method log: from qemu's translation-block log,
   count_tb_log.py, the same count, much slower): bolo-board-count run for two frame counts, the
   difference divided by the frames between them.
3. The VO's cycles per instruction on each aarch64 CPU model: its executed blocks over the
   counted run (qemu's log), each timed by llvm-mca, weighted by how often it ran (tb_profile.py).
4. From these: the pipeline's share of one core for 640x512 at 60 Hz, and the VO's real-time
   factor at 320x256 / 60 Hz = clock / (instructions per frame x CPI x 60).
"""
import argparse
import json
import os
import re
import shlex
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, HERE)
sys.dont_write_bytecode = True  # no __pycache__ in the source tree
import count_tb_log  # noqa: E402
import tb_profile  # noqa: E402

TARGETS = {
    "aarch64": {
        "build": "build-aarch64", "qemu": ["qemu-aarch64", "-L", "/usr/aarch64-linux-gnu"],
        "cpus": [{"label": "A53", "triple": "aarch64", "cpu": "cortex-a53", "clock_ghz": 1.2},
                 {"label": "A72", "triple": "aarch64", "cpu": "cortex-a72", "clock_ghz": 1.5}],
    },
    "armhf": {
        "build": "build-armhf", "qemu": ["qemu-arm", "-L", "/usr/arm-linux-gnueabihf"],
        # LLVM has no scheduling model for the Cortex-A7 (itineraries only, which llvm-mca does
        # not read); the Cortex-A9's, an ARMv7-A core with the same 64-bit NEON datapath, stands in.
        # The compiler's Thumb-2 loops are read in ARM state (mca_loops.thumb_as_arm).
        "cpus": [{"label": "A7 (A9 model)", "triple": "armv7a-linux-gnueabihf", "cpu": "cortex-a9",
                  "mattr": "+neon", "clock_ghz": 1.2, "thumb_as_arm": True}],
    },
}
SOURCES = ["correct_line", "bad_pixel_ingest", "nuc_stage"]
# (name, source, function): the frame store's corrector, the intake with NUC, stuck detection
# and mask (bolo-bench's pipeline), nuc_line; each in its usual (16-bit NUC, no G >= 2^30) case
LOOPS = [
    ("corrector", "correct_line", "correct_neon_loop<true, false>"),
    ("ingest", "bad_pixel_ingest", "ingest_neon_pass<true, true, true, true>"),
    ("nuc_line", "nuc_stage", "nuc_line_neon_pass<true>"),
]


def compile_to_asm(target, out_dir):
    build = os.path.join(ROOT, TARGETS[target]["build"])
    commands = json.load(open(os.path.join(build, "compile_commands.json")))
    paths = {}
    for name in SOURCES:
        entry = next(e for e in commands if e["file"].endswith(f"firmware/src/{name}.cpp"))
        args = shlex.split(entry["command"])
        start = next(i for i, a in enumerate(args) if a.endswith("g++"))
        args = args[start:]
        cleaned = []
        skip = False
        for a in args:
            if skip:
                skip = False
                continue
            if a in ("-o", "-MT", "-MF"):
                skip = True
                continue
            if a in ("-c", "-MD"):
                continue
            cleaned.append(a)
        path = os.path.join(out_dir, f"{target}-{name}.s")
        subprocess.run(cleaned[:-1] + ["-S", "-o", path, cleaned[-1]], cwd=entry["directory"],
                       check=True)
        paths[name] = path
    return paths


def mca(targets, work, llvm_mca, keep):
    loops, cpus = [], []
    for target in targets:
        asm = compile_to_asm(target, work)
        for name, source, function in LOOPS:
            loops.append({"target": target, "name": name, "asm": asm[source], "function": function})
        for cpu in TARGETS[target]["cpus"]:
            cpus.append(dict(cpu, **{"for": target}))
    config = os.path.join(work, "mca.json")
    json.dump({"llvm_mca": llvm_mca, "loops": loops, "cpus": cpus, "keep": keep}, open(config, "w"))
    out = subprocess.run([sys.executable, os.path.join(HERE, "mca_loops.py"), config],
                         capture_output=True, text=True, check=True)
    return json.loads(out.stdout)


def count_instructions(command, work, method):
    """Guest instructions `command` executes under qemu-user."""
    if method == "plugin":
        out = os.path.join(work, "count.txt")
        run = subprocess.run(command[:1] + ["-plugin", f"{work}/insn_count.so,out={out}"] +
                             command[1:], stdout=subprocess.DEVNULL)
        if run.returncode != 0:
            raise RuntimeError(f"{' '.join(command)} failed")
        return int(open(out).read())
    # qemu's own log of each translated block and each execution, read through a FIFO
    fifo = os.path.join(work, "qemu.fifo")
    if os.path.exists(fifo):
        os.remove(fifo)
    os.mkfifo(fifo)
    qemu = subprocess.Popen(command[:1] + ["-d", "in_asm,exec,nochain", "-D", fifo] + command[1:],
                            stdout=subprocess.DEVNULL)
    with open(fifo, "rb") as log:
        executed, _ = count_tb_log.count(log)
    if qemu.wait() != 0:
        raise RuntimeError(f"{' '.join(command)} failed")
    return executed


def block_log(target, args, work):
    """{pc: [runs, instructions]} of one bolo-board-count run under qemu (tb_profile.read_log)."""
    t = TARGETS[target]
    program = os.path.join(ROOT, t["build"], "bench", "bolo-board-count")
    fifo = os.path.join(work, "profile.fifo")
    if os.path.exists(fifo):
        os.remove(fifo)
    os.mkfifo(fifo)
    qemu = subprocess.Popen(t["qemu"][:1] + ["-d", "in_asm,exec,nochain", "-D", fifo] +
                            t["qemu"][1:] + [program] + args, stdout=subprocess.DEVNULL)
    with open(fifo, "rb") as log:
        blocks = tb_profile.read_log(log)
    if qemu.wait() != 0:
        raise RuntimeError(f"bolo-board-count {' '.join(args)} failed")
    return blocks


def run_cpi(target, blocks):
    """CPI of `blocks` on each CPU model of the target (tb_profile.cpi)."""
    return {c["label"]: tb_profile.cpi(blocks, c["triple"], c["cpu"], 0.95)
            for c in TARGETS[target]["cpus"]}


def per_unit(target, args_for, frames, units, work, method):
    """Instructions per unit between two runs of bolo-board-count with frames[0] and frames[1]."""
    t = TARGETS[target]
    program = os.path.join(ROOT, t["build"], "bench", "bolo-board-count")
    counts = [count_instructions(t["qemu"] + [program] + args_for(f), work, method) for f in frames]
    return (counts[1] - counts[0]) / ((frames[1] - frames[0]) * units)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--targets", default="aarch64,armhf")
    parser.add_argument("--vo-frames", required=True, help="file from bolo-vo-bench --write-frames")
    parser.add_argument("--vo-range", default="20,40", help="VO frames counted: FIRST,LAST")
    parser.add_argument("--vo-profile-frames", type=int, default=24,
                        help="VO frames run for the CPI profile (all of them are profiled)")
    parser.add_argument("--llvm-mca", default="llvm-mca")
    parser.add_argument("--json", action="store_true", help="JSON instead of the tables")
    parser.add_argument("--save-json", help="also write the JSON to this file")
    parser.add_argument("--keep", help="directory for the loops and llvm-mca reports")
    parser.add_argument("--method", choices=("plugin", "log"), default="plugin",
                        help="instruction counting: TCG plugin (default) or qemu's execution log")
    args = parser.parse_args()
    targets = args.targets.split(",")
    vo_first, vo_last = (int(v) for v in args.vo_range.split(","))
    result = {"loops": [], "instructions": {}, "summary": {}}
    with tempfile.TemporaryDirectory() as work:
        if args.keep:
            os.makedirs(args.keep, exist_ok=True)
        result["loops"] = mca(targets, work, args.llvm_mca, args.keep)
        if args.method == "plugin":
            subprocess.run(["gcc", "-shared", "-fPIC", "-O2", "-o", f"{work}/insn_count.so",
                            os.path.join(HERE, "insn_count_plugin.c")], check=True)
        for target in targets:
            counts = {}
            for stage in ("pipeline", "corrector"):
                counts[f"{stage}_per_pixel_320x256"] = round(per_unit(
                    target, lambda f, s=stage: [s, "320x256", str(f)], (1, 5), 320 * 256, work,
                    args.method), 3)
            counts["vo_per_frame_320x256"] = round(per_unit(
                target, lambda f: ["vo", args.vo_frames, str(f)], (vo_first, vo_last), 1, work,
                args.method))
            counts["vo_frames_counted"] = f"{vo_first}..{vo_last - 1}"
            counts["method"] = args.method
            result["instructions"][target] = counts
            if target == "aarch64":  # LLVM has no A7 model
                # the pipeline's frames 1..4 whole (blocks of 5 frames' run beyond 1 frame's)
                pipeline = tb_profile.difference(
                    block_log(target, ["pipeline", "320x256", "5"], work),
                    block_log(target, ["pipeline", "320x256", "1"], work))
                result["pipeline_cpi"] = run_cpi(target, pipeline)
                result["vo_cpi"] = run_cpi(target, block_log(
                    target, ["vo", args.vo_frames, str(args.vo_profile_frames)], work))
    by = {(r["target"], r["loop"], r["cpu"]): r for r in result["loops"]}
    for target in targets:
        for cpu in TARGETS[target]["cpus"]:
            label = cpu["label"]
            corrector = by[(target, "corrector", label)]["cycles_per_pixel"]
            ingest = by[(target, "ingest", label)]["cycles_per_pixel"]
            pipeline = corrector + ingest if corrector is not None and ingest is not None else None
            entry = {"target": target, "clock_ghz": cpu["clock_ghz"],
                     "corrector_cycles_per_pixel": corrector and round(corrector, 2),
                     "pipeline_cycles_per_pixel": pipeline and round(pipeline, 2),
                     "pipeline_640x512_60hz_core_share_percent": pipeline and round(
                         100 * pipeline * 640 * 512 * 60 / (cpu["clock_ghz"] * 1e9), 1)}
            if label in result.get("pipeline_cpi", {}):
                whole = (result["instructions"][target]["pipeline_per_pixel_320x256"] *
                         result["pipeline_cpi"][label]["cpi"])
                entry["pipeline_whole_run_cycles_per_pixel"] = round(whole, 2)
                entry["pipeline_whole_run_640x512_60hz_core_share_percent"] = round(
                    100 * whole * 640 * 512 * 60 / (cpu["clock_ghz"] * 1e9), 1)
            if label in result.get("vo_cpi", {}):
                per_frame = result["instructions"][target]["vo_per_frame_320x256"]
                model_cpi = result["vo_cpi"][label]["cpi"]
                entry["vo_cpi"] = model_cpi
                entry["vo_realtime_factor_320x256_60hz"] = round(
                    cpu["clock_ghz"] * 1e9 / (per_frame * model_cpi * 60), 2)
            result["summary"][label] = entry
    if args.save_json:
        with open(args.save_json, "w") as f:
            json.dump(result, f, indent=1)
    if args.json:
        json.dump(result, sys.stdout, indent=1)
        print()
    else:
        print_table(result, targets)


def print_table(result, targets):
    """Markdown tables: the loops per CPU model, the counts per target, the summary."""
    print("Hot loops (llvm-mca, cycles per pixel; instructions per pixel in the loop):\n")
    print("| loop | target | " + " | ".join(
        c["label"] for t in targets for c in TARGETS[t]["cpus"]) + " | instr/px |")
    print("|---|---|" + "---|" * sum(len(TARGETS[t]["cpus"]) for t in targets) + "---|")
    by = {(r["target"], r["loop"], r["cpu"]): r for r in result["loops"]}
    for name, _, function in LOOPS:
        for target in targets:
            cells = []
            for t in targets:
                for c in TARGETS[t]["cpus"]:
                    r = by.get((target, name, c["label"]))
                    cells.append("" if r is None else "llvm-mca failed" if r["cycles_per_pixel"] is None
                                 else f"{r['cycles_per_pixel']:.2f}")
            ipp = by[(target, name, TARGETS[target]["cpus"][0]["label"])]["instructions_per_pixel"]
            print(f"| {name} (`{function}`) | {target} | " + " | ".join(cells) + f" | {ipp:.2f} |")
    print("\nInstructions executed under qemu-user (bolo-board-count, 320x256):\n")
    print("| target | pipeline / pixel | corrector / pixel | VO / frame (frames counted) |")
    print("|---|---|---|---|")
    for target in targets:
        c = result["instructions"][target]
        print(f"| {target} | {c['pipeline_per_pixel_320x256']:.2f} | "
              f"{c['corrector_per_pixel_320x256']:.2f} | "
              f"{c['vo_per_frame_320x256'] / 1e6:.1f} M ({c['vo_frames_counted']}) |")
    print("\nSummary. Loops: the intake and corrector loops under llvm-mca. Whole run: the "
          "instructions qemu counts per pixel x the CPI of the blocks they ran in (llvm-mca).\n")
    print("| CPU model | clock | corrector cycles/px (loop) | pipeline cycles/px (loops) | "
          "pipeline cycles/px (whole run) | 640x512 at 60 Hz: share of one core (loops / whole run) | "
          "VO 320x256 at 60 Hz: real-time factor (CPI) |")
    print("|---|---|---|---|---|---|---|")
    for label, e in result["summary"].items():
        vo = (f"{e['vo_realtime_factor_320x256_60hz']:.2f}x (CPI {e['vo_cpi']:.2f})"
              if "vo_cpi" in e else "-")
        def cell(v, fmt):
            return "-" if v is None else fmt.format(v)
        share = cell(e['pipeline_640x512_60hz_core_share_percent'], '{:.1f} %')
        if "pipeline_whole_run_640x512_60hz_core_share_percent" in e:
            share += f" / {e['pipeline_whole_run_640x512_60hz_core_share_percent']:.1f} %"
        print(f"| {label} | {e['clock_ghz']} GHz | {cell(e['corrector_cycles_per_pixel'], '{:.2f}')} | "
              f"{cell(e['pipeline_cycles_per_pixel'], '{:.2f}')} | "
              f"{cell(e.get('pipeline_whole_run_cycles_per_pixel'), '{:.2f}')} | {share} | {vo} |")
    for what in ("pipeline_cpi", "vo_cpi"):
        for label, p in result.get(what, {}).items():
            print(f"\n{what.split('_')[0]} CPI on the {label} model: {p['cpi']:.2f}, from the "
                  f"{p['blocks']} executed blocks that cover {100 * p['covered']:.0f} % of the "
                  f"run's instructions, each timed by llvm-mca.")


if __name__ == "__main__":
    main()
