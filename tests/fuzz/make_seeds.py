#!/usr/bin/env python3
# SPDX-License-Identifier: LGPL-2.1-or-later
"""Writes the seed corpus of fuzz_pointclass (tests/fuzz/corpus/) in the target's input format."""

import os
import struct
import sys

HERE = os.path.dirname(os.path.abspath(__file__))


def header(nrings, cmode, tmode, derived, exp2=0):
    h0 = (nrings - 1) | (cmode << 2) | (tmode << 4) | (derived << 7)
    e16 = (exp2 + 215) % 411
    return bytes([h0, e16 & 0xFF, e16 >> 8])


def small(v):           # coordinate mode 0: int8 / 4
    return struct.pack("b", int(v * 4))


def ring_small(verts):
    return bytes([len(verts)]) + b"".join(small(x) + small(y) for x, y in verts)


def ring_raw(verts):
    return bytes([len(verts)]) + b"".join(struct.pack("<dd", x, y) for x, y in verts)


def seeds():
    sq = [(0, 0), (8, 0), (8, 8), (0, 8)]
    hole = [(2, 2), (2, 6), (6, 6), (6, 2)]
    bowtie = [(0, 0), (4, 4), (4, 0), (0, 4)]
    star = [(0, 7), (4, -6), (-7, 2), (7, 2), (-4, -6)]
    spiky = [(0, 0), (4, 0), (4, 2), (6, 2), (4, 2), (4, 4), (4, 4), (2, 4), (0, 4), (0, 0)]
    pts = [(1, 1), (0, 0), (4, 0), (8, 4), (9, 9), (-1, 4), (4, 4), (2, 2), (5, 2)]
    pblock = bytes([len(pts)]) + b"".join(small(x) + small(y) for x, y in pts)

    yield "square_tol0", header(1, 0, 0, 1) + ring_small(sq) + pblock + b"\x03"
    yield "square_tol_small", header(1, 0, 1, 1) + ring_small(sq) + bytes([5]) + pblock + b"\x01"
    yield "holes", header(2, 0, 7, 1) + ring_small(sq) + ring_small(hole) + bytes([3]) + pblock + b"\x02"
    yield "bowtie", header(1, 0, 5, 1) + ring_small(bowtie) + pblock + b"\x00"
    yield "pentagram", header(1, 0, 0, 1) + ring_small(star) + pblock + b"\x04"
    yield "spiky_repeats", header(1, 0, 1, 1) + ring_small(spiky) + bytes([2]) + pblock + b"\x05"
    yield "four_rings", (header(4, 0, 1, 1) + ring_small(sq) + ring_small(hole) + ring_small(bowtie)
                         + ring_small(star) + bytes([1]) + pblock + b"\x06")
    yield "scaled_huge", header(1, 2, 3, 1, 190) + bytes([4, 0, 0, 8, 0, 8, 8, 0, 8]) + bytes([3]) \
        + bytes([2, 4, 4, 8, 4]) + b"\x01"
    yield "scaled_tiny", header(1, 2, 3, 1, -203) + bytes([4, 0, 0, 8, 0, 8, 8, 0, 8]) + bytes([3]) \
        + bytes([2, 4, 4, 8, 4]) + b"\x01"
    # aim byte 0x11: snap the 8 clustered vertices onto the 8 reference points of their
    # prepared-grid cell, and query the reference points / cell corners around vertices
    cluster = [(4, 4)] * 8
    yield "grid_refs_all_on_boundary", (header(2, 0, 0, 1) + ring_small(sq) + ring_small(cluster)
                                        + pblock + b"\x00\x11")
    yield "grid_refs_tol", (header(2, 0, 1, 1) + ring_small(sq) + ring_small(cluster + [(5, 3)])
                            + bytes([1]) + pblock + b"\x02\x13")
    yield "grid_refs_star", header(1, 0, 7, 1) + ring_small(star) + bytes([1]) + pblock + b"\x01\x1f"
    raw = [(0.1, 0.2), (1e8 + 0.5, 0.2), (1e8, 3e7), (0.1, 1e8)]
    rpts = [(5e7, 1e7), (0.1, 0.2), (1e8, 1.5e7)]
    yield "raw_doubles", (header(1, 1, 2, 1) + ring_raw(raw) + struct.pack("<d", 1e-3)
                          + bytes([len(rpts)]) + b"".join(struct.pack("<dd", *p) for p in rpts) + b"\x02")
    yield "bad_nan", (header(1, 1, 0, 0) + ring_raw([(0, 0), (1, 0), (float("nan"), 1)])
                      + bytes([1]) + struct.pack("<dd", 0.5, 0.5))
    yield "bad_short_ring", header(2, 0, 0, 0) + ring_small(sq) + ring_small(sq[:2]) + pblock
    yield "bad_negative_tol", header(1, 0, 2, 0) + ring_small(sq) + struct.pack("<d", -1.0) + pblock


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(HERE, "corpus")
    os.makedirs(out, exist_ok=True)
    for name, data in seeds():
        with open(os.path.join(out, name), "wb") as f:
            f.write(data)


if __name__ == "__main__":
    main()
