# SPDX-License-Identifier: LGPL-2.1-or-later
"""Tests of libmfgeom's tolerance-based point classification against an exact rational reference (and shapely)."""

import concurrent.futures
import ctypes
import math
import random
import re
from fractions import Fraction

import numpy as np
import pytest

import exact_reference as reference
from mfgeom import core

OUT, IN, ON = core.OUT, core.IN, core.ON
NAMES = {OUT: "OUT", IN: "IN", ON: "ON"}
MAX_COORD = 1.6069380442589903e+60          # MFG_MAX_COORD = 2**200
MIN_COORD = 6.2230152778611417e-61          # MFG_MIN_COORD = 2**-200 (smallest non-zero |x|)
assert MAX_COORD == 2.0 ** 200 and MIN_COORD == 2.0 ** -200


def in_range(values):
    """Map numbers that mfgeom.h rejects as too small (0 < |x| < 2^-200) to +-2^-200."""
    a = np.asarray(values, dtype=np.float64)
    return np.where((a != 0) & (np.abs(a) < MIN_COORD), np.copysign(MIN_COORD, a), a)

# Status codes of mfg_status (mfgeom.h).
MFG_OK, MFG_ERR_NULL, MFG_ERR_INVALID, MFG_ERR_DEGENERATE = 0, 1, 2, 3


# --------------------------------------------------------------------------- #
# Helpers                                                                     #
# --------------------------------------------------------------------------- #

def _as_rings(rings):
    return [np.asarray(r, dtype=np.float64).reshape(-1, 2) for r in rings]


def _rings_repr(rings, limit=60):
    parts = []
    for r in rings:
        pts = ", ".join(f"({x!r}, {y!r})" for x, y in np.asarray(r, dtype=float).tolist())
        parts.append(f"[{pts}]")
    text = "[" + ", ".join(parts) + "]"
    return text if len(text) < 4000 or limit is None else text[:4000] + " ..."


def _lib_both(rings, pts, tol):
    rings = _as_rings(rings)
    one = core.classify_points(rings, pts, tol)
    with core.Region(rings, tol) as region:
        prep = region.classify(pts)
    return one, prep


def _mismatch(rings, pt, tol, use_ref=True):
    """True when the library (one-shot or prepared) disagrees on this single point."""
    try:
        one, prep = _lib_both(rings, [pt], tol)
    except core.MfgError as e:
        return e.status == "internal error"
    if one[0] != prep[0]:
        return True
    if use_ref:
        return reference.classify(rings, [pt], tol)[0] != one[0]
    return False


def _shrink(rings, pt, tol, use_ref=True):
    """Greedy minimisation of a failing case: drop rings, then vertices (keeping >= 3)."""
    rings = [list(map(tuple, np.asarray(r, dtype=float).tolist())) for r in rings]
    changed = True
    while changed:
        changed = False
        for i in range(len(rings)):
            if len(rings) > 1:
                cand = rings[:i] + rings[i + 1:]
                if _mismatch(cand, pt, tol, use_ref):
                    rings, changed = cand, True
                    break
        if changed:
            continue
        for i, ring in enumerate(rings):
            for j in range(len(ring)):
                if len(ring) > 3:
                    cand = rings[:i] + [ring[:j] + ring[j + 1:]] + rings[i + 1:]
                    if _mismatch(cand, pt, tol, use_ref):
                        rings, changed = cand, True
                        break
            if changed:
                break
    return rings


def _describe_distance(d2, tol):
    """Human-readable exact comparison of a squared distance (Fraction) with tol."""
    tol2 = Fraction(float(tol)) ** 2
    rel = "==" if d2 == tol2 else ("<" if d2 < tol2 else ">")
    if d2 == 0:
        return f"0 {rel} tol"
    log10 = (math.log10(d2.numerator) - math.log10(d2.denominator)) / 2
    text = f"~10^{log10:.3f} {rel} tol"
    if tol2:
        diff = (d2 - tol2) / tol2
        if diff:
            text += f" (dist^2/tol^2 - 1 ~ {'-' if diff < 0 else ''}10^" \
                    f"{math.log10(abs(diff.numerator)) - math.log10(diff.denominator):.2f})"
    return text


def check(rings, pts, tol, use_ref=True, label=""):
    """Classify with one-shot, prepared and (optionally) the exact reference.

    Asserts that all agree; on failure the message holds a minimised reproducer.
    Returns the library's answers.
    """
    pts = np.asarray(pts, dtype=np.float64).reshape(-1, 2)
    try:
        one, prep = _lib_both(rings, pts, tol)
    except core.MfgError as e:
        if e.status != "internal error":
            raise
        culprit = next((tuple(p) for p in pts.tolist() if _mismatch(rings, tuple(p), tol, use_ref)),
                       None)
        if culprit is None:     # fails while building the region: shrink with any point
            culprit = (0.0, 0.0)
        small = _shrink(rings, culprit, tol, use_ref)
        pytest.fail(f"{label}: library reported {e}\nminimal reproducer: rings={_rings_repr(small)}"
                    f" point={culprit!r} tol={float(tol)!r}")
    assert one.dtype == np.uint8 and one.shape == (len(pts),)
    assert np.all(one <= 2)
    bad = np.nonzero(one != prep)[0]
    expected = None
    if use_ref:
        expected = np.array(reference.classify([np.asarray(r).tolist() for r in rings],
                                               pts.tolist(), tol), dtype=np.uint8)
        bad = np.union1d(bad, np.nonzero(one != expected)[0])
    if len(bad):
        i = int(bad[0])
        pt = tuple(pts[i].tolist())
        small = _shrink(rings, pt, tol, use_ref)
        o1, p1 = _lib_both(small, [pt], tol)
        e1 = reference.classify(small, [pt], tol)[0] if use_ref else None
        lines = [f"{label}: {len(bad)} of {len(pts)} points disagree",
                 f"minimal reproducer: rings={_rings_repr(small)}",
                 f"  point=({pt[0]!r}, {pt[1]!r})  [hex {pt[0].hex()}, {pt[1].hex()}]",
                 f"  tol={float(tol)!r}  [hex {float(tol).hex()}]",
                 f"  expected(reference)={NAMES.get(e1)}  one-shot={NAMES[int(o1[0])]}"
                 f"  prepared={NAMES[int(p1[0])]}"]
        if use_ref:
            d2 = reference.distance2(small, pt)
            lines.append(f"  exact distance to boundary: {_describe_distance(d2, tol)}")
        for j in bad[:5]:
            lines.append(f"  point {pts[j].tolist()!r}: ref={NAMES.get(None if expected is None else int(expected[j]))}"
                         f" one={NAMES[int(one[j])]} prep={NAMES[int(prep[j])]}")
        pytest.fail("\n".join(lines))
    return one


def square(x0, y0, x1, y1):
    return [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]


def star_polygon(rng, n, cx=0.0, cy=0.0, r=1.0):
    """Random star-shaped simple polygon around (cx, cy)."""
    angles = sorted(rng.uniform(0, 2 * math.pi) for _ in range(n))
    return [(cx + r * rng.uniform(0.3, 1.0) * math.cos(a),
             cy + r * rng.uniform(0.3, 1.0) * math.sin(a)) for a in angles]


def random_ring(rng, n, scale=1.0):
    """Random (generally self-intersecting) ring."""
    return [(rng.uniform(-scale, scale), rng.uniform(-scale, scale)) for _ in range(n)]


def lattice_ring(rng, n, k=6):
    """Random ring on a small integer lattice: many ties, collinear runs, repeats."""
    return [(float(rng.randint(-k, k)), float(rng.randint(-k, k))) for _ in range(n)]


def near_boundary_points(rng, rings, tol, per_edge=4):
    """Points on edges (rounded), a few ulps off, at +-tol along the normal, vertices."""
    pts = []
    for ring in rings:
        n = len(ring)
        for i in range(n):
            ax, ay = ring[i]
            bx, by = ring[(i + 1) % n]
            pts.append((ax, ay))
            dx, dy = bx - ax, by - ay
            length = math.hypot(dx, dy)
            for _ in range(per_edge):
                s = rng.random()
                px, py = ax + s * dx, ay + s * dy
                pts.append((px, py))
                k = rng.choice((1, 2, 3))
                sgn = rng.choice((-1, 1))
                pts.append((np.nextafter(px, sgn * math.inf) if px else sgn * 2.0 ** -60, py))
                # (a zero coordinate gets a 2^-60 nudge here; offsets down to 2^-200
                # are covered separately by test_tiny_offsets)
                pts.append((px, py + k * (math.ulp(py) if py else 2.0 ** -60) * rng.choice((-1, 1))))
                if length > 0 and tol > 0:
                    nx, ny = -dy / length, dx / length
                    f = rng.choice((1.0, 1 - 2 ** -40, 1 + 2 ** -40, 0.5, 2.0))
                    side = rng.choice((-1, 1))
                    pts.append((px + side * f * tol * nx, py + side * f * tol * ny))
            if tol > 0:
                for sx in (-1, 1):
                    for sy in (-1, 1):
                        pts.append((ax + sx * 0.9 * tol, ay + sy * 0.9 * tol))  # box, not disc
                        pts.append((ax + sx * 0.7 * tol, ay + sy * 0.7 * tol))  # inside disc
    return [tuple(p) for p in in_range(pts).tolist()] if pts else pts


