# SPDX-License-Identifier: LGPL-2.1-or-later
"""bench_mould.py - times the mould tooling end to end (issue 21): from a part to its
core and cavity (Mould parting analysis, parting line, parting and shut-off surfaces,
tooling split and every check of mfgeom.app.mould.check_mould) on generated parts of
about 50, 500 and 5 000 faces.

    MFGEOM_LIBRARY=build/libmfgeom.so /usr/bin/python3 bench/bench_mould.py [--quick]

(--quick: the 50 and 500 face parts.)  The measurement runs in ``freecadcmd`` (this file,
with MFGEOM_BENCH_MOULD_CHILD set to its result file); prints a Markdown table.

The parts: a plate 20 mm thick with features on a 10 mm grid on its top and bottom,
cycling through a rectangular pocket, a blind hole, a round boss, a pocket with filleted
corners, a through-hole (an inner parting loop, filled by a shut-off surface) and a
drilled hole (a cone tip: a sampled face), all demouldable along +-z: the parting line
is the top rim, one loop per through-hole inside it.

No peer: nothing in FreeCAD or its add-ons makes core and cavity (the issue names
SolidWorks Mold Tools and NX MoldWizard, which are not available here).
"""

import json
import math
import os
import subprocess
import sys
import tempfile
import time

SIZES = ((12, "~50"), (140, "~500"), (1400, "~5000"))
MARGIN = 10.0


def make_part(features):
    """The plate with ``features`` features (see the module docstring)."""
    import FreeCAD as App
    import Part
    cols = int(math.ceil(math.sqrt(features / 2)))
    pitch, inset, thick = 10.0, 8.0, 20.0
    size = pitch * (cols - 1) + 2 * inset
    plate = Part.makeBox(size, size, thick)
    cuts, bosses = [], []
    for n in range(features):
        top = n % 2 == 0
        k = n // 2
        x, y = inset + pitch * (k % cols), inset + pitch * (k // cols)
        z0, up = (thick, -1.0) if top else (0.0, 1.0)
        kind = n % 6
        if kind == 0:
            tool = Part.makeBox(5, 4, 4, App.Vector(x - 2.5, y - 2, z0 - 4 if top else -1))
        elif kind == 1:
            tool = Part.makeCylinder(2.0, 5, App.Vector(x, y, z0 - 4 if top else -1))
        elif kind == 2:
            boss = Part.makeCylinder(2.0, 3, App.Vector(x, y, thick if top else -3))
            bosses.append(boss)
            continue
        elif kind == 3:
            box = Part.makeBox(6, 5, 4, App.Vector(x - 3, y - 2.5, z0 - 4 if top else -1))
            vertical = [e for e in box.Edges
                        if abs(e.Vertexes[0].Point.z - e.Vertexes[1].Point.z) > 1]
            tool = box.makeFillet(1.0, vertical)
        elif kind == 4:
            tool = Part.makeCylinder(1.5, thick + 2, App.Vector(x, y, -1))
        else:
            r = 1.8
            cyl = Part.makeCylinder(r, 4, App.Vector(x, y, z0 + up * 4), App.Vector(0, 0, -up))
            tip = Part.makeCone(r, 0, r / math.tan(math.radians(59)),
                                App.Vector(x, y, z0 + up * 3.99), App.Vector(0, 0, up))
            tool = cyl.fuse(tip).removeSplitter()
            tool = tool.fuse(Part.makeCylinder(r, 2, App.Vector(x, y, z0 - up * 1.5),
                                               App.Vector(0, 0, up)))
        cuts.append(tool)
    if bosses:
        plate = plate.fuse(bosses)
    part = plate.cut(cuts)
    return part.Solids[0]


def _child(out_path, sizes):
    from mfgeom.app import mould
    rows = []
    for features, label in sizes:
        t0 = time.perf_counter()
        part = make_part(features)
        t1 = time.perf_counter()
        result, timings = mould.analyse_and_mould(part, MARGIN)
        t2 = time.perf_counter()
        rows.append({"label": label, "faces": len(part.Faces), "build_s": t1 - t0,
                     "total_s": t2 - t1, **timings,
                     "loops": len(result.line.loops),
                     "inner": sum(1 for o in result.line.outer if not o),
                     "core_faces": len(result.core.Faces),
                     "cavity_faces": len(result.cavity.Faces),
                     "checks_ok": all(v["ok"] for v in result.checks.values())})
        with open(out_path, "w", encoding="utf-8") as f:
            json.dump(rows, f)


def main():
    quick = "--quick" in sys.argv[1:]
    sizes = SIZES[:2] if quick else SIZES
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "rows.json")
        env = dict(os.environ, MFGEOM_BENCH_MOULD_CHILD=out,
                   MFGEOM_BENCH_MOULD_SIZES=json.dumps(sizes))
        here = os.path.dirname(os.path.abspath(__file__))
        env["PYTHONPATH"] = os.pathsep.join(
            [os.path.join(os.path.dirname(here), "workbench"), env.get("PYTHONPATH", "")])
        log = os.path.join(tmp, "log")
        with open(log, "w") as f:
            subprocess.run(["timeout", "3600", "freecadcmd", os.path.abspath(__file__)],
                           env=env, stdout=f, stderr=subprocess.STDOUT, check=False)
        rows = json.load(open(out)) if os.path.exists(out) else []
        if len(rows) < len(sizes):
            sys.stderr.write(open(log).read()[-3000:])
    print("| part | faces | analysis s | parting line s | surfaces + split + checks s | "
          "total s | loops (inner) | checks |")
    print("|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['label']} faces | {r['faces']} | {r['analysis_s']:.2f} | "
              f"{r['parting_line_s']:.2f} | {r['blocks_s']:.2f} | {r['total_s']:.2f} | "
              f"{r['loops']} ({r['inner']}) | {'ok' if r['checks_ok'] else 'FAILED'} |")
    return 0 if len(rows) == len(sizes) and all(r["checks_ok"] for r in rows) else 1


if os.environ.get("MFGEOM_BENCH_MOULD_CHILD"):
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(
        os.path.abspath(__file__))), "workbench"))
    _child(os.environ["MFGEOM_BENCH_MOULD_CHILD"],
           json.loads(os.environ.get("MFGEOM_BENCH_MOULD_SIZES", json.dumps(SIZES))))
    os._exit(0)
elif __name__ == "__main__":
    sys.exit(main())
