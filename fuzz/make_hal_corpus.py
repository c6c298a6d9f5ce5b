#!/usr/bin/env python3
"""Writes the seed corpora of the HAL protocol fuzz targets (standard library only):

  fuzz/corpus/flirone_reassembly/  real FLIR ONE Pro bulk transfers (../shared/data/usb/flirone-pro)
                                   and synthetic frames (valid CRCs, small JPEG) in odd splits
  fuzz/corpus/seek_frame/          Seek Compact / CompactPro frames built per the protocol facts
  fuzz/corpus/y16_telemetry/       the real capture's 80x60 frame + 3 telemetry rows as Y16, and
                                   a PureThermal-style 160x122 frame carrying its telemetry row A

Input layouts are those the targets read (fuzz/targets/fuzz_<name>.cpp).

    python3 fuzz/make_hal_corpus.py [SHARED_DATA]
"""
import os
import struct
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
SHARED = sys.argv[1] if len(sys.argv) > 1 else os.path.join(HERE, "..", "..", "shared", "data")
CAPTURE = os.path.join(SHARED, "usb", "flirone-pro")
SEP = b"--xfer--"


def out(target, name, data):
    folder = os.path.join(HERE, "corpus", target)
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(folder, name), "wb") as f:
        f.write(data)


def crc16(data):
    crc = 0
    for b in data:
        crc ^= b << 8
        for _ in range(8):
            crc = ((crc << 1) ^ 0x1021) & 0xFFFF if crc & 0x8000 else (crc << 1) & 0xFFFF
    return crc


def vospi_crc(packet):  # LE words -> BE bytes, T-number and CRC field zeroed
    b = bytearray()
    for i in range(0, len(packet), 2):
        hi, lo = packet[i + 1], packet[i]
        if i == 0:
            hi &= 0x0F
        if i == 2:
            hi = lo = 0
        b += bytes([hi, lo])
    return crc16(b)


def flirone_frame(base=3000, counter=100, jpeg=b"\xff\xd8\xff\xd9", status=b'{"shutterState":"ON","ffcState":"FFC_VALID_RAD","usbNotifiedTimestamp":1.5}\0'):
    thermal = bytearray()
    for p in range(63):
        words = [0] * 80
        if p < 60:
            words = [(base + x + 80 * p) & 0x3FFF for x in range(80)]
        elif p == 60:
            words[3] = 0x838
            words[20], words[21] = counter & 0xFFFF, counter >> 16
            words[24], words[26] = 32000, 32009
        packet = bytearray(struct.pack("<HH80H", 0x6000 if p == 0 else p, 0, *words))
        struct.pack_into("<H", packet, 2, vospi_crc(packet))
        thermal += packet
    total = len(thermal) + len(jpeg) + len(status)
    header = struct.pack("<7I", 0xBEEF, 1, total, len(thermal), len(jpeg), len(status), 12345)
    return header + thermal + jpeg + status


def split(data, size):
    return [data[i:i + size] for i in range(0, len(data), size)]


def capture():
    if not os.path.isdir(CAPTURE):
        print("make_hal_corpus: %s absent: real seeds skipped" % CAPTURE, file=sys.stderr)
        return None
    transfers = []
    for i in range(1, 110):
        with open(os.path.join(CAPTURE, "%d.txt" % i)) as f:
            transfers.append(bytes.fromhex(f.read().strip()))
    return transfers


def main():
    real = capture()
    # ---- flirone_reassembly: flag byte (bit 0 verify CRC, bit 1 skip duplicates, bits 2-3 buffer)
    if real:
        # files 1..6: an empty transfer, then frame 0 and the header of frame 1
        out("flirone_reassembly", "real-frame-0", b"\x0d" + SEP.join(real[0:7]))
        # frame 12 arrives with its thermal part inside a 32 KiB transfer (files 67..71)
        out("flirone_reassembly", "real-frame-12-merged-split", b"\x0d" + SEP.join(real[66:72]))
        # frame 0 with one pixel corrupted: the CRC check must refuse it
        bad = bytearray(real[2])
        bad[500] ^= 0x04
        out("flirone_reassembly", "real-frame-0-bad-crc", b"\x0d" + SEP.join([real[1], bytes(bad)] + real[3:6]))
    a, b = flirone_frame(1000, 3), flirone_frame(2000, 6)
    out("flirone_reassembly", "synthetic-two-frames-one-transfer", b"\x01" + a + b)
    out("flirone_reassembly", "synthetic-164-byte-transfers", b"\x01" + SEP.join(split(a, 164)))
    out("flirone_reassembly", "synthetic-truncated-then-whole", b"\x01" + SEP.join([a[:5000], a, b"", b[100:300]]))
    out("flirone_reassembly", "synthetic-no-crc-check-small-buffer", b"\x00" + SEP.join(split(b, 4096)))

    # ---- seek_frame: model byte, u16 chunk lengths ending in 0, the byte stream
    def seek(model_pro, w, h, type_word, counter_word, header_rows, ftype, dead=(), chunk=None):
        words = [(2000 + i % 1000) for i in range(w * h)]
        for k, d in enumerate(dead):
            words[header_rows * w + d] = 0xFFFF if k % 2 else 0
        words[type_word], words[counter_word] = ftype, 7
        frame = struct.pack("<%dH" % len(words), *words)
        chunk = chunk or (13680 if model_pro else 16224)
        lengths = []
        left = len(frame)
        while left > 0:
            lengths.append(min(chunk, left))
            left -= lengths[-1]
        return bytes([1 if model_pro else 0]) + struct.pack("<%dH" % len(lengths), *lengths) + b"\0\0" + frame
    out("seek_frame", "compact-startup-dead-pixels", seek(False, 208, 156, 10, 40, 0, 4, dead=(3, 11, 500, 32000)))
    out("seek_frame", "compact-shutter", seek(False, 208, 156, 10, 40, 0, 1))
    out("seek_frame", "pro-startup-odd-chunks", seek(True, 342, 260, 2, 1, 4, 4, dead=(0, 1, 87551), chunk=9999))
    out("seek_frame", "compact-zero-length-read", b"\x00" + struct.pack("<HH", 16224, 0) + b"\x00\x00" * 3)

    # ---- y16_telemetry: width, image rows, telemetry rows, bytes per line (u16, u16, u8, u16), buffer
    if real:
        frame0 = b"".join(real[2:6])[28:28 + 10332]
        y16 = b"".join(frame0[p * 164 + 4:(p + 1) * 164] for p in range(63))
        out("y16_telemetry", "real-flirone-80x60-3-telemetry-rows", struct.pack("<HHBH", 80, 60, 3, 160) + y16)
        row_a = frame0[60 * 164 + 4:61 * 164]
        image = b"".join(struct.pack("<160H", *[(y * 100 + x) & 0x3FFF for x in range(160)]) for y in range(120))
        tel = row_a + bytes(160) + bytes(320)
        out("y16_telemetry", "purethermal-160x122-real-row-a", struct.pack("<HHBH", 160, 120, 2, 320) + image + tel)
        padded = b"".join(image[r * 320:(r + 1) * 320] + b"\xee" * 64 for r in range(120)) + tel
        out("y16_telemetry", "purethermal-160x122-padded-384", struct.pack("<HHBH", 160, 120, 2, 384) + padded)
    out("y16_telemetry", "boson-like-64x8-no-telemetry", struct.pack("<HHBH", 64, 8, 0, 0) + bytes(range(256)) * 4)
    out("y16_telemetry", "short-buffer", struct.pack("<HHBH", 160, 120, 2, 320) + bytes(1000))


main()
