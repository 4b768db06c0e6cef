# SPDX-License-Identifier: LGPL-2.1-or-later
"""Point-classification demo on the bundled bracket, run by ``freecadcmd``.

Creates parametric point classifications on a planar face with holes and a pocket and
on the boss's trimmed cylindrical face, fed by a Points cloud, a sketch and a mesh;
times them, cross-checks them against OCCT's own face classifier, and writes
``demo_pointclass.json``, ``demo_pointclass.txt`` and ``demo_pointclass.FCStd`` into
$MFGEOM_OUT (default: <repo>/out).  Exits non-zero if anything fails or disagrees.
Use examples/run_demo.sh, which also renders the result with the GUI.
"""

import json
import math
import os
import sys
import time
import traceback

import numpy as np

import FreeCAD as App
import Part

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
# Running the script straight from a checkout works too: the workbench need not be
# installed in FreeCAD's Mod folder for the App side.
for path in (HERE, os.path.join(REPO, "workbench")):
    if path not in sys.path:
        sys.path.append(path)

import bracket  # noqa: E402  (needs the path above)
import mfgeom  # noqa: E402
from mfgeom import core  # noqa: E402
from mfgeom.app import pointcloud  # noqa: E402

TOLERANCE = 0.3  # mm: wide enough for the ON band to show at the demo's 1 mm point spacing
FINE_TOLERANCE = 0.01  # mm: the workbench default, for the timing run
LIFT = 0.02  # mm: the clouds float just above the surfaces so the render shows them
CROSS_CHECK_POINTS = 400  # per feature: OCCT's classifier is slow, a sample is enough


def out_dir():
    path = os.environ.get("MFGEOM_OUT") or os.path.join(REPO, "out")
    os.makedirs(path, exist_ok=True)
    return os.path.abspath(path)


def open_bracket():
    """The bundled part as a new document (the example file itself is never modified)."""
    src = os.path.join(HERE, "bracket.FCStd")
    if os.path.exists(src):
        doc = App.openDocument(src)
        return doc, doc.getObject("Bracket")
    doc = App.newDocument("bracket")
    return doc, bracket.make_bracket(doc)


def add_cloud(doc, name, pts):
    obj = doc.addObject("Points::Feature", name)
    obj.Points = pointcloud.array_to_kernel(pts)
    return obj


def top_grid():
    lx, ly, lz = bracket.PLATE
    xs = np.arange(-3.0, lx + 3.0 + 1e-9, 1.0)
    ys = np.arange(-3.0, ly + 3.0 + 1e-9, 1.0)
    gx, gy = np.meshgrid(xs, ys)
    return np.column_stack([gx.ravel(), gy.ravel(), np.full(gx.size, lz + LIFT)])


def boss_grid():
    r = bracket.BOSS_R + LIFT
    angles = np.radians(np.arange(0.0, 360.0, 2.5))
    xs = np.arange(bracket.BOSS_X[0] - 4.0, bracket.BOSS_X[1] + 4.0 + 1e-9, 1.0)
    ga, gx = np.meshgrid(angles, xs)
    cy, cz = bracket.PLATE[1] / 2, bracket.BOSS_AXIS_Z
    return np.column_stack([gx.ravel(), cy + r * np.cos(ga.ravel()), cz + r * np.sin(ga.ravel())])


def add_sketch(doc):
    """A sketch on the top face: a zig-zag across a hole and the pocket, plus a circle."""
    sk = doc.addObject("Sketcher::SketchObject", "ProbeSketch")
    sk.Placement = App.Placement(App.Vector(0, 0, bracket.PLATE[2]), App.Rotation())
    pts = [(2, 2), (10, 6), (14, 10), (20, 14), (84, 20), (92, 30), (104, 44), (118, 58)]
    for (x0, y0), (x1, y1) in zip(pts, pts[1:]):
        sk.addGeometry(Part.LineSegment(App.Vector(x0, y0, 0), App.Vector(x1, y1, 0)))
    sk.addGeometry(Part.ArcOfCircle(Part.Circle(App.Vector(110, 50, 0), App.Vector(0, 0, 1), 4.0),
                                    0.0, math.pi))
    return sk


def add_mesh(doc, part):
    import MeshPart
    mesh = doc.addObject("Mesh::Feature", "BracketMesh")
    mesh.Mesh = MeshPart.meshFromShape(Shape=part.Shape, LinearDeflection=0.5,
                                       AngularDeflection=0.3, Relative=False)
    return mesh


def cross_check(obj, face, pts, tol, rng):
    """Compare with OCCT (BRepClass via Face.isInside) where we must agree: points whose
    projection is farther than 2 * tol from the boundary (with Strict, points farther
    than tol from the surface are OUT)."""
    edges = Part.Compound([e for e in face.Edges if not e.Degenerated])
    surface = face.Surface
    idx = rng.choice(len(pts), size=min(CROSS_CHECK_POINTS, len(pts)), replace=False)
    checked = agreed = 0
    for i in idx.tolist():
        p = App.Vector(*pts[i])
        u, v = surface.parameter(p)
        foot = surface.value(u, v)
        if Part.Vertex(foot).distToShape(edges)[0] <= 2 * tol:
            continue
        checked += 1
        if obj.Strict and (p - foot).Length > tol:
            agreed += int(obj.Classes[i] == core.OUT)
            continue
        occt = core.IN if face.isInside(foot, 1e-7, True) else core.OUT
        agreed += int(obj.Classes[i] == occt)
    return checked, agreed


