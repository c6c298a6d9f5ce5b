#!/usr/bin/python3
"""The DSO peer's files (scripts/study/dso-run.sh): a bolo recording as DSO's input, and DSO's
result.txt as a `bolo odometry` output folder that `bolo evaluate` scores like any run.

  dso_io.py input REC OUT [--percentiles LO HI] [--first N] [--stride K]
      OUT/images/NNNNNN.png: frames N, N + K, N + 2K, ... of REC (default all) in 8 bits, one
      linear map for all of them (the LO and HI percentiles of their counts go to 0 and 255);
      OUT/times.txt (`index t_s`: no exposures, DSO's mode=1), OUT/camera.txt (pinhole K in
      pixels, no rectification), OUT/map.json (the map and the frames given).
  dso_io.py output REC RESULT RUN --given MAP_JSON --name NAME --wall-s S --cpu-s S
                   [--exit-status N] [--log FILE]
      RUN/trajectory.tum (the poses of RESULT, matched to the recording's frames by time),
      RUN/stats.csv (a row per frame DSO was given: `tracking` where posed, else `initialising`
      before the first pose and `lost` after it), RUN/summary.json, RUN/points.ply (empty: DSO's
      map is not kept).

Needs NumPy (Debian python3-numpy). Errors name the file and exit 1."""
import argparse
import csv
import json
import math
import struct
import sys
import zlib
from pathlib import Path

import numpy as np


def die(message):
    print(f"dso_io: {message}", file=sys.stderr)
    sys.exit(1)


def frame_times(rec):
    """The t_s column of REC/frames.csv."""
    path = Path(rec, "frames.csv")
    try:
        with open(path, newline="") as f:
            rows = list(csv.DictReader(f))
    except OSError as e:
        die(f"{path}: {e.strerror}")
    if not rows or "t_s" not in rows[0]:
        die(f"{path}: no t_s column")
    times = []
    for n, row in enumerate(rows):
        try:
            times.append(float(row["t_s"]))
        except ValueError:
            die(f"{path}: frame {n}: t_s is not a number: {row['t_s']!r}")
    return times


def load_frames(rec):
    path = Path(rec, "frames.npy")
    try:
        frames = np.load(path, mmap_mode="r")
    except (OSError, ValueError) as e:
        die(f"{path}: {e}")
    if frames.ndim != 3:
        die(f"{path}: expected shape (N, H, W), got {frames.shape}")
    return frames


def pinhole(rec, width, height):
    """DSO's calibration text for REC/camera.json: K in pixels with the centre of the top-left
    pixel at (0, 0), which is DSO's convention for absolute K; no rectification ("none")."""
    path = Path(rec, "camera.json")
    try:
        cam = json.loads(path.read_text())
    except (OSError, ValueError) as e:
        die(f"{path}: {e}")
    if cam.get("model", "pinhole") != "pinhole":
        die(f"{path}: model {cam.get('model')!r}: only pinhole is supported")
    distortion = {k: cam.get(k, 0) for k in ("k1", "k2", "p1", "p2", "k3", "k4", "k5", "k6")}
    if any(v for v in distortion.values()):
        die(f"{path}: non-zero distortion {distortion}: the DSO peer is given undistorted frames only")
    for k in ("fx", "fy", "cx", "cy"):
        if not isinstance(cam.get(k), (int, float)):
            die(f"{path}: {k} missing or not a number")
    if cam["cx"] <= 1 or cam["cy"] <= 1:
        die(f"{path}: cx, cy <= 1 would be read by DSO as a relative calibration")
    return (f"Pinhole {cam['fx']!r} {cam['fy']!r} {cam['cx']!r} {cam['cy']!r} 0\n{width} {height}\n"
            f"none\n{width} {height}\n")


def png_gray8(path, image):
    """A minimal 8-bit greyscale PNG (filter type 0 on every row)."""
    h, w = image.shape
    raw = np.hstack([np.zeros((h, 1), np.uint8), image]).tobytes()

    def chunk(tag, data):
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF)

    path.write_bytes(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 0, 0, 0, 0))
                     + chunk(b"IDAT", zlib.compress(raw, 1)) + chunk(b"IEND", b""))


def write_input(args):
    frames = load_frames(args.rec)
    times = frame_times(args.rec)
    n, h, w = frames.shape
    if len(times) != n:
        die(f"{Path(args.rec, 'frames.csv')}: {len(times)} rows for {n} frames in frames.npy")
    if not 0 <= args.first < n or args.stride < 1:
        die(f"--first {args.first} --stride {args.stride}: {Path(args.rec, 'frames.npy')} has {n} frames")
    given = list(range(args.first, n, args.stride))
    lo, hi = (float(v) for v in np.percentile(frames[args.first::args.stride], args.percentiles))
    if not hi > lo:
        die(f"{Path(args.rec, 'frames.npy')}: flat sequence (percentiles {args.percentiles} both {lo})")
    out = Path(args.out)
    images = out / "images"
    images.mkdir(parents=True, exist_ok=True)
    scale = 255.0 / (hi - lo)
    for k, i in enumerate(given):
        mapped = np.clip(np.rint((frames[i].astype(np.float64) - lo) * scale), 0, 255).astype(np.uint8)
        png_gray8(images / f"{k:06d}.png", mapped)
    (out / "times.txt").write_text("".join(f"{k} {times[i]!r}\n" for k, i in enumerate(given)))
    (out / "camera.txt").write_text(pinhole(args.rec, w, h))
    (out / "map.json").write_text(json.dumps({"percentiles": args.percentiles, "counts_at_0": lo, "counts_at_255": hi,
                                              "frames": given}) + "\n")


