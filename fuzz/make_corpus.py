#!/usr/bin/env python3
"""Writes the seed corpora in fuzz/corpus/<target>/ (standard library only).

Real data comes from ../shared/data (small files whole; frames.npy cut to a few KB and given a
header for fewer frames/rows); the rest is generated here: PNGs (plain, interlaced, wrong depth),
.npy variants, and inputs for the structured targets (raw_stream, pipeline) laid out as
fuzz/targets/fuzz_<name>.cpp reads them. Run from anywhere; rewrites the corpus folders.

    python3 fuzz/make_corpus.py [SHARED_DATA]
"""
import os
import struct
import sys
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
SHARED = sys.argv[1] if len(sys.argv) > 1 else os.path.join(HERE, "..", "..", "shared", "data")
REAL = os.path.join(SHARED, "real")
SEP = b"\n--bolo-file--\n"  # the folder and png targets split their input here


def out(target, name, data):
    folder = os.path.join(HERE, "corpus", target)
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(folder, name), "wb") as f:
        f.write(data if isinstance(data, bytes) else data.encode())


def read(*parts):
    with open(os.path.join(REAL, *parts), "rb") as f:
        return f.read()


# ---- .npy
def npy(descr, shape, data, version=1, fortran=False):
    dims = ", ".join(str(d) for d in shape) + ("," if len(shape) == 1 else "")
    text = "{'descr': '%s', 'fortran_order': %s, 'shape': (%s), }" % (
        descr, "True" if fortran else "False", dims)
    length_bytes = 2 if version == 1 else 4
    total = (6 + 2 + length_bytes + len(text) + 1 + 63) // 64 * 64
    text = text.ljust(total - 6 - 2 - length_bytes - 1) + "\n"
    length = struct.pack("<H" if version == 1 else "<I", len(text))
    return b"\x93NUMPY" + bytes([version, 0]) + length + text.encode("latin1") + data


def npy_data(raw):
    """Array bytes of a .npy file (after its header)."""
    length_bytes = 2 if raw[6] == 1 else 4
    n = int.from_bytes(raw[8:8 + length_bytes], "little")
    return raw[8 + length_bytes + n:]


def u16s(values):
    return struct.pack("<%dH" % len(values), *values)


def f32s(values):
    return struct.pack("<%df" % len(values), *values)


flir1 = npy_data(read("flirone-lepton-telemetry", "frames.npy"))  # (20, 60, 80) uint16
possum = npy_data(read("lepton3-possum", "frames.npy"))           # (N, 120, 160) uint16

# ---- png (16-bit grayscale unless stated)
def chunk(kind, body):
    return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))


ADAM7 = [(0, 0, 8, 8), (4, 0, 8, 8), (0, 4, 4, 8), (2, 0, 4, 4), (0, 2, 2, 4), (1, 0, 2, 2), (0, 1, 1, 2)]


def png(width, height, pixels, depth=16, color=0, interlace=0):
    """pixels: row-major sample values (one per pixel, gray)."""
    bpp = depth // 8

    def row_bytes(xs, y):
        body = b"".join(pixels[y * width + x].to_bytes(bpp, "big") for x in xs)
        return b"\x00" + body  # filter type 0

    raw = b""
    if interlace == 0:
        for y in range(height):
            raw += row_bytes(range(width), y)
    else:
        for x0, y0, dx, dy in ADAM7:
            xs = list(range(x0, width, dx))
            if not xs:
                continue
            for y in range(y0, height, dy):
                raw += row_bytes(xs, y)
    ihdr = struct.pack(">IIBBBBB", width, height, depth, color, 0, 0, interlace)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(raw, 9)) +
            chunk(b"IEND", b""))


def le16(data, count, start=0):
    return list(struct.unpack_from("<%dH" % count, data, start))


