# SPDX-License-Identifier: LGPL-2.1-or-later
"""Batch parting analysis of one part file (FreeCAD App layer): the per-part worker of
``mfgeom parting`` (issue 7, section 4 "Batch").

The command line (:mod:`mfgeom.cli`, FreeCAD-free) starts one worker process per part:

    python3 -m mfgeom.app.parting_batch REQUEST.json RESULT.json

REQUEST is ``{"path": ..., "mode": "Mould" | "NC3Axis", "draft_deg": ..., "weighting":
"count" | "area", "all_faces": bool, "deflection_deg": ..., "tol": rad}``; the worker
writes the part's result (:func:`analyse_file`) to RESULT, or ``{"path", "error"}``, and
exits 0 either way (a worker that dies, e.g. in OCCT on a damaged file, is reported by
the parent from its exit status).  One process per part keeps a crash or a leak in one
part from touching the others.

Which shapes are analysed (the choices the issue left open):

* STEP (.step/.stp), BREP (.brep/.brp): the file's shape; **every solid is analysed on
  its own** (a file with several solids is a catalogue or an assembly, and each solid
  is moulded or machined by itself).  Face names are "FaceN" of the file's whole shape
  (as ``Part.read`` gives it).
* FreeCAD documents (.FCStd): every Part feature with a solid Shape that no other
  Part feature uses (the results of the modelling history: a Body, a Cut, a plain
  Part::Feature; not the tools and bases consumed by them), in document order,
  in global coordinates (their containers' placements applied); each of its solids on
  its own.  Face names are "FaceN" of the object's Shape, as in the GUI and as
  :func:`mfgeom.make_parting_analysis` reports them.
* A file with no solid is an error for that part.

The computation is the one of the PartingAnalysis feature: Gaussian maps of the real
faces (:func:`mfgeom.app.gauss_map.part_gauss`) and :func:`mfgeom.parting.mould_parting`
or :func:`mfgeom.parting.nc_setups`.
"""

import json
import math
import os
import sys
import time

import FreeCAD
import Part

from mfgeom import parting
from mfgeom.app import gauss_map

MODES = ("Mould", "NC3Axis")
STEP_SUFFIXES = (".step", ".stp")
BREP_SUFFIXES = (".brep", ".brp")
FCSTD_SUFFIXES = (".fcstd",)
SUFFIXES = STEP_SUFFIXES + BREP_SUFFIXES + FCSTD_SUFFIXES


class PartError(ValueError):
    """A part that cannot be analysed (unreadable file, no solid)."""


# ------------------------------------------------------------------ loading
def _solid_subsets(shape):
    """[(solid index 1.., face names of that solid in ``shape``)] for every solid."""
    faces = shape.Faces
    out = []
    for k, solid in enumerate(shape.Solids):
        names = [f"Face{i + 1}" for i, f in enumerate(faces)
                 if any(f.isSame(g) for g in solid.Faces)]
        out.append((k + 1, names))
    return out


def _result_objects(doc):
    """Part features (Part::Feature and derived: PartDesign bodies, Part booleans, ...)
    with a solid Shape that no other Part feature uses.  App::Part containers also
    answer ``.Shape`` (the compound of their content) but are not Part features, so
    their content is analysed once, through its own objects."""
    out = []
    for obj in doc.Objects:
        if not obj.isDerivedFrom("Part::Feature"):
            continue
        shape = obj.Shape
        if shape.isNull() or not shape.Solids:
            continue
        if any(user.isDerivedFrom("Part::Feature") for user in obj.InList):
            continue
        out.append(obj)
    return out


def add_module_paths():
    """Puts FreeCAD's module directories (system and user Mod/, and each module in them)
    on sys.path, as freecadcmd does at start-up: a document whose objects come from a
    module (PartDesign::Body, an add-on's features) loads that module by importing it,
    and in plain python3 those objects would otherwise be dropped silently."""
    bases = [os.path.join(FreeCAD.getResourceDir(), "Mod"),
             os.path.join(FreeCAD.getHomePath(), "Mod"),
             os.path.join(FreeCAD.getUserAppDataDir(), "Mod")]
    for base in bases:
        if not os.path.isdir(base):
            continue
        for d in [base] + [os.path.join(base, n) for n in sorted(os.listdir(base))]:
            if os.path.isdir(d) and d not in sys.path:
                sys.path.append(d)


def load_sources(path):
    """[(label, source, face names or None)] to analyse in the part file ``path``: a
    source is a Part.Shape (STEP/BREP) or a document object (FCStd); face names select
    one solid of a shape with several (None: the whole shape, a single solid).  Returns
    (sources, closer): call closer() when done (closes an opened document)."""
    if not os.path.isfile(path):
        raise PartError(f"no such file: {path}")
    suffix = os.path.splitext(path)[1].lower()
    if suffix in STEP_SUFFIXES + BREP_SUFFIXES:
        try:
            shape = Part.read(path)
        except Exception as exc:  # OCCT raises plain RuntimeError / Part.OCCError
            raise PartError(f"cannot read {os.path.basename(path)}: "
                            f"{' '.join(str(exc).split())}") from None
        if shape.isNull() or not shape.Solids:
            raise PartError(f"{os.path.basename(path)} holds no solid")
        stem = os.path.splitext(os.path.basename(path))[0]
        subsets = _solid_subsets(shape)
        if len(subsets) == 1:
            return [(stem, shape, None)], lambda: None
        return [(f"{stem}/Solid{k}", shape, names) for k, names in subsets], lambda: None
    if suffix in FCSTD_SUFFIXES:
        add_module_paths()
        try:
            doc = FreeCAD.openDocument(path, True)
        except Exception as exc:
            raise PartError(f"cannot open {os.path.basename(path)}: "
                            f"{' '.join(str(exc).split())}") from None
        name = doc.Name

        def close():
            if name in FreeCAD.listDocuments():
                FreeCAD.closeDocument(name)
        objs = _result_objects(doc)
        if not objs:
            close()
            raise PartError(f"{os.path.basename(path)} holds no object with a solid")
        sources = []
        for obj in objs:
            subsets = _solid_subsets(obj.Shape)
            if len(subsets) == 1:
                sources.append((obj.Name, obj, None))
            else:
                sources += [(f"{obj.Name}/Solid{k}", obj, names) for k, names in subsets]
        return sources, close
    raise PartError(f"{os.path.basename(path)}: unknown file type (expected "
                    f"{', '.join(SUFFIXES)})")


