# SPDX-License-Identifier: LGPL-2.1-or-later
"""What the document round-trip scripts share (roundtrip_save.py writes a document with one
of each of the workbench's FeaturePython objects and the JSON of their results on one
FreeCAD version; roundtrip_check.py opens it on another, checks the restored and the
recomputed results against the JSON): where the files are, the summary of an object, the
comparison, and the proxy state as saved in Document.xml."""

import json
import math
import os
import sys
import zipfile

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
for _p in (os.path.join(REPO, "workbench"), os.path.join(REPO, "examples"),
           os.path.join(REPO, "examples", "parts")):
    if _p not in sys.path:
        sys.path.append(_p)

# Floats are compared relative to their magnitude: the same library, built by another
# compiler, and another OCCT (Shape.Area, .Volume) may differ in the last bits.
REL = 1e-9
# Objects whose results are OCCT booleans (the mould's core, cavity, inserts): another
# OCCT splits their faces differently (0.20 -> 1.0: an insert with 21 faces instead of
# 20) and integrates their volumes to ~1e-8; kept by solids, volume and area within
# BOOLEAN_REL ({"approx": value} in the summary)
BOOLEAN_RESULTS = ("Mfgeom::MouldBlocks",)
BOOLEAN_REL = 1e-6


def run_main(main):
    """Runs a round-trip script's ``main()`` and exits with its code; an exception is
    printed and exits 1 (the exit code is what the CI job reads)."""
    import traceback
    try:
        code = main()
    except Exception:  # reported; the exit code tells the CI job
        traceback.print_exc()
        code = 1
    sys.stdout.flush()
    sys.exit(code)


def paths():
    """(FCStd, JSON) of the round trip: $MFGEOM_ROUNDTRIP_DIR/roundtrip.{FCStd,json}."""
    directory = os.environ.get("MFGEOM_ROUNDTRIP_DIR")
    if not directory:
        raise SystemExit("set MFGEOM_ROUNDTRIP_DIR (the directory of roundtrip.FCStd/.json)")
    return (os.path.join(directory, "roundtrip.FCStd"),
            os.path.join(directory, "roundtrip.json"))


def freecad_version():
    import FreeCAD
    return ".".join(str(v) for v in FreeCAD.Version()[:3])


# property types whose value is kept as it is (lists of them too)
_SCALAR = ("App::PropertyInteger", "App::PropertyFloat", "App::PropertyBool",
           "App::PropertyString", "App::PropertyEnumeration", "App::PropertyIntegerList",
           "App::PropertyFloatList", "App::PropertyStringList", "App::PropertyBoolList")
_QUANTITY = ("App::PropertyAngle", "App::PropertyLength", "App::PropertyDistance",
             "App::PropertyQuantity")


def _number(x):
    return float(x)


def summary(obj):
    """The results (and inputs) of ``obj`` as plain JSON data: scalar and list properties,
    quantities in their unit, vectors, links by name, and the Shape, Mesh and Points
    outputs by counts and measures."""
    out = {}
    boolean = getattr(getattr(obj, "Proxy", None), "Type", "") in BOOLEAN_RESULTS
    for name in sorted(obj.PropertiesList):
        ptype = obj.getTypeIdOfProperty(name)
        value = getattr(obj, name)
        if name in ("Label", "Label2", "ExpressionEngine", "Visibility"):
            continue
        if boolean and ptype == "Part::PropertyPartShape":
            out[name] = {"solids": len(value.Solids),
                         "volume": {"approx": value.Volume if value.Solids else 0.0},
                         "area": {"approx": value.Area if not value.isNull() else 0.0}}
            continue
        if boolean and ptype == "App::PropertyFloatList":
            out[name] = [{"approx": v} for v in value]
            continue
        if name in ("ExactVertices", "ExactTriangles"):
            # the sweep's exact mesh (10^5 numbers): by count and sums, so the JSON stays
            # small and a mesh that did not survive the trip still shows
            flat = [c for p in value for c in ((p.x, p.y, p.z) if hasattr(p, "x") else (p,))]
            out[name] = {"count": len(value), "sum": math.fsum(flat),
                         "sum_abs": math.fsum(abs(c) for c in flat)}
            continue
        if ptype in _SCALAR:
            out[name] = list(value) if isinstance(value, (list, tuple)) else value
        elif ptype in _QUANTITY:
            out[name] = _number(value.Value)
        elif ptype == "App::PropertyVector":
            out[name] = [value.x, value.y, value.z]
        elif ptype == "App::PropertyLink":
            out[name] = value.Name if value is not None else None
        elif ptype == "App::PropertyLinkSub":
            out[name] = [value[0].Name, list(value[1])] if value else None
        elif ptype == "Part::PropertyPartShape":
            out[name] = shape_summary(value)
        elif ptype == "Mesh::PropertyMeshKernel":
            out[name] = {"points": value.CountPoints, "facets": value.CountFacets,
                         "area": value.Area, "volume": value.Volume}
        elif ptype == "Points::PropertyPointKernel":
            from mfgeom.app import pointcloud
            pts = pointcloud.kernel_to_array(value)
            out[name] = {"count": len(pts),
                         "sum": [float(s) for s in pts.sum(axis=0)] if len(pts) else [0, 0, 0]}
    return out