def random_points(rng, rings, count, margin=0.2):
    xs = [x for r in rings for x, _ in r]
    ys = [y for r in rings for _, y in r]
    x0, x1, y0, y1 = min(xs), max(xs), min(ys), max(ys)
    w, h = (x1 - x0) or 1.0, (y1 - y0) or 1.0
    return [(rng.uniform(x0 - margin * w, x1 + margin * w),
             rng.uniform(y0 - margin * h, y1 + margin * h)) for _ in range(count)]


# --------------------------------------------------------------------------- #
# The reference itself                                                        #
# --------------------------------------------------------------------------- #

def test_reference_integer_and_fraction_versions_agree():
    rng = random.Random(1)
    for trial in range(40):
        rings = [lattice_ring(rng, rng.randint(3, 7), 4) for _ in range(rng.randint(1, 2))]
        if trial % 2:
            rings = [[(x * 0.37 + 0.1, y * 1.3 - 0.2) for x, y in r] for r in rings]
        tol = rng.choice((0.0, 0.25, 0.5, 1e-9, 1.0))
        pts = [(rng.randint(-10, 10) / 2, rng.randint(-10, 10) / 2) for _ in range(25)]
        pts += near_boundary_points(rng, rings, tol, 1)
        assert reference.classify(rings, pts, tol) == reference.classify_fractions(rings, pts, tol)


def test_reference_hand_checked():
    sq = square(0.0, 0.0, 2.0, 2.0)
    assert reference.classify([sq], [(1, 1), (3, 1), (2, 1), (0, 0), (2.5, 1)], 0.0) == \
        [IN, OUT, ON, ON, OUT]
    assert reference.classify([sq], [(2.5, 1), (2.5, 2.5), (-0.25, -0.25), (-0.375, -0.375)], 0.5) == \
        [ON, OUT, ON, OUT]


# --------------------------------------------------------------------------- #
# Basic shapes with hand-written expectations                                 #
# --------------------------------------------------------------------------- #

def test_version():
    assert re.fullmatch(r"\d+\.\d+\.\d+", core.version())


def test_unit_square_tol0():
    sq = [square(0.0, 0.0, 1.0, 1.0)]
    pts = [(0.5, 0.5), (1.5, 0.5), (-0.5, 0.5), (0.5, 1.5), (0.5, -0.5),   # in / out
           (0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0),                  # vertices
           (0.5, 0.0), (1.0, 0.5), (0.5, 1.0), (0.0, 0.5),                  # edge points
           (0.0, 0.25), (2.0 ** -60, 0.5), (-2.0 ** -60, 0.5), (2.0, 0.0), (2.0, 1.0),
           (-1.0, 0.0), (-1.0, 1.0), (0.5, np.nextafter(1.0, 2.0)), (0.5, np.nextafter(1.0, 0.0))]
    want = [IN, OUT, OUT, OUT, OUT,
            ON, ON, ON, ON,
            ON, ON, ON, ON,
            ON, IN, OUT, OUT, OUT,
            OUT, OUT, OUT, IN]
    assert check(sq, pts, 0.0).tolist() == want


def test_square_tolerance_disc_not_box():
    # tol = 5/4; (-3/4, -1) is at distance exactly 5/4 from the corner (0, 0).
    sq = [square(0.0, 0.0, 4.0, 4.0)]
    tol = 1.25
    up = np.nextafter
    pts = [(-0.75, -1.0), (-1.0, -0.75),                                   # exactly tol: ON
           (up(-0.75, -1.0), -1.0), (-0.75, up(-1.0, -2.0)),               # just beyond: OUT
           (up(-0.75, 0.0), -1.0),                                         # just inside: ON
           (-1.0, -1.0), (-1.2, -1.2), (-0.9, -0.9),                       # in box, off disc
           (-0.8, -0.8), (-1.25, 2.0), (up(-1.25, -2.0), 2.0), (5.25, 2.0),
           (up(5.25, 9.0), 2.0), (2.0, 2.0), (2.0, 1.25), (2.0, up(1.25, 2.0)),
           (4.75, 5.0), (5.0, 4.75), (5.0, 5.0)]
    want = [ON, ON, OUT, OUT, ON,
            OUT, OUT, OUT,
            ON, ON, OUT, ON,
            OUT, IN, ON, IN,
            ON, ON, OUT]
    assert check(sq, pts, tol).tolist() == want


def test_square_tolerance_reflex_corner_inside():
    # L-shape: the reflex corner (2, 2); points inside near it, in its tol-box but
    # outside its tol-disc, are IN.
    ring = [(0.0, 0.0), (4.0, 0.0), (4.0, 2.0), (2.0, 2.0), (2.0, 4.0), (0.0, 4.0)]
    tol = 0.5
    # Notch side (outside): the adjacent edges are within tol, so ON up to 0.5 from them.
    # Interior diagonal: (1.625, 1.625) is in the corner's tol-box but 0.53 from it -> IN.
    pts = [(2.45, 2.45), (2.5, 2.5), (2.5, 2.625), (2.625, 2.625), (1.625, 1.625),
           (1.75, 1.625), (1.5, 1.5), (1.5, 2.5), (2.5, 1.5), (1.625, 2.5)]
    want = [ON, ON, ON, OUT, IN, ON, IN, ON, ON, ON]
    assert check([ring], pts, tol).tolist() == want


def test_polygon_with_holes_and_island():
    outer = square(0.0, 0.0, 10.0, 10.0)
    hole1 = square(1.0, 1.0, 4.0, 4.0)[::-1]
    hole2 = square(6.0, 6.0, 9.0, 9.0)
    island = square(2.0, 2.0, 3.0, 3.0)        # inside hole1: IN again
    rings = [outer, hole1, hole2, island]
    pts = [(5.0, 5.0), (2.5, 1.5), (7.5, 7.5), (2.5, 2.5), (11.0, 5.0), (1.0, 2.0),
           (4.0, 4.0), (2.0, 2.5), (6.0, 7.0), (10.0, 10.0), (0.5, 0.5)]
    want = [IN, OUT, OUT, IN, OUT, ON, ON, ON, ON, ON, IN]
    assert check(rings, pts, 0.0).tolist() == want
    # tolerance large enough to swallow the whole island.
    got = check(rings, [(2.5, 2.5), (5.0, 5.0), (0.4, 5.0)], 0.5)
    assert got.tolist() == [ON, IN, ON]


def test_overlapping_rings_even_odd():
    # Two overlapping squares: the overlap is covered twice -> OUT.
    rings = [square(0.0, 0.0, 2.0, 2.0), square(1.0, 1.0, 3.0, 3.0)]
    got = check(rings, [(0.5, 0.5), (1.5, 1.5), (2.5, 2.5), (1.5, 0.5), (2.5, 1.5)], 0.0)
    assert got.tolist() == [IN, OUT, IN, IN, IN]
    # Identical rings twice: everything cancels, boundary stays.
    rings = [square(0.0, 0.0, 2.0, 2.0)] * 2
    assert check(rings, [(1.0, 1.0), (2.0, 1.0), (3.0, 1.0)], 0.0).tolist() == [OUT, ON, OUT]


def test_bowtie():
    ring = [(0.0, 0.0), (2.0, 2.0), (2.0, 0.0), (0.0, 2.0)]
    pts = [(0.5, 1.0), (1.5, 1.0), (1.0, 0.5), (1.0, 1.5), (1.0, 1.0), (3.0, 1.0),
           (0.25, 1.0), (1.75, 1.0), (-1.0, 1.0), (1.0, 1.25)]
    want = [IN, IN, OUT, OUT, ON, OUT, IN, IN, OUT, OUT]
    assert check([ring], pts, 0.0).tolist() == want
    assert check([ring], [(1.0, 1.25), (1.0, 1.5), (1.2, 1.0)], 0.2).tolist() == [ON, OUT, ON]


def _pentagram(r=1.0, cx=0.0, cy=0.0):
    outer = [(cx + r * math.cos(math.pi / 2 + 2 * math.pi * k / 5),
              cy + r * math.sin(math.pi / 2 + 2 * math.pi * k / 5)) for k in range(5)]
    return [outer[(2 * k) % 5] for k in range(5)]


