#!/usr/bin/env python3
# SPDX-License-Identifier: LGPL-2.1-or-later
"""Writes the seed corpus of fuzz_api (tests/fuzz/corpus_api/) in the target's input format."""

import base64
import os
import struct
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
SKIP_PC, SKIP_VM, SKIP_SPH = 1, 2, 4
PC_VERTS = 24
# indices into HOSTILE[] of fuzz_api.c
INT64_MIN_PLUS_2, INT64_MAX = 5, 7


def small(v):                       # coordinate mode 0: int8 / 4
    return struct.pack("b", int(v * 4))


def planar(rings, pts, tol_byte=2, corrupt=None, flags=0):
    out = bytes([flags, len(rings)]) + bytes(len(r) for r in rings)
    out += bytes([0xC0, corrupt[0], corrupt[1]]) if corrupt else b"\x00"
    coords = [c for r in rings for xy in r for c in xy]
    coords += [0] * (4 * PC_VERTS - len(coords))       # the harness reads 4 * PC_VERTS values
    out += b"".join(small(c) for c in coords[:4 * PC_VERTS])
    out += bytes([tol_byte, len(pts)]) + b"".join(small(x) + small(y) for x, y in pts)
    return out


def normals_around(m, draft_byte=0, count_byte=None, flags=8):
    out = bytes([flags, m if count_byte is None else count_byte])
    out += small(0) + small(0) + small(0)              # axis (0, 0, 1)
    out += bytes((13 * i % 41 - 20) & 0xFF for i in range(3 * m))   # spread +-0.3
    return out + bytes([draft_byte])


def sphere_generated(kinds, flags=0x40, level_byte=3, level=None):
    out = bytes([flags, len(kinds)])
    for i, k in enumerate(kinds):
        size = {3: 2, 2: 1, 1: 0, 0: 0}[k]         # 5-gons, 3-vertex arcs, one-vertex points
        out += bytes([k | (size << 2)])
        out += bytes([(40 * i) % 256, 150 + 3 * i, 90, 17 * i % 256])   # lon, lat, rho, start angle
        if k == 3:
            out += bytes([128] * (3 + size))
    out += b"\x00"                                      # no corrupted offset
    if level is not None:                               # a level given as a double
        return out + b"\xF0" + struct.pack("<d", level)
    return out + bytes([0, level_byte])


def sphere_raw_offsets(nsets, sizes, corrupt):
    out = bytes([0x01, nsets]) + bytes(sizes) + bytes([0xC0, corrupt[0], corrupt[1]])
    return out + bytes([3] * nsets)


RUN_SWEEP = 8


def sc(v):                          # the sweep's small coordinates: int8 / 32
    return struct.pack("b", int(round(v * 32)))


def sweep(kind=0, shape=b"", damage=b"\x00", axis_mode=0, point=(0, 0, 0), direction=(0, 0, 1),
          angle_byte=59, tol_byte=0):
    """The sweep section: generated mesh `kind` (0 box, 1 moved box, 2 tetrahedron,
    3-4 octahedron; 5-7 raw), its bytes, damage, axis, angle (byte b: (b + 1) 2 pi / 240,
    0xF0 and up: special values) and tolerance ((4 + byte % 29) / 32 of the extent)."""
    out = bytes([kind]) + shape + damage + bytes([axis_mode])
    for c in range(3):
        out += sc(point[c]) + sc(direction[c])
    return out + bytes([angle_byte, tol_byte])


RUN_MEDIAL = 16


def medial_seed(kind=0, shape=b"", damage=b"\x00", tol_byte=7, mode=0):
    """The medial section: the sweep's mesh (kind, bytes, damage), tolerance ((4 + byte %
    28) / 64 of the diagonal; 0xFC and up: 0, -1, NaN, inf), mode (bit 0 full, bit 1 two
    threads, 0xF0: an unknown flag)."""
    return (bytes([SKIP_PC | SKIP_VM | SKIP_SPH | RUN_MEDIAL, kind]) + shape + damage
            + bytes([tol_byte, mode]))


def box(lo, size):                  # lo corner and edge lengths (multiples of 1/32, < 2)
    return b"".join(sc(lo[c]) + bytes([int(round(size[c] * 32))]) for c in range(3))


def sweep_seed(section):
    return bytes([SKIP_PC | SKIP_VM | SKIP_SPH | RUN_SWEEP]) + section


