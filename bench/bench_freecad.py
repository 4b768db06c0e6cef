# SPDX-License-Identifier: LGPL-2.1-or-later
"""bench_freecad.py - times the FreeCAD path of point classification (feature creation,
recompute and coloured display in the real GUI under Xvfb) for this checkout and for a
baseline commit, and prints a Markdown table with the speed-up and the file size per point.

Run with the system interpreter (it starts FreeCAD itself, once per tree):
    MFGEOM_LIBRARY=build/libmfgeom.so /usr/bin/python3 bench/bench_freecad.py
Options: --quick (3*10^5 points only), --sizes 300000,1000000, --baseline REV
(default: the commit before the lightweight representation; "none" skips it).
Both trees use the same libmfgeom.so, so the table compares the FreeCAD side only.
Inside FreeCAD (MFGEOM_BENCH_CHILD set) the same file runs the measurement.
"""

import json
import os
import sys
import time

# The last commit whose feature stored its points as a Part compound of vertices and
# coloured them through PointColorArray (the representation this benchmark replaced).
BASELINE = "92be5eb"
TARGET_SECONDS = 2.0  # 10^6 points: creation (with display) and recompute, each
TARGET_RATIO = 5.0


# ------------------------------------------------------------------ inside FreeCAD
def _child(out_path, sizes):
    import tempfile

    import numpy as np

    import FreeCAD as App
    import FreeCADGui as Gui
    import Points

    import mfgeom

    rng = np.random.default_rng(20261129)
    rows = []
    tmp = tempfile.mkdtemp(prefix="mfgeom-bench-")
    for n in sizes:
        doc = App.newDocument(f"bench{n}")
        Gui.ActiveDocument = Gui.getDocument(doc.Name)
        box = doc.addObject("Part::Box", "Box")
        box.Length, box.Width, box.Height = 100, 100, 10
        # A face with a hole, so the classification is not a box test.
        hole = doc.addObject("Part::Cylinder", "Hole")
        hole.Radius, hole.Height = 20, 30
        hole.Placement.Base = App.Vector(50, 50, -5)
        cut = doc.addObject("Part::Cut", "Plate")
        cut.Base, cut.Tool = box, hole
        doc.recompute()
        top = [f"Face{i + 1}" for i, f in enumerate(cut.Shape.Faces)
               if abs(f.BoundBox.ZMin - 10) < 1e-9 and abs(f.BoundBox.ZMax - 10) < 1e-9][0]
        pts = np.column_stack([rng.uniform(-5, 105, n), rng.uniform(-5, 105, n),
                               np.full(n, 10.0)])
        cloud = doc.addObject("Points::Feature", "Cloud")
        cloud.Points = Points.Points(list(map(tuple, pts.tolist())))
        doc.recompute()
        for o in (box, hole, cloud):
            o.ViewObject.Visibility = False
        view = Gui.ActiveDocument.ActiveView
        view.viewTop()
        view.fitAll()
        Gui.updateGui()
        before = os.path.join(tmp, f"before{n}.FCStd")
        doc.saveAs(before)

        def shown():
            view.redraw()
            Gui.updateGui()

        t0 = time.perf_counter()
        obj = mfgeom.make_point_classification(doc, (cut, top), cloud, 0.01, name="Classes")
        t_make = time.perf_counter()
        shown()
        t1 = time.perf_counter()
        obj.touch()
        doc.recompute()
        t_recompute = time.perf_counter()
        shown()
        t2 = time.perf_counter()
        after = os.path.join(tmp, f"after{n}.FCStd")
        doc.saveAs(after)
        row = {"n": n, "create": t1 - t0, "recompute": t2 - t1,
               "draw": (t1 - t_make + t2 - t_recompute) / 2,
               "valid": obj.isValid(), "counts": [obj.CountIn, obj.CountOn, obj.CountOut],
               "bytes_per_point": (os.path.getsize(after) - os.path.getsize(before)) / n}
        rows.append(row)
        App.closeDocument(doc.Name)
        for path in (before, after):
            os.remove(path)
    os.rmdir(tmp)
    with open(out_path, "w", encoding="utf-8") as f:
        json.dump(rows, f)


# ------------------------------------------------------------------ driver
def _run_tree(tree, sizes, label):
    """Run the measurement in FreeCAD with ``tree`` installed as the mfgeom add-on."""
    import shutil
    import tempfile
    home = tempfile.mkdtemp(prefix="mfgeom-bench-home-")
    try:
        return _run_in_home(home, tree, sizes, label)
    finally:
        shutil.rmtree(home, ignore_errors=True)