def read_result(path):
    """DSO's result.txt: `t tx ty tz qx qy qz qw` per line, camera-to-world; non-finite poses dropped."""
    poses = []
    try:
        lines = Path(path).read_text().splitlines()
    except OSError as e:
        die(f"{path}: {e.strerror}")
    for n, line in enumerate(lines, 1):
        fields = line.split()
        if not fields:
            continue
        try:
            values = [float(v) for v in fields]
        except ValueError:
            die(f"{path}: line {n}: not numbers")
        if len(values) != 8:
            die(f"{path}: line {n}: expected 8 values (t tx ty tz qx qy qz qw), got {len(values)}")
        if all(math.isfinite(v) for v in values):
            poses.append(values)
    return poses


def write_output(args):
    all_times = frame_times(args.rec)
    try:
        given = json.loads(Path(args.given).read_text())["frames"]
    except (OSError, ValueError, KeyError) as e:
        die(f"{args.given}: no list of the frames given ({e})")
    if len(given) < 2 or not all(isinstance(i, int) and 0 <= i < len(all_times) for i in given):
        die(f"{args.given}: frames {given[:5]}...: fewer than 2, or not frames of {args.rec}")
    times = [all_times[i] for i in given]
    period = (times[-1] - times[0]) / (len(times) - 1)
    pose_of = {}  # frame index -> pose
    for p in read_result(args.result):
        i = int(np.argmin([abs(t - p[0]) for t in times]))
        if abs(times[i] - p[0]) > 0.5 * period:
            die(f"{args.result}: pose at t = {p[0]} s matches no frame of {args.rec}")
        pose_of[i] = p
    run = Path(args.run)
    run.mkdir(parents=True, exist_ok=True)
    with open(run / "trajectory.tum", "w") as f:
        for i in sorted(pose_of):
            f.write(" ".join([repr(times[i])] + [f"{v:.9g}" for v in pose_of[i][1:]]) + "\n")
    ms = 1000.0 * args.wall_s / len(times)
    first = min(pose_of) if pose_of else len(times)
    with open(run / "stats.csv", "w") as f:
        f.write("index,t_s,state,tracked_points,keyframe,residual_rms,tau_h_s,tau_c_s,time_ms\n")
        for i, t in enumerate(times):
            state = "tracking" if i in pose_of else ("initialising" if i < first else "lost")
            f.write(f"{given[i]},{t!r},{state},0,0,0,0,0,{ms:.4f}\n")
    (run / "points.ply").write_text("ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\n"
                                    "property float z\nend_header\n")
    log = Path(args.log).read_text(errors="replace") if args.log else ""
    summary = {"photometric": args.name, "recording": str(Path(args.rec).resolve()), "reinitialisations": 0,
               "frames": len(times), "posed": len(pose_of), "wall_s": args.wall_s, "cpu_s": args.cpu_s,
               "fps_wall": len(times) / args.wall_s if args.wall_s > 0 else None,
               "fps_cpu": len(times) / args.cpu_s if args.cpu_s > 0 else None,
               "dso_exit_status": args.exit_status, "dso_resets": log.count("RESETTING!"), "dso_lost": "LOST!!" in log}
    (run / "summary.json").write_text(json.dumps(summary, indent=2) + "\n")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(dest="command", required=True)
    p = sub.add_parser("input")
    p.add_argument("rec")
    p.add_argument("out")
    p.add_argument("--percentiles", nargs=2, type=float, default=[0.5, 99.5], metavar=("LO", "HI"))
    p.add_argument("--first", type=int, default=0, help="the first frame given to DSO")
    p.add_argument("--stride", type=int, default=1, help="every K-th frame from --first on")
    p.set_defaults(func=write_input)
    p = sub.add_parser("output")
    p.add_argument("rec")
    p.add_argument("result")
    p.add_argument("run")
    p.add_argument("--given", required=True, help="map.json of `dso_io.py input`")
    p.add_argument("--name", required=True)
    p.add_argument("--wall-s", type=float, required=True)
    p.add_argument("--cpu-s", type=float, required=True)
    p.add_argument("--exit-status", type=int, default=0, help="dso_dataset's (a crash: 128 + signal)")
    p.add_argument("--log")
    p.set_defaults(func=write_output)
    args = parser.parse_args()
    args.func(args)


if __name__ == "__main__":
    main()