def seeds():
    sq = [(0, 0), (8, 0), (8, 8), (0, 8)]
    hole = [(2, 2), (2, 6), (6, 6), (6, 2)]
    pts = [(1, 1), (4, 4), (0, 4), (9, 9)]
    yield "pc_square_hole", bytes([SKIP_VM | SKIP_SPH]) + planar([sq, hole], pts)
    # issue 6: offsets {0, 4, INT64_MIN + 2}
    yield "pc_offsets_wrap", bytes([SKIP_VM | SKIP_SPH]) + planar([sq, hole], pts, corrupt=(2, INT64_MIN_PLUS_2))
    # the 2-D medial axis of the same rings (flags bit 6, issue 22): the square with a
    # hole, a thin wedge with a nearly collinear convex corner, and NULL output
    yield "ma_square_hole", bytes([SKIP_VM | SKIP_SPH]) + planar([sq, hole], pts, flags=0x40)
    yield "ma_thin_wedge", bytes([SKIP_VM | SKIP_SPH]) + planar(
        [[(0, 0), (4, 0.0625), (8, 0.125), (8, 0.25), (4, 0.125), (0, 0.0625)]], [], flags=0x40)
    yield "ma_null_out", bytes([SKIP_VM | SKIP_SPH]) + planar([sq], pts, flags=0x40 | 0x80) + bytes([16])
    yield "pc_npoints_huge", bytes([SKIP_VM | SKIP_SPH]) + planar([sq], []) [:-1] + bytes([0xF0 + INT64_MAX])
    yield "vm_cap", bytes([SKIP_PC | SKIP_SPH]) + normals_around(12)
    yield "vm_cap_draft", bytes([SKIP_PC | SKIP_SPH]) + normals_around(12, draft_byte=3)
    yield "vm_circle", bytes([SKIP_PC | SKIP_SPH]) + normals_around(12, flags=8 | 16)
    yield "vm_m_huge", bytes([SKIP_PC | SKIP_SPH]) + normals_around(0, count_byte=0xF0 + INT64_MAX)
    yield "sph_polygons", bytes([SKIP_PC | SKIP_VM]) + sphere_generated([3, 3, 3, 3, 3, 3])
    yield "sph_mixed", bytes([SKIP_PC | SKIP_VM]) + sphere_generated([3, 2, 1, 3, 0, 3])
    yield "sph_offsets_int64_max", bytes([SKIP_PC | SKIP_VM]) + sphere_raw_offsets(1, [3], (1, INT64_MAX))
    yield "sph_offsets_wrap", bytes([SKIP_PC | SKIP_VM]) + sphere_raw_offsets(2, [3, 3], (2, INT64_MIN_PLUS_2))
    yield "sph_npolys_huge", bytes([SKIP_PC | SKIP_VM]) + bytes([0x40, 0xF0 + INT64_MAX])
    # found by fuzzing: a NULL set of weight 1e200 entered the weight scale and tolerance,
    # and the maximum (7.5) disagreed with its covers (5.5)
    yield "sph_ignored_heavy_weight", base64.b64decode(
        "A2JhLv8BLi4uLi4uLkQLyKUDgFpAVYAuLv78/P38gIAAgACA8QQAEfH+C+8LyKVaVf//////////////////LgAu")
    # found by fuzzing: rings repeating a 7-point cycle after a run of (0, 0): copies of a
    # few segments that the prepared region's quadtree split to its depth limit
    yield "pc_copied_segments", base64.b64decode("UgZgFxcXF8cAYA==")
    # found by fuzzing (a harness bug): a step back from an offset already INT64_MIN
    yield "sph_offsets_step_back_from_min", base64.b64decode("AwEDYmEu/wFrLrsGLgIjA3oRwPE=")
    # a subnormal level came back rounded by the weights' scale
    yield "sph_subnormal_level", bytes([SKIP_PC | SKIP_VM]) + sphere_generated(
        [3, 3], level=float.fromhex("0x0.0ffffffcbffffp-1022"))
    # found by fuzzing: 12 normals about (0, 0, 1), draft 0.3; the deque of draft caps
    # returned a vertex at d.p^ = -0.73 (the draft asks sin 0.3)
    offs = [(-20, -7, 6), (19, -9, 4), (17, -11, 2), (-113, -13, 0), (13, -15, -2), (11, -17, -4),
            (9, -19, -6), (7, 20, -8), (5, 18, -10), (3, 16, -12), (1, 14, -14), (127, 12, -16)]
    yield "vm_draft_thin_hull", (bytes([SKIP_PC | SKIP_SPH, 8, 12, 0, 0, 0])
                                 + bytes(c & 0xFF for o in offs for c in o) + bytes([3]))
    # found by fuzzing: a map on a great circle whose projected wedge is all but a
    # half-plane (normals of sizes 2^37 and 2^-23): "degenerate arc"
    yield "vm_arc_nearly_half_plane", base64.b64decode(
        "CUNDQ0Oenpyenp6env//Q0NDQ0NDQ0NDQ0NDQ1tDQ0NDQ0NDQ0NDQ0PR0dHR0dHR0dHR0dHR0dHR0dHR0dHR0dHR0dHR"
        "0dHR0dHR0dHR0dHR0dHR0dHR0dHR0dHR0dHR0dHR0dHR0dHR0dHR0dHR0dHR0dHR0dHR0dHR0dHR0dHR0dHR0dHR0dHR"
        "0dHR0dFDQ0NDQ0NDQ0NDQwCgoloABAAARC3IpT2AAAAACAQAAC2iWkQLyKVa")
    yield "all_sections", (b"\x00" + planar([sq], pts) + normals_around(6)
                           + sphere_generated([3, 3, 2]))
    # rotational sweep: a 1.875 x 1 x 1 box about its edge on the z axis by 90 deg
    b = box((0, 0, 0), (1.875, 1, 1))
    yield "sw_box_edge_90", sweep_seed(sweep(0, b, angle_byte=59))
    # the unit cube about its long diagonal, a full turn (angle 0xF5: 2 pi)
    yield "sw_cube_diagonal_full", sweep_seed(sweep(0, box((0, 0, 0), (1, 1, 1)), direction=(1, 1, 1),
                                                    angle_byte=0xF5, tol_byte=4))
    # a box off the axis, 300 deg; a box with moved corners about an axis through a vertex
    yield "sw_box_off_axis_300", sweep_seed(sweep(0, box((1, 0.5, 0), (1, 1, 1)), angle_byte=199))
    yield "sw_moved_box_vertex_axis", sweep_seed(sweep(1, b + bytes((7 * i) % 23 for i in range(24)),
                                                       axis_mode=4, direction=(0.25, 0.5, 1), angle_byte=80))
    # a tetrahedron about a skew axis, 1.5 deg; a star-shaped octahedron along an edge
    tet = b"".join(sc(v) for v in (0, 0, 0, 1, 0, 0, 0, 1, 0, 0.25, 0.5, 1))
    yield "sw_tetra_small_angle", sweep_seed(sweep(2, tet, point=(0.5, -1, 0), direction=(1, 0.5, 0.25), angle_byte=0))
    octa = sc(0.5) + sc(0.25) + sc(0) + bytes([32, 16, 40, 8, 24, 48])
    yield "sw_octa_edge_axis", sweep_seed(sweep(3, octa, axis_mode=4 | 8, angle_byte=150, tol_byte=8))
    # found by fuzzing: the 1.875 x 1 x 1 box about its long diagonal by 97.5 deg (tol 0.47):
    # MFG_ERR_INTERNAL, the swept surface not closed (713 boundary edges); any partial turn
    yield "sw_box_long_diagonal_97deg", sweep_seed(sweep(0, b, direction=(1.875, 1, 1), angle_byte=64, tol_byte=4))
    # refused meshes: open (a triangle dropped), flipped, a repeated triangle
    yield "sw_open_box", sweep_seed(sweep(0, b, damage=bytes([0xC0, 3])))
    yield "sw_flipped_triangle", sweep_seed(sweep(0, b, damage=bytes([0xC1, 5])))
    yield "sw_nonmanifold_edge", sweep_seed(sweep(0, b, damage=bytes([0xC2, 7])))
    # refused arguments: NaN angle, 2 pi + 2e-12, zero axis direction, tolerance NaN,
    # impossible counts in the raw mesh
    yield "sw_nan_angle", sweep_seed(sweep(0, b, angle_byte=0xF3))
    yield "sw_angle_past_full", sweep_seed(sweep(0, b, angle_byte=0xF7))
    yield "sw_zero_axis", sweep_seed(sweep(0, b, direction=(0, 0, 0)))
    yield "sw_nan_tolerance", sweep_seed(sweep(0, b, tol_byte=0xFB))
    yield "sw_raw_huge_counts", sweep_seed(bytes([5, 0xF0 + INT64_MAX, 0xF0 + INT64_MIN_PLUS_2]))
    # the medial surface (issue 22): a 4-triangle tetrahedron (the leaf search found no
    # point: J + 0 on NULL, UBSan), a box major and full, an octahedron on two threads, an
    # open box, bad tolerances, an unknown flag, huge counts
    yield "md_tetra", medial_seed(2, tet)
    yield "md_box", medial_seed(0, box((0, 0, 0), (1.875, 1, 0.5)), tol_byte=3)
    yield "md_box_full", medial_seed(0, box((0, 0, 0), (1.875, 1, 0.5)), tol_byte=3, mode=1)
    yield "md_octa_threads", medial_seed(3, octa, tol_byte=5, mode=2)
    yield "md_open_box", medial_seed(0, b, damage=bytes([0xC0, 3]))
    yield "md_nan_tolerance", medial_seed(0, b, tol_byte=0xFE)
    yield "md_unknown_flag", medial_seed(0, b, mode=0xF0)
    yield "md_raw_huge_counts", medial_seed(5, bytes([0xF0 + INT64_MAX, 0xF0 + INT64_MIN_PLUS_2]))


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(HERE, "corpus_api")
    os.makedirs(out, exist_ok=True)
    for name, data in seeds():
        with open(os.path.join(out, name), "wb") as f:
            f.write(data)


if __name__ == "__main__":
    main()
