# SPDX-License-Identifier: LGPL-2.1-or-later
"""bench_medial.py - times the 3-D medial surface (issue 9 section 6; design section 8):
mfgeom.core.medial_surface on the analytic solids (cuboid, cube, square prism), the
L-bracket, the T-section, the 48-gon disc (50 faces), a generated ribbed tray (251 faces)
and a tessellated cup (examples/parts/cup.py revolved with 625 segments: 5000
triangles), each in a fresh python (time of the library call, peak memory), at a
tolerance of 0.5 % of the bounding-box diagonal; the published figures of the peers for
comparison; then the growth with the tolerance (1, 0.5, 0.25 % of the diagonal) and with
the number of disc facets (12, 48, 192).

Run with the system interpreter:
    MFGEOM_LIBRARY=build/libmfgeom.so /usr/bin/python3 bench/bench_medial.py [--quick]
        [--timeout S] [--threads N]
Prints a Markdown table (bench/run.sh collects it into bench/results.md).  A case whose
call fails shows the library's error message instead of its time.  After the timed
calls, each main case's result is checked by the independent oracle
(tests/python/medial_oracle.py; --no-check skips it): the largest |radius - distance to
the boundary| and the share of points touching too few elements on a sample, and the
share of the oracle's major medial probe points within the tolerance of the result.

The peers are not run here: their times are the figures their authors published --
Lee & Lee (seed 004), Table 3: 22 boundary elements 5-13 min, 51 elements 5 h 20 min
(elements = faces + edges + vertices); MAPC (exact medial axis of polyhedra): a 6-face
box 10 s, a 252-face part 3.8 h.  Ratios are peer time / ours on the case of about the
same size (different machines and years: indicative only).  The practical peer, run
here: bench/bench_medial_voronoi.py (boundary samples' inner Voronoi vertices, scipy).
"""

import json
import math
import os
import resource
import subprocess
import sys
import tempfile
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "tests", "python"))
import medial_solids as solids   # noqa: E402  (the test solids, one place)

TOL_FRAC = 0.005
TIMEOUT = 600.0                   # s per case
MEMORY_FRACTION = 0.5             # of physical memory, as each child's address-space limit
TARGETS = {"disc48": 1.0, "tray": 10.0, "cup": 60.0}   # s (issue: 50 faces, 250 faces, 5k)
# issue 22: (case, tolerance as a fraction of L) -> s
TARGETS_22 = {("cup", TOL_FRAC): 5.0, ("tray", TOL_FRAC): 2.0, ("box", 0.0001): 1.0,
              ("cup6250", TOL_FRAC): 60.0}

# name: (what, builder)
CASES = {
    "cuboid": ("cuboid 100 x 60 x 20", solids.cuboid),
    "cube": ("cube 40", solids.cube),
    "square_prism": ("square prism 20 x 20 x 100", solids.square_prism),
    "l_bracket": ("L-bracket 50 x 50 x 40, wall 10", solids.l_bracket),
    "t_section": ("T-section 60 x 60 x 40, wall 10", solids.t_section),
    "disc48": ("48-gon disc R 50, thickness 4", lambda: solids.ngon_disc(48)),
    "tray": ("ribbed tray 200 x 150 x 40, walls 3, 8 x 5 ribs", solids.ribbed_tray),
    "cup": ("cup R 20, h 30, wall 3 (examples/parts/cup.py), 625 segments", lambda: solids.cup(625)),
    "cup32": ("cup, 32 segments", lambda: solids.cup(32)),
    "cup125": ("cup, 125 segments", lambda: solids.cup(125)),
    "cup2500": ("cup, 2500 segments (20k triangles)", lambda: solids.cup(2500)),
    "cup6250": ("cup, 6250 segments (50k triangles)", lambda: solids.cup(6250)),
    "cup25000": ("cup, 25000 segments (200k triangles)", lambda: solids.cup(25000)),
    "disc12": ("12-gon disc R 50, thickness 4", lambda: solids.ngon_disc(12)),
    "disc192": ("192-gon disc R 50, thickness 4", lambda: solids.ngon_disc(192)),
    "box": ("box 2 x 1 x 0.5 (12 triangles)", lambda: solids.cuboid(2.0, 1.0, 0.5)),
}
MAIN = ["cuboid", "cube", "square_prism", "l_bracket", "t_section", "disc48", "tray", "cup"]
FULL = ["l_bracket", "disc48", "tray"]            # also in full mode
TOL_GROWTH = [("l_bracket", f) for f in (0.01, 0.005, 0.0025)] + \
             [("tray", f) for f in (0.01, 0.005, 0.0025)] + \
             [("box", f) for f in (0.001, 0.0003, 0.0001)]   # issue 22: L/1000 .. L/10^4
