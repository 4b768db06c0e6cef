# SPDX-License-Identifier: LGPL-2.1-or-later
"""bench_sweep.py - the rotational sweep benchmark of issue 20: ours
(mfgeom.core.rotational_sweep) against three peers on the same triangle meshes in one run,
with an independent reference volume, the issue's lower bound on the output size, and a
conservativeness check of every result.

    MFGEOM_LIBRARY=build/libmfgeom.so /usr/bin/python3 bench/bench_sweep.py [options]

    --quick                  arm-90 and box-90, N = 12 only (< 1 min once cached)
    --cases a,b,...          the cases to run (default: all but nut50k-360; see --list)
    --peers fuse,cgal,vdb    the peers to run (default all three; "none" for ours alone)
    --copies 12,36           the N of the peers' unions of turned copies
    --timeout S              per run of ours and of each peer (default 300 s)
    --mem-gb G               address-space cap per run (default 8 GB): past it the run
                             fails to allocate and is reported "oom"
    --no-skip                run a peer even where a smaller run of it timed out
    --refresh                rebuild the cached meshes, references and lower bounds
    --list                   the cases, their inputs and axes

Prints Markdown (bench/run.sh collects it into bench/results.md); progress on stderr.
/usr/bin/python3 is needed (numpy); FreeCAD's freecadcmd, the CGAL program
build-bench/bench/bench_sweep_cgal (built here with cmake if missing) and python3-openvdb
are used for the peers and the checker.

THE CASES (tolerance 0.01 mm for all; sizes = bounding boxes):
  arm-90       the 9-face stepped crank arm (examples/parts/sweep_arm.py, 90 x 38 x 10 mm)
               about its hub axis (the z axis through (8, 8, 0)), 90 degrees
  box-90       a 30 x 20 x 10 mm box about its 10 mm edge (the z axis), 90 degrees
  torusNk-A    a torus R 20, r 6 mm (52 x 52 x 12 mm) with its own axis along x,
               tessellated by FreeCAD's MeshPart (linear deflection 0.25 / 0.025 / 0.0025
               mm: ~1k / 10k / 100k triangles), turned A = 90 or 360 degrees about the z
               axis through (3, 2, 0): perpendicular to the torus's axis, through its hole
               and, near z = +-20, through its tube, so every part of it sweeps a different
               surface (the first design's benchmark used this axis too)
  nut50k-90    a real part: the pump nut of Open CASCADE's samples (tests/corpus/Pump_Nut.
               brep.gz, LGPL-2.1 with the OCCT exception, tests/corpus/LICENSES.md; 60 x
               15 x 60 mm, 25 faces: cones, tori, planes), tessellated by MeshPart at 0.003
               mm / 0.1 rad (~48k triangles), turned 90 degrees about a tilted axis through
               a point 15 mm from its centre (direction (0.2, 1, 0.3), its own axis is y).
               nut50k-360: the same about the same axis by 360 degrees (not by default).
Meshes are cached in bench/sweep-cache/ (gitignored) with the references and lower bounds.

OURS: core.rotational_sweep in a fresh /usr/bin/python3 (the library call alone timed, best
of 3 when under 1 s); memory = the child's peak RSS (python, numpy and the input included).

THE PEERS, each in its own process, timed around the union alone (inputs built first):
  fuse   FreeCAD's Shape.multiFuse of N copies turned by theta k / (N - 1), k = 0..N-1
         (360 degrees: 2 pi k / N) - what FreeCAD users do today.  On the arm and the box
         the B-rep (its faces are planar: the same geometry as the mesh); on the others a
         solid built from the mesh (one planar face per triangle).  Result: its
         tessellation (exact, every face is planar).
  cgal   CGAL 5.5's Polygon_mesh_processing::corefine_and_compute_union of the same N
         copies, in a balanced tree of pairs (neighbouring copies first), kernel
         Exact_predicates_exact_constructions_kernel (bench/bench_sweep_cgal.cpp; with the
         inexact-constructions kernel the chained unions crash on the 1k torus).
  vdb    OpenVDB 10 (python3-openvdb): one narrow-band level set (half width 3 voxels) of
         the N copies together (createLevelSetFromPolygons; the sign by its flood fill, so
         overlapping closed copies give their union), mesh extracted at iso value 0
         (convertToPolygons, adaptivity 0, quads split in two).  Voxel size: tol, or the
         finest that a pilot run (voxel = size / 150) predicts to fit half the memory cap
         and --vdb-seconds (default 60 s, --quick 5 s; memory and time taken to grow as
         1/h^2): the voxel size is printed (it is never tol on these parts: a 0.01 mm band
         over a torus's copies needs tens of GB).  Its sign comes from a flood fill from
         outside, so a cavity enclosed by the copies counts as inside: the tori at 360
         degrees enclose one (a spindle round the axis, |z| < ~14 mm, outside SV).
  A peer that timed out or ran out of memory at N = 12 is not run at N = 36, nor on the
  next larger torus of the same angle (--no-skip runs them anyway).

THE MEASURES (same for every method):
  time      the computation alone, in its own process (ours: the library call)
  memory    the peak RSS of that process (wait4's ru_maxrss), MB
  error     (V - V_ref) / V_ref, V by the divergence theorem on the result mesh
  conserv.  the input's surface sampled (its vertices, up to 1500; 1500 points uniform by
            area; 1000 on edges) and turned by t = 0, theta and 30 random t in between
            (~128k points): a point counts as outside when it is farther than 1e-9 of the
            part's size (bounding-box diagonal) from the result's surface and outside by
            ray parity (bench_sweep_cgal contain: CGAL AABB tree, exact predicates, two
            rays, a third when they disagree).  "yes" = none outside; else the count and
            the largest distance.
  V_ref     the swept volume of the input mesh by the directed-circle rule: on each
            circle about the axis, the solid's arcs [a, b] turned by 0..theta cover
            [a, b + theta]; the covered angle integrated over radius and height
            (sweep_reference.py: Gauss-Legendre between the breaks of the integrand; no code
            shared with any method).  Its uncertainty (printed) is the gap to the same rule
            at a coarser quadrature; on the box it reproduces the analytic volume to 5e-8.
  LB        the issue's lower bound on the output size at tolerance tol:
              LB = K0 + Ktheta + sum over silhouette pieces of 2 ceil(f theta / step(r))
                   + sum over planar regions perpendicular to the axis of ceil(f theta /
                   step(r))
            step(r) = 2 acos(1 - tol / r) ~ sqrt(8 tol / r), the angle whose chord stays
            within tol of the circle of radius r (r = the piece's largest distance to the
            axis; 0 triangles if r <= tol).  K0 / Ktheta: input triangles with a part where
            n . tau < 0 (bounding SV at t = 0) / > 0 (at t = theta), tau = a x (p - c) the
            velocity, that is not hidden (a sample of that part - its centroid, then halfway
            to its corners - moved 1e-6 size along n and turned to 0 / theta is outside SV
            by the membership oracle); none at 360 degrees.  Silhouette pieces: the zero
            lines of n . tau inside triangles and the parts of mesh edges where the two
            faces' n . tau have opposite signs; each sweeps a strip of quads (2 triangles
            each) at the angular step; f = the fraction of 8 turned positions of the piece's
            midpoint (moved 1e-6 size outward) outside SV.  Faces perpendicular to the axis
            sweep planar sectors bounded by an arc at their largest radius.  It is the
            issue's estimate (each silhouette edge its own strip, no merging), not a proof.
  ratio     peer time / our time for the fastest peer whose |error| <= ours (and the
            fastest peer whatever its error).

TARGETS (issue 20): torus10k-90 < 2 s and < 500 MB; torus100k-* < 20 s and < 2 GB; output
<= 3 LB; >= 10x faster than the fastest peer at equal or better accuracy; ours conservative.
"""

