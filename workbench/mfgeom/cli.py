# SPDX-License-Identifier: LGPL-2.1-or-later
"""The ``mfgeom`` command-line tool, for scripting outside FreeCAD: libmfgeom's visibility maps,
maximum/level/minimum intersections, point classification and 2-D medial axis on JSON, the
parting analysis of part files, and the rotational sweep and medial surface of mesh files.

Every subcommand reads one JSON document from a file (or stdin when the file is omitted
or ``-``) and prints one JSON document on stdout.  Errors are printed on stderr as
``{"error": "..."}`` and the exit code is 2 -- every error: bad usage or input, a missing
library, a closed stdin, and a stdout that cannot take the result (closed, a pipe whose
reader has gone, a full disk).

    mfgeom visibility-map   [FILE] [--draft-angle RAD] [--negative]
        in:  {"normals": [[x, y, z], ...], "draft_angle": 0, "negative": false}
             or a bare list of normals
        out: {"kind": "polygon", "vertices": [[x, y, z], ...], "closed": false}
    mfgeom max-intersection [FILE]
    mfgeom level-regions    [FILE] --level K
    mfgeom min-intersection [FILE]
        in:  {"maps": [MAP, ...], "weights": [w, ...]} or a bare list of maps; a MAP is a
             list of vertices (a counter-clockwise convex polygon) or an object
             {"kind": ..., "vertices": [...], "closed": false} as visibility-map prints it
        out: {"count": c, "direction": [x, y, z], "margin": rad,
              "regions": [{"kind", "closed", "vertices", "cover", "centre", "margin"}, ...]}
             (min-intersection regions have kind "face" and no vertices: faces of the
             arrangement, not convex; a list of vertices is scaled to unit length)
    mfgeom classify-points  [FILE] [--names]
        in:  {"rings": [[[x, y], ...], ...], "points": [[x, y], ...], "tol": e}
        out: {"codes": [0 | 1 | 2, ...]}   (0 OUT, 1 IN, 2 ON; --names adds "names")
    mfgeom medial-axis      [FILE] --tolerance T [-o OUT]
        in:  {"rings": [[[x, y], ...], ...], "tolerance": T} or a bare list of rings
        out: {"tolerance", "branches": [{"points": [[x, y], ...], "radii": [...],
              "ends": [j0, j1]}], "junctions": [{"point": [x, y], "radius", "degree",
              "elements": [...]}], "seconds"}   (ends: junction index, -1 a leaf;
             elements: edge e -> e, reflex vertex k -> -1-k); with -o the document
             goes to OUT and stdout gets {"output", "branches", "junctions", "points"}
    mfgeom parting PART.step|.stp|.brep|.FCStd ... [--mode mould|nc3axis] [--draft DEG]
                   [--weighting count|area] [--all-faces] [--deflection DEG]
                   [--json OUT] [--csv OUT] [-j N] [--timeout S]
        in:  part files (not JSON); each is analysed by its own worker process
             (mfgeom.app.parting_batch, which needs FreeCAD), N at a time
        out: {"options": {...}, "parts": [PART, ...], "failed": k} in the order given,
             PART = {"path", "solids": [REPORT, ...], "timings"} or {"path", "error"};
             REPORT = mfgeom.parting.report(...) of one solid ("direction",
             "margin_deg", "covered_count", "total_count", "undercut_faces",
             "side_cores" | "setups", "faces", "timings_s", ...) with its "name",
             "source" (PATH:NAME) and "uncovered_faces".  With --json the document
             goes to OUT and stdout gets {"json": OUT, "parts": n, "failed": k};
             --csv writes one row per face of every solid (write_report_csv).  A
             failing part does not stop the others; the exit code is 2 (with
             {"error": ...} on stderr naming the failed parts) if any part failed, 0
             if all succeeded.
    mfgeom sweep IN.stl|.obj --axis-point X Y Z --axis-dir X Y Z --angle DEG
                 --tolerance T -o OUT.stl|.obj [--ascii] [--json REPORT]
        in:  a closed, outward oriented triangle mesh (mfgeom.meshio: STL binary or
             ASCII, OBJ), not JSON
        out: the volume swept by turning it about the axis by 0 .. DEG degrees (360: the
             solid of revolution) is written to OUT (STL binary unless --ascii, or OBJ);
             stdout gets {"input", "output", "axis_point", "axis_dir", "angle_deg",
             "tolerance", "input_triangles", "input_vertices", "triangles", "vertices",
             "volume", "area", "bbox": [[min], [max]], "time_s": {"read", "sweep",
             "write"}}; --json also writes it to REPORT
    mfgeom medial-surface IN.stl|.obj --tolerance T [--full] [--threads N]
                          [--json OUT.json] [--ply OUT.ply | --obj OUT.obj]
        in:  a closed, outward oriented triangle mesh (as sweep), not JSON; a curved
             solid comes in tessellated and gets the medial surface of its tessellation
        out: the medial surface (major part; --full: all of it) within T of the true
             one: {"input", "tolerance", "full", "threads", "input_vertices",
             "input_triangles", "elements": {"faces", "edges", "vertices", "kinds",
             "convex", "face_of_triangle", "face_planes", "edge_segments",
             "vertex_points"}, "sheets": [{"elements", "form", "form_name", "area",
             "vertices", "triangles", "radii"}, ...], "seams": [{"elements", "kind",
             "points", "radii", "ends"}, ...], "junctions": [{"point", "radius",
             "elements", "kind"}, ...], "cost": {...}, "time_s": {"read", "medial",
             "write"}} (mfgeom.medialio.document).  With --json the document goes to
             OUT.json and stdout gets a summary {"input", "json", "ply"/"obj", "faces",
             "edges", "vertices", "sheets", "seams", "junctions", "sheet_triangles",
             "time_s"}.  --ply writes the sheets as one ASCII PLY mesh with a per-vertex
             "radius" and a per-face "sheet"; --obj the sheets and seams as OBJ groups
"""