def _run_in_home(home, tree, sizes, label):
    import subprocess
    os.makedirs(os.path.join(home, "Mod"))
    os.symlink(tree, os.path.join(home, "Mod", "mfgeom"))
    out = os.path.join(home, "result.json")
    env = dict(os.environ, FREECAD_USER_HOME=home, QTWEBENGINE_DISABLE_SANDBOX="1",
               MFGEOM_BENCH_CHILD=out, MFGEOM_BENCH_SIZES=",".join(map(str, sizes)))
    log = os.path.join(home, "freecad.log")
    with open(log, "w") as f:
        subprocess.run(["timeout", "1800", "xvfb-run", "-a", "freecad", os.path.abspath(__file__)],
                       env=env, stdout=f, stderr=subprocess.STDOUT, check=False)
    if not os.path.exists(out):
        with open(log, errors="replace") as f:
            tail = f.read()[-2000:]
        sys.stderr.write(f"bench_freecad: the {label} run failed; log tail:\n{tail}\n")
        return None
    with open(out, encoding="utf-8") as f:
        return {r["n"]: r for r in json.load(f)}


def _baseline_tree(root, rev):
    import subprocess
    import tempfile
    tree = tempfile.mkdtemp(prefix="mfgeom-baseline-")
    archive = subprocess.run(["git", "-C", root, "archive", rev, "package.xml", "workbench",
                              "icons"], capture_output=True, check=True).stdout
    subprocess.run(["tar", "-x", "-C", tree], input=archive, check=True)
    # The archived tree carries no library: both trees use MFGEOM_LIBRARY.
    return tree


def main():
    import argparse
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--sizes", default="300000,1000000")
    parser.add_argument("--baseline", default=BASELINE)
    args = parser.parse_args()
    sizes = [300000] if args.quick else [int(s) for s in args.sizes.split(",")]
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    lib = os.environ.get("MFGEOM_LIBRARY", os.path.join(root, "build", "libmfgeom.so"))
    os.environ["MFGEOM_LIBRARY"] = lib
    now = _run_tree(root, sizes, "current")
    old = None
    if args.baseline != "none":
        import shutil
        tree = _baseline_tree(root, args.baseline)
        try:
            old = _run_tree(tree, sizes, f"baseline {args.baseline}")
        finally:
            shutil.rmtree(tree, ignore_errors=True)
    print("## FreeCAD path: point classification feature in the GUI (Xvfb)")
    print()
    load = " / ".join(f"{x:.1f}" for x in os.getloadavg())
    print(f"Random points on a 100 x 100 mm plate face with a hole, tolerance 0.01 mm; "
          f"create = make_point_classification + first coloured redraw, recompute = touch + "
          f"document recompute + redraw; baseline = commit {args.baseline} (Part compound of "
          f"vertices, PointColorArray); same library {os.path.basename(lib)}. Load average "
          f"at the end: {load} on {os.cpu_count()} CPUs; Xvfb renders with Mesa in "
          f"software, one redraw of 10^6 points costs ~0.4-0.9 s of each time.")
    print()
    print("| points | baseline create s | baseline recompute s | baseline B/pt | "
          "now create s | now recompute s | of which one redraw s | now B/pt | "
          "speed-up (create+recompute) |")
    print("|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    ok = now is not None
    for n in sizes:
        r = (now or {}).get(n)
        b = (old or {}).get(n)

        def cell(row, key, fmt):
            return format(row[key], fmt) if row else "n/a"
        ratio = "n/a"
        if r and b:
            ratio = f"{(b['create'] + b['recompute']) / (r['create'] + r['recompute']):.1f}x"
        print(f"| {n} | {cell(b, 'create', '.2f')} | {cell(b, 'recompute', '.2f')} | "
              f"{cell(b, 'bytes_per_point', '.1f')} | {cell(r, 'create', '.2f')} | "
              f"{cell(r, 'recompute', '.2f')} | {cell(r, 'draw', '.2f')} | "
              f"{cell(r, 'bytes_per_point', '.1f')} | {ratio} |")
        if r is None or not r["valid"]:
            ok = False
    big = (now or {}).get(1000000)
    if big:
        met = big["create"] < TARGET_SECONDS and big["recompute"] < TARGET_SECONDS
        print()
        print(f"Target: 10^6 points created and displayed in < {TARGET_SECONDS:g} s and "
              f"recomputed in < {TARGET_SECONDS:g} s, >= {TARGET_RATIO:g}x the baseline: "
              f"{'met' if met else 'MISSED'} "
              f"({big['create']:.2f} s, {big['recompute']:.2f} s).")
    return 0 if ok else 1


if os.environ.get("MFGEOM_BENCH_CHILD"):
    # Run by FreeCAD as a macro: measure, then leave (the GUI would keep running).
    rc = 0
    try:
        _child(os.environ["MFGEOM_BENCH_CHILD"],
               [int(s) for s in os.environ["MFGEOM_BENCH_SIZES"].split(",")])
    except Exception:  # reported in the log; the driver sees the missing result file
        import traceback
        traceback.print_exc()
        rc = 1
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(rc)
elif __name__ == "__main__":
    sys.exit(main())
