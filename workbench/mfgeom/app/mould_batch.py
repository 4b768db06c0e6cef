# SPDX-License-Identifier: LGPL-2.1-or-later
"""Core, cavity and inserts of one part file (FreeCAD App layer): the worker of
``mfgeom mould PART --out DIR`` (issue 21), started by :mod:`mfgeom.cli` as

    python3 -m mfgeom.app.mould_batch REQUEST.json RESULT.json

REQUEST is ``{"path", "out", "margin", "zero_draft_side"}``.  The part file is read as
the parting batch reads it (:func:`mfgeom.app.parting_batch.load_sources`); every solid
is moulded on its own (:func:`mfgeom.app.mould.analyse_and_mould`) and written to
``OUT/<name>_core.step``, ``_cavity.step``, ``_insert<k>.step``, each atomically (a
temporary file renamed into place, so a failure leaves no truncated file).  RESULT gets
``{"path", "solids": [{"name", "files", "volumes", "checks", "timings"} or {"name",
"error"}], "failed"}`` or ``{"path", "error"}``; the worker exits 0 either way.
"""

import json
import os
import sys

import FreeCAD  # noqa: F401  (before Part: Part alone crashes in plain python3)
import Part

from mfgeom.app import mould, parting_batch


def mould_solid(label, source, names, out, margin, zero_draft_side):
    """One solid of a part file: its result entry, its STEP files written (or none)."""
    from mfgeom.app import gauss_map
    shape = gauss_map.shape_of(source)
    if names is not None:   # one solid of several: the faces given are its own
        shape = Part.Solid(Part.Shell([shape.Faces[int(n[4:]) - 1] for n in names]))
    result, timings = mould.analyse_and_mould(shape, margin, zero_draft_side)
    files = mould.export_step_files(result.core, result.cavity, result.inserts, out,
                                    label.replace("/", "_"))
    return {"name": label, "files": files,
            "direction": [float(c) for c in result.line.direction],
            "volumes": {"block": result.block.solid.Volume, "part": result.line.shape.Volume,
                        "core": result.core.Volume, "cavity": result.cavity.Volume,
                        "inserts": [s.Volume for s in result.inserts]},
            "parting_loops": [{"outer": o, "planar": p, "length": w.Length}
                              for w, o, p in zip(result.line.loops, result.line.outer,
                                                 result.line.planar)],
            "split_faces": list(result.line.split_faces),
            "checks": {k: bool(v["ok"]) for k, v in result.checks.items()},
            "timings": timings}


def mould_file(path, out, margin=10.0, zero_draft_side="Cavity"):
    """Mould every solid of the part file ``path`` into the directory ``out``: per solid
    its entry, or ``{"name", "error"}`` where it cannot be moulded (the others are)."""
    os.makedirs(out, exist_ok=True)
    sources, close = parting_batch.load_sources(path)
    solids = []
    try:
        for label, source, names in sources:
            try:
                solids.append(mould_solid(label, source, names, out, margin, zero_draft_side))
            except Exception as exc:  # one solid's failure is its own entry
                solids.append({"name": label, "error": parting_batch.error_text(exc)})
    finally:
        close()
    return {"path": path, "solids": solids,
            "failed": sum(1 for s in solids if "error" in s)}


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    if len(argv) != 2:
        sys.stderr.write("usage: python3 -m mfgeom.app.mould_batch REQUEST.json RESULT.json\n")
        return 2
    with open(argv[0], encoding="utf-8") as f:
        req = json.load(f)
    path = req.get("path", "")
    try:
        text = json.dumps(mould_file(path, req["out"], float(req.get("margin", 10.0)),
                                     req.get("zero_draft_side", "Cavity")), allow_nan=False)
    except Exception as exc:  # reported as the part's error, never a traceback
        text = json.dumps({"path": path, "error": parting_batch.error_text(exc)})
    with open(argv[1], "w", encoding="utf-8") as f:
        f.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