import argparse
import io
import json
import math
import os
import sys

from mfgeom import paths

EXIT_ERROR = 2
CODE_NAMES = {0: "OUT", 1: "IN", 2: "ON"}


class CliError(Exception):
    """A user-facing error: reported as {"error": message} with exit code 2."""


class _Parser(argparse.ArgumentParser):
    """argparse that reports usage errors as JSON too."""

    def error(self, message):
        raise CliError(f"{self.prog}: {message}")

    def _print_message(self, message, file=None):
        # --help and usage go to stdout: a stdout that cannot take them is a CliError too
        if message and (file is None or file is sys.stdout):
            _flush_stdout(message)
        else:
            super()._print_message(message, file)


# --------------------------------------------------------------------------- #
# Input helpers                                                               #
# --------------------------------------------------------------------------- #

def _read_json(path):
    where = "stdin" if path in (None, "-") else path
    try:
        if where == "stdin":
            if sys.stdin is None:            # started with stdin closed (<&-)
                raise CliError("cannot read stdin: it is closed; give the input FILE or "
                               "pipe the JSON in")
            text = sys.stdin.read()
        else:
            with open(path, encoding="utf-8") as f:
                text = f.read()
    except OSError as exc:
        raise CliError(f"cannot read {where}: {exc.strerror or exc}") from None
    except UnicodeDecodeError as exc:
        raise CliError(f"cannot read {where}: not UTF-8 text ({exc.reason} at byte "
                       f"{exc.start})") from None
    try:
        return json.loads(text)
    except json.JSONDecodeError as exc:
        raise CliError(f"invalid JSON in {where}: {exc}") from None


def _field(doc, key, default=None, required=False):
    if isinstance(doc, dict):
        if key in doc and doc[key] is not None:
            return doc[key]
        if required:
            raise CliError(f"missing key {key!r}")
        return default
    raise CliError(f"expected a JSON object with key {key!r}")


def _number(value, what):
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise CliError(f"{what} must be a number, got {json.dumps(value)}")
    return float(value)


def _vectors(value, dim, what):
    """A list of dim-vectors of numbers (an empty list is allowed)."""
    if not isinstance(value, list):
        raise CliError(f"{what} must be a list of [{', '.join('xyz'[:dim])}] lists")
    out = []
    for i, v in enumerate(value):
        if not isinstance(v, list) or len(v) != dim:
            raise CliError(f"{what}[{i}] must be a list of {dim} numbers")
        out.append([_number(x, f"{what}[{i}]") for x in v])
    return out


def _maps(doc):
    """The maps and weights of a max/level/min-intersection input."""
    from mfgeom import core
    maps_in = doc if isinstance(doc, list) else _field(doc, "maps", required=True)
    weights = None if isinstance(doc, list) else _field(doc, "weights")
    if not isinstance(maps_in, list):
        raise CliError("'maps' must be a list")
    maps = []
    for i, m in enumerate(maps_in):
        if isinstance(m, dict):
            kind = m.get("kind", "polygon")
            if kind not in ("null", "point", "edge", "polygon"):
                raise CliError(f"maps[{i}].kind must be null, point, edge or polygon, "
                               f"got {json.dumps(kind)}")
            verts = _vectors(m.get("vertices", []), 3, f"maps[{i}].vertices")
            closed = m.get("closed", False)
            if not isinstance(closed, bool):
                raise CliError(f"maps[{i}].closed must be true or false")
            maps.append(core.VisibilityMap(kind, verts, closed))
        else:
            maps.append(_vectors(m, 3, f"maps[{i}]"))
    if weights is not None:
        if not isinstance(weights, list):
            raise CliError("'weights' must be a list of numbers")
        weights = [_number(w, f"weights[{i}]") for i, w in enumerate(weights)]
    return maps, weights


