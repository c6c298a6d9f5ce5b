#!/usr/bin/env python3
"""Cycles per pixel of the firmware's hot loops as the cross compiler emits them, from llvm-mca.

For each loop: the function (found by its demangled name in the compiler's -S output), its
largest innermost loop (see innermost_loop),
fed to llvm-mca with a CPU's scheduling model. Cycles per iteration = llvm-mca's total cycles /
iterations; divided by the pixels one iteration handles, read from the loop itself: the largest
step of a pointer that the loop adds to itself (bytes; two per uint16 pixel).

  mca_loops.py CONFIG.json  ->  JSON on stdout
CONFIG: {"llvm_mca": "llvm-mca", "loops": [{"name", "asm", "function"}],
         "cpus": [{"label", "triple", "cpu", "mattr"}], "keep": DIR or null}
"""
import json
import re
import subprocess
import sys

LABEL = re.compile(r"^(\.L\w+):")
BRANCH_TARGET = re.compile(r"(\.L\w+)\s*$")


def functions(asm_lines):
    """name -> (first, last) line indices of each function's body."""
    out = {}
    start = {}
    for i, line in enumerate(asm_lines):
        m = re.match(r"^\s*\.type\s+([^,]+),\s*[%@]function", line)
        if m:
            start[m.group(1)] = i
        m = re.match(r"^\s*\.size\s+([^,]+),\s*\.-", line)
        if m and m.group(1) in start:
            out[m.group(1)] = (start[m.group(1)], i)
    return out


def demangle(names):
    result = subprocess.run(["c++filt"], input="\n".join(names), capture_output=True, text=True,
                            check=True)
    return dict(zip(names, result.stdout.splitlines()))


def instruction(line):
    """The instruction on an assembly line (comments dropped), or None."""
    text = re.split(r"//|@", line, maxsplit=1)[0].strip()
    if not text or text.startswith(".") or LABEL.match(text) or text.endswith(":"):
        return None
    return text


def innermost_loop(body):
    """Instructions of the largest innermost loop: a label and the last backward branch to it,
    with no other such loop inside, and no call or return (which marks a region that runs from
    inside a loop through out-of-line code back into it)."""
    labels = {}
    loops = []
    for i, line in enumerate(body):
        m = LABEL.match(line.strip())
        if m:
            labels[m.group(1)] = i
            continue
        text = instruction(line)
        if text is None:
            continue
        target = BRANCH_TARGET.search(text)
        if target and target.group(1) in labels and text.split()[0].startswith(("b", "cb", "tb")):
            loops.append((labels[target.group(1)], i))
    inner = [a for a in loops if not any(b != a and a[0] <= b[0] and b[1] <= a[1] for b in loops)]
    bodies = [[t for t in (instruction(l) for l in body[a:b + 1]) if t is not None] for a, b in inner]
    bodies = [b for b in bodies if not any(re.match(r"(bl|blx|ret|bx\s+lr)\b|pop\s.*pc", t) for t in b)]
    return max(bodies, key=len) if bodies else None


def pixels_per_iteration(loop_text):
    """Half the largest immediate a register adds to itself in the loop (its pixel pointers'
    step in bytes), or None."""
    steps = []
    for t in loop_text:
        m = re.match(r"adds?(?:\.w)?\s+(\w+),\s*(\w+),\s*#?(\d+)$", t)
        if m and m.group(1) == m.group(2):
            steps.append(int(m.group(3)))
    return max(steps) // 2 if steps else None


def sequential_pair(first, second):
    """Whether ldrd/strd's two registers form the even/odd pair ARM state requires."""
    a, b = (re.fullmatch(r"r(\d+)", r) for r in (first, second))
    return bool(a and b) and int(a[1]) % 2 == 0 and int(b[1]) == int(a[1]) + 1


def thumb_as_arm(loop_text):
    """A Thumb-2 loop in ARM state, which llvm-mca models: IT instructions dropped (ARM predicates
    each instruction itself), cbz/cbnz as cmp + beq/bne, ldrd/strd of a pair ARM state cannot
    encode as two ldr/str, vswp (which the A9 model lacks) as one vorr, .w/.n suffixes dropped."""
    out = []
    for t in loop_text:
        mnemonic, _, operands = t.replace("\t", " ").partition(" ")
        operands = operands.strip()
        mnemonic = re.sub(r"\.[wn]$", "", mnemonic)
        if re.fullmatch(r"it[te]{0,3}", mnemonic):
            continue
        if mnemonic in ("cbz", "cbnz"):
            reg, target = (o.strip() for o in operands.split(","))
            out += [f"cmp {reg}, #0", f"{'beq' if mnemonic == 'cbz' else 'bne'} {target}"]
            continue
        if mnemonic == "vswp":  # no scheduling data in LLVM 14's A9 model: one NEON issue, as vmov
            first, second = (o.strip() for o in operands.split(","))
            out.append(f"vorr {first}, {second}, {second}")
            continue
        pair = re.fullmatch(r"(\w+),\s*(\w+),\s*\[(\w+)(?:,\s*#(-?\d+))?\]", operands)
        if mnemonic in ("ldrd", "strd") and pair and not sequential_pair(pair[1], pair[2]):
            # ARM state pairs an even register with the next one; Thumb-2 pairs any two
            first, second, base, offset = pair[1], pair[2], pair[3], int(pair[4] or 0)
            single = mnemonic[:-1]
            out += [f"{single} {first}, [{base}, #{offset}]", f"{single} {second}, [{base}, #{offset + 4}]"]
            continue
        out.append(f"{mnemonic} {operands}".strip())
    return out