import argparse
import gzip
import hashlib
import json
import math
import os
import re
import resource
import shutil
import signal
import subprocess
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
import sweep_reference as sr  # noqa: E402  (numpy only)

PYTHON = "/usr/bin/python3"
TOL = 0.01                      # mm
TIMEOUT = 300.0                 # s per run
MEM_GB = 8.0                    # address space per run
COPIES = (12, 36)
PEERS = ("fuse", "cgal", "vdb")
VDB_SECONDS = 60.0              # time budget of the OpenVDB level set (sets its voxel)
VDB_SECONDS_QUICK = 5.0
CACHE = os.path.join(HERE, "sweep-cache")
CGAL_BIN = os.path.join(ROOT, "build-bench", "bench", "bench_sweep_cgal")
CACHE_VERSION = 1               # bump when a cached quantity's definition changes

TORUS = (20.0, 6.0)
TORUS_AXIS = ((3.0, 2.0, 0.0), (0.0, 0.0, 1.0))
NUT_CENTRE = (81.301, 270.523, 0.0)
NUT_AXIS = ((NUT_CENTRE[0] + 15.0, NUT_CENTRE[1], NUT_CENTRE[2]), (0.2, 1.0, 0.3))
MESHES = {
    "arm": {"kind": "arm", "axis": ((8.0, 8.0, 0.0), (0.0, 0.0, 1.0)), "brep": True,
            "what": "9-face crank arm 90 x 38 x 10 mm (examples/parts/sweep_arm.py)"},
    "box": {"kind": "box", "dims": (30.0, 20.0, 10.0), "axis": ((0.0, 0.0, 0.0), (0.0, 0.0, 1.0)),
            "brep": True, "what": "box 30 x 20 x 10 mm about its 10 mm edge"},
    "torus1k": {"kind": "torus", "deflection": 0.25, "axis": TORUS_AXIS, "brep": False,
                "what": "torus R 20 r 6 mm, MeshPart 0.25 mm"},
    "torus10k": {"kind": "torus", "deflection": 0.025, "axis": TORUS_AXIS, "brep": False,
                 "what": "torus R 20 r 6 mm, MeshPart 0.025 mm"},
    "torus100k": {"kind": "torus", "deflection": 0.0025, "axis": TORUS_AXIS, "brep": False,
                  "what": "torus R 20 r 6 mm, MeshPart 0.0025 mm"},
    "nut50k": {"kind": "corpus", "file": "Pump_Nut.brep.gz", "deflection": 0.003,
               "angular": 0.1, "axis": NUT_AXIS, "brep": False,
               "what": "pump nut 60 x 15 x 60 mm (tests/corpus/Pump_Nut.brep.gz), MeshPart "
                       "0.003 mm / 0.1 rad"},
}
CASES = {   # name: (mesh, degrees, family for the skip rule, order in the family)
    "arm-90": ("arm", 90.0, "arm", 0),
    "box-90": ("box", 90.0, "box", 0),
    "torus1k-90": ("torus1k", 90.0, "torus-90", 1),
    "torus10k-90": ("torus10k", 90.0, "torus-90", 2),
    "torus100k-90": ("torus100k", 90.0, "torus-90", 3),
    "torus1k-360": ("torus1k", 360.0, "torus-360", 1),
    "torus10k-360": ("torus10k", 360.0, "torus-360", 2),
    "torus100k-360": ("torus100k", 360.0, "torus-360", 3),
    "nut50k-90": ("nut50k", 90.0, "nut-90", 0),
    "nut50k-360": ("nut50k", 360.0, "nut-360", 0),
}
DEFAULT_CASES = [c for c in CASES if c != "nut50k-360"]
QUICK_CASES = ["arm-90", "box-90"]
# targets of issue 20
TARGET_10K = (2.0, 500.0)       # s, MB: torus10k-90
TARGET_100K = (20.0, 2048.0)    # s, MB: torus100k-*
TARGET_LB_RATIO = 3.0
TARGET_SPEEDUP = 10.0
OOM_PATTERNS = re.compile(r"MemoryError|bad_alloc|NOMEM|out of memory|Cannot allocate|"
                          r"std::length_error", re.I)


def log(msg):
    print(f"bench_sweep [{time.strftime('%H:%M:%S')}]: {msg}", file=sys.stderr, flush=True)


# ------------------------------------------------------------------ files
def write_mesh_bin(path, v, t):
    with open(path, "wb") as f:
        np.array([len(v), len(t)], dtype=np.int64).tofile(f)
        np.ascontiguousarray(v, dtype=np.float64).tofile(f)
        np.ascontiguousarray(t, dtype=np.int64).tofile(f)


def read_mesh_bin(path):
    with open(path, "rb") as f:
        nv, nt = np.fromfile(f, dtype=np.int64, count=2)
        v = np.fromfile(f, dtype=np.float64, count=3 * nv).reshape(-1, 3)
        t = np.fromfile(f, dtype=np.int64, count=3 * nt).reshape(-1, 3)
    return v, t