# --------------------------------------------------------------------------- #
# Output helpers                                                              #
# --------------------------------------------------------------------------- #

def _list(array):
    return [[float(x) for x in row] for row in array]


def _regions_json(res):
    regions = []
    for r in range(len(res.regions)):
        regions.append({
            "kind": res.kinds[r],
            "closed": bool(res.closed[r]),
            "vertices": _list(res.regions[r]),
            "cover": [int(i) for i in res.covers[r]],
            "centre": [float(x) for x in res.centres[r]],
            "margin": float(res.margins[r]),
        })
    count = res.count
    count = int(count) if float(count).is_integer() and not isinstance(count, bool) else count
    return {
        "count": count,
        "direction": None if res.direction is None else [float(x) for x in res.direction],
        "margin": float(res.margin),
        "regions": regions,
    }


# --------------------------------------------------------------------------- #
# Subcommands                                                                 #
# --------------------------------------------------------------------------- #

def cmd_visibility_map(args):
    from mfgeom import core
    doc = _read_json(args.file)
    if isinstance(doc, list):
        normals, draft, negative = doc, 0.0, False
    else:
        normals = _field(doc, "normals", required=True)
        draft = _number(_field(doc, "draft_angle", 0.0), "draft_angle")
        negative = _field(doc, "negative", False)
        if not isinstance(negative, bool):
            raise CliError("'negative' must be true or false")
    if args.draft_angle is not None:
        draft = args.draft_angle
    if args.negative:
        negative = True
    import numpy as np
    normals = np.asarray(_vectors(normals, 3, "normals"), dtype=np.float64).reshape(-1, 3)
    vm = core.visibility_map(normals, draft_angle=draft, negative=negative)
    return {"kind": vm.kind, "vertices": _list(vm.vertices), "closed": bool(vm.closed)}


def cmd_max_intersection(args):
    from mfgeom import core
    maps, weights = _maps(_read_json(args.file))
    return _regions_json(core.max_intersection(maps, weights=weights))


def cmd_level_regions(args):
    from mfgeom import core
    maps, weights = _maps(_read_json(args.file))
    return _regions_json(core.level_regions(maps, args.level, weights=weights))


def cmd_min_intersection(args):
    from mfgeom import core
    maps, weights = _maps(_read_json(args.file))
    out = _regions_json(core.min_intersection(maps, weights=weights))
    for r in out["regions"]:   # faces of least coverage are not convex: no vertices
        r.pop("vertices", None)
    return out


def cmd_classify_points(args):
    import numpy as np
    from mfgeom import core
    doc = _read_json(args.file)
    rings_in = _field(doc, "rings", required=True)
    if not isinstance(rings_in, list):
        raise CliError("'rings' must be a list of rings")
    rings = [np.asarray(_vectors(r, 2, f"rings[{i}]"), dtype=np.float64).reshape(-1, 2)
             for i, r in enumerate(rings_in)]
    points = np.asarray(_vectors(_field(doc, "points", required=True), 2, "points"),
                        dtype=np.float64).reshape(-1, 2)
    tol = _number(_field(doc, "tol", 0.0), "tol")
    codes = [int(c) for c in core.classify_points(rings, points, tol)]
    out = {"codes": codes}
    if args.names:
        out["names"] = [CODE_NAMES[c] for c in codes]
    return out