def test_pentagram_even_odd_centre_is_out():
    ring = _pentagram()
    tips = [(0.0, 0.8), (0.76 * math.cos(math.radians(18)), 0.76 * math.sin(math.radians(18)))]
    got = check([ring], [(0.0, 0.0), (0.05, -0.05)] + tips + [(2.0, 0.0), (0.0, -0.9)], 0.0)
    assert got.tolist() == [OUT, OUT, IN, IN, OUT, OUT]
    rng = random.Random(5)
    check([ring], random_points(rng, [ring], 400), 0.0, label="pentagram")
    check([ring], random_points(rng, [ring], 400), 0.05, label="pentagram tol")


def test_repeated_vertices_collinear_runs_closing_vertex():
    base = square(0.0, 0.0, 4.0, 4.0)
    variants = [
        base + [base[0]],                                           # closing vertex repeated
        [v for v in base for _ in range(3)],                        # every vertex tripled
        [(0.0, 0.0), (1.0, 0.0), (2.0, 0.0), (3.0, 0.0), (4.0, 0.0), (4.0, 2.0), (4.0, 4.0),
         (2.0, 4.0), (0.0, 4.0), (0.0, 3.0), (0.0, 1.0), (0.0, 0.0)],  # collinear runs
        [(0.0, 0.0), (3.0, 0.0), (1.0, 0.0), (4.0, 0.0), (4.0, 4.0), (0.0, 4.0)],  # back-track
    ]
    pts = [(x / 2.0, y / 2.0) for x in range(-2, 11) for y in range(-2, 11)]
    pts += [(2.0, MIN_COORD), (2.0, -MIN_COORD), (4.0, 0.0), (-1.0, 0.0), (5.0, 4.0)]
    base_ans = check([base], pts, 0.0)
    for tol in (0.0, 0.25):
        base_ans = check([base], pts, tol)
        for v in variants:
            assert check([v], pts, tol).tolist() == base_ans.tolist()


def test_spike_and_degenerate_parts():
    # A zero-area spike sticking out of a square: its segment is boundary.
    ring = [(0.0, 0.0), (2.0, 0.0), (2.0, 1.0), (3.0, 1.0), (2.0, 1.0), (2.0, 2.0), (0.0, 2.0)]
    pts = [(2.5, 1.0), (3.0, 1.0), (3.0001, 1.0), (2.5, 1.125), (2.5, 0.875), (1.0, 1.0),
           (1.875, 1.0), (3.125, 1.0), (3.0, 1.125), (3.125, 1.125)]
    assert check([ring], pts, 0.0).tolist() == [ON, ON, OUT, OUT, OUT, IN, IN, OUT, OUT, OUT]
    assert check([ring], pts, 0.125).tolist() == [ON, ON, ON, ON, ON, IN, ON, ON, ON, OUT]
    # A ring whose vertices are all equal (>= 3 vertices): either rejected as degenerate,
    # or its boundary is a single point.
    for c, tol, want in ((1.0, 0.2, [ON, ON, OUT]), (1.0, 0.0, [ON, OUT, OUT]),
                         (0.0, 0.0, [ON, OUT, OUT]), (0.0, 0.2, [ON, ON, OUT])):
        point_ring = [(c, c)] * 3
        try:
            got = check([point_ring], [(c, c), (c, c + 0.125), (c - 0.5, c - 0.5)], tol)
        except core.MfgError as e:
            assert e.status in ("degenerate input", "invalid argument"), str(e)
            # then both APIs must reject it
            with pytest.raises(core.MfgError):
                core.classify_points([point_ring], [(1.0, 1.0)], tol)
            with pytest.raises(core.MfgError):
                core.Region([point_ring], tol)
        else:
            assert got.tolist() == want
    # The same, as an extra ring next to a real square: must not change the square's answers
    # except at the point itself.
    try:
        got = check([square(0.0, 0.0, 4.0, 4.0), [(1.0, 1.0)] * 4], [(1.0, 1.0), (2.0, 2.0)], 0.0)
    except core.MfgError as e:
        assert e.status in ("degenerate input", "invalid argument"), str(e)
    else:
        assert got.tolist() == [ON, IN]
    # A flat (zero-area) ring next to a square.
    flat = [(5.0, 0.0), (7.0, 0.0), (6.0, 0.0)]
    got = check([square(0.0, 0.0, 2.0, 2.0), flat], [(6.0, 0.0), (6.0, 0.01), (1.0, 1.0)], 0.0)
    assert got.tolist() == [ON, OUT, IN]


def test_points_exactly_on_lattice_edges_and_vertices():
    rng = random.Random(11)
    for trial in range(100):
        rings = [lattice_ring(rng, rng.randint(3, 9)) for _ in range(rng.randint(1, 3))]
        pts = [(x / 2.0, y / 2.0) for x in range(-14, 15) for y in range(-14, 15)]
        check(rings, pts, 0.0, label=f"lattice trial {trial}")
        if trial % 4 == 0:
            check(rings, pts, 0.5, label=f"lattice trial {trial} tol .5")
            check(rings, pts, 2.0 ** -60, label=f"lattice trial {trial} tol 2^-60")


def test_points_on_ray_through_vertices():
    # Many vertices at the same heights, horizontal edges, spikes touching y levels.
    ring = [(0.0, 0.0), (2.0, 0.0), (3.0, 1.0), (4.0, 0.0), (5.0, 1.0), (6.0, 1.0), (7.0, 2.0),
            (8.0, 1.0), (9.0, 1.0), (9.0, 3.0), (8.0, 3.0), (7.0, 2.0), (6.0, 3.0), (5.0, 2.0),
            (4.0, 3.0), (3.0, 2.0), (2.0, 3.0), (1.0, 1.0), (0.0, 1.0)]
    hole = [(1.0, 2.0), (1.5, 2.5), (1.0, 3.0), (0.5, 2.5)]
    for rings in ([ring], [ring, hole], [ring[::-1], hole]):
        ys = [0.0, 1.0, 2.0, 3.0, 2.5, 0.5, 1.5]
        xs = [x / 4.0 for x in range(-8, 45)]
        pts = [(x, y) for y in ys for x in xs]
        for tol in (0.0, 2.0 ** -40, 0.25, 0.5):
            check(rings, pts, tol, label=f"ray tol={tol}")


def _unit_directions():
    base = [(Fraction(3, 5), Fraction(4, 5)), (Fraction(5, 13), Fraction(12, 13)),
            (Fraction(8, 17), Fraction(15, 17)), (Fraction(1), Fraction(0)),
            (Fraction(20, 29), Fraction(21, 29))]
    out = []
    for c, s in base:
        for cc, ss in ((c, s), (s, c)):
            for sx in (1, -1):
                for sy in (1, -1):
                    out.append((sx * cc, sy * ss))
    return out


FACTORS = [1 - Fraction(1, 2 ** 50), Fraction(1), 1 + Fraction(1, 2 ** 50),
           1 - Fraction(1, 2 ** 52), 1 + Fraction(1, 2 ** 52), 1 + Fraction(1, 2 ** 30)]


def test_adversarial_vertex_disc_boundary():
    """Points at tol*(1 +- 2^-50) from a vertex (made exact then rounded): the reference
    decides on the rounded point and the library must agree exactly."""
    rng = random.Random(21)
    ons = offs = 0
    dirs = _unit_directions()
    for trial in range(12):
        ring = lattice_ring(rng, rng.randint(3, 7), 5) if trial % 3 else _pentagram(3.0)
        for tol in (0.75, 1.0 / 3.0, 2.5, 1e-3):
            ftol = Fraction(tol)
            for vi in range(len(ring)):
                vx, vy = ring[vi]
                moved = [(x - vx, y - vy) for x, y in ring]       # vertex vi at the origin
                pts = []
                for c, s in dirs:
                    for f in FACTORS:
                        pts.append((float(ftol * f * c), float(ftol * f * s)))
                pts += [(0.9 * tol, 0.9 * tol), (-0.9 * tol, 0.9 * tol), (0.9 * tol, -0.9 * tol),
                        (-0.9 * tol, -0.9 * tol), (tol, tol), (-tol, 0.0), (0.0, tol)]
                got = check([moved], pts, tol, label=f"adversarial vertex trial {trial}")
                ons += int(np.sum(got == ON))
                offs += int(np.sum(got != ON))
    assert ons > 100 and offs > 100  # both sides of the disc boundary were exercised