def clearance_results(doc):
    """The clearance check of the mesh sweep against the obstacle and the slab."""
    import mfgeom
    sweep = doc.getObject("SweepMesh")
    others = [doc.getObject("Obstacle"), doc.getObject("Slab")]
    return [{"name": r.name, "status": r.status, "volume": float(r.interference_volume),
             "distance": None if r.min_distance is None else float(r.min_distance)}
            for r in mfgeom.check_clearance(sweep, others, tolerance=0.01)]


def shape_summary(shape):
    if shape.isNull():
        return {"null": True}
    box = shape.BoundBox
    out = {"type": shape.ShapeType, "solids": len(shape.Solids), "shells": len(shape.Shells),
           "faces": len(shape.Faces), "edges": len(shape.Edges),
           "vertexes": len(shape.Vertexes), "area": shape.Area, "length": shape.Length,
           "box": [box.XMin, box.YMin, box.ZMin, box.XMax, box.YMax, box.ZMax]}
    if shape.Solids:
        out["volume"] = shape.Volume
    return out


def differences(want, got, where=""):
    """Where ``got`` differs from ``want`` (lists of strings; floats within REL, those
    marked {"approx": value} within BOOLEAN_REL)."""
    if isinstance(want, dict) and set(want) == {"approx"} and isinstance(got, dict) \
            and set(got) == {"approx"}:
        a, b = want["approx"], got["approx"]
        return [] if math.isclose(a, b, rel_tol=BOOLEAN_REL, abs_tol=BOOLEAN_REL) else \
            [f"{where}: {b!r}, saved {a!r} (within {BOOLEAN_REL})"]
    if isinstance(want, dict) and isinstance(got, dict):
        diffs = []
        for key in sorted(set(want) | set(got)):
            if key not in got:
                diffs.append(f"{where}.{key}: missing")
            elif key not in want:
                diffs.append(f"{where}.{key}: not in the saved results")
            else:
                diffs += differences(want[key], got[key], f"{where}.{key}")
        return diffs
    if isinstance(want, list) and isinstance(got, list):
        if len(want) != len(got):
            return [f"{where}: {len(got)} items, saved {len(want)}"]
        diffs = []
        for i, (a, b) in enumerate(zip(want, got)):
            diffs += differences(a, b, f"{where}[{i}]")
            if len(diffs) > 5:
                break
        return diffs
    if isinstance(want, bool) or isinstance(got, bool) or not (
            isinstance(want, (int, float)) and isinstance(got, (int, float))):
        return [] if want == got else [f"{where}: {got!r}, saved {want!r}"]
    if isinstance(want, int) and isinstance(got, int):
        return [] if want == got else [f"{where}: {got}, saved {want}"]
    if math.isclose(want, got, rel_tol=REL, abs_tol=REL):
        return []
    return [f"{where}: {got!r}, saved {want!r}"]


def saved_proxy_states(fcstd):
    """{object name: the proxy state as Document.xml holds it (decoded JSON)}."""
    import xml.etree.ElementTree as ET
    with zipfile.ZipFile(fcstd) as archive:
        root = ET.fromstring(archive.read("Document.xml"))
    states = {}
    for obj in root.iter("Object"):
        for prop in obj.iter("Property"):
            if prop.get("name") != "Proxy":
                continue
            python = prop.find("Python")
            if python is None:
                continue
            text = python.get("value", "")
            if python.get("encoded") == "yes":
                import base64
                text = base64.b64decode(text).decode("utf-8")
            try:
                states[obj.get("name")] = {"state": json.loads(text),
                                           "module": python.get("module"),
                                           "class": python.get("class")}
            except ValueError:
                states[obj.get("name")] = {"state": text, "module": python.get("module"),
                                           "class": python.get("class")}
    return states
