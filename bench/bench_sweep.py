# SPDX-License-Identifier: LGPL-2.1-or-later
"""bench_sweep.py - times the rotational swept volume (issue 8 section 4): ours
(mfgeom.core.rotational_sweep on the part's tessellation) against what FreeCAD users do
today, multiFuse of N rotated copies (N = 12 and 36), on the same parts in one run, with
the volume of each against an independent reference; then the scaling of ours on a
tessellated torus of ~1k, ~10k and ~100k triangles.

Run with the system interpreter (FreeCAD's side runs in ``freecadcmd``):
    MFGEOM_LIBRARY=build/libmfgeom.so /usr/bin/python3 bench/bench_sweep.py
Options: --quick (no N = 36 fuse, torus ~1k and ~10k only), --no-fuse36, --fuse-timeout S
(each fuse runs in its own freecadcmd and is stopped after S s, default 600: it is then
reported as "> S s" and its speed-up as a lower bound).
Prints a Markdown table (bench/run.sh collects it into bench/results.md).

Three stages, three processes:
  1. freecadcmd (MFGEOM_BENCH_SWEEP_CHILD set): builds the parts, tessellates them (timed)
     and saves each mesh as .npz; then per part and N, one freecadcmd
     (MFGEOM_BENCH_SWEEP_FUSE set) runs the multiFuse peer (timed alone, its Volume).
  2. per mesh, a fresh python (MFGEOM_BENCH_SWEEP_OURS set): times our library call alone
     (best of 3 below 1 s) and its peak memory (ru_maxrss growth over the call), checks the
     result with mfg_mesh_check_closed and computes its volume by the divergence theorem.
  3. the reference volume of every sweep, by `reference_volume` below: numpy only, no code
     shared with FreeCAD or libmfgeom.

The reference (the issue's membership rule, integrated): on the circle of radius r about
the axis at height h, the input solid O covers arcs whose ends are where the circle meets
the slice of O's boundary at h; the swept volume covers, on that circle, each arc [a, b]
turned by 0..theta, i.e. [a, b + theta].  So the covered angle is 2 pi minus, over the gaps
between O's arcs, max(0, gap - theta), and V = integral over h and r of r * covered(r, h),
by Gauss-Legendre between the integrand's breaks (see reference_volume), at two orders:
their difference is the stated uncertainty.  On planar parts it is exact to ~1e-10
relative (it reproduces the box's analytic volume, and pi / sqrt(3) for the cube spun
about its diagonal); on the tessellated torus to ~1e-4.
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

ANGLE_DEG = 90.0
TOLERANCE = 0.01            # mm, the issue's
TARGET_ARM_S = 0.5          # 9-face part at 90 deg, 0.01 mm
TARGET_RATIO = 100.0        # >= 100x faster than multiFuse of 36 copies
TARGET_10K_S = 2.0          # 10k triangles
FUSE_COPIES = (12, 36)
FUSE_TIMEOUT = 600.0        # s: a fuse still running then is reported as "> 600 s"
PLANAR_PARTS = ("arm", "box")
OURS_TIMEOUT = 300.0        # s per mesh (all its repeats)
OURS_MEMORY_FRACTION = 0.5  # of physical memory, as our child's address-space limit
BOX = (30.0, 20.0, 10.0)    # a x b x c, spun about its edge of length c (the z axis)
TORUS = (20.0, 6.0)         # major, minor radius; its own axis along x
TORUS_AXIS = ((3.0, 2.0, 0.0), (0.0, 0.0, 1.0))   # through the ring's hole and tube
TORUS_TARGETS = (1000, 10000, 100000)
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


# ------------------------------------------------------------------ the reference
def _frame(axis_dir):
    """Rows e1, e2, a: right-handed, a along the axis (angles grow counter-clockwise about a)."""
    a = np.asarray(axis_dir, dtype=np.float64)
    a = a / np.linalg.norm(a)
    helper = np.array([1.0, 0.0, 0.0]) if abs(a[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    e1 = np.cross(a, helper)
    e1 /= np.linalg.norm(e1)
    return np.stack([e1, np.cross(a, e1), a])


def _slice_segments(tri, h):
    """The segments (k, 2, 2) in which the plane w = h cuts the triangles (T, 3, 3) in
    axis coordinates (u, v, w): per crossing triangle its two edges that change side."""
    above = tri[:, :, 2] > h
    n_above = above.sum(axis=1)
    t = tri[(n_above == 1) | (n_above == 2)]
    above = t[:, :, 2] > h
    pts = []
    for i, j in ((0, 1), (1, 2), (2, 0)):
        m = above[:, i] != above[:, j]
        wi, wj = t[:, i, 2], t[:, j, 2]
        f = np.where(m, (h - wi) / np.where(m, wj - wi, 1.0), np.nan)
        pts.append(t[:, i, :2] + f[:, None] * (t[:, j, :2] - t[:, i, :2]))
    p = np.stack(pts, axis=1)                      # (k, 3, 2), one row NaN per triangle
    ok = ~np.isnan(p[:, :, 0])
    order = np.argsort(~ok, axis=1, kind="stable")[:, :2]
    return np.take_along_axis(p, order[:, :, None], axis=1)


def _covered_angle(seg, radii, theta):
    """Per radius: the angle of its circle (about the origin, in the slice plane) that the
    slice's region, turned counter-clockwise by 0..theta, covers."""
    a, d = seg[:, 0], seg[:, 1] - seg[:, 0]
    qa = np.einsum("ij,ij->i", d, d)
    qb = np.einsum("ij,ij->i", a, d)
    qc = np.einsum("ij,ij->i", a, a)[None, :] - radii[:, None] ** 2     # (R, E)
    disc = qb[None, :] ** 2 - qa[None, :] * qc
    good = (disc >= 0) & (qa[None, :] > 0)
    root = np.sqrt(np.where(good, disc, 0.0))
    angles = []
    for sgn in (-1.0, 1.0):
        s = (-qb[None, :] + sgn * root) / np.where(qa > 0, qa, 1.0)[None, :]
        hit = good & (s >= 0) & (s < 1)          # half-open: a shared end counts once
        x = a[None, :, 0] + s * d[None, :, 0]
        y = a[None, :, 1] + s * d[None, :, 1]
        angles.append(np.where(hit, np.arctan2(y, x), np.inf))
    ang = np.sort(np.concatenate(angles, axis=1), axis=1)        # (R, 2E), inf last
    n = np.isfinite(ang).sum(axis=1)
    two_pi = 2.0 * math.pi
    # Is the arc after the first crossing inside?  Parity of a ray from its midpoint.
    first = np.where(n > 0, ang[:, 0], 0.0)
    second = np.where(n > 1, ang[:, np.minimum(1, ang.shape[1] - 1)], first + two_pi)
    mid = 0.5 * (first + second)
    px, py = radii * np.cos(mid), radii * np.sin(mid)
    inside = _inside_2d(seg, px, py)
    covered = np.where(inside, two_pi, 0.0)                      # no crossing at all
    rows = np.nonzero(n > 0)[0]
    if len(rows):
        s = ang[rows]
        k = np.arange(s.shape[1])[None, :]
        nn = n[rows][:, None]
        nxt = np.roll(s, -1, axis=1)
        last = nn - 1
        np.put_along_axis(nxt, last, s[:, :1] + two_pi, axis=1)
        with np.errstate(invalid="ignore"):                      # inf - inf past the n-th
            length = nxt - s                                      # arc k: crossing k to k+1
        arc_inside = (k % 2 == 0) == inside[rows][:, None]
        gap = (k < nn) & ~arc_inside
        lost = np.where(gap, np.maximum(0.0, np.where(gap, length, 0.0) - theta), 0.0)
        covered[rows] = two_pi - lost.sum(axis=1) if theta < two_pi else two_pi
    return covered