FACET_GROWTH = ["disc12", "disc48", "disc192"]
CUP_GROWTH = ["cup32", "cup125", "cup"]
LARGE_CUP = ["cup2500", "cup6250", "cup25000"]   # --large: issue 22's real-part sizes
LARGE_MEMORY_MB = 2048.0                          # issue 22: 200k triangles in < 2 GB

# (peer, what, published time, seconds low, seconds high, our case to compare with)
PEERS = [
    ("Lee & Lee (seed 004), Table 3", "22 boundary elements", "5 - 13 min", 5 * 60, 13 * 60,
     "cuboid"),
    ("Lee & Lee (seed 004), Table 3", "51 boundary elements", "5 h 20 min",
     5 * 3600 + 20 * 60, 5 * 3600 + 20 * 60, "t_section"),
    ("MAPC", "6-face box", "10 s", 10, 10, "cuboid"),
    ("MAPC", "252 faces", "3.8 h", 3.8 * 3600, 3.8 * 3600, "tray"),
]


# ------------------------------------------------------------------ the child
def _call(core, v, t, tol, full, threads):
    kw = {"major_only": not full}
    if threads is not None:
        kw["threads"] = threads
    return core.medial_surface(v, t, tol, **kw)


def _raw_call(core, v, t, tol, full, threads):
    """Before the binding has medial_surface: the C entry point through ctypes, for its
    status and message (the result itself is only freed)."""
    import ctypes
    lib = core.load()
    f = lib.mfg_medial_surface
    f.restype = ctypes.c_int
    f.argtypes = [ctypes.POINTER(ctypes.c_double), ctypes.c_int64,
                  ctypes.POINTER(ctypes.c_int64), ctypes.c_int64, ctypes.c_double,
                  ctypes.c_uint32, ctypes.c_int32, ctypes.POINTER(ctypes.c_void_p)]
    v = np.ascontiguousarray(v, np.float64)
    t = np.ascontiguousarray(t, np.int64)
    out = ctypes.c_void_p()
    st = f(v.ctypes.data_as(ctypes.POINTER(ctypes.c_double)), len(v),
           t.ctypes.data_as(ctypes.POINTER(ctypes.c_int64)), len(t), tol, 1 if full else 0,
           threads or 0, ctypes.byref(out))
    core._check(st)
    lib.mfg_medial_free.argtypes = [ctypes.c_void_p]
    lib.mfg_medial_free(out)
    return None


