# SPDX-License-Identifier: LGPL-2.1-or-later
"""bench_thickness.py - the wall-thickness analysis (issue 21, section 4) against the
ray-cast peer, the method of FreeCAD's DFM workbench: from each sample along the inward
normal to the opposite wall.

    MFGEOM_LIBRARY=build/libmfgeom.so /usr/bin/python3 bench/bench_thickness.py [--quick]

(--quick: the bundled tray and cup only.)  Runs in ``freecadcmd`` (this file, with
MFGEOM_BENCH_THICKNESS_CHILD set to its result file); prints a Markdown table.

Both methods get the same samples (the analysis' points: faces tessellated and subdivided
to the default spacing) and the same polyhedron (the medial surface's input mesh).
*Ours*: :func:`mfgeom.app.thickness_feature.thickness_of_shape` minus the sampling, i.e.
the library call (medial surface + ball query).  *Peer*: per sample a ray from the sample
along its inward normal (the area-weighted normal of its face's triangles at that
point) to the first facet of the same polyhedron it meets (numpy, every ray against every
facet: the values; its time is a brute-force one), and the DFM workbench's own form, an
OCCT section of the part with the ray's segment, timed on 300 random samples and
projected to all samples (its values are the numpy rays' up to the tessellation).  The
normals are not timed.  Differing: the share of samples where |ray - ball| > 10 % of the ball, split
into the ray longer (at corners and rib roots the ray runs along the wall or into the
other wall) and shorter.
"""

import json
import os
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)


def vertex_normals(points, triangles):
    """Area-weighted unit normals at the samples (each face's own points)."""
    import numpy as np
    a = points[triangles]
    n = np.cross(a[:, 1] - a[:, 0], a[:, 2] - a[:, 0])     # 2 x area, outward
    out = np.zeros_like(points)
    for k in range(3):
        np.add.at(out, triangles[:, k], n)
    return out / np.maximum(np.linalg.norm(out, axis=1), 1e-300)[:, None]


def ray_peer(vertices, triangles, points, normals, chunk=2048):
    """(thickness per sample (nan: no hit), seconds): from each sample along -normal to
    the first facet hit beyond a rounding allowance (Moller-Trumbore, every ray against
    every facet, vectorised in numpy; FreeCAD's Mesh.nearestFacetOnRay cannot serve: it
    returns hits behind the origin too)."""
    import numpy as np
    A = vertices[triangles[:, 0]]
    e1 = vertices[triangles[:, 1]] - A
    e2 = vertices[triangles[:, 2]] - A
    L = float(np.linalg.norm(vertices.max(0) - vertices.min(0)))
    eps = 1e-9 * L
    out = np.full(len(points), np.nan)
    t0 = time.perf_counter()
    for s in range(0, len(points), chunk):
        o = points[s:s + chunk, None, :]                    # (m, 1, 3)
        d = -normals[s:s + chunk, None, :]
        pv = np.cross(d, e2[None])                          # (m, n, 3)
        det = np.einsum("mnk,nk->mn", pv, e1)
        with np.errstate(divide="ignore", invalid="ignore"):
            inv = 1.0 / det
            tv = o - A[None]
            u = np.einsum("mnk,mnk->mn", tv, pv) * inv
            qv = np.cross(tv, e1[None])
            v = np.einsum("mnk,mk->mn", qv, d[:, 0]) * inv
            t = np.einsum("mnk,nk->mn", qv, e2) * inv
        with np.errstate(invalid="ignore"):
            hit = (np.abs(det) > 1e-300) & (u >= 0) & (v >= 0) & (u + v <= 1) & (t > eps)
            t = np.where(hit, t, np.inf).min(axis=1)
        out[s:s + chunk] = np.where(np.isfinite(t), t, np.nan)
    return out, time.perf_counter() - t0


def occt_ray_seconds(shape, points, normals, count=300, seed=1):
    """Seconds per sample of the DFM workbench's form of the method: an OCCT section of
    the part with the ray's segment (BRepAlgoAPI_Section through Part.Shape.section), on
    ``count`` random samples."""
    import numpy as np
    import FreeCAD as App
    import Part
    rng = np.random.default_rng(seed)
    pick = rng.choice(len(points), size=min(count, len(points)), replace=False)
    L = shape.BoundBox.DiagonalLength
    t0 = time.perf_counter()
    for i in pick:
        p, n = App.Vector(*points[i]), App.Vector(*normals[i])
        edge = Part.LineSegment(p - n * (1e-6 * L), p - n * L).toShape()
        shape.section(edge)
    return (time.perf_counter() - t0) / len(pick)