def copy_angles(theta, n):
    """The N copies' angles: theta k / (N - 1), or 2 pi k / N for a full turn."""
    if theta >= 2 * math.pi * (1 - 1e-12):
        return [2 * math.pi * k / n for k in range(n)]
    return [theta * k / (n - 1) for k in range(n)] if n > 1 else [0.0]


# ------------------------------------------------------------------ running a child
def run_child(cmd, timeout, mem_gb, logpath, env=None):
    """Runs cmd in its own session with an address-space cap, stopped (the whole group)
    after ``timeout`` s.  Returns {"status": ok | timeout | oom | failed, "rc", "wall",
    "rss_mb" (this child's peak RSS, wait4), "error" (last line of its output)}."""
    cap = int(mem_gb * 2 ** 30) if mem_gb else 0

    def pre():
        os.setsid()
        if cap:
            resource.setrlimit(resource.RLIMIT_AS, (cap, cap))
    t0 = time.monotonic()
    with open(logpath, "w") as out:
        p = subprocess.Popen(cmd, env=env, stdout=out, stderr=subprocess.STDOUT,
                             preexec_fn=pre, cwd=ROOT)
        timed_out = False
        while True:
            pid, st, ru = os.wait4(p.pid, os.WNOHANG)
            if pid:
                break
            if time.monotonic() - t0 > timeout:
                timed_out = True
                try:
                    os.killpg(p.pid, signal.SIGKILL)
                except ProcessLookupError:
                    pass
                pid, st, ru = os.wait4(p.pid, 0)
                break
            time.sleep(0.02)
    p.returncode = rc = os.waitstatus_to_exitcode(st)
    wall = time.monotonic() - t0
    with open(logpath, errors="replace") as f:
        text = f.read()
    lines = [ln for ln in text.strip().splitlines() if ln.strip()]
    last = lines[-1][-300:] if lines else f"exit status {rc}"
    if timed_out:
        status = "timeout"
        last = f"stopped after {timeout:g} s"
    elif rc == 0:
        status = "ok"
    elif rc == -signal.SIGKILL or OOM_PATTERNS.search(text[-20000:]):
        status = "oom"
    else:
        status = "failed"
    return {"status": status, "rc": rc, "wall": wall, "rss_mb": ru.ru_maxrss / 1024.0,
            "cpu_s": ru.ru_utime + ru.ru_stime, "error": last}


# ------------------------------------------------------------------ children: freecadcmd
def _fc_prepare(job):
    """In freecadcmd: tessellate the meshes job["meshes"] into job["dir"]/<name>.npz."""
    import FreeCAD as App
    import MeshPart
    import Part
    for name in job["meshes"]:
        spec = MESHES[name]
        t0 = time.perf_counter()
        shape = _fc_shape(name)
        if spec["kind"] in ("arm", "box"):
            p, f = shape.tessellate(TOL)
            v = np.array([(q.x, q.y, q.z) for q in p], dtype=np.float64)
            t = np.array(f, dtype=np.int64)
        else:
            mesh = MeshPart.meshFromShape(Shape=shape, LinearDeflection=spec["deflection"],
                                          AngularDeflection=spec.get("angular", 1.0),
                                          Relative=False)
            p, f = mesh.Topology
            v = np.array([(q.x, q.y, q.z) for q in p], dtype=np.float64)
            t = np.array(f, dtype=np.int64)
        secs = time.perf_counter() - t0
        bb = shape.BoundBox
        info = {"faces": len(shape.Faces), "volume_part": shape.Volume, "tess_s": secs,
                "bbox": [bb.XLength, bb.YLength, bb.ZLength],
                "freecad": ".".join(App.Version()[:3])}
        np.savez(os.path.join(job["dir"], name + ".npz"), vertices=v, triangles=t,
                 info=json.dumps(info))
        print(f"prepared {name}: {len(t)} triangles", flush=True)
    del Part


def _fc_shape(name):
    import FreeCAD as App
    import Part
    spec = MESHES[name]
    if spec["kind"] == "arm":
        sys.path.insert(0, os.path.join(ROOT, "examples", "parts"))
        import sweep_arm
        assert tuple(sweep_arm.AXIS_POINT) == spec["axis"][0], "sweep_arm's axis moved"
        return sweep_arm.make()
    if spec["kind"] == "box":
        return Part.makeBox(*spec["dims"])
    if spec["kind"] == "torus":
        return Part.makeTorus(TORUS[0], TORUS[1], App.Vector(0, 0, 0), App.Vector(1, 0, 0))
    with gzip.open(os.path.join(ROOT, "tests", "corpus", spec["file"])) as f:
        data = f.read()
    with tempfile.NamedTemporaryFile(suffix=".brep", delete=False) as tmp:
        tmp.write(data)
    try:
        shape = Part.Shape()
        shape.read(tmp.name)
    finally:
        os.unlink(tmp.name)
    return shape.Solids[0]


def _fc_fuse(job):
    """In freecadcmd: multiFuse of N turned copies (B-rep or the mesh as a solid)."""
    import FreeCAD as App
    import Part
    if job["brep"]:
        shape = _fc_shape(job["mesh_name"])
    else:
        # the mesh as a solid: one planar face per triangle, sewn (FreeCAD's Part >
        # Create shape from mesh, then Convert to solid)
        d = np.load(job["npz"])
        v, t = d["vertices"], d["triangles"]
        shell = Part.Shape()
        shell.makeShapeFromMesh(([App.Vector(*map(float, p)) for p in v],
                                 [tuple(map(int, f)) for f in t]), 1e-7)
        shape = Part.makeSolid(shell)
    ap, ad = job["axis"]
    copies = []
    for ang in copy_angles(job["theta"], job["n"]):
        c = shape.copy()
        c.rotate(App.Vector(*ap), App.Vector(*ad), math.degrees(ang))
        copies.append(c)
    t0 = time.perf_counter()
    fused = copies[0].multiFuse(copies[1:])
    secs = time.perf_counter() - t0
    p, f = fused.tessellate(TOL)
    v = np.array([(q.x, q.y, q.z) for q in p], dtype=np.float64).reshape(-1, 3)
    write_mesh_bin(job["out"], v, np.array(f, dtype=np.int64).reshape(-1, 3))
    with open(job["json"], "w") as fj:
        json.dump({"s": secs, "volume_brep": fused.Volume, "valid": fused.isValid(),
                   "solids": len(fused.Solids), "faces": len(fused.Faces)}, fj)