def run_mca(llvm_mca, cpu, loop_text, keep_path):
    if cpu.get("thumb_as_arm"):
        loop_text = thumb_as_arm(loop_text)
    source = "\t.syntax unified\n" if cpu["triple"].startswith("arm") else ""
    source += "".join(f"\t{t}\n" for t in loop_text)
    if keep_path:
        with open(keep_path, "w") as f:
            f.write(source)
    args = [llvm_mca, f"-mtriple={cpu['triple']}", f"-mcpu={cpu['cpu']}", "-iterations=200",
            "-resource-pressure", "-instruction-info=false"]
    if cpu.get("mattr"):
        args.append(f"-mattr={cpu['mattr']}")
    result = subprocess.run(args, input=source, capture_output=True, text=True)
    if result.returncode != 0:
        raise RuntimeError(f"llvm-mca {cpu['cpu']}: {result.stderr.strip()}")
    out = result.stdout
    iterations = int(re.search(r"^Iterations:\s+(\d+)", out, re.M).group(1))
    cycles = int(re.search(r"^Total Cycles:\s+(\d+)", out, re.M).group(1))
    # Busiest resource: the per-iteration pressure table's largest column.
    names = re.findall(r"^\[(\d+(?:\.\d+)?)\]\s+-\s+(\S+)", out, re.M)
    busiest = None
    m = re.search(r"Resource pressure per iteration:\n(.*)\n(.*)\n", out)
    if m and names:
        values = m.group(2).split()
        pairs = [(float(v), names[k][1]) for k, v in enumerate(values) if v != "-" and k < len(names)]
        if pairs:
            busiest = max(pairs)
    return cycles / iterations, busiest, out


def main():
    config = json.load(open(sys.argv[1]))
    keep = config.get("keep")
    results = []
    cache = {}
    for loop in config["loops"]:
        if loop["asm"] not in cache:
            lines = open(loop["asm"]).read().splitlines()
            funcs = functions(lines)
            cache[loop["asm"]] = (lines, funcs, demangle(list(funcs)))
        lines, funcs, names = cache[loop["asm"]]
        matches = [f for f in funcs if "::" + loop["function"] + "(" in names[f]]
        if len(matches) != 1:
            raise SystemExit(f"mca_loops: {loop['function']}: {len(matches)} functions in {loop['asm']}")
        first, last = funcs[matches[0]]
        body = innermost_loop(lines[first:last + 1])
        if body is None:
            raise SystemExit(f"mca_loops: {loop['function']}: no loop found")
        pixels = pixels_per_iteration(body)
        if pixels is None:
            raise SystemExit(f"mca_loops: {loop['function']}: no pointer step in its loop")
        loop = dict(loop, pixels=pixels)
        for cpu in config["cpus"]:
            if cpu.get("for") and cpu["for"] != loop.get("target"):
                continue
            tag = re.sub(r"\W+", "_", cpu["label"]).strip("_")
            keep_path = f"{keep}/{loop['target']}-{loop['name']}-{tag}.s" if keep else None
            try:
                per_iteration, busiest, report = run_mca(config["llvm_mca"], cpu, body, keep_path)
            except RuntimeError as error:  # an instruction the CPU model has no data for
                results.append({"target": loop.get("target"), "loop": loop["name"],
                                "cpu": cpu["label"], "instructions_per_iteration": len(body),
                                "pixels_per_iteration": loop["pixels"],
                                "instructions_per_pixel": round(len(body) / loop["pixels"], 3),
                                "cycles_per_pixel": None,
                                "error": str(error).splitlines()[0][:200]})
                continue
            if keep:
                with open(f"{keep}/{loop['target']}-{loop['name']}-{tag}.mca.txt", "w") as f:
                    f.write(report)
            results.append({
                "target": loop.get("target"), "loop": loop["name"], "cpu": cpu["label"],
                "instructions_per_iteration": len(body), "pixels_per_iteration": loop["pixels"],
                "cycles_per_iteration": round(per_iteration, 2),
                "cycles_per_pixel": round(per_iteration / loop["pixels"], 3),
                "instructions_per_pixel": round(len(body) / loop["pixels"], 3),
                "busiest_resource": busiest[1] if busiest else None,
                "busiest_resource_cycles_per_iteration": busiest[0] if busiest else None,
            })
    json.dump(results, sys.stdout, indent=1)
    print()


if __name__ == "__main__":
    main()