def test_adversarial_edge_band_boundary():
    """Points at tol*(1 +- 2^-50) from edge interiors (feet translated to the origin)."""
    rng = random.Random(22)
    rings = [
        [(0.0, 0.0), (8.0, 6.0), (-4.0, 11.0), (-9.0, -1.0)],                   # 3-4-5 edges
        [(0.0, 0.0), (12.0, 5.0), (4.0, 20.0), (-15.0, 12.0), (-6.0, -3.0)],
        _pentagram(4.0),
        lattice_ring(rng, 6, 7),
    ]
    ons = offs = 0
    for ring in rings:
        n = len(ring)
        for tol in (0.5, 0.1, 3.0):
            ftol = Fraction(tol)
            for i in range(n):
                a = tuple(map(Fraction, ring[i]))
                b = tuple(map(Fraction, ring[(i + 1) % n]))
                for s in (Fraction(1, 2), Fraction(1, 4), Fraction(3, 8)):
                    fx, fy = a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1])
                    if float(fx) != fx or float(fy) != fy:
                        continue
                    moved = [(x - float(fx), y - float(fy)) for x, y in ring]
                    dx, dy = b[0] - a[0], b[1] - a[1]
                    l2 = dx * dx + dy * dy
                    if l2 == 0:
                        continue
                    rn, rd = math.isqrt(l2.numerator), math.isqrt(l2.denominator)
                    if rn * rn == l2.numerator and rd * rd == l2.denominator:
                        length = Fraction(rn, rd)
                    else:
                        length = Fraction(math.sqrt(float(l2)))
                    nx, ny = -dy / length, dx / length
                    pts = []
                    for f in FACTORS:
                        for side in (1, -1):
                            pts.append((float(side * ftol * f * nx), float(side * ftol * f * ny)))
                    got = check([moved], pts, tol, label="adversarial edge")
                    ons += int(np.sum(got == ON))
                    offs += int(np.sum(got != ON))
    assert ons > 50 and offs > 50


def test_exact_tolerance_threshold_dyadic():
    # Exact equality cases: distance == tol exactly must be ON, one ulp further must not.
    ring = [(0.0, 0.0), (16.0, 12.0), (16.0, 40.0), (-10.0, 40.0)]   # edge 1 direction (4,3)
    tol = 5.0
    # The foot (8, 6) on edge 0; normal (-3, 4)/5 * 5 = (-3, 4).
    pts = [(5.0, 10.0), (11.0, 2.0), (np.nextafter(5.0, 0.0), 10.0), (5.0, np.nextafter(10.0, 11.0)),
           (np.nextafter(11.0, 12.0), 2.0), (11.0, np.nextafter(2.0, 3.0)),
           (-3.0, -4.0), (3.0, -4.0), (-4.0, -3.0), (np.nextafter(-3.0, -4.0), -4.0)]
    # (5, 10) is inside (above edge 0): moving away from the edge gives IN, not OUT.
    want = [ON, ON, IN, IN, OUT, ON, ON, ON, ON, OUT]
    got = check([ring], pts, tol)
    assert got.tolist() == want


# --------------------------------------------------------------------------- #
# Random polygons                                                             #
# --------------------------------------------------------------------------- #

def _random_case(rng, kind):
    if kind == "star":
        rings = [star_polygon(rng, rng.randint(3, 25), rng.uniform(-1, 1), rng.uniform(-1, 1))]
        if rng.random() < 0.5:   # add a hole-ish ring (may overlap: even-odd anyway)
            rings.append(star_polygon(rng, rng.randint(3, 8), rings[0][0][0] * 0.1, 0.0, 0.25))
    elif kind == "self":
        rings = [random_ring(rng, rng.randint(3, 15)) for _ in range(rng.randint(1, 3))]
    else:
        rings = [lattice_ring(rng, rng.randint(3, 12)) for _ in range(rng.randint(1, 3))]
    return rings


@pytest.mark.parametrize("kind", ["star", "self", "lattice"])
def test_random_polygons_vs_reference(kind):
    rng = random.Random({"star": 101, "self": 102, "lattice": 103}[kind])
    for trial in range(80):
        rings = _random_case(rng, kind)
        for tol in (0.0, 1e-12, rng.choice((1e-6, 0.01)), rng.choice((0.2, 0.7))):
            pts = random_points(rng, rings, 60)
            pts += near_boundary_points(rng, rings, tol, per_edge=2)
            check(rings, pts, tol, label=f"{kind} trial {trial} tol {tol}")


def test_invariance_start_orientation_ring_order():
    rng = random.Random(31)
    for trial in range(90):
        kind = ("star", "self", "lattice")[trial % 3]
        rings = _random_case(rng, kind)
        tol = rng.choice((0.0, 1e-9, 0.05, 0.3))
        pts = random_points(rng, rings, 80) + near_boundary_points(rng, rings, tol, per_edge=2)
        base = check(rings, pts, tol, label=f"invariance base {trial}")
        for _ in range(4):
            variant = []
            for r in rings:
                k = rng.randrange(len(r))
                r2 = r[k:] + r[:k]
                if rng.random() < 0.5:
                    r2 = r2[::-1]
                if rng.random() < 0.3:
                    r2 = r2 + [r2[0]]                        # explicit closing vertex
                variant.append(r2)
            rng.shuffle(variant)
            one, prep = _lib_both(variant, pts, tol)
            bad = np.nonzero((one != base) | (prep != base))[0]
            if len(bad):
                i = int(bad[0])
                pytest.fail(f"answer changed under rotation/reversal/reordering: point {pts[i]!r} "
                            f"tol={tol!r}\n original rings={_rings_repr(rings)} -> {NAMES[int(base[i])]}\n"
                            f" variant rings={_rings_repr(variant)} -> one-shot {NAMES[int(one[i])]},"
                            f" prepared {NAMES[int(prep[i])]}")


# --------------------------------------------------------------------------- #
# Prepared vs one-shot on large inputs                                         #
# --------------------------------------------------------------------------- #

