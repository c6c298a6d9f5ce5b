#!/usr/bin/env python3
"""Instructions executed, from qemu-user's log of `-d in_asm,exec,nochain` (read from stdin or a
FIFO as it is written). Each translated block is listed once (`IN:` and one line per guest
instruction, the first one's address is the block's pc); with `nochain` every execution of a
block logs a `Trace` line with that pc. The sum over the Trace lines of their block's length is
the count of guest instructions executed (a block left early by an exception counts whole).
Prints: executed_instructions executed_blocks"""
import sys


def count(source):
    """(instructions executed, blocks executed) of a log read as bytes lines."""
    lengths: dict[bytes, int] = {}
    executed = blocks = 0
    pending_pc = None
    pending_len = 0
    for line in source:
        if line.startswith(b"Trace "):
            # Trace 0: 0xHOST [cs_base/pc/flags/cflags]
            pc = line.split(b"[", 1)[1].split(b"/", 2)[1].lstrip(b"0")
            executed += lengths.get(pc, 0)
            blocks += 1
        elif line.startswith(b"0x"):
            if pending_pc is None:
                pending_pc = line[2:line.index(b":")].lstrip(b"0")
                pending_len = 0
            pending_len += 1
        elif pending_pc is not None:  # the blank line that ends a block listing
            lengths[pending_pc] = pending_len
            pending_pc = None
    return executed, blocks


def main() -> int:
    source = open(sys.argv[1], "rb") if len(sys.argv) > 1 else sys.stdin.buffer
    print(*count(source))
    return 0


if __name__ == "__main__":
    sys.exit(main())
