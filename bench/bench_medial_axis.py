# SPDX-License-Identifier: LGPL-2.1-or-later
"""bench_medial_axis.py - the 2-D medial axis (issue 9 sections 2 and 6): ours
(mfg_medial_axis) against its peer, FreeCAD's Path.Voronoi (Boost.Polygon's segment
Voronoi diagram), on the same faces in one run: the hand-derived shapes (rectangle,
frame, L, regular 5-star), jittered needle stars with 16 random convex holes at ~1k, 10k
and 100k segments, and a pocket face of examples/parts/pocket_block.py (its top face with
the pocket's opening, built with FreeCAD's Part in this process, no GUI), and circles of
10k and 100k vertices rounded to an integer grid (near-cocircular; issue 22).

    MFGEOM_LIBRARY=build/libmfgeom.so /usr/bin/python3 bench/bench_medial_axis.py [--quick]
        [--tol T] [--repeat N] [--only NAME]

Columns: our library call alone (C, best of N) and through the binding (numpy result);
Boost's construct() alone (best of N; the fair peer: it gives no interior classification,
no radii along edges, no parabola samples -- its Python extraction is timed too, once);
the ratio ours(C) / construct (Boost's extraction with Python is timed once, with its
parabolas sampled at tol / 10); branches / junctions of both (Boost's with its junctions
joined by chains shorter than tol contracted, mfgeom's rule); agreement: the largest
distance of our samples to Boost's inner axis edges (edges incident to the boundary --
radius 0 at an end -- and points with radius < tol excluded; at most 20 000 random
samples each way) and of Boost's samples to ours.  Boost's input is truncated to a
1/scale grid (scale 1000; |x| < 2^31/scale): all inputs here are on the 1e-3 grid and
medial_voronoi hands Boost exactly those values, so both see the same segments.  Growth: the exponent
of time ~ n^k between the star sizes, and ours against the tolerance on the 10k star."""
import argparse
import ctypes
import math
import os
import sys
import time

import numpy as np

_HERE = os.path.dirname(os.path.abspath(__file__))
_REPO = os.path.dirname(_HERE)
sys.path.insert(0, os.path.join(_REPO, "workbench"))
sys.path.insert(0, os.path.join(_REPO, "tests", "python"))
from mfgeom import core  # noqa: E402
import medial_voronoi  # noqa: E402
from scipy.spatial import cKDTree  # noqa: E402


def star(n, R, r, jitter, rng):
    ang = np.arange(2 * n) * math.pi / n
    rad = np.where(np.arange(2 * n) % 2 == 0, R, r) * (1 + jitter * rng.uniform(-1, 1, 2 * n))
    return np.c_[rad * np.cos(ang), rad * np.sin(ang)]