def cmd_medial_axis(args):
    """The medial axis of a face given as rings (outer boundary and holes, even-odd, as
    classify-points reads them): branches with points and radii, junctions with points,
    radii, degrees and the boundary elements their discs touch."""
    import time
    import numpy as np
    from mfgeom import core
    doc = _read_json(args.file)
    rings_in = doc if isinstance(doc, list) else _field(doc, "rings", required=True)
    if not isinstance(rings_in, list):
        raise CliError("'rings' must be a list of rings")
    rings = [np.asarray(_vectors(r, 2, f"rings[{i}]"), dtype=np.float64).reshape(-1, 2)
             for i, r in enumerate(rings_in)]
    tol = args.tolerance
    if tol is None and isinstance(doc, dict):
        tol = doc.get("tolerance", doc.get("tol"))
    if tol is None:
        raise CliError("give --tolerance T (or \"tolerance\" in the input)")
    tol = _number(tol, "tolerance")
    if not (math.isfinite(tol) and tol > 0.0):
        raise CliError(f"--tolerance must be positive, got {tol:g}")
    t0 = time.perf_counter()
    ax = core.medial_axis(rings, tol)
    seconds = time.perf_counter() - t0
    jn = ax.junctions
    out = {"tolerance": tol,
           "branches": [{"points": b.points.tolist(), "radii": b.radii.tolist(),
                         "ends": [int(e) for e in b.ends]} for b in ax.branches],
           "junctions": [{"point": jn.points[j].tolist(), "radius": float(jn.radii[j]),
                          "degree": int(jn.degrees[j]),
                          "elements": [int(e) for e in jn.elements[j]]}
                         for j in range(len(jn))],
           "seconds": seconds}
    if not args.output:
        return out
    _write_json(args, args.output, out)
    return {"output": args.output, "tolerance": tol, "branches": len(ax.branches),
            "junctions": len(jn), "points": int(sum(len(b.radii) for b in ax.branches)),
            "seconds": seconds}


# --------------------------------------------------------------------------- #
# parting: batch of part files, one FreeCAD worker process per part           #
# --------------------------------------------------------------------------- #

PART_SUFFIXES = (".step", ".stp", ".brep", ".brp", ".fcstd")
# Where FreeCAD's Python modules are: mfgeom.paths (MFGEOM_FREECAD_LIB overrides).  Without
# them the workers run in freecadcmd.
FREECAD_LIB_DIRS = paths.FREECAD_LIB_DIRS
_freecad_lib = paths.freecad_lib


def _worker_command(request, result, module="parting_batch", what="parting"):
    """argv and environment of a worker (``mfgeom.app.<module>``): plain python3 with
    FreeCAD's lib directory on sys.path when it can be found, else freecadcmd."""
    import shutil
    workbench = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    env = dict(os.environ)
    lib = _freecad_lib()
    # FreeCAD's lib and Mod/Part (FreeCAD 1.0's Part needs its PartEnums module)
    dirs = [workbench] + paths.freecad_python_paths(lib)
    if env.get("PYTHONPATH"):
        dirs.append(env["PYTHONPATH"])
    env["PYTHONPATH"] = os.pathsep.join(dirs)
    if lib:
        return [sys.executable, "-m", f"mfgeom.app.{module}", request, result], env
    freecadcmd = shutil.which("freecadcmd") or shutil.which("FreeCADCmd")
    if not freecadcmd:
        raise CliError(f"{what} needs FreeCAD: its Python modules were not found in "
                       f"{', '.join(FREECAD_LIB_DIRS)} (set MFGEOM_FREECAD_LIB) and "
                       "freecadcmd is not on PATH")
    code = (f"import sys; sys.path.insert(0, {workbench!r}); "
            f"from mfgeom.app import {module}; "
            f"{module}.main([{request!r}, {result!r}])")
    return [freecadcmd, "-c", code], env


def _run_part(path, options, timeout, module="parting_batch"):
    """One part in its own worker process: its result entry (or {"path", "error"})."""
    import subprocess
    import tempfile
    import time
    with tempfile.TemporaryDirectory(prefix="mfgeom-parting-") as tmp:
        request, result = os.path.join(tmp, "request.json"), os.path.join(tmp, "result.json")
        with open(request, "w", encoding="utf-8") as f:
            json.dump({"path": os.path.abspath(path), **options}, f)
        cmd, env = _worker_command(request, result, module)
        t0 = time.perf_counter()
        try:
            proc = subprocess.run(cmd, env=env, stdin=subprocess.DEVNULL,
                                  capture_output=True, text=True, errors="replace",
                                  timeout=timeout)
        except subprocess.TimeoutExpired:
            return {"path": path, "error": f"timed out after {timeout:g} s"}
        wall = time.perf_counter() - t0
        try:
            with open(result, encoding="utf-8") as f:
                out = json.load(f)
        except (OSError, ValueError):
            tail = " ".join(proc.stderr.split()[-40:])
            status = (f"killed by signal {-proc.returncode}" if proc.returncode < 0
                      else f"exit code {proc.returncode}")
            return {"path": path, "error": f"the worker failed ({status})"
                                           + (f": {tail}" if tail else "")}
    out["path"] = path                     # as the user gave it
    if "error" not in out:
        out.setdefault("timings", {})["wall_s"] = wall   # with the worker's start
        for solid in out["solids"]:
            solid["source"] = f"{path}:{solid['name']}"
    return out


