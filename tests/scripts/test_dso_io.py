#!/usr/bin/env python3
"""scripts/study/dso_io.py, the DSO peer's converter (no DSO needed): a small recording becomes
DSO's input (PNGs with one linear map for the sequence, times.txt, camera.txt; all frames or every
second from frame 1), and a result.txt
with three of four frames posed, a similarity away from the truth, becomes a run that
`bolo evaluate` (argv[1]) scores with an ATE of ~0 and 75 % of the frames posed. Exit 77 (skip)
without NumPy for /usr/bin/python3, which the study scripts run."""
import json
import math
import subprocess
import sys
import tempfile
from pathlib import Path

SKIP = 77
PYTHON = "/usr/bin/python3"
CONVERTER = Path(__file__).resolve().parents[2] / "scripts" / "study" / "dso_io.py"
failures = []


def check(name, got, want):
    if got != want:
        failures.append(f"{name}: got {got!r}, want {want!r}")


if subprocess.run([PYTHON, "-c", "import numpy"], capture_output=True).returncode != 0:
    print(f"SKIP: {PYTHON} has no NumPy (Debian python3-numpy)")
    sys.exit(SKIP)

bolo = sys.argv[1]
with tempfile.TemporaryDirectory() as tmp:
    rec, dso_in, run = Path(tmp, "rec"), Path(tmp, "in"), Path(tmp, "run")
    rec.mkdir()
    # 4 frames of 6x4 counts 1000 + 10 * (frame + column): the 0.5 / 99.5 percentiles are near 1000 and 1080.
    script = (f"import numpy as np; i, y, x = np.mgrid[0:4, 0:4, 0:6]; "
              f"np.save('{rec}/frames.npy', (1000 + 10 * (i + x)).astype('<u2'))")
    subprocess.run([PYTHON, "-c", script], check=True)
    times = [0.0, 0.1, 0.2, 0.3]
    (rec / "frames.csv").write_text("index,t_s,exposure_s,readout_s,ffc,fpa_temp_c,housing_temp_c\n"
                                    + "".join(f"{i},{t},0.05,0.05,0,,\n" for i, t in enumerate(times)))
    (rec / "camera.json").write_text(json.dumps({"model": "pinhole", "fx": 5.0, "fy": 5.0, "cx": 2.5, "cy": 1.5}))
    truth = [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (1.0, 1.0, 0.0), (2.0, 1.0, 0.5)]
    (rec / "poses.tum").write_text("".join(f"{t} {x} {y} {z} 0 0 0 1\n" for t, (x, y, z) in zip(times, truth)))

    subprocess.run([PYTHON, str(CONVERTER), "input", str(rec), str(dso_in)], check=True)
    pngs = sorted(p.name for p in (dso_in / "images").iterdir())
    check("images", pngs, ["000000.png", "000001.png", "000002.png", "000003.png"])
    check("png signature", (dso_in / "images" / "000000.png").read_bytes()[:8], b"\x89PNG\r\n\x1a\n")
    check("times.txt", (dso_in / "times.txt").read_text(), "0 0.0\n1 0.1\n2 0.2\n3 0.3\n")
    check("camera.txt", (dso_in / "camera.txt").read_text(), "Pinhole 5.0 5.0 2.5 1.5 0\n6 4\nnone\n6 4\n")
    mapping = json.loads((dso_in / "map.json").read_text())
    check("map", (round(mapping["counts_at_0"], 2), round(mapping["counts_at_255"], 2)), (1000.0, 1080.0))

    # Every second frame from frame 1: frames 1 and 3, numbered from 0, with their own times.
    strided = Path(tmp, "strided")
    subprocess.run([PYTHON, str(CONVERTER), "input", str(rec), str(strided), "--first", "1", "--stride", "2"], check=True)
    check("strided images", sorted(p.name for p in (strided / "images").iterdir()), ["000000.png", "000001.png"])
    check("strided times.txt", (strided / "times.txt").read_text(), "0 0.1\n1 0.3\n")
    check("strided frames", json.loads((strided / "map.json").read_text())["frames"], [1, 3])

    # DSO's poses of frames 1-3 in its own frame: the truth scaled by 0.5 and shifted, with
    # Eigen's padded columns; frame 0 never posed.
    result = dso_in / "result.txt"
    result.write_text("".join(f"{t} {0.5 * x + 3:>10} {0.5 * y - 1:>10} {0.5 * z:>10} 0 0 0 1\n"
                              for t, (x, y, z) in list(zip(times, truth))[1:]))
    subprocess.run([PYTHON, str(CONVERTER), "output", str(rec), str(result), str(run), "--given", str(dso_in / "map.json"),
                    "--name", "dso", "--wall-s", "0.4", "--cpu-s", "0.4"], check=True)
    check("poses", len((run / "trajectory.tum").read_text().splitlines()), 3)
    states = [line.split(",")[2] for line in (run / "stats.csv").read_text().splitlines()[1:]]
    check("states", states, ["initialising", "tracking", "tracking", "tracking"])
    summary = json.loads((run / "summary.json").read_text())
    check("fps", summary["fps_wall"], 10.0)

    subprocess.run([bolo, "evaluate", str(run), "--json", str(run / "evaluation.json")], check=True,
                   stdout=subprocess.DEVNULL)
    e = json.loads((run / "evaluation.json").read_text())
    check("coverage", e["coverage"], 0.75)
    if not e["ate_rmse_m"] < 1e-6:
        failures.append(f"ATE {e['ate_rmse_m']} m, want ~0")
    if not math.isclose(e["scale"], 2.0, rel_tol=1e-6):
        failures.append(f"scale {e['scale']}, want 2")

    # A frame DSO's result names at a time no frame has is an error naming the file.
    result.write_text("0.05 0 0 0 0 0 0 1\n")
    bad = subprocess.run([PYTHON, str(CONVERTER), "output", str(rec), str(result), str(run), "--given",
                          str(dso_in / "map.json"), "--name", "dso", "--wall-s", "1", "--cpu-s", "1"],
                         capture_output=True, text=True)
    check("bad time exit", bad.returncode, 1)
    if str(result) not in bad.stderr:
        failures.append(f"bad time message does not name {result}: {bad.stderr!r}")

if failures:
    print("\n".join(failures))
    sys.exit(1)
print("ok: recording -> DSO input -> result.txt -> bolo evaluate")