def star_with_holes(nseg, holes, seed):
    """A jittered star of nseg edges (tips 100, notches 40, +-15 %) with `holes` convex
    holes (regular 3..8-gons of radius 1.5..4) inside radius 30; on the 1e-3 grid.  (The
    generator of tests/python/test_medial_axis_battery.py.)"""
    rng = np.random.default_rng(seed)
    rings = [star(nseg // 2, 100.0, 40.0, 0.15, rng)]
    centres = []
    while len(centres) < holes:
        c = rng.uniform(-30, 30, 2)
        rr = rng.uniform(1.5, 4)
        if np.hypot(*c) + rr > 32 or any(np.hypot(*(c - c2)) < rr + r2 + 1 for c2, r2 in centres):
            continue
        centres.append((c, rr))
        k = int(rng.integers(3, 9))
        a = rng.uniform(0, 2 * math.pi) + np.arange(k) * 2 * math.pi / k
        rings.append(c + rr * np.c_[np.cos(a), np.sin(a)])
    return [np.round(r, 3) for r in rings]


def circle_on_grid(n, R):
    phi = np.linspace(0, 2 * np.pi, n, endpoint=False)
    return np.round(R * np.c_[np.cos(phi), np.sin(phi)])


def pocket_face():
    """The top face of examples/parts/pocket_block.py (60 x 40 with the 20 x 15 opening of
    the +z pocket) as rings, from FreeCAD's Part; None if FreeCAD is missing."""
    if not medial_voronoi.available():
        return None
    sys.path.insert(0, os.path.join(_REPO, "examples", "parts"))
    import pocket_block
    solid = pocket_block.make()
    top = max(solid.Faces, key=lambda f: (round(f.CenterOfMass.z, 6), f.Area))
    rings = []
    for w in top.Wires:
        pts = [(round(v.x, 3), round(v.y, 3)) for v in w.discretize(Deflection=1e-3)]
        if pts[0] == pts[-1]:
            pts = pts[:-1]
        rings.append(np.array(pts, float))
    return rings


def ours_c(rings, tol, repeat):
    """Best time of the library call alone (ctypes, result freed)."""
    xy, off = core._flatten_rings(rings)
    best = math.inf
    for _ in range(repeat):
        res = ctypes.POINTER(core._MedialAxis)()
        t = time.perf_counter()
        st = core._lib.mfg_medial_axis(core._ptr(xy, ctypes.c_double),
                                       core._ptr(off, ctypes.c_int64), len(off) - 1, tol,
                                       ctypes.byref(res))
        best = min(best, time.perf_counter() - t)
        if st != 0:
            raise RuntimeError(f"mfg_medial_axis failed ({st})")
        core._lib.mfg_medial_axis_free(res)
    return best


def dist_to_polylines(P, lines, piece=2.0):
    """Distance of points P (m, 2) to the union of polylines (list of (k, 2)): chords cut
    into pieces <= `piece`, a k-d tree of the piece midpoints, exact point-segment
    distances of the nearest pieces (k doubled until the k-th midpoint is farther than the
    best distance + piece / 2: then no other piece can be nearer)."""
    S0, S1 = [], []
    for L in lines:
        a, b = L[:-1], L[1:]
        n = np.maximum(1, np.ceil(np.linalg.norm(b - a, axis=1) / piece)).astype(int)
        for i in range(n.max()):
            m = n > i
            S0.append(a[m] + (b[m] - a[m]) * (i / n[m])[:, None])
            S1.append(a[m] + (b[m] - a[m]) * ((i + 1) / n[m])[:, None])
    S0, S1 = np.concatenate(S0), np.concatenate(S1)
    tree = cKDTree((S0 + S1) / 2)
    out = np.full(len(P), np.inf)
    todo = np.arange(len(P))
    k = 8
    while len(todo):
        k = min(k, len(S0))
        dm, idx = tree.query(P[todo], k=k)
        dm, idx = dm.reshape(len(todo), -1), idx.reshape(len(todo), -1)
        a, b = S0[idx], S1[idx]
        d = b - a
        l2 = np.maximum(np.einsum('ijk,ijk->ij', d, d), 1e-300)
        q = P[todo][:, None, :] - a
        t = np.clip(np.einsum('ijk,ijk->ij', q, d) / l2, 0, 1)
        r = q - t[..., None] * d
        best = np.sqrt(np.einsum('ijk,ijk->ij', r, r)).min(axis=1)
        out[todo] = best
        done = (dm[:, -1] > best + piece / 2) | (k >= len(S0))
        todo = todo[~done]
        k *= 4
    return out


def boost_classify(rings, pts):
    """Inside test for Boost's edge midpoints: our point classification (IN)."""
    return core.classify_points(rings, pts, 0.0) == 1


def run_shape(name, rings, tol, repeat, out):
    nseg = sum(len(r) for r in rings)
    rep = repeat if nseg < 20000 else max(1, repeat // 2)
    t_c = ours_c(rings, tol, rep)
    t_py = math.inf
    for _ in range(rep):
        t = time.perf_counter()
        ax = core.medial_axis(rings, tol)
        t_py = min(t_py, time.perf_counter() - t)
    row = dict(name=name, nseg=nseg, ours_c=t_c, ours_py=t_py, branches=len(ax.branches),
               junctions=len(ax.junctions), samples=int(sum(len(b.radii) for b in ax.branches)))
    if medial_voronoi.available():
        tb = math.inf
        for _ in range(rep):
            vd, tc = medial_voronoi.construct(rings)
            tb = min(tb, tc)
        row.update(boost=tb)
        if name.startswith("circle") and nseg > 20000:
            # the extraction of Boost's ~10^5 parabolic edges sampled at tol / 10 ran past
            # 15 GB in Python: construct() alone, no agreement columns
            row.update(boost_extract=math.nan, boost_branches=-1, boost_junctions=-1,
                       ours_to_boost=math.nan, boost_to_ours=math.nan)
            out.append(row)
            return row
        t = time.perf_counter()
        # Boost's parabolas sampled at tol / 10: the agreement then measures our error
        edges, _ = medial_voronoi.axis_edges(rings, tol / 10, vd=vd, inside_fn=boost_classify)
        t_ex = time.perf_counter() - t
        nb, nj = medial_voronoi.topology(rings, tol, edges=edges)
        row.update(boost=tb, boost_extract=t_ex, boost_branches=nb, boost_junctions=nj)
        inner = [(p, r) for a, b, p, r in edges if min(r[0], r[-1]) > 1e-9]
        bl = [p for p, r in inner]
        ol = [b.points for b in ax.branches]
        P = np.concatenate([b.points[b.radii >= tol] for b in ax.branches])
        Q = np.concatenate([p[r >= tol] for p, r in inner]) if inner else np.zeros((0, 2))
        rng = np.random.default_rng(0)    # at most 20 000 query points each way
        P = P[rng.choice(len(P), 20000, replace=False)] if len(P) > 20000 else P
        Q = Q[rng.choice(len(Q), 20000, replace=False)] if len(Q) > 20000 else Q
        row["ours_to_boost"] = float(dist_to_polylines(P, bl).max()) if len(P) and bl else math.nan
        row["boost_to_ours"] = float(dist_to_polylines(Q, ol).max()) if len(Q) else math.nan
    out.append(row)
    return row


def fmt_ms(s):
    return "%.2f" % (1e3 * s) if s < 10 else "%.0f" % (1e3 * s)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="stars at 1k and 10k only")
    ap.add_argument("--tol", type=float, default=1e-2, help="tolerance (default 1e-2)")
    ap.add_argument("--repeat", type=int, default=5, help="best of N (default 5)")
    ap.add_argument("--only", default="", help="only the shapes whose name contains this")
    args = ap.parse_args()
    shapes = [
        ("rectangle 10x4", [np.array([(0, 0), (10, 0), (10, 4), (0, 4)], float)]),
        ("frame 10/2", [np.array([(0, 0), (10, 0), (10, 10), (0, 10)], float),
                        np.array([(2, 2), (2, 8), (8, 8), (8, 2)], float)]),
        ("L 10/8/2", [np.array([(0, 0), (10, 0), (10, 2), (2, 2), (2, 8), (0, 8)], float)]),
        ("star 5 (regular)", [np.round(star(5, 10.0, 4.0, 0.0, np.random.default_rng(1)), 3)]),
    ]
    pf = pocket_face()
    if pf is not None:
        shapes.append(("pocket_block top face", pf))
    sizes = (1000, 10000) if args.quick else (1000, 10000, 100000)
    for n in sizes:
        shapes.append((f"jittered star {n} + 16 holes", star_with_holes(n, 16, 7)))
    # near-cocircular rings (issue 22): a finely tessellated round face rounded to an
    # integer grid (turns from 1e-3 down to 1e-14 rad either way; integers, so Boost and
    # we see the same ring: on the 1e-3 grid, not exact in binary, a turn of 1e-14 may be
    # 0 for Boost, and a nearly flat convex corner has a long branch that a flat one has not)
    for n in ((10000,) if args.quick else (10000, 100000)):
        shapes.append((f"circle {n} (R {n}, integer grid)", [circle_on_grid(n, float(n))]))
    rows = []
    core.medial_axis(shapes[0][1], args.tol)       # load the library before timing
    shapes = [sh for sh in shapes if args.only in sh[0]]
    print(f"tolerance {args.tol:g}; best of {args.repeat}; "
          f"Path.Voronoi {'available' if medial_voronoi.available() else 'MISSING'}", flush=True)
    hdr = ("| shape | segments | ours C (ms) | ours binding (ms) | Boost construct (ms) | "
           "ratio | Boost + Python extraction (ms) | ours br/jn | Boost br/jn | "
           "ours->Boost | Boost->ours |")
    print(hdr)
    print("|" + "---|" * 11)
    for name, rings in shapes:
        r = run_shape(name, rings, args.tol, args.repeat, rows)
        b = r.get("boost")
        print("| %s | %d | %s | %s | %s | %s | %s | %d/%d | %s | %s | %s |" % (
            name, r["nseg"], fmt_ms(r["ours_c"]), fmt_ms(r["ours_py"]),
            fmt_ms(b) if b else "-", "%.2f" % (r["ours_c"] / b) if b else "-",
            fmt_ms(b + r["boost_extract"]) if b else "-", r["branches"], r["junctions"],
            "%d/%d" % (r["boost_branches"], r["boost_junctions"]) if b else "-",
            "%.2e" % r["ours_to_boost"] if b else "-", "%.2e" % r["boost_to_ours"] if b else "-"),
            flush=True)
    st = [r for r in rows if r["name"].startswith("jittered")]
    for a, c in zip(st, st[1:]):
        k = math.log(c["ours_c"] / a["ours_c"]) / math.log(c["nseg"] / a["nseg"])
        kb = (math.log(c["boost"] / a["boost"]) / math.log(c["nseg"] / a["nseg"])
              if "boost" in a else math.nan)
        print(f"growth {a['nseg']} -> {c['nseg']} segments: ours time ~ n^{k:.2f}, "
              f"Boost construct ~ n^{kb:.2f}")
    if args.only:
        return
    # growth with the tolerance (only the sampling of curved pieces depends on it)
    rings = star_with_holes(10000, 16, 7)
    print("\n| tolerance (10k star) | ours C (ms) | samples |")
    print("|---|---|---|")
    for tol in (1e-1, 1e-2, 1e-3, 1e-4, 1e-5):
        t = ours_c(rings, tol, max(1, args.repeat // 2))
        ax = core.medial_axis(rings, tol)
        print("| %g | %s | %d |" % (tol, fmt_ms(t), sum(len(b.radii) for b in ax.branches)),
              flush=True)


if __name__ == "__main__":
    main()