def _grid_border_points(rings, tol, region):
    st = region.stats()
    cols, rows = max(st["columns"], 1), max(st["rows"], 1)
    xs = [x for r in rings for x, _ in r]
    ys = [y for r in rings for _, y in r]
    xlo, xhi, ylo, yhi = min(xs), max(xs), min(ys), max(ys)
    cand_x, cand_y = set(), set()
    for (a, b, n, out) in ((xlo, xhi, cols, cand_x), (ylo, yhi, rows, cand_y),
                           (xlo - tol, xhi + tol, cols, cand_x), (ylo - tol, yhi + tol, rows, cand_y)):
        cell = (b - a) / n
        for i in range(n + 1):
            for v in (a + i * cell, a + (b - a) * i / n, a + i * ((b - a) / n)):
                for w in (v, np.nextafter(v, -math.inf), np.nextafter(v, math.inf)):
                    out.add(float(w))
    cand_x = sorted(cand_x)
    cand_y = sorted(cand_y)
    return cand_x, cand_y


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_prepared_equals_one_shot_large(seed):
    rng = random.Random(seed)
    nprng = np.random.default_rng(seed)
    if seed == 1:
        rings = [star_polygon(rng, 1500, 0.0, 0.0, 10.0)]
    elif seed == 2:
        rings = [random_ring(rng, 200, 5.0), star_polygon(rng, 300, 1.0, 1.0, 3.0)]
    else:
        rings = [lattice_ring(rng, 300, 20) for _ in range(3)]
    for tol in (0.0, 1e-10, 0.01, 0.5):
        arr = _as_rings(rings)
        allv = np.concatenate(arr)
        lo, hi = allv.min(axis=0), allv.max(axis=0)
        span = hi - lo
        pts = [nprng.uniform(lo - 0.3 * span, hi + 0.3 * span, size=(40000, 2))]
        # points on edges and slightly off them
        starts = allv[nprng.integers(0, len(allv), 5000)]
        ends = np.roll(allv, -1, axis=0)[nprng.integers(0, len(allv), 5000)]
        s = nprng.random((5000, 1))
        pts.append(starts + s * (ends - starts))
        nbr = [a + nprng.random((len(a), 1)) * (np.roll(a, -1, axis=0) - a) for a in arr]
        nbr = np.concatenate(nbr)
        pts.append(nbr)
        pts.append(np.nextafter(nbr, nbr + 1))
        pts.append(np.nextafter(nbr, nbr - 1))
        pts.append(nbr + tol * nprng.choice([-1.0, 1.0], size=nbr.shape))
        pts.append(allv)
        # bbox border, outside bbox, bbox +- tol
        bx = [lo[0], hi[0], lo[0] - tol, hi[0] + tol, np.nextafter(lo[0] - tol, -np.inf),
              np.nextafter(hi[0] + tol, np.inf), lo[0] - 1e6, hi[0] + 1e6]
        by = [lo[1], hi[1], lo[1] - tol, hi[1] + tol, np.nextafter(lo[1] - tol, -np.inf),
              np.nextafter(hi[1] + tol, np.inf), lo[1] - 1e6, hi[1] + 1e6]
        ys_in = nprng.uniform(lo[1], hi[1], 200)
        xs_in = nprng.uniform(lo[0], hi[0], 200)
        pts.append(np.array([(x, y) for x in bx for y in ys_in] + [(x, y) for y in by for x in xs_in]
                            + [(x, y) for x in bx for y in by]))
        with core.Region(arr, tol) as region:
            gx, gy = _grid_border_points(rings, tol, region)
            gx = np.array(gx)
            gy = np.array(gy)
            # grid-line crossings (subsampled) and lines x = grid line at random y
            sub_x = gx[:: max(1, len(gx) // 150)]
            sub_y = gy[:: max(1, len(gy) // 150)]
            pts.append(np.array(np.meshgrid(sub_x, sub_y)).T.reshape(-1, 2))
            pts.append(np.column_stack([nprng.choice(gx, 5000), nprng.uniform(lo[1], hi[1], 5000)]))
            pts.append(np.column_stack([nprng.uniform(lo[0], hi[0], 5000), nprng.choice(gy, 5000)]))
            # vertex coordinates combined (horizontal / vertical alignments with vertices)
            pts.append(np.column_stack([nprng.choice(allv[:, 0], 5000), nprng.choice(allv[:, 1], 5000)]))
            P = np.ascontiguousarray(in_range(np.concatenate(pts)))
            prep = region.classify(P)
            st = region.stats()
        one = core.classify_points(arr, P, tol)
        bad = np.nonzero(one != prep)[0]
        if len(bad):
            i = int(bad[0])
            pt = tuple(P[i].tolist())
            small = _shrink(rings, pt, tol, use_ref=False)
            o1, p1 = _lib_both(small, [pt], tol)
            pytest.fail(f"prepared != one-shot on {len(bad)} of {len(P)} points (stats {st}).\n"
                        f"minimal: rings={_rings_repr(small)} point={pt!r} tol={tol!r}: "
                        f"one-shot {NAMES[int(o1[0])]} prepared {NAMES[int(p1[0])]} "
                        f"reference {NAMES[reference.classify(small, [pt], tol)[0]]}")
        assert st["columns"] >= 1 and st["rows"] >= 1
        assert 0 <= st["edge_cells"] <= st["columns"] * st["rows"]
        assert st["grid_entries"] >= st["edge_cells"]
        assert st["edge_entries"] == st["list_entries"] + st["ordered_entries"]
        assert st["nodes"] >= st["list_leaves"] + st["ordered_leaves"] >= st["edge_cells"]
        # spot check a subsample against the exact reference
        idx = nprng.choice(len(P), 120, replace=False)
        check(rings, P[idx], tol, label=f"large seed {seed} subsample")


def _spiky_star(n, r_out=1.0, r_in=0.2, cx=0.0, cy=0.0):
    """The benchmark's star: 2n vertices alternating between radii r_out and r_in."""
    k = np.arange(2 * n)
    r = np.where(k % 2 == 0, r_out, r_in)
    return np.column_stack([cx + r * np.cos(k * math.pi / n), cy + r * np.sin(k * math.pi / n)])


def _comb(n, width=0.3, gap=0.7, height=50.0):
    """A base with n long thin teeth."""
    pts = [(0.0, 0.0), (n * (width + gap), 0.0)]
    for k in range(n - 1, -1, -1):
        x0 = k * (width + gap)
        pts += [(x0 + width, 1.0 + height), (x0, 1.0 + height)] + ([(x0, 1.0)] if k else [])
    return np.array(pts)


@pytest.mark.parametrize("tol", [0.0, 1e-9, 1e-4, 0.05])
def test_prepared_dense_spikes(tol):
    """Regions a uniform grid cannot separate: the benchmark's star (5000 spikes), a comb
    of 600 thin teeth, and 2000 spikes inside one grid cell of a large frame.  The
    prepared index refines them (ordered slabs, a deep quadtree) and must still answer
    as the one-shot path, and as the exact reference on a subsample."""
    rng = random.Random(int(tol * 1e9) + 11)
    nprng = np.random.default_rng(int(tol * 1e9) + 11)
    cases = {
        "star": [_spiky_star(5000)],
        "comb": [_comb(600)],
        "deep": [np.array(square(0.0, 0.0, 1000.0, 1000.0)), _spiky_star(2000, 0.4, 0.05, 500.3, 500.7)],
    }
    for name, rings in cases.items():
        allv = np.concatenate(rings)
        lo, hi = allv.min(axis=0), allv.max(axis=0)
        near = near_boundary_points(rng, [r.tolist() for r in rings], tol, per_edge=1)
        pts = [np.array(near), nprng.uniform(lo - 0.05 * (hi - lo), hi + 0.05 * (hi - lo), size=(30000, 2))]
        if name == "deep":  # most queries inside the dense cell
            pts.append(nprng.uniform((499.85, 500.25), (500.75, 501.15), size=(30000, 2)))
        P = np.ascontiguousarray(in_range(np.concatenate(pts)))
        with core.Region(rings, tol) as region:
            prep = region.classify(P)
            st = region.stats()
        one = core.classify_points(rings, P, tol)
        bad = np.nonzero(one != prep)[0]
        if len(bad):
            i = int(bad[0])
            pytest.fail(f"{name} tol={tol!r}: prepared != one-shot on {len(bad)} of {len(P)} points, "
                        f"first {tuple(P[i].tolist())!r}: one-shot {NAMES[int(one[i])]}, "
                        f"prepared {NAMES[int(prep[i])]} (stats {st})")
        counts = np.bincount(one, minlength=3)
        assert counts[ON] > 0 and counts[OUT] > 0 and (counts[IN] > 0 or tol >= 0.05)
        # The refinement is really in use (a tol wider than the gaps leaves nothing to
        # order: every slab would have to reach across neighbouring spikes).
        if tol <= 1e-4:
            assert st["ordered_leaves"] > 0 and st["ordered_entries"] > 0, st
        if name == "deep" and tol <= 1e-4:
            assert st["max_depth"] >= 4, st
        # exact reference on a subsample (near-boundary points first)
        idx = np.concatenate([nprng.choice(len(near), 40, replace=False),
                              nprng.choice(len(P), 20, replace=False)])
        check([r.tolist() for r in rings], P[idx], tol, label=f"dense spikes {name} tol={tol}")


# Reference-point fractions and grid formulas of the prepared region (pointclass_grid.c),
# used only to aim test points and vertices at cell borders and reference points; if the
# implementation changes they are just ordinary points and the checks stay valid.
_REF_FX = [0.5, 0.3819660112501051, 0.6180339887498949, 0.2360679774997897,
           0.7639320225002103, 0.1458980337503155, 0.8541019662496845, 0.4142135623730950]
_REF_FY = [0.5, 0.6180339887498949, 0.3819660112501051, 0.8541019662496845,
           0.1458980337503155, 0.7639320225002103, 0.2360679774997897, 0.2679491924311227]


def _grid_geometry(rings, tol, cols, rows):
    xs = [x for r in rings for x, _ in r]
    ys = [y for r in rings for _, y in r]
    x0, x1, y0, y1 = min(xs) - tol, max(xs) + tol, min(ys) - tol, max(ys) + tol
    w, h = x1 - x0, y1 - y0
    margin = max(128.0 * 2.0 ** -53 * (abs(x0) + abs(x1) + abs(y0) + abs(y1) + w + h), 2.0 ** -1000)
    gx0, gy0 = x0 - 2.0 * margin, y0 - 2.0 * margin
    return gx0, gy0, (w + 4.0 * margin) / cols, (h + 4.0 * margin) / rows


def _ref_point(geo, i, j, k):
    gx0, gy0, cw, ch = geo
    return (gx0 + (i + _REF_FX[k]) * cw, gy0 + (j + _REF_FY[k]) * ch)


@pytest.mark.parametrize("tol", [0.0, 1e-9, 0.05, 0.3])
def test_grid_reference_points_and_cell_borders(tol):
    """Rings through the prepared grid's cell reference points (all 8 of one cell are
    vertices), queries at every reference point, cell border and corner."""
    rng = random.Random(int(tol * 1000) + 7)
    frame = square(0.0, 0.0, 10.0, 10.0)
    for trial in range(4):
        inner = [(rng.uniform(2, 8), rng.uniform(2, 8)) for _ in range(14)]
        with core.Region([frame, inner], tol) as region:
            st = region.stats()
        cols, rows = st["columns"], st["rows"]
        geo = _grid_geometry([frame, inner], tol, cols, rows)
        ci, cj = cols // 2 + rng.randint(-1, 1), rows // 2 + rng.randint(-1, 1)
        # 8 vertices: the reference points of cell (ci, cj), ordered around its centre
        refs = [_ref_point(geo, ci, cj, k) for k in range(8)]
        cx, cy = _ref_point(geo, ci, cj, 0)
        star = sorted(refs, key=lambda p: math.atan2(p[1] - cy, p[0] - cx))
        # 6 vertices on the centre reference points of a row and a column of cells, so
        # that horizontal / vertical edges run exactly through further reference points
        a = _ref_point(geo, ci - 3, cj + 2, 0)
        b = _ref_point(geo, ci + 3, cj + 2, 0)
        c = _ref_point(geo, ci + 3, cj - 3, 0)
        d = _ref_point(geo, ci - 2, cj - 3, 0)
        e = _ref_point(geo, ci - 2, cj - 1, 0)
        f = _ref_point(geo, ci - 3, cj - 1, 0)
        inner2 = star[:4] + [a, b, c, d, e, f] + star[4:]
        assert len(inner2) == len(inner)
        variants = [[frame, inner2], [frame, star], [frame, [a, b, c, d, e, f]]]
        for rings in variants:
            try:
                with core.Region(rings, tol) as region:
                    st2 = region.stats()
            except core.MfgError as exc:
                pytest.fail(f"Region failed: {exc}\n rings={_rings_repr(rings)}\n tol={tol!r}\n"
                            f" one-shot on the same rings: "
                            f"{core.classify_points(rings, [(5.0, 5.0)], tol).tolist()}")
            cols2, rows2 = st2["columns"], st2["rows"]
            geo2 = _grid_geometry(rings, tol, cols2, rows2)
            pts = []
            for i in range(cols2):
                for j in range(rows2):
                    for k in range(8):
                        pts.append(_ref_point(geo2, i, j, k))
            gx0, gy0, cw, ch = geo2
            for i in range(cols2 + 1):
                for j in range(rows2 + 1):
                    bx, by = gx0 + i * cw, gy0 + j * ch
                    pts += [(bx, by), (bx, gy0 + (j + 0.5) * ch), (gx0 + (i + 0.5) * cw, by),
                            (np.nextafter(bx, -math.inf), by), (bx, np.nextafter(by, math.inf))]
            check(rings, in_range(pts), tol,
                  label=f"grid refs tol={tol} trial {trial} ({cols2}x{rows2})")


def test_prepared_all_reference_points_on_boundary():
    """Minimal fuzzer case: the 8 vertices of ring 1 are the 8 reference points of one grid
    cell (tol = 0), so no reference point of that cell is off the boundary."""
    rings = [[(0.0, 0.0), (8.0, 0.0), (8.0, 8.0), (0.0, 8.0)],
             [(4.6111456180003074, 4.1167184270002783), (4.1167184270002783, 4.6111456180003074),
              (4.6832815729999036, 4.1888543819998745), (4.3313708498985513, 4.2143593539449462),
              (4.4000000000000909, 4.4000000000000909), (4.3055728090001537, 4.4944271910000282),
              (4.4944271910000282, 4.3055728090001537), (4.1888543819998745, 4.6832815729999036)]]
    pts = [(x / 8.0, y / 8.0) for x in range(-4, 70, 3) for y in range(-4, 70, 3)] + rings[1]
    pts += [((a[0] + b[0]) / 2, (a[1] + b[1]) / 2) for a, b in zip(rings[1], rings[1][1:])]
    for tol in (0.0, 2.0 ** -40):
        check(rings, pts, tol, label=f"all reference points on the boundary, tol={tol}")


def test_prepared_reused_many_batches_and_threads():
    rng = random.Random(41)
    rings = [star_polygon(rng, 200, 0, 0, 5), star_polygon(rng, 40, 0.2, 0.1, 1)]
    region = core.Region(rings, 0.01)
    batches = [np.array(random_points(rng, rings, 3000)) for _ in range(16)]
    want = [core.classify_points(rings, b, 0.01) for b in batches]
    with concurrent.futures.ThreadPoolExecutor(4) as ex:
        got = list(ex.map(region.classify, batches))
    for w, g in zip(want, got):
        assert np.array_equal(w, g)
    region.close()
    with pytest.raises(core.MfgError):
        region.classify(batches[0])
    region.close()   # idempotent


# --------------------------------------------------------------------------- #
# Scales                                                                      #
# --------------------------------------------------------------------------- #

@pytest.mark.parametrize("scale", [1e-8, 1e-3, 1.0, 1e3, 1e8, 1e20, 1e50])
@pytest.mark.parametrize("shift", [0.0, 1e-8, 1e3, 1e8])
def test_scales_and_translations(scale, shift):
    rng = random.Random(int(math.log10(scale) * 7 + math.log10(shift or 1) * 3) & 0xffff)
    for trial in range(3):
        rings = _random_case(rng, ("star", "self", "lattice")[trial])
        rings = [[(x * scale + shift * scale, y * scale - shift * scale) for x, y in r] for r in rings]
        for tol in (0.0, 1e-13 * scale, 0.05 * scale):
            pts = random_points(rng, rings, 40) + near_boundary_points(rng, rings, tol, per_edge=1)
            check(rings, pts, tol, label=f"scale {scale} shift {shift}")


def test_translation_large_offset_small_features():
    # Features of size 1e-8 at offset 1e8 (only ~30 bits of relative precision left).
    rng = random.Random(51)
    for trial in range(10):
        rings = [[(1e8 + x * 1e-8, -1e8 + y * 1e-8) for x, y in lattice_ring(rng, rng.randint(3, 9))]]
        pts = [(1e8 + x * 0.5e-8, -1e8 + y * 0.5e-8) for x in range(-14, 15) for y in range(-14, 15)]
        for tol in (0.0, 1e-8, 3e-9):
            check(rings, pts + near_boundary_points(rng, rings, tol, 1), tol, label="offset 1e8")


def test_huge_coordinates_near_max_coord():
    rng = random.Random(61)
    big = 2.0 ** 196
    for trial in range(8):
        rings = [[(x * big, y * big) for x, y in lattice_ring(rng, rng.randint(3, 8), 8)]]
        pts = [(x * big / 2, y * big / 2) for x in range(-16, 17, 3) for y in range(-16, 17, 3)]
        pts += [(MAX_COORD, MAX_COORD), (-MAX_COORD, 0.0), (0.0, -MAX_COORD)]
        for tol in (0.0, big * 0.75, MAX_COORD, MIN_COORD):
            pts2 = [p for p in pts + near_boundary_points(rng, rings, tol, 1)
                    if max(abs(p[0]), abs(p[1])) <= MAX_COORD]
            check(rings, pts2, tol, label=f"huge coords trial {trial}")
    ring = [(-MAX_COORD, -MAX_COORD), (MAX_COORD, -MAX_COORD), (MAX_COORD, MAX_COORD),
            (-MAX_COORD, MAX_COORD)]
    got = check([ring], [(0.0, 0.0), (MAX_COORD, 0.0), (1.0, 2.0), (-MAX_COORD, -MAX_COORD)], 0.0)
    assert got.tolist() == [IN, ON, IN, ON]
    got = check([ring], [(0.0, 0.0), (MAX_COORD / 2, 0.0)], MAX_COORD)
    assert got.tolist() == [ON, ON]


def test_tiny_offsets():
    """Points at tiny distances (down to MFG_MIN_COORD = 2^-200) from ordinary edges:
    squared distances are far below double precision of the coordinates, and degree-4
    terms reach 2^-800, yet everything must be decided exactly."""
    sq = [square(0.0, 0.0, 1.0, 1.0)]
    tiny = [MIN_COORD, 2.0 * MIN_COORD, 1e-60, 2.0 ** -150, 1e-40, 2.0 ** -60]
    pts, want = [], []
    for t in tiny:
        pts += [(t, 0.5), (-t, 0.5), (0.5, t), (0.5, -t), (1.0 - 2.0 ** -53, 0.5), (t, t), (-t, -t)]
        want += [IN, OUT, IN, OUT, IN, IN, OUT]
    assert check(sq, pts, 0.0).tolist() == want
    # ... and with a tolerance of the same tiny size
    for t in tiny:
        got = check(sq, [(-t, 0.5), (-2 * t, 0.5), (-t, -t), (0.5, -t), (0.5, t)], t)
        assert got.tolist() == [ON, OUT, OUT, ON, ON]
    # Tiny offsets from slanted edges through the origin (the point's coordinates are tiny
    # too, so the offset is not lost in rounding).
    tri = [(-1.0, -3.0), (1.0, 3.0), (-2.0, 5.0)]
    for t in tiny:
        pts = [(t, 3 * t), (t, 3 * t + t), (t, 3 * t - t), (2 * t, 6 * t), (-t, -3 * t)]
        for tol in (0.0, t, t / 2 if t / 2 >= MIN_COORD else t):
            check([tri], pts, tol, label=f"slanted tiny t={t} tol={tol}")
    rng = random.Random(91)
    for trial in range(20):
        rings = [lattice_ring(rng, rng.randint(3, 9)) for _ in range(rng.randint(1, 2))]
        pts = []
        for ring in rings:
            for (ax, ay), (bx, by) in zip(ring, ring[1:] + ring[:1]):
                for s in (0.25, 0.5, 0.75):
                    px, py = ax + s * (bx - ax), ay + s * (by - ay)
                    for t in (MIN_COORD, 1e-50, 2.0 ** -100, 1e-17):
                        pts += [(px + t, py), (px - t, py), (px, py + t), (px, py - t)]
        pts = in_range(pts)
        for tol in (0.0, MIN_COORD, 1e-50):
            check(rings, pts, tol, label=f"tiny offsets trial {trial} tol {tol}")


@pytest.mark.parametrize("exp2", [100, 140, 170, 190, 196])
def test_huge_scale_multi_ring_large_tolerance(exp2):
    """Several lattice rings scaled by 2^exp2, tolerances up to a few cells, points on a
    finer lattice reaching well outside the bounding box (found by the fuzzer)."""
    s = 2.0 ** exp2
    base = [[(15.375, -0.125), (-0.125, -0.125), (-0.125, -0.125)],
            [(-0.125, -11.5), (7.0, 0.5), (0.5, -12.75)]]
    rings = [[(x * s, y * s) for x, y in r] for r in base]
    if 28.05 * s <= MAX_COORD:
        check(rings, [(12.0 * s, -28.0 * s), (11.975 * s, -28.05 * s)], 16.0 * s,
              label=f"fuzzer case at 2^{exp2}")
    rng = random.Random(exp2)
    for trial in range(12):
        rings = [[(rng.randint(-16, 16) * s / 8, rng.randint(-16, 16) * s / 8)
                  for _ in range(rng.randint(3, 6))] for _ in range(rng.randint(1, 3))]
        pts = [(rng.randint(-64, 64) * s / 16, rng.randint(-64, 64) * s / 16) for _ in range(150)]
        pts += [(rng.uniform(-4, 4) * s, rng.uniform(-4, 4) * s) for _ in range(100)]
        for tol in (0.0, rng.randint(1, 8) * s / 8, rng.randint(8, 40) * s / 8):
            check(rings, pts, tol, label=f"huge multi-ring 2^{exp2} trial {trial}")


@pytest.mark.parametrize("scale", [1e-40, 2.0 ** -150, 1e-50, 2.0 ** -190, 2.0 ** -198])
def test_tiny_coordinates(scale):
    # In range per mfgeom.h (0 or 2^-200 <= |x| <= 2^200): must be decided exactly even
    # where degree-4 products of coordinate differences reach ~2^-800.
    rng = random.Random(71)
    for trial in range(6):
        rings = [[(x * scale, y * scale) for x, y in lattice_ring(rng, rng.randint(3, 8), 6)]]
        pts = [(x * scale / 2, y * scale / 2) for x in range(-13, 14, 2) for y in range(-13, 14)]
        for tol in (0.0, scale * 0.75, scale * 2.0):
            check(rings, pts, tol, label=f"tiny scale {scale} trial {trial}")
    # Mixed: big polygon, tiny tolerance / tiny offsets.
    ring = [(0.0, 0.0), (1e50, 0.0), (1e50, 3e49), (0.0, 1e50)]
    pts = [(5e49, scale), (5e49, -scale), (5e49, 0.0), (scale, scale), (-scale, 5e49)]
    for tol in (0.0, scale, scale * 0.5):
        check([ring], pts, tol, label=f"mixed 1e50/{scale}")


@pytest.mark.parametrize("bad", [1e-300, 5e-324, -2.0 ** -1000, np.nextafter(MIN_COORD, 0.0),
                                 -1e-61])
def test_error_values_below_min_coord(bad):
    """mfgeom.h: non-zero magnitudes below MFG_MIN_COORD = 2^-200 are MFG_ERR_INVALID."""
    for k in range(2):
        ring = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]
        ring[1][k] = bad
        _both_raise([ring], PTS, 0.0, r"range|coord|small|2\^-200|magnitude")
        pts = [[0.5, 0.5], [0.25, 0.25]]
        pts[1][k] = bad
        _both_raise(SQ, pts, 0.0, r"point|range|coord|small|2\^-200", where="points")
    _both_raise(SQ, PTS, abs(bad), r"tol")


def test_min_coord_and_zero_are_accepted():
    ring = [(0.0, 0.0), (MIN_COORD, 0.0), (MIN_COORD, MIN_COORD), (-0.0, MIN_COORD)]
    pts = [(MIN_COORD, MIN_COORD), (0.0, 0.0),
           (-MIN_COORD, 0.0), (2 * MIN_COORD, 2 * MIN_COORD), (-0.0, -0.0)]
    assert check([ring], pts, 0.0).tolist() == [ON, ON, OUT, OUT, ON]
    assert check([ring], pts, MIN_COORD).tolist() == [ON, ON, ON, OUT, ON]
    big = [(-MAX_COORD, -MAX_COORD), (MAX_COORD, -MAX_COORD), (0.0, MAX_COORD)]
    assert check([big], [(MIN_COORD, MIN_COORD), (0.0, -MAX_COORD)], MIN_COORD).tolist() == [IN, ON]


# --------------------------------------------------------------------------- #
# shapely as a second reference                                               #
# --------------------------------------------------------------------------- #

def test_shapely_agrees_far_from_boundary():
    from shapely.geometry import Point, Polygon
    rng = random.Random(81)
    checked = 0
    for trial in range(20):
        n = rng.randint(12, 40)
        shell = [(r * math.cos(a), r * math.sin(a)) for a, r in
                 ((2 * math.pi * (k + rng.uniform(-0.3, 0.3)) / n, rng.uniform(7.0, 10.0))
                  for k in range(n))]
        holes = []
        for (hx, hy) in ((-2.0, 0.0), (2.0, 0.5), (0.0, -2.0))[: rng.randint(1, 3)]:
            h = star_polygon(rng, rng.randint(3, 12), hx, hy, 1.0)
            if rng.random() < 0.5:
                h = h[::-1]
            holes.append(h)
        poly = Polygon(shell, holes)
        if not poly.is_valid:
            continue
        rings = [shell] + holes
        pts = random_points(rng, rings, 1500, margin=0.1)
        for tol in (0.0, 0.05):
            got = check(rings, pts, tol, use_ref=False)
            for (x, y), g in zip(pts, got):
                p = Point(x, y)
                if poly.boundary.distance(p) <= tol + 1e-9:
                    continue
                want = IN if poly.contains(p) else OUT
                assert g == want, f"shapely disagrees at {(x, y)!r} tol={tol}: lib {NAMES[int(g)]}"
                checked += 1
        check(rings, pts[:150], 0.05, label="shapely case vs exact")
    assert checked > 10000


# --------------------------------------------------------------------------- #
# Input validation                                                            #
# --------------------------------------------------------------------------- #

SQ = [square(0.0, 0.0, 1.0, 1.0)]
PTS = [(0.5, 0.5)]


def _both_raise(rings, pts, tol, pattern, where="both"):
    """Both APIs must raise MfgError whose detail matches ``pattern``."""
    errors = []
    with pytest.raises(core.MfgError) as e1:
        core.classify_points(rings, pts, tol)
    errors.append(e1.value)
    with pytest.raises(core.MfgError) as e2:
        if where == "points":
            core.Region(rings, tol).classify(pts)
        else:
            core.Region(rings, tol)
    errors.append(e2.value)
    for e in errors:
        assert e.status and isinstance(e.status, str)
        assert e.detail, f"empty mfg_last_error for {e!r}"
        assert re.search(pattern, e.detail, re.I), f"message {e.detail!r} does not match {pattern!r}"
    return errors


@pytest.mark.parametrize("n", [0, 1, 2])
def test_error_ring_too_short(n):
    ring = [(0.0, 0.0), (1.0, 0.0)][:n]
    _both_raise([np.array(ring, dtype=float).reshape(-1, 2)], PTS, 0.0, r"ring|vert")
    _both_raise(SQ + [np.array(ring, dtype=float).reshape(-1, 2)], PTS, 0.1, r"ring|vert")


def test_error_no_rings():
    _both_raise([], PTS, 0.0, r"ring")


@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf, 2.0 * MAX_COORD, -1e61,
                                 np.nextafter(MAX_COORD, math.inf)])
def test_error_bad_ring_coordinates(bad):
    for k in range(2):
        ring = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]
        ring[2][k] = bad
        _both_raise([ring], PTS, 0.0, r"nan|inf|finite|coord|range|vert|ring|large|magnitude")