def _child(spec, out):
    from mfgeom import core
    name, frac, full, threads, check = spec
    v, t = CASES[name][1]()
    L = float(np.linalg.norm(v.max(0) - v.min(0)))
    tol = frac * L
    call = _call if hasattr(core, "medial_surface") else _raw_call
    rss0 = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    times = []
    res = None
    row = {"library": core.version(), "L": L, "tol": tol, "triangles_in": int(len(t)),
           "binding": call is _call}
    try:
        while len(times) < 3 and sum(times) < 1.0:
            res = None
            t0 = time.perf_counter()
            res = call(core, v, t, tol, full, threads)
            times.append(time.perf_counter() - t0)
    except core.MfgError as exc:
        row["error"] = str(exc)
    rss1 = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    row.update({"s": min(times) if times else None, "runs": len(times),
                "peak_mb": (rss1 - rss0) / 1024.0})
    if res is not None:
        kinds = np.asarray(res.element_kinds)
        area = 0.0
        ntri = 0
        for s in res.sheets:
            x = np.asarray(s.vertices, float)[np.asarray(s.triangles, np.int64)]
            area += 0.5 * float(np.linalg.norm(np.cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0]),
                                               axis=1).sum())
            ntri += len(s.triangles)
        row.update({"faces": int((kinds == 2).sum()), "edges": int((kinds == 1).sum()),
                    "vertices": int((kinds == 0).sum()), "sheets": len(res.sheets),
                    "sheet_triangles": ntri, "sheet_area": area, "seams": len(res.seams),
                    "junctions": int(len(np.asarray(res.junctions.points).reshape(-1, 3))),
                    "cells": int(getattr(res, "cells_visited", -1)),
                    "leaves": int(getattr(res, "leaves", -1))})
        if check:
            t0 = time.perf_counter()
            row.update(_check_against_oracle(v, t, res, tol, full))
            row["check_s"] = time.perf_counter() - t0
    with open(out, "w") as f:
        json.dump(row, f)


def _check_against_oracle(v, t, res, tol, full, nsample=3000, nprobes=300):
    """Quality of the result by the independent oracle of tests/python/medial_oracle.py
    (not timed): on a seeded sample of sheet vertices and every seam point and junction,
    the largest |radius - distance to the boundary| and the share touching fewer
    elements than 2 / 3 / 4 (within 1e-6 L); of the oracle's medial probe points on the
    major part (full mode: all), the share within the tolerance of the result."""
    from medial_oracle import Polyhedron, distance_to_pieces, result_pieces
    P = Polyhedron(v, t)
    rng = np.random.default_rng(5)
    sv = [np.asarray(s.vertices, float).reshape(-1, 3) for s in res.sheets]
    sr = [np.asarray(s.radii, float) for s in res.sheets]
    X = np.concatenate(sv) if sv else np.zeros((0, 3))
    r = np.concatenate(sr) if sr else np.zeros(0)
    pick = rng.permutation(len(X))[:nsample]
    X, r = X[pick], r[pick]
    need = [np.full(len(X), 2)]
    for c in res.seams:
        X = np.concatenate([X, np.asarray(c.points, float).reshape(-1, 3)])
        r = np.concatenate([r, np.asarray(c.radii, float)])
        need.append(np.full(len(c.points), 3))
    J = np.asarray(res.junctions.points, float).reshape(-1, 3)
    X = np.concatenate([X, J])
    r = np.concatenate([r, np.asarray(res.junctions.radii, float)])
    need = np.concatenate(need + [np.full(len(J), 4)])
    out = {"checked_points": int(len(X))}
    if len(X):
        D = P.distance(X)
        T = P.touching(X, 1e-6 * P.diag, D=D)
        out["max_radius_error"] = float(np.abs(D - r).max())
        out["under_touching"] = float((T.sum(1) < need).mean())
    Xp, tstar, q, face = P.probes(nprobes, margin=2 * tol, seed=11, iters=54)
    if full:
        want = np.ones(len(Xp), bool)
    else:
        Tp = P.touching(Xp, 1e-6 * P.diag, D=tstar)
        want = np.array([P.is_major(row) for row in Tp])
    out["probes"] = int(want.sum())
    if want.any():
        d = distance_to_pieces(Xp[want], *result_pieces(res), tol)
        out["probes_within_tol"] = float((d <= tol).mean())
    return out


# ------------------------------------------------------------------ the driver
def _cap_memory():
    total = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    cap = int(total * MEMORY_FRACTION)
    resource.setrlimit(resource.RLIMIT_AS, (cap, cap))


