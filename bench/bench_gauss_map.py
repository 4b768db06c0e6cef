# SPDX-License-Identifier: LGPL-2.1-or-later
"""bench_gauss_map.py - times mfgeom.app.gauss_map.part_gauss (the Gaussian maps of a
part's faces and the edge adjacency, from OCCT) on generated parts with many B-spline
faces (issue 17, item 3: the 305-face fan under 2 s end to end, a 5 000-face mixed part
under 5 s).

Run with the system interpreter (FreeCAD is found by mfgeom.paths):
    MFGEOM_LIBRARY=build/libmfgeom.so /usr/bin/python3 bench/bench_gauss_map.py [--profile]
The parts are built once and cached as BREP files under build/bench_gauss_map/ (building
the 5 000-face part takes a few minutes of OCCT booleans).  Prints a Markdown table: per
part the faces, the B-spline faces, part_gauss wall and CPU time (best of 3 each), its
normals, the largest shrink and the warnings; --profile prints cProfile's top entries
for the biggest part.

The parts:
* fan: a disc (radius 60, 6 thick) with a hex hub bore and ``BLADES`` blades, each lofted
  (ruled=False) through 3 twisted B-spline sections (a cambered aerofoil-like closed curve
  interpolated through 12 points), fused on the disc (no fillets: OCCT took minutes).
* mixed: bench_parting.make_part (a cube with pockets, holes, drilled holes, filleted
  pockets, bosses and inclined holes on each side) with ``MIXED_PER_SIDE`` features a side,
  plus a 10 x 10 field of B-spline bumps (each a small lofted blade) on one side.
"""

import math
import os
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
sys.path.append(os.path.join(REPO, "workbench"))
sys.path.append(HERE)
from mfgeom import paths  # noqa: E402
paths.add_freecad_to_path()  # FreeCAD's lib and Mod/Part

import FreeCAD as App  # noqa: E402
import Part  # noqa: E402

BLADES = 30
MIXED_PER_SIDE = 170
CACHE = os.path.join(REPO, "build", "bench_gauss_map")


def _section(chord, thickness, twist_deg, z, radius_at):
    """A closed B-spline aerofoil-like section at height z, rotated by twist about z."""
    pts = []
    n = 12
    for k in range(n):
        t = 2 * math.pi * k / n
        x = chord / 2 * math.cos(t)
        y = thickness / 2 * math.sin(t) + 0.15 * chord * (1 - (2 * x / chord) ** 2) / 2
        pts.append((x, y))
    c, s = math.cos(math.radians(twist_deg)), math.sin(math.radians(twist_deg))
    vec = [App.Vector(radius_at + c * x - s * y, s * x + c * y, z) for x, y in pts]
    curve = Part.BSplineCurve()
    curve.interpolate(vec, PeriodicFlag=True)
    return Part.Wire([curve.toShape()])


def make_blade(radius_at, height, chord, z0=0.0, twist=25.0):
    sections = [_section(chord * (1 - 0.2 * f), chord * 0.12, twist * f, z0 + height * f,
                         radius_at) for f in (-0.05, 0.5, 1.0)]
    return Part.makeLoft(sections, True, False)


def make_fan():
    disc = Part.makeCylinder(60, 6)
    hub = Part.makeCylinder(14, 16)
    hexagon = Part.makePolygon([App.Vector(8 * math.cos(k * math.pi / 3),
                                           8 * math.sin(k * math.pi / 3), -1)
                                for k in range(7)])
    bore = Part.Face(hexagon).extrude(App.Vector(0, 0, 20))
    body = disc.fuse(hub)
    blades = []
    for k in range(BLADES):
        b = make_blade(38, 24, 22, z0=6.0)
        b.rotate(App.Vector(), App.Vector(0, 0, 1), 360.0 * k / BLADES)
        blades.append(b)
    body = body.cut(bore).fuse(blades)
    return body.Solids[0] if len(body.Solids) == 1 else body


def make_mixed():
    import bench_parting
    block = bench_parting.make_part(MIXED_PER_SIDE)
    bb = block.BoundBox
    bumps = []
    for i in range(10):
        for j in range(10):
            b = make_blade(0, 3, 6, z0=-0.5, twist=40)
            b.translate(App.Vector(bb.XMin + 12 + 8.5 * i, bb.YMin + 12 + 8.5 * j, bb.ZMax))
            bumps.append(b)
    part = block.fuse(bumps)
    return part.Solids[0] if len(part.Solids) == 1 else part


def cached(name, maker):
    os.makedirs(CACHE, exist_ok=True)
    path = os.path.join(CACHE, name + ".brep")
    if os.path.exists(path):
        s = Part.Shape()
        s.read(path)
        return s
    t0 = time.perf_counter()
    s = maker()
    s.exportBrep(path)
    sys.stderr.write(f"built {name}: {len(s.Faces)} faces in {time.perf_counter() - t0:.1f} s\n")
    return s


def count_bspline(shape):
    return sum(1 for f in shape.Faces
               if isinstance(f.Surface, (Part.BSplineSurface, Part.BezierSurface)))


def main():
    from mfgeom.app import gauss_map
    parts = [("fan", cached("fan", make_fan)), ("mixed", cached("mixed", make_mixed))]
    only = [a for a in sys.argv[1:] if not a.startswith("--")]
    if only:
        parts = [p for p in parts if p[0] in only]
    print("| part | faces | B-spline faces | part_gauss wall (s) | CPU (s) | normals "
          "| max shrink (rad) | warnings |")
    print("|---|---|---|---|---|---|---|---|")
    for name, shape in parts:
        best, best_cpu = math.inf, math.inf
        for _ in range(3):
            warnings = []
            t0, c0 = time.perf_counter(), time.process_time()
            faces, adj, _ = gauss_map.part_gauss(shape, warnings=warnings)
            best = min(best, time.perf_counter() - t0)
            best_cpu = min(best_cpu, time.process_time() - c0)
        print(f"| {name} | {len(shape.Faces)} | {count_bspline(shape)} | {best:.2f} | "
              f"{best_cpu:.2f} | {sum(len(f.normals) for f in faces)} | "
              f"{max(f.shrink for f in faces):.2g} | {len(warnings)} |", flush=True)
    if "--profile" in sys.argv:
        import cProfile
        import pstats
        name, shape = parts[-1]
        prof = cProfile.Profile()
        prof.enable()
        gauss_map.part_gauss(shape)
        prof.disable()
        pstats.Stats(prof).sort_stats("cumulative").print_stats(25)


if __name__ == "__main__":
    main()