@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf, 2.0 * MAX_COORD,
                                 np.nextafter(-MAX_COORD, -math.inf)])
def test_error_bad_point_coordinates(bad):
    for k in range(2):
        pts = [[0.5, 0.5], [0.2, 0.3], [0.0, 0.0]]
        pts[1][k] = bad
        _both_raise(SQ, pts, 0.0, r"point|nan|inf|finite|coord|range", where="points")


@pytest.mark.parametrize("tol", [-1.0, -1e-300, -0.0 - 5e-324, math.nan, math.inf, -math.inf,
                                 np.nextafter(MAX_COORD, math.inf), -MIN_COORD])
def test_error_bad_tolerance(tol):
    _both_raise(SQ, PTS, tol, r"tol")


def test_negative_zero_tolerance_is_zero():
    assert check(SQ, [(0.5, 0.0), (0.5, 0.5), (2.0, 2.0)], -0.0).tolist() == [ON, IN, OUT]


def test_max_coord_is_accepted():
    ring = [(0.0, 0.0), (MAX_COORD, 0.0), (0.0, MAX_COORD)]
    assert check([ring], [(-MAX_COORD, -MAX_COORD), (1.0, 1.0)], MAX_COORD).tolist()[1] == ON


def test_error_status_codes_and_untouched_output():
    lib = core._lib
    xy = np.array([0, 0, 1, 0, 1, 1, 0, 1], dtype=np.float64)
    pts = np.array([0.5, 0.5, 2, 2], dtype=np.float64)
    d = lambda a: a.ctypes.data_as(ctypes.POINTER(ctypes.c_double))           # noqa: E731
    i64 = lambda a: a.ctypes.data_as(ctypes.POINTER(ctypes.c_int64))          # noqa: E731
    u8 = lambda a: a.ctypes.data_as(ctypes.POINTER(ctypes.c_uint8))           # noqa: E731

    def call(xy, offs, nrings, pts, npts, tol):
        out = np.full(max(npts, 2), 0xAB, dtype=np.uint8)
        st = lib.mfg_classify_points(d(xy) if xy is not None else None,
                                     i64(offs) if offs is not None else None, nrings,
                                     d(pts) if pts is not None else None, npts, tol,
                                     u8(out))
        if st != MFG_OK:
            assert np.all(out == 0xAB), "output written on failure"
            assert lib.mfg_last_error().decode() != ""
        return st, out

    good = np.array([0, 4], dtype=np.int64)
    assert call(xy, good, 1, pts, 2, 0.0)[1].tolist() == [IN, OUT]
    assert call(xy, good, 1, pts, 2, -1.0)[0] == MFG_ERR_INVALID
    assert call(xy, good, 1, pts, 2, math.nan)[0] == MFG_ERR_INVALID
    assert call(xy, np.array([0, 2], dtype=np.int64), 1, pts, 2, 0.0)[0] == MFG_ERR_DEGENERATE
    assert call(xy, np.array([0, 4, 4], dtype=np.int64), 2, pts, 2, 0.0)[0] == MFG_ERR_DEGENERATE
    assert call(xy, np.array([0], dtype=np.int64), 0, pts, 2, 0.0)[0] in (MFG_ERR_INVALID,
                                                                         MFG_ERR_DEGENERATE)
    assert call(xy, good, -1, pts, 2, 0.0)[0] in (MFG_ERR_INVALID, MFG_ERR_DEGENERATE)
    assert call(xy, np.array([1, 4], dtype=np.int64), 1, pts, 2, 0.0)[0] != MFG_OK      # offs[0] != 0
    assert call(xy, np.array([0, 4, 3, 4], dtype=np.int64), 3, pts, 2, 0.0)[0] != MFG_OK  # decreasing
    assert call(xy, good, 1, pts, -1, 0.0)[0] == MFG_ERR_INVALID
    bad_pts = np.array([0.5, 0.5, math.nan, 2], dtype=np.float64)
    assert call(xy, good, 1, bad_pts, 2, 0.0)[0] == MFG_ERR_INVALID
    nan_xy = xy.copy()
    nan_xy[3] = math.nan
    assert call(nan_xy, good, 1, pts, 2, 0.0)[0] == MFG_ERR_INVALID
    assert call(None, good, 1, pts, 2, 0.0)[0] == MFG_ERR_NULL
    assert call(xy, None, 1, pts, 2, 0.0)[0] == MFG_ERR_NULL
    assert call(xy, good, 1, None, 2, 0.0)[0] == MFG_ERR_NULL
    out = np.zeros(2, dtype=np.uint8)
    assert lib.mfg_classify_points(d(xy), i64(good), 1, d(pts), 2, 0.0, None) == MFG_ERR_NULL
    # prepared API
    handle = ctypes.c_void_p()
    assert lib.mfg_region_new(d(xy), i64(good), 1, -1.0, ctypes.byref(handle)) == MFG_ERR_INVALID
    assert not handle.value, "region handle written on failure"
    assert lib.mfg_region_new(d(xy), i64(good), 1, 0.0, None) == MFG_ERR_NULL
    assert lib.mfg_region_new(d(xy), i64(good), 1, 0.0, ctypes.byref(handle)) == MFG_OK
    assert handle.value
    out[:] = 0xAB
    assert lib.mfg_region_classify(handle, d(bad_pts), 2, u8(out)) == MFG_ERR_INVALID
    assert np.all(out == 0xAB)
    assert lib.mfg_region_classify(None, d(pts), 2, u8(out)) == MFG_ERR_NULL
    assert lib.mfg_region_classify(handle, d(pts), 2, u8(out)) == MFG_OK
    assert out.tolist() == [IN, OUT]
    assert lib.mfg_region_stats(None, i64(np.zeros(4, dtype=np.int64))) == MFG_ERR_NULL
    info = core._RegionInfo()
    assert lib.mfg_region_info(None, ctypes.byref(info)) == MFG_ERR_NULL
    assert lib.mfg_region_info(handle, None) == MFG_ERR_NULL
    assert lib.mfg_region_info(handle, ctypes.byref(info)) == MFG_OK
    assert info.columns >= 1 and info.rows >= 1 and info.edge_cells >= 1
    lib.mfg_region_free(handle)
    lib.mfg_region_free(None)
    assert lib.mfg_status_str(99)   # never NULL
    for s in range(6):
        assert lib.mfg_status_str(s)