def cmd_parting(args):
    from concurrent.futures import ThreadPoolExecutor
    if args.jobs < 1:
        raise CliError("-j must be at least 1")
    if not 0.0 <= args.draft < 90.0:
        raise CliError(f"--draft must be in [0, 90) degrees, got {args.draft:g}")
    if not 0.0 < args.deflection < 90.0:
        raise CliError(f"--deflection must be in (0, 90) degrees, got {args.deflection:g}")
    if args.timeout is not None and not args.timeout > 0:
        raise CliError("--timeout must be positive")
    if not math.isfinite(args.draft + args.deflection):
        raise CliError("--draft and --deflection must be finite")
    options = {"mode": {"mould": "Mould", "nc3axis": "NC3Axis"}[args.mode],
               "draft_deg": args.draft, "weighting": args.weighting,
               "all_faces": bool(args.all_faces), "deflection_deg": args.deflection}
    _worker_command("", "")                # FreeCAD missing: one error, not one per part
    with ThreadPoolExecutor(max_workers=args.jobs) as pool:
        parts = list(pool.map(lambda p: _run_part(p, options, args.timeout), args.parts))
    failed = [p for p in parts if "error" in p]
    doc = {"options": options, "parts": parts, "failed": len(failed)}
    if failed:
        args.failure = (f"{len(failed)} of {len(parts)} parts failed: "
                        + "; ".join(f"{p['path']}: {p['error']}" for p in failed))
    if args.csv:
        from mfgeom.parting import write_report_csv   # numpy, no FreeCAD
        try:
            write_report_csv(args.csv, [s for p in parts for s in p.get("solids", [])])
        except OSError as exc:
            raise CliError(f"cannot write {args.csv}: {exc.strerror or exc}") from None
        args.outputs.add(args.csv)
    if args.json:
        _write_json(args, args.json, doc)
        return {"json": args.json, "parts": len(parts), "failed": len(failed)}
    return doc


def cmd_mould(args):
    if not (math.isfinite(args.margin) and args.margin > 0):
        raise CliError(f"--margin must be a positive length, got {args.margin:g}")
    if args.timeout is not None and not args.timeout > 0:
        raise CliError("--timeout must be positive")
    _worker_command("", "", "mould_batch", "mould")   # FreeCAD missing: say so first
    options = {"out": os.path.abspath(args.out), "margin": args.margin,
               "zero_draft_side": args.zero_draft_side}
    part = _run_part(args.part, options, args.timeout, "mould_batch")
    if "error" in part:
        raise CliError(f"{args.part}: {part['error']}")
    failed = [s for s in part["solids"] if "error" in s]
    if failed:   # the others were written; printed, then exit code 2 with this message
        args.failure = (f"{len(failed)} of {len(part['solids'])} solids failed: "
                        + "; ".join(f"{s['name']}: {s['error']}" for s in failed))
    return part


def _write_json(args, path, doc):
    """``doc`` as JSON to ``path`` (fileio.write_atomic: never a truncated file), recorded
    in the command's outputs so that a later failure removes it."""
    from mfgeom.fileio import write_atomic
    try:
        write_atomic(path, json.dumps(doc, indent=args.indent, allow_nan=False) + "\n")
    except OSError as exc:
        raise CliError(f"cannot write {path}: {exc.strerror or exc}") from None
    args.outputs.add(path)


def _finite(values, what):
    if not all(math.isfinite(x) for x in values):
        raise CliError(f"{what} must be finite, got {' '.join(f'{x:g}' for x in values)}")
    return [float(x) for x in values]


def cmd_sweep(args):
    import time
    from mfgeom import core, meshio
    point = _finite(args.axis_point, "--axis-point")
    direction = _finite(args.axis_dir, "--axis-dir")
    if not any(direction):
        raise CliError("--axis-dir must not be the zero vector")
    if not (math.isfinite(args.angle) and 0.0 < args.angle <= 360.0):
        raise CliError(f"--angle must be in (0, 360] degrees, got {args.angle:g}")
    if not (math.isfinite(args.tolerance) and args.tolerance > 0.0):
        raise CliError(f"--tolerance must be positive, got {args.tolerance:g}")
    meshio.mesh_format(args.output)        # a bad output name fails before the work
    t0 = time.perf_counter()
    vertices, triangles = meshio.read_mesh(args.input)
    t1 = time.perf_counter()
    # 360 degrees exactly is the full turn: math.radians(360) is 2*pi to the last bit
    try:
        result = core.rotational_sweep(vertices, triangles, point, direction,
                                       math.radians(args.angle), args.tolerance)
    except core.MfgError as exc:           # e.g. an open mesh: say which file
        raise CliError(f"{args.input}: {exc}") from None
    t2 = time.perf_counter()
    meshio.write_mesh(args.output, result.vertices, result.triangles, ascii=args.ascii)
    args.outputs.add(args.output)
    t3 = time.perf_counter()
    report = {"input": args.input, "output": args.output, "axis_point": point,
              "axis_dir": direction, "angle_deg": float(args.angle),
              "tolerance": float(args.tolerance), "input_vertices": int(len(vertices)),
              "input_triangles": int(len(triangles)), "vertices": int(len(result.vertices)),
              "triangles": int(len(result.triangles)), "volume": result.volume,
              "area": result.area, "bbox": _list(result.bbox),
              "time_s": {"read": t1 - t0, "sweep": t2 - t1, "write": t3 - t2}}
    if args.json:
        _write_json(args, args.json, report)
    return report