def parts(quick):
    sys.path[:0] = [os.path.join(REPO, "examples", "parts"), os.path.join(REPO, "tests", "corpus")]
    import cup
    import thin_wall
    out = [("ribbed tray (bundled)", thin_wall.make()), ("cup (bundled)", cup.make())]
    if not quick:
        import corpus
        part = [p for p in corpus.parts() if p.file.startswith("bottle")][0]
        out.append(("OCCT bottle (corpus)", corpus.load(part)[1][0]))
        part = [p for p in corpus.parts() if p.file.startswith("Pump_TopCover")][0]
        out.append(("OCCT Pump_TopCover (corpus)", corpus.load(part)[1][0]))
    return out


def child(result_file, quick):
    import numpy as np
    sys.path.insert(0, os.path.join(REPO, "workbench"))
    from mfgeom import core
    from mfgeom.app import thickness_feature as tf
    from mfgeom.app.sweep_feature import source_mesh
    rows = []
    for name, shape in parts(quick):
        diag = shape.BoundBox.DiagonalLength
        tol = defl = tf.TOLERANCE_FRACTION * diag
        v, t, _c = source_mesh(shape, defl)
        pts, tris, _faces = tf.sample_mesh(shape, defl, tf.default_spacing(shape, defl))
        t0 = time.perf_counter()
        try:
            res = core.wall_thickness(v, t, pts, tol, major_only=False)
        except core.MfgError as exc:
            rows.append({"part": name, "error": str(exc)})
            continue
        ours = time.perf_counter() - t0
        normals = vertex_normals(pts, tris)
        ray, peer = ray_peer(v, t, pts, normals)
        occt = occt_ray_seconds(shape, pts, normals) * len(pts)
        ball = res.thickness
        ok = np.isfinite(ray) & (ball > 1e-9 * diag)
        rel = (ray[ok] - ball[ok]) / ball[ok]
        w = tf.vertex_areas(pts, tris)[ok]
        rows.append({"part": name, "faces": len(shape.Faces), "triangles": len(t),
                     "samples": len(pts), "ours": ours, "peer": peer, "occt": occt,
                     "differ": float(np.mean(np.abs(rel) > 0.1)),
                     "differ_area": float(w[np.abs(rel) > 0.1].sum() / w.sum()),
                     "longer": float(np.mean(rel > 0.1)), "shorter": float(np.mean(rel < -0.1)),
                     "misses": int((~np.isfinite(ray)).sum()),
                     "range": [float(ball.min()), float(ball.max())]})
        print(rows[-1], flush=True)
    with open(result_file, "w") as f:
        json.dump(rows, f)


def main():
    quick = "--quick" in sys.argv
    with tempfile.TemporaryDirectory() as d:
        out = os.path.join(d, "rows.json")
        env = dict(os.environ, MFGEOM_BENCH_THICKNESS_CHILD=out,
                   MFGEOM_BENCH_QUICK="1" if quick else "0")
        subprocess.run(["freecadcmd", os.path.abspath(__file__)], env=env, check=True,
                       stdout=subprocess.DEVNULL)
        with open(out) as f:
            rows = json.load(f)
    print("| part | faces | mesh triangles | samples | ours (medial + balls) | rays, numpy "
          "| rays, OCCT section (projected) | OCCT rays / ours | rays differing > 10 % "
          "(longer / shorter) | thickness range |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        if "error" in r:
            print(f"| {r['part']} | refused: {r['error']} |")
            continue
        print(f"| {r['part']} | {r['faces']} | {r['triangles']} | {r['samples']} | "
              f"{r['ours']:.2f} s | {r['peer']:.2f} s | {r['occt']:.0f} s | "
              f"{r['occt'] / r['ours']:.1f} | "
              f"{100 * r['differ']:.1f} % ({100 * r['longer']:.1f} / {100 * r['shorter']:.1f}); "
              f"{100 * r['differ_area']:.1f} % of the area"
              f"{'; ' + str(r['misses']) + ' rays missed' if r['misses'] else ''} | "
              f"{r['range'][0]:.3g} .. {r['range'][1]:.3g} mm |")


if os.environ.get("MFGEOM_BENCH_THICKNESS_CHILD"):
    child(os.environ["MFGEOM_BENCH_THICKNESS_CHILD"], os.environ.get("MFGEOM_BENCH_QUICK") == "1")
    os._exit(0)
elif __name__ == "__main__":
    main()