def _inside_2d(seg, px, py):
    """Crossing-number parity of the points against the closed set of segments."""
    (x0, y0), (x1, y1) = seg[:, 0].T, seg[:, 1].T
    out = np.zeros(len(px), dtype=bool)
    step = max(1, 2_000_000 // max(1, len(seg)))
    for s in range(0, len(px), step):
        X, Y = px[s:s + step, None], py[s:s + step, None]
        straddle = (y0[None] > Y) != (y1[None] > Y)
        xc = x0[None] + (Y - y0[None]) * (x1 - x0)[None] / np.where(y1 != y0, y1 - y0, 1.0)[None]
        out[s:s + step] = (np.count_nonzero(straddle & (xc > X), axis=1) % 2) == 1
    return out


def _gauss_nodes(breaks, n, pieces):
    """Nodes and weights integrating over [breaks[0], breaks[-1]]: per interval [a, b]
    between consecutive breaks, x = a + (b - a) (3 u^2 - 2 u^3) (flat at both ends, so a
    sqrt onset at either end, e.g. where a circle starts to cut a segment's line, becomes
    smooth in u) with u in ``pieces`` equal parts of [0, 1], n Gauss-Legendre nodes each."""
    g, gw = np.polynomial.legendre.leggauss(n)
    u = ((np.arange(pieces)[:, None] + (g[None, :] + 1) / 2) / pieces).ravel()
    uw = np.tile(gw / (2 * pieces), pieces)
    a, b = np.asarray(breaks[:-1])[:, None], np.asarray(breaks[1:])[:, None]
    return ((a + (b - a) * (3 * u ** 2 - 2 * u ** 3)).ravel(),
            ((b - a) * 6 * u * (1 - u) * uw).ravel())


def reference_volume(vertices, triangles, axis_point, axis_dir, theta, n):
    """Volume swept by the closed mesh turning by 0..theta (< 2 pi) about the axis: the
    exact covered angle per circle, integrated over heights and radii.  In r, per slice,
    Gauss-Legendre between its breaks (n nodes x 4 pieces per interval; x 1 piece above
    100 segments).  In h, Gauss-Legendre the same way between the vertex heights when
    there are at most 64 of them (planar parts: the integrand is smooth between them),
    with 1 piece up to 1000 of them, else on 64 equal intervals of n nodes."""
    frame = _frame(axis_dir)
    loc = (np.asarray(vertices, dtype=np.float64) - np.asarray(axis_point)) @ frame.T
    tri = loc[np.asarray(triangles, dtype=np.int64)]
    rmax = float(np.sqrt((loc[:, 0] ** 2 + loc[:, 1] ** 2).max())) * (1 + 1e-9)
    heights = np.unique(loc[:, 2])
    # heights a rounding apart (a planar face tessellated with 10 and 10 + 2e-15) are one:
    # a slice between them would cut that face's triangles into open scraps
    span = heights[-1] - heights[0]
    heights = heights[np.concatenate([[True], np.diff(heights) > 1e-9 * span])]
    heights[-1] = loc[:, 2].max()
    if len(heights) <= 1000:     # smooth between vertex heights
        zs, zw = _gauss_nodes(heights, n, 4 if len(heights) <= 64 else 1)
    else:                        # 64 equal intervals, kinks between nodes
        zs, zw = _gauss_nodes(np.linspace(heights[0], heights[-1], 65), n, 1)
    total = 0.0
    for h, wz in zip(zs, zw):
        seg = _slice_segments(tri, h)
        if not len(seg):
            continue
        # breaks in r: the radii of the segments' ends and of the feet of the
        # perpendiculars from the axis (where a circle starts to cut a segment twice)
        p, d = seg[:, 0], seg[:, 1] - seg[:, 0]
        dd = np.einsum("ij,ij->i", d, d)
        f = np.clip(-np.einsum("ij,ij->i", p, d) / np.where(dd > 0, dd, 1.0), 0, 1)
        foot = np.hypot(*(p + f[:, None] * d).T)
        ends = np.hypot(*seg.reshape(-1, 2).T)
        radii, rw = _gauss_nodes(np.unique(np.concatenate([[0.0, rmax], foot, ends])),
                                 n, 4 if len(seg) < 100 else 1)
        total += float(np.sum(rw * radii * _covered_angle(seg, radii, theta))) * wz
    return total


def mesh_volume(vertices, triangles):
    """Divergence theorem: the signed volume of a closed, outward triangle mesh."""
    v = np.asarray(vertices, dtype=np.float64)
    t = np.asarray(triangles, dtype=np.int64)
    return float(np.einsum("ij,ij->i", v[t[:, 0]], np.cross(v[t[:, 1]], v[t[:, 2]])).sum() / 6)


# ------------------------------------------------------------------ inside freecadcmd
def _fc_mesh(mesh):
    p, f = mesh.Topology
    return (np.array([(q.x, q.y, q.z) for q in p], dtype=np.float64),
            np.array(f, dtype=np.int64))


def _planar_part(name):
    """(shape, (axis point, axis direction), exact volume or None, description)."""
    import Part
    sys.path.insert(0, os.path.join(ROOT, "examples", "parts"))
    import sweep_arm
    if name == "arm":
        return (sweep_arm.make(), (sweep_arm.AXIS_POINT, sweep_arm.AXIS_DIR), None,
                "9-face stepped crank arm (examples/parts/sweep_arm.py) about its hub axis")
    a, b, c = BOX
    theta = math.radians(ANGLE_DEG)
    return (Part.makeBox(a, b, c), ((0.0, 0.0, 0.0), (0.0, 0.0, 1.0)),
            c * (a * b + (a * a + b * b) * theta / 2),
            f"box {a:g} x {b:g} x {c:g} about its {c:g} mm edge")


def _fuse(name, n, out):
    """What users do: multiFuse of n copies turned by angle * k / (n - 1), k = 0 .. n-1."""
    import FreeCAD as App
    shape, (axis_point, axis_dir), _, _ = _planar_part(name)
    copies = []
    for k in range(n):
        c = shape.copy()
        c.rotate(App.Vector(*axis_point), App.Vector(*axis_dir), ANGLE_DEG * k / (n - 1))
        copies.append(c)
    t0 = time.perf_counter()
    fused = copies[0].multiFuse(copies[1:])
    t = time.perf_counter() - t0
    with open(out, "w") as f:
        json.dump({"n": n, "s": t, "volume": fused.Volume, "valid": fused.isValid(),
                   "solids": len(fused.Solids), "faces": len(fused.Faces)}, f)


def _child(outdir, quick):
    import FreeCAD as App
    import MeshPart
    import Part

    cases = []
    for name in PLANAR_PARTS:
        shape, axis, exact, what = _planar_part(name)     # fresh: no cached triangulation
        t0 = time.perf_counter()
        p, f = shape.tessellate(TOLERANCE)
        t_tess = time.perf_counter() - t0
        v = np.array([(q.x, q.y, q.z) for q in p], dtype=np.float64)
        t = np.array(f, dtype=np.int64)
        np.savez(os.path.join(outdir, name + ".npz"), vertices=v, triangles=t)
        cases.append({"name": name, "what": what, "faces": len(shape.Faces),
                      "volume_part": shape.Volume, "tess_s": t_tess, "axis": axis,
                      "exact": exact, "fuses": [], "triangles": len(t), "kind": "peer"})
    for target in TORUS_TARGETS[:2] if quick else TORUS_TARGETS:
        shape = Part.makeTorus(TORUS[0], TORUS[1], App.Vector(0, 0, 0), App.Vector(1, 0, 0))
        t0 = time.perf_counter()
        # ~250 / target: 0.025 mm gives 9996 triangles on this torus (FreeCAD 0.20.2)
        mesh = MeshPart.meshFromShape(Shape=shape, LinearDeflection=250.0 / target,
                                      AngularDeflection=1.0, Relative=False)
        t_tess = time.perf_counter() - t0
        v, t = _fc_mesh(mesh)
        name = f"torus{target}"
        np.savez(os.path.join(outdir, name + ".npz"), vertices=v, triangles=t)
        cases.append({"name": name, "what": f"torus R {TORUS[0]:g}, r {TORUS[1]:g}, "
                      f"deflection {250.0 / target:g} mm", "faces": len(shape.Faces),
                      "volume_part": shape.Volume, "tess_s": t_tess, "axis": TORUS_AXIS,
                      "exact": None, "fuses": [], "triangles": len(t), "kind": "scaling"})
    with open(os.path.join(outdir, "cases.json"), "w") as f:
        json.dump({"cases": cases, "freecad": ".".join(App.Version()[:3])}, f)


# ------------------------------------------------------------------ ours, in a fresh python
def _ours(npz, axis_point, axis_dir, out):
    from mfgeom import core
    data = np.load(npz)
    v, t = data["vertices"], data["triangles"]
    core.mesh_check(v, t, require_closed=True)           # the input is a closed solid
    theta = math.radians(ANGLE_DEG)
    rss0 = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    times = []
    while len(times) < 3 and sum(times) < 1.0:
        res = None                                       # the previous result is freed
        t0 = time.perf_counter()
        res = core.rotational_sweep(v, t, axis_point, axis_dir, theta, TOLERANCE)
        times.append(time.perf_counter() - t0)
    rss1 = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    rv, rt = np.asarray(res.vertices), np.asarray(res.triangles)
    try:
        core.mesh_check(rv, rt, require_closed=True)
        closed = "yes"
    except core.MfgError as exc:
        closed = f"NO: {exc}"
    row = {"s": min(times), "runs": len(times), "volume": float(res.volume),
           "volume_mesh": mesh_volume(rv, rt), "triangles": int(len(rt)),
           "vertices": int(len(rv)), "peak_mb": (rss1 - rss0) / 1024.0, "closed": closed,
           "library": core.version()}
    with open(out, "w") as f:
        json.dump(row, f)


# ------------------------------------------------------------------ driver
def _rel(x, ref):
    return "n/a" if x is None or ref is None else f"{(x - ref) / ref:+.2e}"


def main():
    import argparse
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true",
                    help="no N = 36 fuse, torus ~1k and ~10k triangles only")
    ap.add_argument("--no-fuse36", action="store_true",
                    help="skip the N = 36 fuse (minutes; see --fuse-timeout)")
    ap.add_argument("--fuse-timeout", type=float, default=FUSE_TIMEOUT,
                    help=f"seconds per fuse before it is stopped (default {FUSE_TIMEOUT:g})")
    args = ap.parse_args()
    fuse36 = not (args.quick or args.no_fuse36)
    env = dict(os.environ)
    env.setdefault("MFGEOM_LIBRARY", os.path.join(ROOT, "build", "libmfgeom.so"))
    env["PYTHONPATH"] = os.path.join(ROOT, "workbench")
    title = "## Rotational swept volume (bench_sweep.py)\n"
    with tempfile.TemporaryDirectory(prefix="mfgeom-bench-sweep-") as tmp:
        cenv = dict(env, MFGEOM_BENCH_SWEEP_CHILD=tmp,
                    MFGEOM_BENCH_SWEEP_QUICK=str(int(args.quick)))
        log = os.path.join(tmp, "log.txt")
        with open(log, "w") as f:
            subprocess.run(["timeout", "3600", "freecadcmd", os.path.abspath(__file__)],
                           env=cenv, stdout=f, stderr=subprocess.STDOUT, check=False)
        try:
            with open(os.path.join(tmp, "cases.json")) as f:
                meta = json.load(f)
        except (OSError, ValueError):
            with open(log, errors="replace") as f:
                sys.stderr.write(f.read()[-4000:])
            print(title + "\n(the measurement in freecadcmd failed: see stderr)")
            return 1
        theta = math.radians(ANGLE_DEG)
        failed = False
        for case in meta["cases"]:      # the peers first: one at a time, nothing else running
            for n in FUSE_COPIES if case["kind"] == "peer" else ():
                if n == 36 and not fuse36:
                    continue
                case["fuses"].append(_run_fuse(case["name"], n, env, tmp, args.fuse_timeout))
                print(f"bench_sweep: {case['name']} multiFuse N = {n}: {case['fuses'][-1]}",
                      file=sys.stderr, flush=True)
        for case in meta["cases"]:
            npz = os.path.join(tmp, case["name"] + ".npz")
            out = os.path.join(tmp, case["name"] + ".ours.json")
            oenv = dict(env, MFGEOM_BENCH_SWEEP_OURS=json.dumps([npz] + list(case["axis"]) + [out]))
            try:
                r = subprocess.run([sys.executable, os.path.abspath(__file__)], env=oenv,
                                   capture_output=True, text=True, check=False,
                                   timeout=OURS_TIMEOUT, preexec_fn=_cap_memory)
            except subprocess.TimeoutExpired:
                r = subprocess.CompletedProcess([], 1, "", f"stopped after {OURS_TIMEOUT:g} s")
            if r.returncode != 0 or not os.path.exists(out):
                sys.stderr.write(f"bench_sweep: ours failed on {case['name']} (exit status "
                                 f"{r.returncode}):\n{r.stderr[-3000:]}\n")
                case["ours"], case["ours_error"] = None, (r.stderr.strip().splitlines()
                                                          or [f"exit status {r.returncode}"])[-1]
                failed = True
            else:
                with open(out) as f:
                    case["ours"] = json.load(f)
            data = np.load(npz)
            # the reference at two resolutions (the finer one reported, the gap its
            # uncertainty)
            fine = 8 if case["kind"] == "peer" else 4
            t0 = time.perf_counter()
            refs = [reference_volume(data["vertices"], data["triangles"], *case["axis"],
                                     theta, n) for n in (fine, fine // 2)]
            case["reference"], case["reference_err"] = refs[0], abs(refs[0] - refs[1])
            case["reference_s"] = time.perf_counter() - t0
            print(f"bench_sweep: {case['name']}: reference {refs} "
                  f"({case['reference_s']:.1f} s)", file=sys.stderr, flush=True)
    _print(meta, fuse36, args.quick)
    return 1 if failed else 0


def _cap_memory():
    """Our call's child gets at most OURS_MEMORY_FRACTION of the machine's memory as
    address space: past it the library's allocations fail and it reports
    MFG_ERR_NOMEM (shown in the table), instead of the kernel's OOM killer picking a
    process, possibly not ours."""
    total = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    cap = int(total * OURS_MEMORY_FRACTION)
    resource.setrlimit(resource.RLIMIT_AS, (cap, cap))


def _run_fuse(name, n, env, tmp, timeout):
    """The multiFuse of n copies in its own freecadcmd, stopped after ``timeout`` s
    (then {"n", "s": timeout, "timed_out": True})."""
    out = os.path.join(tmp, f"{name}.fuse{n}.json")
    fenv = dict(env, MFGEOM_BENCH_SWEEP_CHILD=tmp,
                MFGEOM_BENCH_SWEEP_FUSE=json.dumps([name, n, out]))
    t0 = time.perf_counter()
    with open(os.path.join(tmp, f"fuse{n}.log"), "w") as log:
        subprocess.run(["timeout", "--kill-after=10", str(int(timeout)), "freecadcmd",
                        os.path.abspath(__file__)],
                       env=fenv, stdout=log, stderr=subprocess.STDOUT, check=False)
    if os.path.exists(out):
        with open(out) as f:
            return json.load(f)
    return {"n": n, "s": time.perf_counter() - t0, "timed_out": True}


def _print(meta, fuse36, quick):
    cases = meta["cases"]
    lib = next((c["ours"]["library"] for c in cases if c.get("ours")), "?")
    load = " / ".join(f"{x:.1f}" for x in os.getloadavg())
    print("## Rotational swept volume (bench_sweep.py)\n")
    print(f"Sweep by {ANGLE_DEG:g} deg, tolerance {TOLERANCE:g} mm; ours = "
          f"mfgeom.core.rotational_sweep (libmfgeom {lib}) on the part's tessellation, in a "
          "fresh python (library call only; best of 3 below 1 s; tessellation timed "
          f"apart, in freecadcmd / FreeCAD {meta['freecad']}); peer = FreeCAD's "
          "Shape.multiFuse of N copies turned by angle * k / (N - 1), k = 0 .. N-1 (the "
          "union users build today), timed alone, its Shape.Volume. Reference = the "
          "exact covered angle on each circle about the axis, integrated by Gauss-Legendre "
          "between the breaks of the integrand (numpy, independent of both; +- = the gap "
          "to the same rule with half the nodes); for the box also the analytic volume. Errors are (V - V_ref) / V_ref: ours "
          "must be >= 0 (conservative), the fuse is below (it misses the material "
          f"between copies). Load average at the end: {load} on {os.cpu_count()} CPUs.\n")
    print("| part | faces / triangles in | tessellation s | method | time s | peer time / ours "
          "(speed-up) | volume mm^3 | error vs reference | error vs exact | result |")
    print("|---|---:|---:|---|---:|---:|---:|---:|---:|---|")
    targets = []
    for c in (c for c in cases if c["kind"] == "peer"):
        o = c.get("ours")
        ref, exact = c["reference"], c["exact"]
        head = f"| {c['name']} | {c['faces']} / {c['triangles']} | {c['tess_s']:.3f} "
        refcell = f"{ref:.3f} +- {c['reference_err']:.1g}"
        print(head + f"| reference | {c['reference_s']:.1f} | | {refcell} | | "
              f"{_rel(ref, exact)} | |")
        if exact is not None:
            print(f"| {c['name']} | | | exact (analytic) | | | {exact:.3f} | | | |")
        if o:
            print(f"| {c['name']} | | | ours | {o['s']:.4f} | 1 | {o['volume']:.3f} | "
                  f"{_rel(o['volume'], ref)} | {_rel(o['volume'], exact)} | "
                  f"{o['triangles']} triangles, closed: {o['closed']}; "
                  f"divergence volume {o['volume_mesh']:.2f} |")
        else:
            print(f"| {c['name']} | | | ours | failed: {c.get('ours_error')} | | | | | |")
        for fz in c["fuses"]:
            more = "> " if fz.get("timed_out") else ""
            ratio = f"{more}{fz['s'] / o['s']:.0f}x" if o else "n/a"
            if fz.get("timed_out"):
                print(f"| {c['name']} | | | multiFuse N = {fz['n']} | > {fz['s']:.0f} | "
                      f"{ratio} | | | | stopped unfinished after {fz['s']:.0f} s |")
                continue
            print(f"| {c['name']} | | | multiFuse N = {fz['n']} | {fz['s']:.2f} | {ratio} | "
                  f"{fz['volume']:.2f} | {_rel(fz['volume'], ref)} | "
                  f"{_rel(fz['volume'], exact)} | {fz['faces']} faces, "
                  f"{fz['solids']} solid(s), valid {fz['valid']} |")
        if o:
            ok = o["volume"] >= ref - c["reference_err"] - 1e-9 * ref
            targets.append((f"{c['name']}: ours {o['volume']:.3f} >= reference {ref:.3f} "
                            f"(conservative)", ok))
            if exact is not None:
                targets.append((f"{c['name']}: ours {o['volume']:.3f} >= exact "
                                f"{exact:.3f}, excess {o['volume'] - exact:.3f} mm^3",
                                o["volume"] >= exact * (1 - 1e-12)))
        if c["name"] == "arm" and o:
            targets.append((f"9-face part at {ANGLE_DEG:g} deg, {TOLERANCE:g} mm in "
                            f"{o['s']:.3f} s (target < {TARGET_ARM_S:g} s)",
                            o["s"] < TARGET_ARM_S))
            f36 = [fz for fz in c["fuses"] if fz["n"] == 36]
            if f36:
                ratio = f36[0]["s"] / o["s"]     # a lower bound when the fuse was stopped
                more = "more than " if f36[0].get("timed_out") else ""
                targets.append((f"9-face part: {more}{ratio:.0f}x faster than multiFuse "
                                f"N = 36 (target >= {TARGET_RATIO:g}x)", ratio >= TARGET_RATIO))
    print("\n### Scaling: tessellated torus (R 20, r 6 mm, its axis along x) swept "
          f"{ANGLE_DEG:g} deg about the z axis through {TORUS_AXIS[0]} (through its hole "
          "and tube)\n")
    print("Peak memory = growth of ru_maxrss over the calls (the input mesh already "
          "loaded). Growth exponent = log(t2/t1) / log(n2/n1) between consecutive "
          "sizes. The reference is the swept volume of the tessellated torus (the input "
          "mesh).\n")
    print("| triangles in | tessellation s | ours s | runs | result triangles | peak memory "
          "MB | growth exponent | volume mm^3 | error vs reference | result |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|")
    prev = None
    for c in (c for c in cases if c["kind"] == "scaling"):
        o = c.get("ours")
        if not o:
            print(f"| {c['triangles']} | {c['tess_s']:.3f} | failed: {c.get('ours_error')} "
                  "| | | | | | | |")
            prev = None
            continue
        grow = ""
        if prev:
            grow = f"{math.log(o['s'] / prev[1]) / math.log(c['triangles'] / prev[0]):.2f}"
        print(f"| {c['triangles']} | {c['tess_s']:.3f} | {o['s']:.4f} | {o['runs']} | "
              f"{o['triangles']} | {o['peak_mb']:.1f} | {grow} | {o['volume']:.2f} | "
              f"{_rel(o['volume'], c['reference'])} (+- {c['reference_err'] / c['reference']:.0e}) | "
              f"closed: {o['closed']} |")
        prev = (c["triangles"], o["s"])
        if 5000 <= c["triangles"] <= 20000:
            targets.append((f"{c['triangles']} triangles in {o['s']:.3f} s (target < "
                            f"{TARGET_10K_S:g} s)", o["s"] < TARGET_10K_S))
    if not fuse36:
        print("\n(multiFuse N = 36 skipped: " + ("--quick" if quick else "--no-fuse36") + ")")
    print("\n### Targets\n")
    for text, ok in targets:
        print(f"- {text}: {'MET' if ok else 'MISSED'}")
    print(f"\n{sum(ok for _, ok in targets)} of {len(targets)} targets met.")


if os.environ.get("MFGEOM_BENCH_SWEEP_CHILD"):
    # Run by freecadcmd as a script: measure, then leave.
    rc = 0
    try:
        if os.environ.get("MFGEOM_BENCH_SWEEP_FUSE"):
            _fuse(*json.loads(os.environ["MFGEOM_BENCH_SWEEP_FUSE"]))
        else:
            _child(os.environ["MFGEOM_BENCH_SWEEP_CHILD"],
                   bool(int(os.environ["MFGEOM_BENCH_SWEEP_QUICK"])))
    except Exception:  # reported in the log; the driver sees the missing result file
        import traceback
        traceback.print_exc()
        rc = 1
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(rc)
elif os.environ.get("MFGEOM_BENCH_SWEEP_OURS"):
    _npz, _point, _dir, _out = json.loads(os.environ["MFGEOM_BENCH_SWEEP_OURS"])
    _ours(_npz, _point, _dir, _out)
elif __name__ == "__main__":
    sys.exit(main())