def cmd_medial_surface(args):
    import time
    from mfgeom import core, medialio, meshio
    if not (math.isfinite(args.tolerance) and args.tolerance > 0.0):
        raise CliError(f"--tolerance must be positive, got {args.tolerance:g}")
    if args.threads < 0:
        raise CliError(f"--threads must be >= 0 (0: every CPU), got {args.threads}")
    outputs = [(opt, path) for opt, path in (("--json", args.json), ("--ply", args.ply),
                                              ("--obj", args.obj)) if path]
    for opt, path in outputs:              # a missing directory fails before the work
        folder = os.path.dirname(os.path.abspath(str(path)))
        if not os.path.isdir(folder):
            raise CliError(f"cannot write {path} ({opt}): no directory {folder}")
    t0 = time.perf_counter()
    vertices, triangles = meshio.read_mesh(args.input)
    t1 = time.perf_counter()
    try:
        m = core.medial_surface(vertices, triangles, args.tolerance,
                                major_only=not args.full, threads=args.threads)
    except core.MfgError as exc:           # e.g. an open mesh: say which file
        raise CliError(f"{args.input}: {exc}") from None
    t2 = time.perf_counter()
    if args.ply:
        medialio.write_ply(args.ply, m)
        args.outputs.add(args.ply)
    if args.obj:
        medialio.write_obj(args.obj, m)
        args.outputs.add(args.obj)
    doc = {"input": args.input, "tolerance": float(args.tolerance), "full": bool(args.full),
           "threads": int(args.threads), "input_vertices": int(len(vertices)),
           "input_triangles": int(len(triangles))}
    doc.update(medialio.document(m))
    t3 = time.perf_counter()
    times = {"read": t1 - t0, "medial": t2 - t1, "write": t3 - t2}
    doc["time_s"] = times
    if not args.json:
        return doc
    _write_json(args, args.json, doc)
    summary = {"input": args.input, "json": args.json}
    summary.update({opt[2:]: path for opt, path in outputs if opt != "--json"})
    summary.update(faces=m.nfaces, edges=m.nedges, vertices=m.nvertices,
                   sheets=len(m.sheets), seams=len(m.seams), junctions=len(m.junctions),
                   sheet_triangles=int(sum(len(s.triangles) for s in m.sheets)),
                   time_s=times)
    return summary


def cmd_version(args):
    from mfgeom import __version__, core
    return {"package": __version__, "library": core.version(), "library_path": core.library_path}