def run_case(name, frac, full, threads, check, env, tmp, timeout):
    out = os.path.join(tmp, f"{name}-{frac}-{int(full)}.json")
    cenv = dict(env, MFGEOM_BENCH_MEDIAL_CHILD=json.dumps([[name, frac, full, threads, check],
                                                           out]))
    try:
        r = subprocess.run([sys.executable, os.path.abspath(__file__)], env=cenv,
                           capture_output=True, text=True, check=False, timeout=timeout,
                           preexec_fn=_cap_memory)
    except subprocess.TimeoutExpired:
        return {"error": f"stopped after {timeout:g} s", "s": None, "timed_out": True}
    if r.returncode != 0 or not os.path.exists(out):
        tail = (r.stderr.strip().splitlines() or [f"exit status {r.returncode}"])[-1]
        return {"error": f"child failed (exit {r.returncode}): {tail}", "s": None}
    with open(out) as f:
        return json.load(f)


def _elements(name):
    """Faces / edges / vertices of the merged polyhedron, from the independent oracle
    (so the table has them even when the library fails)."""
    from medial_oracle import Polyhedron
    P = Polyhedron(*CASES[name][1]())
    return P.nfaces, P.nedges, P.nverts


def _fmt_s(x):
    if x is None:
        return "-"
    return f"{x:.3f}" if x < 10 else f"{x:.1f}"


def _fmt_q(x, spec):
    return "-" if x is None else format(x, spec)


def main():
    import argparse
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true",
                    help="main table without the cup (no full mode, no growth series)")
    ap.add_argument("--timeout", type=float, default=TIMEOUT, help="seconds per case")
    ap.add_argument("--threads", type=int, default=None,
                    help="threads for the library (default: its own, all online CPUs)")
    ap.add_argument("--cases", default=None, help="comma-separated subset of the main cases")
    ap.add_argument("--large", action="store_true",
                    help="also the cup at 20k, 50k and 200k triangles (issue 22; ~15 min)")
    ap.add_argument("--no-check", action="store_true",
                    help="skip the oracle's quality check of the main cases (not timed)")
    args = ap.parse_args()
    env = dict(os.environ)
    env.setdefault("MFGEOM_LIBRARY", os.path.join(ROOT, "build", "libmfgeom.so"))
    env["PYTHONPATH"] = os.path.join(ROOT, "workbench")
    main_cases = (args.cases.split(",") if args.cases else
                  [n for n in MAIN if n != "cup"] if args.quick else MAIN)
    rows = {}
    with tempfile.TemporaryDirectory(prefix="mfgeom-bench-medial-") as tmp:
        todo = [(n, TOL_FRAC, False) for n in main_cases]
        if not args.quick:
            todo += [(n, TOL_FRAC, True) for n in FULL if n in main_cases]
            todo += [(n, f, False) for n, f in TOL_GROWTH
                     if n in main_cases or (n not in MAIN and not args.cases)]
            if not args.cases:  # --cases: those cases (and their tolerance growth) only
                todo += [(n, TOL_FRAC, False) for n in FACET_GROWTH]
                todo += [(n, TOL_FRAC, False) for n in CUP_GROWTH]
        if args.large:
            todo += [(n, TOL_FRAC, False) for n in CUP_GROWTH + LARGE_CUP]
        for key in todo:
            if key in rows:
                continue
            t0 = time.perf_counter()
            check = not args.no_check and key[1] == TOL_FRAC and key[0] in main_cases
            rows[key] = run_case(*key[:3], args.threads, check, env, tmp, args.timeout)
            rows[key].setdefault("triangles_in", int(len(CASES[key[0]][1]()[1])))
            print(f"bench_medial: {key}: {rows[key].get('s')} s "
                  f"({time.perf_counter() - t0:.1f} s wall) {rows[key].get('error', '')}",
                  file=sys.stderr, flush=True)
    elems = {n: _elements(n) for n in set(k[0] for k in rows)}
    _print(rows, elems, main_cases, args)
    return 0


