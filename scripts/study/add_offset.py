#!/usr/bin/env python3
"""Copies a recording with a camera offset added to every raw count.

A camera's raw counts start from what a pixel reads with no scene signal, not from 0;
`bolo simulate`, like the paper's model, has no such offset. This writes SRC again as DST with
OFFSET counts added to frames.npy (uint16, within the recording's bit depth) and every other
file copied as it is.

    scripts/study/add_offset.py SRC DST OFFSET
"""
import array
import json
import shutil
import struct
import sys
from pathlib import Path


def fail(message):
    print(f"add_offset.py: {message}", file=sys.stderr)
    sys.exit(2)


def main():
    if len(sys.argv) != 4:
        fail("usage: add_offset.py SRC DST OFFSET")
    src, dst, offset = Path(sys.argv[1]), Path(sys.argv[2]), int(sys.argv[3])
    frames = src / "frames.npy"
    data = frames.read_bytes() if frames.is_file() else fail(f"{frames}: absent")
    if data[:6] != b"\x93NUMPY" or data[6] != 1:
        fail(f"{frames}: not a version 1 .npy file")
    header_len = struct.unpack("<H", data[8:10])[0]
    header = data[10:10 + header_len].decode("latin-1")
    if "'<u2'" not in header:
        fail(f"{frames}: field descr: not <u2")
    bits = json.loads((src / "recording.json").read_text())["bits"]
    counts = array.array("H")
    counts.frombytes(data[10 + header_len:])
    if sys.byteorder != "little":
        counts.byteswap()
    top = max(counts) + offset
    if top >= 1 << bits or min(counts) + offset < 0:
        fail(f"{frames}: an offset of {offset} counts leaves the {bits}-bit range (up to {top})")
    shifted = array.array("H", (c + offset for c in counts))
    if sys.byteorder != "little":
        shifted.byteswap()
    tmp = dst.with_name(dst.name + ".partial")
    shutil.rmtree(tmp, ignore_errors=True)
    shutil.copytree(src, tmp)
    (tmp / "frames.npy").write_bytes(data[:10 + header_len] + shifted.tobytes())
    shutil.rmtree(dst, ignore_errors=True)
    tmp.rename(dst)


if __name__ == "__main__":
    main()