def test_empty_points():
    for pts in ([], np.zeros((0, 2)), np.zeros(0)):
        r = core.classify_points(SQ, pts, 0.1)
        assert r.dtype == np.uint8 and r.shape == (0,)
        with core.Region(SQ, 0.1) as region:
            r = region.classify(pts)
        assert r.dtype == np.uint8 and r.shape == (0,)


@pytest.mark.parametrize("pts", [[0.5, 0.5], [0.5, 0.5, 0.1], np.zeros((3, 3)), np.zeros((2, 2, 2)),
                                 np.zeros((4, 1)), 0.5])
def test_wrong_point_shapes(pts):
    with pytest.raises(ValueError):
        core.classify_points(SQ, pts, 0.0)
    with core.Region(SQ, 0.0) as region:
        with pytest.raises(ValueError):
            region.classify(pts)


def test_wrong_types():
    with pytest.raises((TypeError, ValueError)):
        core.classify_points(SQ, [["a", "b"]], 0.0)
    with pytest.raises((TypeError, ValueError)):
        core.classify_points(SQ, [(0.5, 0.5)], "x")
    with pytest.raises((TypeError, ValueError)):
        core.classify_points([[(0, 0, 0), (1, 0, 0), (1, 1, 0)]], PTS, 0.0)
    with pytest.raises((TypeError, ValueError)):
        core.classify_points([np.zeros(6)], PTS, 0.0)
    with pytest.raises((TypeError, ValueError)):
        core.classify_points(5, PTS, 0.0)
    with pytest.raises((TypeError, ValueError)):
        core.Region([[(0, 0, 0), (1, 0, 0), (1, 1, 0)]], 0.0)


def test_input_dtypes_and_layouts():
    ring_i = np.array([[0, 0], [4, 0], [4, 4], [0, 4]], dtype=np.int32)
    ring_f = np.asfortranarray(ring_i.astype(np.float32))
    pts = np.array([[1, 1], [4, 2], [5, 5], [0, 0]], dtype=np.int64)[::1]
    pts_strided = np.array([[1, 1, 9], [4, 2, 9], [5, 5, 9], [0, 0, 9]], dtype=float)[:, :2]
    want = [IN, ON, OUT, ON]
    assert core.classify_points([ring_i], pts, 0).tolist() == want
    assert core.classify_points([ring_f], pts_strided, 0).tolist() == want
    assert core.classify_points(ring_i, pts, 0).tolist() == want        # single ring array
    assert core.Region([ring_f], 0).classify(pts_strided).tolist() == want
