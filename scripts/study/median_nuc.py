#!/usr/bin/env python3
"""A NUC file (`bolo correct --nuc`, docs/cli.md) for a recording of a moving camera, from its own
frames: each pixel's temporal median, less its box-blurred self (radius R, default 7), is the
fixed pattern; the offsets take it out, the gains stay 1. The scene moves under the pixels, so its
share of the median is smooth and the blur keeps it. Plain Python (no NumPy).

    scripts/study/median_nuc.py REC OUT.npy [R]
"""
import array
import ast
import statistics
import struct
import sys


def read_frames(rec):
    with open(rec + "/frames.npy", "rb") as f:
        if f.read(6) != b"\x93NUMPY":
            sys.exit("median_nuc: %s/frames.npy: not a .npy file" % rec)
        major = f.read(2)[0]
        header_len = struct.unpack("<H" if major == 1 else "<I", f.read(2 if major == 1 else 4))[0]
        header = ast.literal_eval(f.read(header_len).decode("latin1"))
        if header["descr"] != "<u2" or header["fortran_order"] or len(header["shape"]) != 3:
            sys.exit("median_nuc: %s/frames.npy: expected <u2 frames of shape (N, H, W)" % rec)
        pixels = array.array("H")
        pixels.frombytes(f.read())
    return header["shape"], pixels


def box_blur(image, w, h, r):
    rows = [0.0] * (w * h)
    for y in range(h):
        line = image[y * w:(y + 1) * w]
        for x in range(w):
            lo, hi = max(0, x - r), min(w, x + r + 1)
            rows[y * w + x] = sum(line[lo:hi]) / (hi - lo)
    out = [0.0] * (w * h)
    for x in range(w):
        column = rows[x::w]
        for y in range(h):
            lo, hi = max(0, y - r), min(h, y + r + 1)
            out[y * w + x] = sum(column[lo:hi]) / (hi - lo)
    return out


def main():
    if len(sys.argv) not in (3, 4):
        sys.exit(__doc__)
    rec, out = sys.argv[1], sys.argv[2]
    radius = int(sys.argv[3]) if len(sys.argv) == 4 else 7
    (n, h, w), pixels = read_frames(rec)
    count = w * h
    median = [statistics.median(pixels[p::count]) for p in range(count)]
    smooth = box_blur(median, w, h, radius)
    offset = [smooth[p] - median[p] for p in range(count)]
    header = "{'descr': '<f4', 'fortran_order': False, 'shape': (2, %d, %d), }" % (h, w)
    header += " " * (63 - (10 + len(header)) % 64) + "\n"
    with open(out, "wb") as f:
        f.write(b"\x93NUMPY\x01\x00" + struct.pack("<H", len(header)) + header.encode("latin1"))
        f.write(array.array("f", [1.0] * count + offset).tobytes())
    print("median_nuc: %s: fixed pattern %.2f counts rms over %d frames" % (out, statistics.pstdev(offset), n))


main()
