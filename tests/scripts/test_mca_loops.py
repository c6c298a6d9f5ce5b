#!/usr/bin/env python3
"""scripts/board-cost/mca_loops.py reads armhf's Thumb-2 loops in ARM state for llvm-mca's
Cortex-A9 model: the conversion's rules, and that a loop holding what ARM state or the A9 model
cannot take (an ldrd of an odd/even pair, a vswp) gets a cycle count. Exit 77 (skip) without
llvm-mca."""
import os
import shutil
import sys

sys.dont_write_bytecode = True
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts",
                                "board-cost"))
import mca_loops  # noqa: E402

SKIP = 77
failures = []


def check(name, got, want):
    if got != want:
        failures.append(f"{name}: got {got!r}, want {want!r}")


check("it dropped, suffix dropped", mca_loops.thumb_as_arm(["ite\tne", "addne.w\tr1, r1, #4"]),
      ["addne r1, r1, #4"])
check("cbz", mca_loops.thumb_as_arm(["cbz\tr3, .L5"]), ["cmp r3, #0", "beq .L5"])
check("ldrd odd pair", mca_loops.thumb_as_arm(["ldrd\tr2, r1, [sp]"]),
      ["ldr r2, [sp, #0]", "ldr r1, [sp, #4]"])
check("strd offset", mca_loops.thumb_as_arm(["strd\tr3, r7, [r0, #8]"]),
      ["str r3, [r0, #8]", "str r7, [r0, #12]"])
check("ldrd even pair kept", mca_loops.thumb_as_arm(["ldrd\tr2, r3, [sp]"]), ["ldrd r2, r3, [sp]"])
check("vswp", mca_loops.thumb_as_arm(["vswp\td22, d23"]), ["vorr d22, d23, d23"])

if failures:
    print("\n".join(failures))
    sys.exit(1)

if shutil.which("llvm-mca") is None:
    print("SKIP: llvm-mca not installed (the conversion's rules passed)")
    sys.exit(SKIP)
loop = ["vld1.16\t{d16-d17}, [r0]!", "vswp\td16, d17", "vst1.16\t{d16-d17}, [r2]!",
        "ldrd\tr2, r1, [sp]", "orrs\tr2, r2, r1", "subs\tr4, r4, #8", "bne\t.L3"]
cpu = {"label": "A7 (A9 model)", "triple": "armv7a-linux-gnueabihf", "cpu": "cortex-a9",
       "mattr": "+neon", "thumb_as_arm": True}
cycles, _, _ = mca_loops.run_mca("llvm-mca", cpu, loop, None)
if not cycles > 0:
    print(f"llvm-mca gave {cycles} cycles per iteration")
    sys.exit(1)
print(f"ok: {cycles:.2f} cycles per iteration on the A9 model")