def build_parser():
    p = _Parser(prog="mfgeom", description=(
        "libmfgeom from the shell: visibility maps and maximum intersection of spherical "
        "convex polygons (Ha 2001), tolerance-based point classification (Chung & Park "
        "2002), the 2-D medial axis on JSON; the parting analysis of part files; the "
        "rotational sweep and the medial surface of mesh files.  Each subcommand prints "
        "JSON; errors go to stderr as {\"error\": ...} with exit code 2."))
    p.add_argument("--indent", type=int, default=None, help="pretty-print with this indent")
    sub = p.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    sub.required = True

    def add(name, func, help_text):
        sp = sub.add_parser(name, help=help_text, description=help_text)
        sp.add_argument("file", nargs="?", default=None, metavar="FILE",
                        help="input JSON file (default or '-': stdin)")
        sp.set_defaults(func=func)
        return sp

    sp = add("visibility-map", cmd_visibility_map,
             "VM(P) = {d : d.p >= 0} of the normals P: {kind, vertices, closed}")
    sp.add_argument("--draft-angle", type=float, default=None, metavar="RAD",
                    help="shrink the map to {d : d.p^ >= sin(RAD)} (overrides the input)")
    sp.add_argument("--negative", action="store_true", help="the negative map -VM(P)")
    add("max-intersection", cmd_max_intersection,
        "regions covered by the greatest total weight of the maps")
    sp = add("level-regions", cmd_level_regions,
             "locally maximal regions whose covered weight is at least --level")
    sp.add_argument("--level", type=float, required=True, metavar="K")
    add("min-intersection", cmd_min_intersection,
        "the least covered weight and a direction in each least-covered face")
    sp = add("classify-points", cmd_classify_points,
             "classify 2-D points against rings (even-odd) as OUT 0 / IN 1 / ON 2")
    sp.add_argument("--names", action="store_true", help="also print OUT/IN/ON names")
    help_text = ("the medial axis of a face given as JSON rings (outer boundary and holes): "
                 "branches (points, radii, end junctions) and junctions (point, radius, "
                 "degree, touching boundary elements) as JSON")
    sp = add("medial-axis", cmd_medial_axis, help_text)
    sp.add_argument("--tolerance", type=float, default=None, metavar="T",
                    help="samples and interpolated radii within T of the true axis, junctions "
                         "closer than T merged (model units; default: the input's "
                         "\"tolerance\")")
    sp.add_argument("-o", "--output", default=None, metavar="OUT",
                    help="write the axis to OUT (JSON); stdout gets a summary")
    help_text = ("mould parting direction (undercuts, side cores) or 3-axis NC set-up plan "
                 "of every solid in the part files, one FreeCAD worker process per part")
    sp = sub.add_parser("parting", help=help_text, description=help_text)
    sp.add_argument("parts", nargs="+", metavar="PART",
                    help="part files: .step/.stp, .brep/.brp or .FCStd")
    sp.add_argument("--mode", choices=("mould", "nc3axis"), default="mould")
    sp.add_argument("--draft", type=float, default=0.0, metavar="DEG",
                    help="mould: draft angle; nc3axis: tool-axis tilt allowance (degrees)")
    sp.add_argument("--weighting", choices=("count", "area"), default="count")
    sp.add_argument("--all-faces", action="store_true",
                    help="nc3axis: plan for every surface, not only the pockets")
    sp.add_argument("--deflection", type=float, default=math.degrees(1e-3), metavar="DEG",
                    help="largest shrink of a sampled face's map (degrees, default 1e-3 rad)")
    sp.add_argument("--json", default=None, metavar="OUT",
                    help="write the results to OUT; stdout gets a summary")
    sp.add_argument("--csv", default=None, metavar="OUT",
                    help="also write one CSV row per face of every solid to OUT")
    sp.add_argument("-j", "--jobs", type=int, default=1, metavar="N",
                    help="parts analysed at the same time (worker processes)")
    sp.add_argument("--timeout", type=float, default=None, metavar="S",
                    help="give up on a part after S seconds (an error entry)")
    sp.set_defaults(func=cmd_parting, file=None)
    help_text = ("core, cavity and side-core inserts of every solid in a part file (mould "
                 "parting analysis, parting line and surfaces, tooling split, checked), "
                 "written as STEP files into --out")
    sp = sub.add_parser("mould", help=help_text, description=help_text)
    sp.add_argument("part", metavar="PART", help="a part file: .step/.stp, .brep/.brp or .FCStd")
    sp.add_argument("--out", required=True, metavar="DIR",
                    help="directory for <name>_core.step, _cavity.step, _insert<k>.step")
    sp.add_argument("--margin", type=float, default=10.0, metavar="MM",
                    help="the mould block's margin around the part (default 10)")
    sp.add_argument("--zero-draft-side", choices=("Cavity", "Core"), default="Cavity",
                    help="where zero-draft walls touching both sides go (Cavity: the parting "
                         "line along their +d edge)")
    sp.add_argument("--timeout", type=float, default=None, metavar="S",
                    help="give up after S seconds")
    sp.set_defaults(func=cmd_mould, file=None)
    help_text = ("the volume swept by a closed triangle mesh (STL/OBJ) turning about an "
                 "axis by 0 .. DEG degrees, written as STL/OBJ; prints its volume, area, "
                 "box and triangle counts")
    sp = sub.add_parser("sweep", help=help_text, description=help_text)
    sp.add_argument("input", metavar="IN", help="closed mesh: .stl (binary or ASCII) or .obj")
    sp.add_argument("--axis-point", type=float, nargs=3, required=True, metavar=("X", "Y", "Z"))
    sp.add_argument("--axis-dir", type=float, nargs=3, required=True, metavar=("X", "Y", "Z"),
                    help="right-handed: counter-clockwise seen from its tip")
    sp.add_argument("--angle", type=float, required=True, metavar="DEG",
                    help="turn in degrees, (0, 360]; 360 gives the solid of revolution")
    sp.add_argument("--tolerance", type=float, required=True, metavar="T",
                    help="largest distance of the result's boundary from the true one "
                         "(model units)")
    sp.add_argument("-o", "--output", required=True, metavar="OUT",
                    help="result mesh: .stl or .obj")
    sp.add_argument("--ascii", action="store_true", help="write ASCII STL (default binary)")
    sp.add_argument("--json", default=None, metavar="REPORT",
                    help="also write the printed report to REPORT")
    sp.set_defaults(func=cmd_sweep, file=None)
    help_text = ("the medial surface of a closed triangle mesh (STL/OBJ): sheets, seams and "
                 "junctions with their radii and the boundary elements they touch, as JSON, "
                 "PLY (per-vertex radius) or OBJ")
    sp = sub.add_parser("medial-surface", help=help_text, description=help_text)
    sp.add_argument("input", metavar="IN", help="closed mesh: .stl (binary or ASCII) or .obj")
    sp.add_argument("--tolerance", type=float, required=True, metavar="T",
                    help="largest distance of the sheets and seams from the true ones "
                         "(model units)")
    sp.add_argument("--full", action="store_true",
                    help="the full medial surface (default: the major part, sheets between "
                         "elements whose closures are disjoint)")
    sp.add_argument("--threads", type=int, default=0, metavar="N",
                    help="worker threads (default 0: every CPU); the result does not depend on it")
    sp.add_argument("--json", default=None, metavar="OUT",
                    help="write the document to OUT; stdout gets a summary")
    out = sp.add_mutually_exclusive_group()
    out.add_argument("--ply", default=None, metavar="OUT",
                     help="write the sheets to OUT as ASCII PLY with a per-vertex radius")
    out.add_argument("--obj", default=None, metavar="OUT",
                     help="write the sheets (triangles) and seams (polylines) to OUT as OBJ")
    sp.set_defaults(func=cmd_medial_surface, file=None)
    sv = sub.add_parser("version", help="versions of the package and the loaded library")
    sv.set_defaults(func=cmd_version, file=None)
    return p