# ------------------------------------------------------------------ children: python
def _child_ours(job):
    from mfgeom import core
    d = np.load(job["npz"])
    v, t = d["vertices"], d["triangles"]
    rss0 = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    times = []
    res = None
    while len(times) < 3 and sum(times) < 1.0:
        res = None                                       # the previous result is freed
        t0 = time.perf_counter()
        res = core.rotational_sweep(v, t, job["axis"][0], job["axis"][1], job["theta"], TOL)
        times.append(time.perf_counter() - t0)
    rv, rt = np.asarray(res.vertices), np.asarray(res.triangles)
    try:
        core.mesh_check(rv, rt, require_closed=True)
        closed = "yes"
    except core.MfgError as exc:
        closed = f"NO: {exc}"
    write_mesh_bin(job["out"], rv, rt)
    with open(job["json"], "w") as f:
        json.dump({"s": min(times), "runs": len(times), "volume_lib": float(res.volume),
                   "closed": closed, "rss_before_mb": rss0 / 1024.0,
                   "library": core.version()}, f)


def _child_vdb(job):
    import pyopenvdb as vdb
    d = np.load(job["npz"])
    v, t = d["vertices"], d["triangles"]
    ap, ad = job["axis"]
    pts = [sr.rotate(v, ap, ad, a) for a in copy_angles(job["theta"], job["n"])]
    allv = np.concatenate(pts).astype(np.float32)
    allt = np.concatenate([t + k * len(v) for k in range(len(pts))]).astype(np.int32)
    del pts

    def level_set(h):
        g = vdb.FloatGrid.createLevelSetFromPolygons(
            allv, triangles=allt, transform=vdb.createLinearTransform(voxelSize=h),
            halfWidth=3.0)
        p, tr, q = g.convertToPolygons(isovalue=0.0, adaptivity=0.0)
        return g, p, tr, q

    tol = job["tol"]
    size = float(np.linalg.norm(v.max(axis=0) - v.min(axis=0)))
    pilot = {}
    h = tol
    if job.get("pilot", True):
        hp = max(tol, size / 150.0)
        rss0 = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024.0
        t0 = time.perf_counter()
        g, p, tr, q = level_set(hp)
        tp = time.perf_counter() - t0
        grow = max(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024.0 - rss0, 1e6)
        del g, p, tr, q
        # memory and time grow as 1/h^2 (a narrow band over the same surface)
        k = max(grow / (0.5 * job["mem_bytes"] - rss0), tp / job["vdb_seconds"])
        h = hp * math.sqrt(max(k, 0.0))
        if h > tol:        # rounded up to two significant digits
            e = 10.0 ** (math.floor(math.log10(h)) - 1)
            h = math.ceil(h / e - 1e-9) * e
        h = max(tol, h)
        pilot = {"pilot_voxel": hp, "pilot_s": tp, "pilot_mb": grow / 2 ** 20}
    t0 = time.perf_counter()
    g, p, tr, q = level_set(h)
    secs = time.perf_counter() - t0
    tris = np.concatenate([tr.reshape(-1, 3), q[:, [0, 1, 2]], q[:, [0, 2, 3]]]) \
        if len(q) else tr.reshape(-1, 3)
    tris = tris[:, ::-1].astype(np.int64)       # convertToPolygons winds them inward
    write_mesh_bin(job["out"], p.astype(np.float64), tris)
    with open(job["json"], "w") as f:
        json.dump(dict(pilot, s=secs, voxel=h, active_voxels=int(g.activeVoxelCount()),
                       openvdb=".".join(map(str, vdb.LIBRARY_VERSION))), f)


# ------------------------------------------------------------------ the cache
def _mesh_hash(v, t):
    h = hashlib.sha256()
    h.update(np.ascontiguousarray(v, dtype=np.float64).tobytes())
    h.update(np.ascontiguousarray(t, dtype=np.int64).tobytes())
    return h.hexdigest()[:16]


def ensure_meshes(names, refresh, timeout):
    os.makedirs(CACHE, exist_ok=True)
    missing = [n for n in names if refresh or not os.path.exists(os.path.join(CACHE, n + ".npz"))]
    if missing:
        log(f"tessellating {', '.join(missing)} in freecadcmd")
        job = os.path.join(CACHE, "prepare.json")
        with open(job, "w") as f:
            json.dump({"meshes": missing, "dir": CACHE}, f)
        env = dict(os.environ, MFGEOM_BENCH_SWEEP_PREPARE=job)
        r = run_child(["freecadcmd", os.path.abspath(__file__)], timeout, 0,
                      os.path.join(CACHE, "prepare.log"), env=env)
        gone = [n for n in missing if not os.path.exists(os.path.join(CACHE, n + ".npz"))]
        if gone:
            raise RuntimeError(f"freecadcmd could not tessellate {gone}: {r['error']} "
                               f"(see {CACHE}/prepare.log)")


def cached(key, compute, refresh):
    path = os.path.join(CACHE, key + ".json")
    if not refresh and os.path.exists(path):
        with open(path) as f:
            return json.load(f)
    value = compute()
    with open(path, "w") as f:
        json.dump(value, f)
    return value


# ------------------------------------------------------------------ checks
def check_result(res_bin, pts_bin, eps, tmp, name, timeout):
    """Conservativeness of one result: (outside count, total, largest distance)."""
    out = os.path.join(tmp, name + ".dist")
    r = run_child([CGAL_BIN, "contain", res_bin, pts_bin, out, repr(eps)], timeout * 4, 0,
                  os.path.join(tmp, name + ".contain.log"))
    if r["status"] != "ok":
        return {"checked": False, "error": r["error"]}
    dist = np.fromfile(out, dtype=np.float64)
    bad = dist > eps
    return {"checked": True, "outside": int(bad.sum()), "points": int(len(dist)),
            "max_out": float(dist.max()) if bad.any() else 0.0}