# ------------------------------------------------------------------ results
def analyse_source(source, face_names, label="", mode="Mould", draft_deg=0.0,
                   weighting="count", all_faces=False,
                   deflection_deg=math.degrees(gauss_map.DEFAULT_DEFLECTION),
                   tol=parting.DEFAULT_TOL):
    """Parting analysis of one solid: :func:`mfgeom.parting.report` (with
    ``timings_s`` {"gauss_maps", "analysis"}) plus ``name`` (``label``) and
    ``uncovered_faces`` (the considered faces the main direction does not cover, as the
    feature's UncoveredFaces)."""
    t0 = time.perf_counter()
    warnings = []   # faces skipped or approximated: the part is analysed all the same
    faces, adj, _ = gauss_map.part_gauss(source, math.radians(deflection_deg),
                                         face_names=face_names, warnings=warnings)
    t1 = time.perf_counter()
    draft = math.radians(draft_deg)
    if mode == "Mould":
        r = parting.mould_parting(faces, adj, draft_angle=draft, weighting=weighting, tol=tol)
    else:
        r = parting.nc_setups(faces, adj, tilt=draft, weighting=weighting,
                              all_faces=all_faces, tol=tol)
    t2 = time.perf_counter()
    rep = parting.report(r, faces, draft_angle=draft, weighting=weighting,
                         all_faces=all_faces, tol=tol, source=label,
                         timings={"gauss_maps": t1 - t0, "analysis": t2 - t1},
                         warnings=warnings)
    covered = set(r.covered)
    uncovered = [f for s in r.considered if s not in covered for f in r.surfaces[s].faces]
    return {"name": label, **rep,
            "uncovered_faces": [faces[f].name for f in sorted(uncovered)]}


def check_request(req):
    """The request's options, checked (raises PartError)."""
    mode = req.get("mode", "Mould")
    if mode not in MODES:
        raise PartError(f"mode must be one of {MODES}, got {mode!r}")
    if req.get("weighting", "count") not in ("count", "area"):
        raise PartError("weighting must be count or area")
    draft = float(req.get("draft_deg", 0.0))
    if not 0.0 <= draft < 90.0:
        raise PartError(f"the draft angle must be in [0, 90) degrees, got {draft}")
    deflection = float(req.get("deflection_deg", math.degrees(gauss_map.DEFAULT_DEFLECTION)))
    if not 0.0 < deflection < 90.0:
        raise PartError(f"the deflection must be in (0, 90) degrees, got {deflection}")
    return {"mode": mode, "draft_deg": draft, "weighting": req.get("weighting", "count"),
            "all_faces": bool(req.get("all_faces", False)), "deflection_deg": deflection,
            "tol": float(req.get("tol", parting.DEFAULT_TOL))}


def analyse_file(path, **options):
    """Parting analysis of every solid in the part file ``path`` (see the module
    docstring).  Returns ``{"path", "solids": [REPORT, ...], "timings": {"load_s",
    "total_s"}}`` (REPORT: :func:`analyse_source`); raises PartError (or the analysis'
    own errors) when the part cannot be analysed."""
    opts = check_request(options)
    t0 = time.perf_counter()
    sources, close = load_sources(path)
    try:
        t1 = time.perf_counter()
        solids = []
        for label, source, names in sources:
            solids.append(analyse_source(source, names, label, **opts))
    finally:
        close()
    t2 = time.perf_counter()
    return {"path": path, "solids": solids,
            "timings": {"load_s": t1 - t0, "total_s": t2 - t0}}


def error_text(exc):
    text = " ".join(str(exc).split())
    if isinstance(exc, PartError):
        return text
    return f"{type(exc).__name__}: {text}" if text else type(exc).__name__


def main(argv=None):
    """Worker entry point: ``REQUEST.json RESULT.json`` (see the module docstring)."""
    argv = sys.argv[1:] if argv is None else argv
    if len(argv) != 2:
        sys.stderr.write("usage: python3 -m mfgeom.app.parting_batch REQUEST.json "
                         "RESULT.json\n")
        return 2
    with open(argv[0], encoding="utf-8") as f:
        req = json.load(f)
    path = req.get("path", "")
    try:
        options = {k: v for k, v in req.items() if k != "path"}
        text = json.dumps(analyse_file(path, **options), allow_nan=False)
    except Exception as exc:  # one part's failure is its own entry, never the batch's
        text = json.dumps({"path": path, "error": error_text(exc)})
    with open(argv[1], "w", encoding="utf-8") as f:
        f.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