def _print(rows, elems, main_cases, args):
    lib = next((r["library"] for r in rows.values() if r.get("library")), "?")
    load = " / ".join(f"{x:.1f}" for x in os.getloadavg())
    thr = args.threads if args.threads is not None else "default (online CPUs)"
    print("## Medial surface (bench_medial.py)\n")
    print(f"mfgeom.core.medial_surface (libmfgeom {lib}), tolerance {TOL_FRAC * 100:g} % of "
          f"the bounding-box diagonal L, major part unless marked full; threads: {thr}; "
          "each case in a fresh python, time of the library call alone (best of 3 below 1 s), "
          "peak memory = growth of ru_maxrss over the calls. Elements = faces / edges / "
          "vertices of the merged polyhedron. Load average at the end: "
          f"{load} on {os.cpu_count()} CPUs.\n")
    print("| case | triangles | elements (F / E / V = total) | mode | tolerance | time s | "
          "peak MB | sheets | sheet triangles | sheet area | seams | junctions | "
          "max abs(r - D) | under-touching | probes within tol | result |")
    print("|---|---:|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|")

    def line(name, frac, full):
        r = rows.get((name, frac, full))
        if r is None:
            return
        f, e, v = elems[name]
        tri = r.get("triangles_in", "")
        tol = f"{r['tol']:.4g}" if r.get("tol") else "-"
        mode = "full" if full else "major"
        if r.get("s") is None or r.get("error"):
            print(f"| {name} | {tri} | {f} / {e} / {v} = {f + e + v} | {mode} | {tol} | - | - | "
                  f"| | | | | | | | failed: {r.get('error')} |")
            return
        if "sheets" not in r:
            print(f"| {name} | {tri} | {f} / {e} / {v} = {f + e + v} | {mode} | {tol} | "
                  f"{_fmt_s(r['s'])} | {r['peak_mb']:.1f} | | | | | | | | | "
                  "ok (no binding to read it) |")
            return
        print(f"| {name} | {tri} | {f} / {e} / {v} = {f + e + v} | {mode} | {tol} | "
              f"{_fmt_s(r['s'])} | {r['peak_mb']:.1f} | {r['sheets']} | {r['sheet_triangles']} "
              f"| {r['sheet_area']:.1f} | {r['seams']} | {r['junctions']} | "
              f"{_fmt_q(r.get('max_radius_error'), '.1e')} | {_fmt_q(r.get('under_touching'), '.1%')} | "
              f"{_fmt_q(r.get('probes_within_tol'), '.1%')} of {r.get('probes', '-')} | "
              f"{CASES[name][0]}; {r['runs']} run(s) |")

    for n in main_cases:
        line(n, TOL_FRAC, False)
    for n in FULL:
        line(n, TOL_FRAC, True)

    print("\n### Published peer figures (not run here; cited as published)\n")
    print("| peer | input | published time | our case | ours s | peer / ours |")
    print("|---|---|---:|---|---:|---:|")
    for peer, what, published, lo, hi, ours in PEERS:
        r = rows.get((ours, TOL_FRAC, False), {})
        s = r.get("s") if not r.get("error") else None
        size = ("not run" if ours not in elems else
                f"{elems[ours][0]} faces, {sum(elems[ours])} elements")
        ratio = "-" if not s else (f"{lo / s:.3g}x" if lo == hi else f"{lo / s:.3g}x - {hi / s:.3g}x")
        print(f"| {peer} | {what} | {published} | {ours} ({size}) | {_fmt_s(s)} | {ratio} |")

    if not args.quick:
        print("\n### Growth with the tolerance\n")
        print("| case | tolerance % L | tolerance | time s | peak MB | sheet triangles | "
              "exponent vs 1/tolerance |")
        print("|---|---:|---:|---:|---:|---:|---:|")
        for name in sorted(set(n for n, _ in TOL_GROWTH)):
            prev = None
            for n, frac in TOL_GROWTH:
                if n != name or (n, frac, False) not in rows:
                    continue
                r = rows[(n, frac, False)]
                if r.get("error") or r.get("s") is None:
                    print(f"| {n} | {frac * 100:g} | | failed: {r.get('error')} | | | |")
                    prev = None
                    continue
                ex = ""
                if prev:
                    ex = f"{math.log(r['s'] / prev[1]) / math.log(prev[0] / frac):.2f}"
                print(f"| {n} | {frac * 100:g} | {r['tol']:.4g} | {_fmt_s(r['s'])} | "
                      f"{r['peak_mb']:.1f} | {r.get('sheet_triangles', '')} | {ex} |")
                prev = (frac, r["s"])
        print("\n### Growth with the disc's facets (tolerance 0.5 % L)\n")
        print("| facets | faces | time s | peak MB | seams | junctions | exponent vs faces |")
        print("|---:|---:|---:|---:|---:|---:|---:|")
        prev = None
        for n in FACET_GROWTH:
            r = rows.get((n, TOL_FRAC, False))
            if r is None:
                continue
            f = elems[n][0]
            if r.get("error") or r.get("s") is None:
                print(f"| {n[4:]} | {f} | failed: {r.get('error')} | | | | |")
                prev = None
                continue
            ex = f"{math.log(r['s'] / prev[1]) / math.log(f / prev[0]):.2f}" if prev else ""
            print(f"| {n[4:]} | {f} | {_fmt_s(r['s'])} | {r['peak_mb']:.1f} | "
                  f"{r.get('seams', '')} | {r.get('junctions', '')} | {ex} |")
            prev = (f, r["s"])

        print("\n### Growth with the cup's segments (tolerance 0.5 % L)\n")
        print("| segments | triangles | faces | time s | peak MB | sheets | seams | junctions | "
              "exponent vs triangles |")
        print("|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
        prev = None
        for n in CUP_GROWTH + LARGE_CUP:
            r = rows.get((n, TOL_FRAC, False))
            if r is None:
                continue
            seg = n[3:] or "625"
            f = elems[n][0]
            tri = r.get("triangles_in", "")
            if r.get("error") or r.get("s") is None:
                print(f"| {seg} | {tri} | {f} | failed: {r.get('error')} | | | | | |")
                prev = None
                continue
            ex = (f"{math.log(r['s'] / prev[1]) / math.log(tri / prev[0]):.2f}"
                  if prev else "")
            print(f"| {seg} | {tri} | {f} | {_fmt_s(r['s'])} | {r['peak_mb']:.1f} | "
                  f"{r.get('sheets', '')} | {r.get('seams', '')} | {r.get('junctions', '')} | {ex} |")
            prev = (tri, r["s"])

    print("\n### Targets (issue 9 section 6)\n")
    met = 0
    total = 0
    for name, target in TARGETS.items():
        r = rows.get((name, TOL_FRAC, False))
        if r is None:
            continue
        total += 1
        s = None if r.get("error") else r.get("s")
        ok = s is not None and s < target
        met += ok
        what = {"disc48": "50 faces", "tray": "250 faces", "cup": "5k triangles"}[name]
        print(f"- {what} ({name}) in {_fmt_s(s)} s (target < {target:g} s): "
              f"{'MET' if ok else 'MISSED'}")
    print(f"\n{met} of {total} targets met.")
    print("\n### Targets (issue 22)\n")
    for (name, frac), target in TARGETS_22.items():
        r = rows.get((name, frac, False))
        if r is None:
            continue
        s = None if r.get("error") else r.get("s")
        ok = s is not None and s < target
        print(f"- {CASES[name][0]} at tolerance {frac * 100:g} % L in {_fmt_s(s)} s, "
              f"{r.get('peak_mb', float('nan')):.0f} MB (target < {target:g} s): "
              f"{'MET' if ok else 'MISSED'}")
    r = rows.get((LARGE_CUP[-1], TOL_FRAC, False))
    if r is not None:
        mb = float("nan") if r.get("error") else r.get("peak_mb", float("nan"))
        print(f"- {CASES[LARGE_CUP[-1]][0]} completes in {_fmt_s(r.get('s'))} s with "
              f"{mb:.0f} MB (target: completes, < {LARGE_MEMORY_MB:g} MB): "
              f"{'MET' if mb < LARGE_MEMORY_MB else 'MISSED'}")


if os.environ.get("MFGEOM_BENCH_MEDIAL_CHILD"):
    _spec, _out = json.loads(os.environ["MFGEOM_BENCH_MEDIAL_CHILD"])
    _child(_spec, _out)
elif __name__ == "__main__":
    sys.exit(main())