# ------------------------------------------------------------------ the driver
def _cgal_binary():
    if os.access(CGAL_BIN, os.X_OK):
        return True
    if not shutil.which("cmake"):
        return False
    log("building bench_sweep_cgal (cmake, build-bench/)")
    b = os.path.join(ROOT, "build-bench")
    for cmd in (["cmake", "-S", ROOT, "-B", b, "-DMFG_BUILD_BENCH=ON",
                 "-DCMAKE_BUILD_TYPE=Release"],
                ["cmake", "--build", b, "--target", "bench_sweep_cgal", "-j2"]):
        if subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL).returncode:
            return False
    return os.access(CGAL_BIN, os.X_OK)


def _have_vdb():
    return subprocess.run([PYTHON, "-c", "import pyopenvdb"], stdout=subprocess.DEVNULL,
                          stderr=subprocess.DEVNULL).returncode == 0


def run_case(name, args, env, tmp, failures):
    mesh_name, deg, family, order = CASES[name]
    spec = MESHES[mesh_name]
    theta = math.radians(deg)
    npz = os.path.join(CACHE, mesh_name + ".npz")
    d = np.load(npz)
    v, t = d["vertices"], d["triangles"]
    info = json.loads(str(d["info"]))
    axis = spec["axis"]
    mh = _mesh_hash(v, t)
    size = float(np.linalg.norm(v.max(axis=0) - v.min(axis=0)))
    eps = 1e-9 * size
    row = {"case": name, "mesh": mesh_name, "deg": deg, "triangles_in": int(len(t)),
           "what": spec["what"], "size": size, "bbox": info["bbox"], "info": info,
           "axis": axis, "runs": {}}
    key = f"v{CACHE_VERSION}-{mesh_name}-{mh}-{deg:g}"
    t0 = time.perf_counter()
    row["ref"] = cached(key + "-ref", lambda: dict(zip(
        ("volume", "err", "diag"),
        sr.reference_with_error(v, t, axis[0], axis[1], theta))), args.refresh)
    row["ref_s"] = time.perf_counter() - t0
    log(f"{name}: reference {row['ref']['volume']:.6f} +- {row['ref']['err']:.2g}")
    row["lb"] = cached(key + f"-lb-{TOL:g}", lambda: sr.lower_bound(
        v, t, axis[0], axis[1], theta, TOL), args.refresh)
    log(f"{name}: lower bound {row['lb']['lb']}")
    pts = sr.turned_samples(v, t, axis[0], axis[1], theta)
    pts_bin = os.path.join(tmp, name + ".pts")
    with open(pts_bin, "wb") as f:
        np.array([len(pts)], dtype=np.int64).tofile(f)
        pts.tofile(f)
    in_bin = os.path.join(tmp, mesh_name + ".bin")
    if not os.path.exists(in_bin):
        write_mesh_bin(in_bin, v, t)
    ref = row["ref"]["volume"]

    def finish(method, r, job):
        """Reads a finished run's json and result mesh: volume, triangles, check."""
        if r["status"] == "ok" and os.path.exists(job["json"]) and os.path.exists(job["out"]):
            with open(job["json"]) as f:
                r.update(json.load(f))
            rv, rt = read_mesh_bin(job["out"])
            r["triangles"] = int(len(rt))
            r["volume"] = sr.mesh_volume(rv, rt)
            r["err"] = (r["volume"] - ref) / ref
            del rv, rt
            if args.no_check or not os.access(CGAL_BIN, os.X_OK):
                r["check"] = {"checked": False, "error": "no checker"}
            else:
                r["check"] = check_result(job["out"], pts_bin, eps, tmp, f"{name}.{method}",
                                          args.timeout)
        elif r["status"] == "ok":
            r["status"] = "failed"
            r["error"] = "no result written"
        row["runs"][method] = r
        c = r.get("check", {})
        log(f"{name}: {method}: {r['status']} " + (
            f"{r['s']:.3f} s, {r['rss_mb']:.0f} MB, {r['triangles']} triangles, error "
            f"{r['err']:+.2e}, outside {c.get('outside', '?')}" if r["status"] == "ok"
            else r["error"]))
        if r["status"] != "ok" and method == "ours":
            failures.append(f"{name}: ours {r['status']}: {r['error']}")

    def job_for(method):
        return {"npz": npz, "axis": axis, "theta": theta, "tol": TOL,
                "out": os.path.join(tmp, f"{name}.{method}.bin"),
                "json": os.path.join(tmp, f"{name}.{method}.json"),
                "mem_bytes": args.mem_gb * 2 ** 30, "timeout": args.timeout,
                "brep": spec["brep"], "mesh_name": mesh_name,
                "vdb_seconds": min(args.vdb_seconds, 0.5 * args.timeout)}

    # ours
    job = job_for("ours")
    jpath = os.path.join(tmp, f"{name}.ours.job")
    with open(jpath, "w") as f:
        json.dump(job, f)
    log(f"{name}: ours ({len(t)} triangles, {deg:g} deg)")
    r = run_child([PYTHON, os.path.abspath(__file__), "--child-ours", jpath], args.timeout,
                  args.mem_gb, os.path.join(tmp, f"{name}.ours.log"), env=env)
    finish("ours", r, job)
    # peers
    for peer in args.peers:
        for n in args.copies:
            method = f"{peer}{n}"
            why = skip_reason(peer, n, name, family, order, args)
            if why:
                row["runs"][method] = {"status": "skipped", "error": why}
                log(f"{name}: {method}: skipped ({why})")
                continue
            job = job_for(method)
            job["n"] = n
            jpath = os.path.join(tmp, f"{name}.{method}.job")
            with open(jpath, "w") as f:
                json.dump(job, f)
            logp = os.path.join(tmp, f"{name}.{method}.log")
            log(f"{name}: {method}")
            if peer == "fuse":
                r = run_child(["freecadcmd", os.path.abspath(__file__)], args.timeout,
                              args.mem_gb, logp,
                              env=dict(env, MFGEOM_BENCH_SWEEP_FUSE=jpath))
            elif peer == "cgal":
                r = run_child([CGAL_BIN, "union", in_bin, str(n), repr(theta),
                               *map(repr, axis[0]), *map(repr, axis[1]), job["out"],
                               "epeck", "tree"], args.timeout, args.mem_gb, logp)
                if r["status"] == "ok":
                    with open(logp) as f:
                        line = [ln for ln in f if ln.startswith("{")]
                    with open(job["json"], "w") as f:
                        f.write(line[-1] if line else "{}")
            else:
                r = run_child([PYTHON, os.path.abspath(__file__), "--child-vdb", jpath],
                              args.timeout, args.mem_gb, logp, env=env)
            finish(method, r, job)
            if r["status"] in ("timeout", "oom"):
                SKIPS.setdefault((peer, family), (order, n, name, r["status"]))
                SKIPS.setdefault((peer, n, name), r["status"])
    return row