def _fail(message):
    try:
        sys.stderr.write(json.dumps({"error": str(message)}) + "\n")
        sys.stderr.flush()
    except (AttributeError, OSError, ValueError):   # stderr closed too: the code must do
        pass
    return EXIT_ERROR


def _drop_stdout():
    """After a failed write, point fd 1 at /dev/null so that the interpreter's flush at
    exit does not fail again (and print a traceback or exit 120)."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)
    except (AttributeError, OSError, ValueError):
        pass


def _flush_stdout(text=""):
    """Writes ``text`` to stdout and flushes it; a stdout that cannot take it is a
    CliError (reported on stderr, exit 2) instead of a traceback."""
    if sys.stdout is None:                    # started with stdout closed (>&-)
        raise CliError("cannot write the result: stdout is closed")
    try:
        sys.stdout.flush()
        try:
            fd = sys.stdout.fileno()
        except (AttributeError, io.UnsupportedOperation):   # a caller's StringIO
            sys.stdout.write(text)
            sys.stdout.flush()
            return
        # To the descriptor, in a loop: with PYTHONUNBUFFERED=1 sys.stdout.write ignores
        # a short write to a pipe whose reader has gone, and the result is cut silently.
        data = memoryview(text.encode("utf-8"))
        while data:
            data = data[os.write(fd, data):]
    except (OSError, ValueError) as exc:      # EPIPE (reader gone), ENOSPC, EBADF, closed
        _drop_stdout()
        reason = exc.strerror if isinstance(exc, OSError) and exc.strerror else exc
        raise CliError(f"cannot write the result to stdout: {reason}") from None


def main(argv=None):
    from mfgeom.fileio import Outputs
    outputs = Outputs()   # what this command wrote: removed again if it fails (issue 22)
    try:
        args = build_parser().parse_args(argv)
        args.outputs = outputs
        result = args.func(args)
        text = json.dumps(result, indent=args.indent, allow_nan=False)
        _flush_stdout(text + "\n")
        if getattr(args, "failure", None):   # parting: some parts failed, the rest printed
            return _fail(args.failure)       # (and their report files stay)
    except (CliError, ImportError, ValueError, TypeError, RuntimeError) as exc:
        # usage and input errors, the library not loadable, core.MfgError (a RuntimeError)
        outputs.remove_all()
        return _fail(exc)
    except SystemExit as exc:            # --help / --version printed by argparse
        try:
            _flush_stdout()
        except CliError as err:
            return _fail(err)
        return exc.code
    except KeyboardInterrupt:
        outputs.remove_all()
        return _fail("interrupted")
    except Exception as exc:             # anything unforeseen is still reported as JSON
        outputs.remove_all()
        return _fail(f"{type(exc).__name__}: {exc}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