def run():
    rng = np.random.default_rng(20261122)
    out = out_dir()
    doc, part = open_bracket()
    top = (part, bracket.top_face_name(part))
    boss = (part, bracket.boss_face_name(part))

    clouds = {
        "TopGrid": add_cloud(doc, "TopGrid", top_grid()),
        "BossGrid": add_cloud(doc, "BossGrid", boss_grid()),
    }
    lx, ly, lz = bracket.PLATE
    big = np.column_stack([rng.uniform(-2, lx + 2, 100_000), rng.uniform(-2, ly + 2, 100_000),
                           np.full(100_000, lz)])
    clouds["LargeCloud"] = add_cloud(doc, "LargeCloud", big)
    sketch = add_sketch(doc)
    mesh = add_mesh(doc, part)
    doc.recompute()

    jobs = [  # name, face ref, points ref, tolerance, visible in the render
        ("TopFace_Grid", top, clouds["TopGrid"], TOLERANCE, True),
        ("BossFace_Grid", boss, clouds["BossGrid"], TOLERANCE, True),
        ("TopFace_Sketch", top, sketch, TOLERANCE, False),
        ("TopFace_MeshVertices", top, mesh, FINE_TOLERANCE, False),
        ("TopFace_100k_random", top, clouds["LargeCloud"], FINE_TOLERANCE, False),
    ]
    report = {"library": core.library_path, "library_version": core.version(),
              "freecad": ".".join(App.Version()[:3]), "part": part.Label, "features": []}
    failures = []
    for name, face_ref, points_ref, tol, visible in jobs:
        t0 = time.perf_counter()
        obj = mfgeom.make_point_classification(doc, face_ref, points_ref, tol, name=name)
        seconds = time.perf_counter() - t0
        n = len(obj.Classes)
        face = part.Shape.getElement(face_ref[1])
        pts = pointcloud.kernel_to_array(obj.Points)
        checked, agreed = cross_check(obj, face, pts, tol, rng)
        entry = {
            "name": name, "face": f"{part.Label}.{face_ref[1]}", "surface": face.Surface.TypeId,
            "points_from": points_ref.TypeId, "points": n, "tolerance_mm": tol,
            "method": obj.Method, "parameter_tolerance": obj.ParameterTolerance,
            "distortion": obj.Distortion, "in": obj.CountIn, "on": obj.CountOn,
            "out": obj.CountOut, "max_distance_to_surface_mm": obj.MaxDistanceToSurface.Value,
            "seconds": seconds, "points_per_second": n / seconds if seconds > 0 else None,
            "occt_cross_check": {"checked": checked, "agreed": agreed},
            "valid": obj.isValid(),
        }
        report["features"].append(entry)
        if not obj.isValid() or obj.CountIn + obj.CountOn + obj.CountOut != n or agreed != checked:
            failures.append(name)
    # Visibility set headless is not kept in the file (no GuiDocument.xml): tell the
    # renderer what to show.
    report["show"] = [part.Name] + [name for name, *_r, visible in jobs if visible]
    fcstd = os.path.join(out, "demo_pointclass.FCStd")
    doc.saveAs(fcstd)
    report["fcstd"] = fcstd
    report["failures"] = failures
    with open(os.path.join(out, "demo_pointclass.json"), "w", encoding="utf-8") as f:
        json.dump(report, f, indent=2)
    lines = [f"mfgeom point classification demo (libmfgeom {report['library_version']}, "
             f"FreeCAD {report['freecad']})", f"part: {part.Label}", ""]
    head = (f"{'feature':24} {'face':16} {'method':6} {'tol mm':>7} {'points':>7} {'IN':>7} "
            f"{'ON':>6} {'OUT':>7} {'ms':>8} {'pts/s':>9}  OCCT agree")
    lines += [head, "-" * len(head)]
    for e in report["features"]:
        lines.append(
            f"{e['name']:24} {e['face']:16} {e['method']:6} {e['tolerance_mm']:7.3f} "
            f"{e['points']:7d} {e['in']:7d} {e['on']:6d} {e['out']:7d} {e['seconds'] * 1e3:8.1f} "
            f"{e['points_per_second']:9.0f}  {e['occt_cross_check']['agreed']}/"
            f"{e['occt_cross_check']['checked']}")
    lines += ["", f"saved {fcstd}",
              "result: " + ("OK" if not failures else "FAILED: " + ", ".join(failures))]
    text = "\n".join(lines) + "\n"
    with open(os.path.join(out, "demo_pointclass.txt"), "w", encoding="utf-8") as f:
        f.write(text)
    App.Console.PrintMessage(text)
    App.closeDocument(doc.Name)
    return 1 if failures else 0


try:
    rc = run()
except Exception:  # the script's exit code is the only signal a wrapper gets
    traceback.print_exc()
    rc = 2
sys.exit(rc)