SKIPS = {}


def skip_reason(peer, n, name, family, order, args):
    if args.no_skip:
        return None
    for m in args.copies:
        if m < n and (peer, m, name) in SKIPS:
            return f"{SKIPS[(peer, m, name)]} at N = {m}"
    prev = SKIPS.get((peer, family))
    if prev and prev[0] < order and prev[1] <= n:
        return f"{prev[3]} on {prev[2]} at N = {prev[1]}"
    return None


# ------------------------------------------------------------------ the report
def _fmt_err(x):
    return f"{x:+.1e}"


def _cons(r):
    c = r.get("check", {})
    if not c.get("checked"):
        return "?"
    if c["outside"] == 0:
        return "yes"
    return f"no ({c['outside']}/{c['points']}, {c['max_out']:.2g} mm)"


def _cell(r):
    if r["status"] == "skipped":
        return "skipped"
    if r["status"] != "ok":
        return f"{r['status']} ({r['wall']:.0f} s, {r['rss_mb']:.0f} MB)"
    extra = f", h {r['voxel']:g}" if "voxel" in r else ""
    return (f"{r['s']:.2f} s, {r['rss_mb']:.0f} MB, {_fmt_err(r['err'])}, "
            f"{'cons.' if _cons(r) == 'yes' else 'not cons.'}{extra}")


def best_peer(row):
    """(fastest peer at |error| <= ours, fastest peer at all): (method, run) or None."""
    o = row["runs"].get("ours", {})
    peers = [(m, r) for m, r in row["runs"].items() if m != "ours" and r["status"] == "ok"]
    fastest = min(peers, key=lambda mr: mr[1]["s"]) if peers else None
    if o.get("status") != "ok":
        return None, fastest
    eq = [(m, r) for m, r in peers if abs(r["err"]) <= abs(o["err"])]
    return (min(eq, key=lambda mr: mr[1]["s"]) if eq else None), fastest


def report(rows, args, meta):
    out = []
    p = out.append
    lib = next((r["runs"]["ours"].get("library") for r in rows
                if r["runs"].get("ours", {}).get("library")), "?")
    load = " / ".join(f"{x:.1f}" for x in os.getloadavg())
    p("## Rotational swept volume (bench_sweep.py, issue 20)\n")
    p(f"`{meta['command']}` on {meta['date']}: libmfgeom {lib}, FreeCAD {meta['freecad']}, "
      f"CGAL 5.5 (Epeck, balanced tree), OpenVDB {meta['openvdb']}; tolerance {TOL:g} mm; "
      f"every run in its own process, stopped after {args.timeout:g} s, address space "
      f"capped at {args.mem_gb:g} GB; {os.cpu_count()} CPUs, load average at the end "
      f"{load}. How each number is measured: the docstring of bench/bench_sweep.py and "
      "docs/benchmarks.md.\n")
    p("Cells: time (the computation alone), peak RSS of its process, volume error "
      "(V − V_ref)/V_ref, conservative (no point of the turned input outside). vdb: h = "
      "voxel size (mm). ratio = peer time / our time for the fastest peer with |error| ≤ "
      "ours (— none), then for the fastest peer at any error.\n")
    methods = ["ours"] + [f"{pe}{n}" for pe in args.peers for n in args.copies]
    head = ("| case | triangles in | LB | ours | ours: triangles (/ LB) | ours: conservative | "
            + " | ".join(methods[1:]) + " | ratio: at ≥ our accuracy; fastest |")
    p(head)
    p("|" + "---|" * (head.count("|") - 1))
    for row in rows:
        o = row["runs"].get("ours", {"status": "?", "error": "", "wall": 0, "rss_mb": 0})
        lb = row["lb"]["lb"]
        if o["status"] == "ok":
            tri = f"{o['triangles']} ({o['triangles'] / lb:.1f}×)"
            cons = _cons(o)
        else:
            tri, cons = "—", "—"
        eq, fast = best_peer(row)
        ratio = (f"{eq[0]} {eq[1]['s'] / o['s']:.2g}×" if eq else "—") if o["status"] == "ok" \
            else "n/a"
        if fast and o["status"] == "ok":
            ratio += f"; {fast[0]} {fast[1]['s'] / o['s']:.2g}×"
        cells = [_cell(row["runs"].get(m, {"status": "skipped"})) for m in methods[1:]]
        p(f"| {row['case']} | {row['triangles_in']} | {lb} | {_cell(o)} | {tri} | {cons} | "
          + " | ".join(cells) + f" | {ratio} |")
    p("")
    p("### Details per case\n")
    p("| case | input | axis (point; direction) | V_ref mm³ (± uncertainty) | LB = K0 + Kθ + "
      "strips + sectors | method | status | time s (CPU s of the process) | peak RSS MB | "
      "triangles | volume mm³ | "
      "error | outside / points (largest distance mm) | notes |")
    p("|---|---|---|---|---|---|---|---:|---:|---:|---:|---:|---|---|")
    for row in rows:
        lbp = row["lb"]
        lbtxt = (f"{lbp['lb']} = {lbp['kept_start']} + {lbp['kept_end']} + "
                 f"{lbp['strip_triangles']} ({lbp['pieces_visible']} of {lbp['pieces']} "
                 f"pieces) + {lbp['sector_triangles']}")
        ref = row["ref"]
        first = True
        for m in methods:
            r = row["runs"].get(m)
            if r is None:
                continue
            lead = (f"| {row['case']} | {row['what']}, {row['triangles_in']} triangles, "
                    f"{' × '.join(f'{x:.1f}' for x in row['bbox'])} mm | "
                    f"{_axis_txt(row['axis'])} | {ref['volume']:.4f} (± {ref['err']:.1g}, "
                    f"{ref['err'] / ref['volume']:.0e}) | {lbtxt} ") if first else \
                "| | | | | "
            first = False
            if r["status"] == "ok":
                c = r.get("check", {})
                chk = (f"{c['outside']} / {c['points']} ({c['max_out']:.3g})"
                       if c.get("checked") else f"not checked: {c.get('error', '')}")
                note = _notes(m, r)
                p(lead + f"| {m} | ok | {r['s']:.3f} ({r['cpu_s']:.0f}) | {r['rss_mb']:.0f} | "
                  f"{r['triangles']} | "
                  f"{r['volume']:.4f} | {_fmt_err(r['err'])} | {chk} | {note} |")
            else:
                p(lead + f"| {m} | {r['status']} | "
                  + (f"> {r['wall']:.0f}" if r["status"] == "timeout" else
                     (f"{r['wall']:.1f}" if "wall" in r else "")) + " | "
                  + (f"{r['rss_mb']:.0f}" if "rss_mb" in r else "") + " | | | | | "
                  + f"{r['error'].replace('|', '/')} |")
    p("")
    for row in rows:
        if row["mesh"] == "box" and row["deg"] < 360:
            a, b, c = MESHES["box"]["dims"]
            th = math.radians(row["deg"])
            exact = c * (a * b + (a * a + b * b) * th / 2)
            ref = row["ref"]["volume"]
            p(f"Check of the reference: the box about its edge has the analytic swept volume "
              f"c (a b + (a² + b²) θ / 2) = {exact:.6f} mm³; V_ref − that = "
              f"{ref - exact:+.2g} mm³ ({(ref - exact) / exact:+.1e}).\n")
    p(growth(rows))
    p("### Targets (issue 20)\n")
    targets = evaluate_targets(rows)
    for text, verdict in targets:
        p(f"- {text}: **{verdict}**")
    npass = sum(v == "PASS" for _, v in targets)
    nmiss = sum(v == "MISS" for _, v in targets)
    p(f"\n{npass} PASS, {nmiss} MISS, {len(targets) - npass - nmiss} not decidable.")
    return "\n".join(out)