def main():
    # npy
    out("npy", "flirone-1x60x80.npy", npy("<u2", (1, 60, 80), flir1[:60 * 80 * 2]))
    out("npy", "possum-1x8x160.npy", npy("<u2", (1, 8, 160), possum[:8 * 160 * 2]))
    out("npy", "possum-3x4x16-v2.npy", npy("<u2", (3, 4, 16), possum[:3 * 4 * 16 * 2], version=2))
    out("npy", "scene-2x3x4-f4.npy", npy("<f4", (2, 3, 4), f32s([i * 0.5 - 3 for i in range(24)])))
    out("npy", "empty-0x4x4-v3.npy", npy("<u2", (0, 4, 4), b"", version=3))
    out("npy", "flat-5.npy", npy("<u2", (5,), u16s(range(5))))
    out("npy", "fortran-2x2x2.npy", npy("<u2", (2, 2, 2), u16s(range(8)), fortran=True))

    # frames.csv, recording.json: the shared recordings' own
    for rec in sorted(os.listdir(REAL)):
        out("frames_csv", rec + ".csv", read(rec, "frames.csv"))
        out("recording_json", rec + ".json", read(rec, "recording.json"))
    out("frames_csv", "all-columns-crlf-bom.csv",
        "\ufeffindex,t_s,exposure_s,readout_s,ffc,fpa_temp_c,housing_temp_c\r\n"
        "0,0.0,0.01,0.1,1,30.5,25.25\r\n1,0.1111,1e-2,0.1,0,,\r\n2,,,,,-1.5e1,\r\n"
        "3,0.4, 0.01 ,0.1,0,30.6,25.3\r\n\r\n")
    out("recording_json", "extra-keys.json",
        '{"format": "bolo-recording", "version": 1.0, "width": 4, "height": 3, "bits": 16,'
        ' "fps": null, "units": "centikelvin", "sensor": "s\\u00e9nsor", "source": null,'
        ' "notes": "", "camera": {"k": [[1, 0, 2], [0, 1, 1.5], [0, 0, 1]]}, "tags": ["a", 1, -2,'
        ' 3.25e-7, true, false, null], "big": 18446744073709551615, "neg": -9223372036854775808}\n')

    # whole folders: recording.json, frames.csv, frames.npy[, camera.json[, scene.npy]]
    info = ('{"format": "bolo-recording", "version": 1, "sensor": "FLIR ONE Pro", "width": 80,'
            ' "height": 60, "bits": 14, "fps": 8.6, "units": "counts"}\n')
    csv = read("flirone-lepton-telemetry", "frames.csv").decode().splitlines()
    out("recording_folder", "flirone-2-frames",
        SEP.join([info.encode(), ("\n".join(csv[:3]) + "\n").encode(),
                  npy("<u2", (2, 60, 80), flir1[:2 * 60 * 80 * 2])]))
    small = ('{"format": "bolo-recording", "version": 1, "width": 4, "height": 3, "fps": 30,'
             ' "units": "counts", "extra": {"x": 1}}\n')
    rows = ("index,t_s,exposure_s,readout_s,ffc,fpa_temp_c,housing_temp_c\n"
            "0,0.0,0.01,0.02,0,30.0,25.0\n1,0.0333,0.01,0.02,1,30.1,25.0\n2,0.0667,,,,,\n")
    out("recording_folder", "small-scene-camera",
        SEP.join([small.encode(), rows.encode(), npy("<u2", (3, 3, 4), u16s(range(0, 3600, 100))),
                  b'{"model": "pinhole", "fx": 100.0, "fy": 100.0, "cx": 2.0, "cy": 1.5}\n',
                  npy("<f4", (3, 3, 4), f32s([i * 0.25 for i in range(36)]))]))

    # png
    gradient = [(x * 4096 + y * 257) & 0xFFFF for y in range(8) for x in range(16)]
    out("png", "gradient-16x8.png", png(16, 8, gradient))
    out("png", "flirone-80x60.png", png(80, 60, le16(flir1, 80 * 60)))
    out("png", "interlaced-13x11.png", png(13, 11, [(i * 977) & 0xFFFF for i in range(143)], interlace=1))
    out("png", "gray8-6x4.png", png(6, 4, [i * 10 for i in range(24)], depth=8))
    out("png", "two-frames.png", png(16, 8, gradient) + SEP + png(16, 8, gradient[::-1]))

    # raw_stream: width, height, bits (1 byte each), period, exposure, readout (u32), then the
    # pipeline configuration (pipeline_harness.hpp), then the stream itself.
    def pipeline_config(options, period=None, density=None, short=None):
        cfg = struct.pack("<IIII", 12_000_000, 12_000_000, 10_000_000, 90_000_000)
        cfg += b"\x01" + struct.pack("<I", period) if period is not None else b"\x00"
        cfg += bytes([options]) + struct.pack("<I", 12345)
        if options & 2:
            if options & 4:
                cfg += bytes([density])
            cfg += struct.pack("<HH", 0, 0x3FFF)
        if options & 0x80:
            cfg += bytes([short])
        return cfg

    raw_head = bytes([40, 30, 14]) + struct.pack("<III", 111_000_000, 10_000_000, 90_000_000)
    out("raw_stream", "flirone-40x30-2-frames-tail",
        raw_head + pipeline_config(2 | 8) + flir1[:2 * 40 * 30 * 2 + 77])
    out("raw_stream", "flirone-40x30-nuc-mask",
        raw_head + pipeline_config(1 | 2 | 4 | 8, period=111_000_000, density=20) + flir1[:3 * 40 * 30 * 2])
    out("raw_stream", "tiny-3x2-short-arena",
        bytes([3, 2, 16]) + struct.pack("<III", 0, 0, 0) + pipeline_config(0x80 | 2, short=3) +
        bytes(range(40)))

    # pipeline: width, height (1 byte each), pipeline configuration, pixel seed (u32), operations
    def whole_frame(dt, exposure, readout, ffc, rails):
        return bytes([6]) + struct.pack("<IIIBB", dt, exposure, readout, ffc, rails)

    ops = b"".join(whole_frame(33_333_333, 10_000_000, 20_000_000, 1, 0x11) for _ in range(4))
    out("pipeline", "16x8-nuc-mask-4-frames",
        bytes([16, 8]) + pipeline_config(1 | 2 | 4 | 8, period=33_333_333, density=10) +
        struct.pack("<I", 7) + ops)
    begin = bytes([0, 0x3F]) + struct.pack("<IIIB", 33_000_000, 10_000_000, 20_000_000, 0)
    push_next = bytes([2, 0x01 | 0x04 | 0x08]) + u16s([0x3FFF, 5, 6, 7, 8])  # next row, width 5
    out("pipeline", "5x3-by-lines",
        bytes([5, 3]) + pipeline_config(2 | 8) + struct.pack("<I", 9) +
        begin + push_next * 3 + bytes([5]) + begin + push_next * 2 + bytes([5]) +
        bytes([2, 0x02, 1, 7]) + bytes(14) + bytes([5]))
    out("pipeline", "odd-headers",
        bytes([8, 4]) + pipeline_config(2) + struct.pack("<I", 3) +
        bytes([0, 0x00, 9, 4]) + struct.pack("<QBqBIIB", 2**63, 1, -2**63, 1, 1, 1, 3) +
        bytes([2, 0x04]) + bytes([5]) + whole_frame(1, 1, 1, 0, 0) + bytes([7]) + bytes(8) +
        whole_frame(2**32 - 1, 2**32 - 1, 2**32 - 1, 2, 0xFF))


if __name__ == "__main__":
    main()