def _axis_txt(axis):
    return (f"({', '.join(f'{x:g}' for x in axis[0])}); "
            f"({', '.join(f'{x:g}' for x in axis[1])})")


def _notes(m, r):
    if m == "ours":
        return (f"{r.get('runs', 1)} run(s); closed: {r.get('closed', '?')}; RSS before the "
                f"call {r.get('rss_before_mb', 0):.0f} MB")
    if m.startswith("vdb"):
        return (f"voxel {r['voxel']:g} mm, {r['active_voxels']} active voxels; pilot at "
                f"{r.get('pilot_voxel', 0):.3g} mm: {r.get('pilot_s', 0):.1f} s")
    if m.startswith("fuse"):
        return (f"B-rep volume {r.get('volume_brep', 0):.4f}, {r.get('faces', '?')} faces, "
                f"{r.get('solids', '?')} solid(s), valid {r.get('valid', '?')}")
    if m.startswith("cgal"):
        return f"union ok: {r.get('ok', '?')}"
    return ""


def growth(rows):
    lines = ["### Growth of ours with size (tori)\n",
             "Exponent = log(t2 / t1) / log(n2 / n1) between consecutive sizes, n = input "
             "triangles; and against n = input + output triangles.\n",
             "| angle | n in | n out | time s | exponent (in) | exponent (in + out) |",
             "|---|---:|---:|---:|---:|---:|"]
    any_row = False
    for deg in (90.0, 360.0):
        prev = None
        for row in rows:
            if not row["mesh"].startswith("torus") or row["deg"] != deg:
                continue
            o = row["runs"].get("ours", {})
            if o.get("status") != "ok":
                lines.append(f"| {deg:g} | {row['triangles_in']} | | {o.get('status', '?')} | | |")
                prev = None
                continue
            any_row = True
            n_in, n_io = row["triangles_in"], row["triangles_in"] + o["triangles"]
            e1 = e2 = ""
            if prev:
                e1 = f"{math.log(o['s'] / prev[2]) / math.log(n_in / prev[0]):.2f}"
                e2 = f"{math.log(o['s'] / prev[2]) / math.log(n_io / prev[1]):.2f}"
            lines.append(f"| {deg:g} | {n_in} | {o['triangles']} | {o['s']:.3f} | {e1} | {e2} |")
            prev = (n_in, n_io, o["s"])
    return "\n".join(lines) + "\n" if any_row or len(lines) > 4 else ""


def evaluate_targets(rows):
    out = []
    for row in rows:
        o = row["runs"].get("ours", {})
        ok = o.get("status") == "ok"
        name = row["case"]
        status = o.get("status", "not run")
        if name == "torus10k-90":
            s, mb = TARGET_10K
            out.append((f"{name}: time < {s:g} s: " + (f"{o['s']:.2f} s" if ok else status),
                        "PASS" if ok and o["s"] < s else "MISS"))
            out.append((f"{name}: memory < {mb:g} MB: " + (f"{o['rss_mb']:.0f} MB" if ok
                                                            else status),
                        "PASS" if ok and o["rss_mb"] < mb else "MISS"))
        if name.startswith("torus100k"):
            s, mb = TARGET_100K
            out.append((f"{name}: time < {s:g} s: " + (f"{o['s']:.2f} s" if ok else status),
                        "PASS" if ok and o["s"] < s else "MISS"))
            out.append((f"{name}: memory < {mb:g} MB: " + (f"{o['rss_mb']:.0f} MB" if ok
                                                            else status),
                        "PASS" if ok and o["rss_mb"] < mb else "MISS"))
        lb = row["lb"]["lb"]
        out.append((f"{name}: output <= {TARGET_LB_RATIO:g} LB: " +
                    (f"{o['triangles']} / {lb} = {o['triangles'] / lb:.1f}" if ok else status),
                    "PASS" if ok and o["triangles"] <= TARGET_LB_RATIO * lb else "MISS"))
        eq, fast = best_peer(row)
        if not ok:
            out.append((f"{name}: >= {TARGET_SPEEDUP:g}x faster than the fastest peer at "
                        f"equal or better accuracy: ours {status}", "MISS"))
        elif eq:
            ratio = eq[1]["s"] / o["s"]
            out.append((f"{name}: >= {TARGET_SPEEDUP:g}x faster than the fastest peer at "
                        f"equal or better accuracy ({eq[0]}, error {_fmt_err(eq[1]['err'])} vs "
                        f"ours {_fmt_err(o['err'])}): {ratio:.2g}x",
                        "PASS" if ratio >= TARGET_SPEEDUP else "MISS"))
        else:
            runs = [m for m, r in row["runs"].items() if m != "ours" and r["status"] == "ok"]
            out.append((f"{name}: no peer at equal or better accuracy (finished: "
                        f"{', '.join(runs) or 'none'})", "n/a"))
        c = o.get("check", {})
        out.append((f"{name}: ours conservative: " + (_cons(o) if ok else status),
                    "PASS" if ok and c.get("checked") and c["outside"] == 0 else "MISS"))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true", help="arm-90 and box-90, N = 12")
    ap.add_argument("--cases", help="comma-separated case names (see --list)")
    ap.add_argument("--peers", default=",".join(PEERS), help="fuse,cgal,vdb or none")
    ap.add_argument("--copies", default=",".join(map(str, COPIES)), help="N values")
    ap.add_argument("--timeout", type=float, default=TIMEOUT, help="s per run")
    ap.add_argument("--mem-gb", type=float, default=MEM_GB, help="address space per run")
    ap.add_argument("--vdb-seconds", type=float, help="time budget of the OpenVDB level set "
                    f"(its voxel size is the finest a pilot predicts to fit; default "
                    f"{VDB_SECONDS:g} s, --quick {VDB_SECONDS_QUICK:g} s)")
    ap.add_argument("--no-skip", action="store_true", help="no skipping after a timeout")
    ap.add_argument("--no-check", action="store_true", help="no conservativeness check")
    ap.add_argument("--refresh", action="store_true", help="rebuild the cache")
    ap.add_argument("--keep", help="keep the runs' files (results, logs) in this folder")
    ap.add_argument("--list", action="store_true", help="list the cases")
    ap.add_argument("--child-ours", help=argparse.SUPPRESS)
    ap.add_argument("--child-vdb", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.child_ours or args.child_vdb:
        with open(args.child_ours or args.child_vdb) as f:
            job = json.load(f)
        (_child_ours if args.child_ours else _child_vdb)(job)
        return 0
    if args.list:
        for c, (m, deg, _, _) in CASES.items():
            star = "" if c in DEFAULT_CASES else "  (not by default)"
            print(f"{c:15s} {MESHES[m]['what']}, {deg:g} deg about {_axis_txt(MESHES[m]['axis'])}"
                  f"{star}")
        return 0
    cases = args.cases.split(",") if args.cases else (QUICK_CASES if args.quick else DEFAULT_CASES)
    bad = [c for c in cases if c not in CASES]
    if bad:
        ap.error(f"unknown case(s) {bad}; --list shows them")
    args.peers = [] if args.peers == "none" else args.peers.split(",")
    if args.vdb_seconds is None:
        args.vdb_seconds = VDB_SECONDS_QUICK if args.quick else VDB_SECONDS
    args.copies = [12] if args.quick and "--copies" not in " ".join(sys.argv) else \
        sorted(int(x) for x in args.copies.split(","))
    env = dict(os.environ)
    env.setdefault("MFGEOM_LIBRARY", os.path.join(ROOT, "build", "libmfgeom.so"))
    env["PYTHONPATH"] = os.path.join(ROOT, "workbench")
    if not os.path.exists(env["MFGEOM_LIBRARY"]):
        log(f"MFGEOM_LIBRARY={env['MFGEOM_LIBRARY']} does not exist (bash scripts/build.sh)")
        return 2
    if not _cgal_binary():
        log("bench_sweep_cgal is missing and could not be built (libcgal-dev, cmake): no CGAL "
            "peer, no conservativeness check")
        args.peers = [x for x in args.peers if x != "cgal"]
    if "vdb" in args.peers and not _have_vdb():
        log("pyopenvdb is missing (apt-get install python3-openvdb): no OpenVDB peer")
        args.peers = [x for x in args.peers if x != "vdb"]
    if "fuse" in args.peers and not shutil.which("freecadcmd"):
        log("freecadcmd is missing: no FreeCAD peer")
        args.peers = [x for x in args.peers if x != "fuse"]
    ensure_meshes(sorted({CASES[c][0] for c in cases}), args.refresh, 1800)
    fc = json.loads(str(np.load(os.path.join(CACHE, CASES[cases[0]][0] + ".npz"))["info"]))
    vdbv = subprocess.run([PYTHON, "-c", "import pyopenvdb as v; print('.'.join(map(str, "
                           "v.LIBRARY_VERSION)))"], capture_output=True, text=True).stdout.strip()
    meta = {"command": "MFGEOM_LIBRARY=" + os.path.relpath(env["MFGEOM_LIBRARY"], ROOT)
            + " /usr/bin/python3 bench/bench_sweep.py " + " ".join(sys.argv[1:]),
            "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
            "freecad": fc.get("freecad", "?"), "openvdb": vdbv or "?"}
    failures = []
    rows = []
    tmp = args.keep or tempfile.mkdtemp(prefix="mfgeom-bench-sweep-")
    os.makedirs(tmp, exist_ok=True)
    try:
        # the family's cases in order of size, so the skip rule sees the smaller one first
        first = {}
        for i, c in enumerate(cases):
            first.setdefault(CASES[c][2], i)
        for c in sorted(cases, key=lambda c: (first[CASES[c][2]], CASES[c][3])):
            rows.append(run_case(c, args, env, tmp, failures))
    finally:
        if not args.keep:
            shutil.rmtree(tmp, ignore_errors=True)
    print(report(rows, args, meta))
    for f in failures:
        log(f)
    return 0


if os.environ.get("MFGEOM_BENCH_SWEEP_PREPARE") or os.environ.get("MFGEOM_BENCH_SWEEP_FUSE"):
    # run by freecadcmd as a script: do the job, then leave
    _rc = 0
    try:
        if os.environ.get("MFGEOM_BENCH_SWEEP_FUSE"):
            with open(os.environ["MFGEOM_BENCH_SWEEP_FUSE"]) as _f:
                _fc_fuse(json.load(_f))
        else:
            with open(os.environ["MFGEOM_BENCH_SWEEP_PREPARE"]) as _f:
                _fc_prepare(json.load(_f))
    except MemoryError:
        print("MemoryError", flush=True)
        _rc = 4
    except Exception:  # reported in the log; the driver sees the missing result
        import traceback
        traceback.print_exc()
        _rc = 1
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(_rc)
elif __name__ == "__main__":
    sys.exit(main())
