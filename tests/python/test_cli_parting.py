# SPDX-License-Identifier: LGPL-2.1-or-later
"""Tests of ``mfgeom parting`` (batch parting analysis of part files, issue 7 section 4),
run as subprocesses on STEP and FCStd files written from examples/parts, and compared
with the PartingAnalysis feature (mfgeom.make_parting_analysis) computed in this process.

Needs FreeCAD's Python modules (Debian's /usr/lib/freecad-python3/lib, or
MFGEOM_FREECAD_LIB): skipped with the reason otherwise."""

import json
import math
import os
import subprocess
import sys

import numpy as np
import pytest

from mfgeom import core, paths

_HERE = os.path.dirname(os.path.abspath(__file__))
_REPO = os.path.dirname(os.path.dirname(_HERE))
PYTHON = "/usr/bin/python3"
LAUNCHER = os.path.join(_REPO, "tools", "mfgeom")

_LIB = paths.add_freecad_to_path()  # FreeCAD's lib and Mod/Part (Part needs it on 1.0)
if _LIB is None:
    pytest.skip("FreeCAD's Python modules not found (set MFGEOM_FREECAD_LIB)",
                allow_module_level=True)
if os.path.join(_REPO, "examples", "parts") not in sys.path:
    sys.path.append(os.path.join(_REPO, "examples", "parts"))
try:
    import FreeCAD as App  # noqa: E402
    import Part  # noqa: E402
except ImportError as _exc:
    pytest.skip(f"FreeCAD not importable from {_LIB}: {_exc}", allow_module_level=True)

import bspline_part  # noqa: E402
import cup  # noqa: E402
import cup_hole  # noqa: E402
import draft_flip  # noqa: E402
import pocket_block  # noqa: E402

import mfgeom  # noqa: E402

EXAMPLES = {"cup": cup, "cup_hole": cup_hole, "pocket_block": pocket_block,
            "draft_flip": draft_flip, "bspline_part": bspline_part}
PLACEMENT = App.Placement(App.Vector(5, -7, 11), App.Rotation(App.Vector(1, 2, 3), 37))
CONTAINER = App.Placement(App.Vector(-3, 2, 1), App.Rotation(App.Vector(0, 1, -1), 71))


def _env():
    env = dict(os.environ)
    env["PYTHONPATH"] = os.path.join(_REPO, "workbench")
    env["MFGEOM_LIBRARY"] = os.path.abspath(core.library_path)
    return env


def run(args, launcher=False):
    """(exit code, parsed stdout or None, parsed stderr or None)."""
    cmd = [LAUNCHER] if launcher else [PYTHON, "-m", "mfgeom.cli"]
    proc = subprocess.run(cmd + ["parting"] + list(args), capture_output=True, text=True,
                          env=_env(), timeout=600, cwd=_REPO)
    out = json.loads(proc.stdout) if proc.stdout.strip() else None
    err = json.loads(proc.stderr) if proc.stderr.strip() else None
    return proc.returncode, out, err


def without_timings(doc):
    if isinstance(doc, dict):
        return {k: without_timings(v) for k, v in doc.items()
                if k not in ("timings", "timings_s")}
    if isinstance(doc, list):
        return [without_timings(v) for v in doc]
    return doc


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    """STEP files of every example, a STEP with two solids, and an FCStd holding the
    cup with a hole under a rotated Placement inside a rotated App::Part container, the
    pocket block as a Part::Cut of a box by its pockets' tools, and the draft-flip part."""
    d = tmp_path_factory.mktemp("parts")
    out = {}
    for name, mod in EXAMPLES.items():
        path = str(d / f"{name}.step")
        mod.make().exportStep(path)
        out[name] = path
    two = Part.makeCompound([cup.make(), cup_hole.make().translated(App.Vector(100, 0, 0))])
    out["two"] = str(d / "two.stp")
    two.exportStep(out["two"])
    doc = App.newDocument("cli_parting_src")
    try:
        box = doc.addObject("Part::Feature", "Blank")
        box.Shape = Part.makeBox(*pocket_block.SIZE)
        tool = doc.addObject("Part::Feature", "Tools")
        tool.Shape = Part.makeBox(*pocket_block.SIZE).cut(pocket_block.make())
        cut = doc.addObject("Part::Cut", "Block")
        cut.Base, cut.Tool = box, tool
        container = doc.addObject("App::Part", "Assembly")
        container.Placement = CONTAINER
        hole = doc.addObject("Part::Feature", "CupHole")
        hole.Shape = cup_hole.make()
        hole.Placement = PLACEMENT
        container.addObject(hole)
        flip = doc.addObject("Part::Feature", "DraftFlip")
        flip.Shape = draft_flip.make()
        doc.recompute()
        out["fcstd"] = str(d / "parts.FCStd")
        doc.saveAs(out["fcstd"])
    finally:
        App.closeDocument(doc.Name)
    bad = d / "corrupt.step"
    bad.write_text("ISO-10303-21;\nthis is not a STEP file\n")
    out["corrupt"] = str(bad)
    out["missing"] = str(d / "missing.step")
    return out


def feature_result(doc, obj, mode, draft=0.0, weighting="Count", faces=None,
                   name="PartingAnalysis"):
    return mfgeom.make_parting_analysis(doc, obj, mode=mode, draft_angle=draft,
                                        weighting=weighting, faces=faces, name=name)


def assert_same(solid, fa):
    """A CLI solid entry equals the PartingAnalysis feature's properties (same faces,
    same direction up to rounding: both are computed by the same code on shapes read
    the same way, so any difference is the batch path's)."""
    d = np.array(solid["direction"])
    assert np.allclose(d, [fa.Direction.x, fa.Direction.y, fa.Direction.z], atol=1e-9)
    assert math.isclose(solid["margin_deg"], fa.MarginDeg, abs_tol=1e-9)
    assert solid["covered_count"] == fa.CoveredCount
    assert solid["total_count"] == fa.TotalCount
    assert solid["uncovered_faces"] == list(fa.UncoveredFaces)
    assert solid["unresolved_faces"] == list(fa.UnresolvedFaces)
    if fa.Mode == "Mould":
        assert solid["core_faces"] == list(fa.CoreFaces)
        assert solid["cavity_faces"] == list(fa.CavityFaces)
        assert solid["insufficient_draft_faces"] == list(fa.InsufficientDraftFaces)
        assert solid["zero_draft_faces"] == list(fa.ZeroDraftFaces)
        assert sorted(solid["undercut_faces"]) == sorted(fa.UncoveredFaces)
        assert len(solid["side_cores"]) == len(fa.SideCoreDirections)
        for c, v in zip(solid["side_cores"], fa.SideCoreDirections):
            assert np.allclose(c["direction"], [v.x, v.y, v.z], atol=1e-9)
        for c, js in zip(solid["side_cores"], fa.SideCores):
            assert c["faces"] == json.loads(js)["faces"]
    else:
        assert len(solid["setups"]) == len(fa.Setups)
        for s, js in zip(solid["setups"], fa.Setups):
            ref = json.loads(js)
            assert np.allclose(s["direction"], ref["direction"], atol=1e-9)
            assert s["faces"] == ref["faces"]
            assert math.isclose(s["margin_deg"], ref["margin_deg"], abs_tol=1e-9)


@pytest.mark.parametrize("mode,draft,weighting", [("Mould", 0.0, "Count"),
                                                  ("NC3Axis", 0.0, "Count"),
                                                  ("Mould", 3.0, "Area")])
def test_step_files_match_the_feature(files, mode, draft, weighting):
    names = list(EXAMPLES)
    rc, out, err = run([files[n] for n in names] + ["--mode", mode.lower(), "--draft",
                                                    str(draft), "--weighting",
                                                    weighting.lower(), "-j", "2"])
    assert rc == 0 and err is None, err
    assert out["failed"] == 0 and [p["path"] for p in out["parts"]] == [files[n] for n in names]
    doc = App.newDocument("cli_parting_ref")
    try:
        for name, part in zip(names, out["parts"]):
            assert len(part["solids"]) == 1
            solid = part["solids"][0]
            assert solid["name"] == name and solid["mode"] == mode
            obj = doc.addObject("Part::Feature", name)
            obj.Shape = Part.read(files[name])
            assert solid["face_count"] == len(obj.Shape.Faces)
            assert solid["source"] == f"{files[name]}:{name}"
            assert_same(solid, feature_result(doc, obj, mode, draft, weighting))
            assert solid["timings_s"]["gauss_maps"] >= 0 and part["timings"]["wall_s"] > 0
    finally:
        App.closeDocument(doc.Name)
    by_name = dict(zip(names, out["parts"]))
    if mode == "Mould" and draft == 0.0:
        # what the examples are made to show (examples/parts): the cup is covered
        # entirely along z, the cup with a hole has its hole as the one undercut
        c = by_name["cup"]["solids"][0]
        assert c["covered_count"] == c["total_count"]
        assert abs(abs(c["direction"][2]) - 1) < 1e-12
        h = by_name["cup_hole"]["solids"][0]
        assert h["covered_count"] == h["total_count"] - 1 and len(h["side_cores"]) == 1
    if mode == "NC3Axis":
        assert len(by_name["pocket_block"]["solids"][0]["setups"]) == 3


def test_several_solids_are_analysed_each(files):
    rc, out, err = run([files["two"]])
    assert rc == 0 and err is None
    solids = out["parts"][0]["solids"]
    assert [s["name"] for s in solids] == ["two/Solid1", "two/Solid2"]
    shape = Part.read(files["two"])
    doc = App.newDocument("cli_parting_two")
    try:
        obj = doc.addObject("Part::Feature", "Two")
        obj.Shape = shape
        for k, solid in enumerate(solids):
            names = [f"Face{i + 1}" for i, f in enumerate(shape.Faces)
                     if any(f.isSame(g) for g in shape.Solids[k].Faces)]
            assert solid["face_count"] == len(names)
            assert set(solid["uncovered_faces"] + solid["core_faces"]
                       + solid["cavity_faces"]) <= set(names)
            assert_same(solid, feature_result(doc, obj, "Mould", faces=names))
    finally:
        App.closeDocument(doc.Name)
    # the second solid is the cup with a hole: one undercut surface
    assert solids[1]["covered_count"] == solids[1]["total_count"] - 1


def test_fcstd_objects_in_global_coordinates_and_j2_equals_j1(files):
    args = [files["fcstd"], files["cup_hole"], files["pocket_block"], "--mode", "nc3axis"]
    rc1, out1, err1 = run(args + ["-j", "1"])
    rc2, out2, err2 = run(args + ["-j", "2"], launcher=True)
    assert rc1 == rc2 == 0 and err1 is None and err2 is None
    assert without_timings(out1) == without_timings(out2)
    rc, mould, err = run([files["fcstd"]])
    assert rc == 0 and err is None
    doc = App.openDocument(files["fcstd"], True)
    try:
        # the consumed blank and tools and the App::Part container are not analysed
        assert [s["name"] for s in out1["parts"][0]["solids"]] == ["Block", "CupHole",
                                                                    "DraftFlip"]
        for name, nc_solid, mould_solid in zip(["Block", "CupHole", "DraftFlip"],
                                               out1["parts"][0]["solids"],
                                               mould["parts"][0]["solids"]):
            obj = doc.getObject(name)
            assert_same(nc_solid, feature_result(doc, obj, "NC3Axis", name="NC" + name))
            assert_same(mould_solid, feature_result(doc, obj, "Mould", name="M" + name))
        # global coordinates: the cup with a hole's parting direction is its axis moved
        # by the container's and its own placements
        axis = (CONTAINER.multiply(PLACEMENT)).Rotation.multVec(App.Vector(0, 0, 1))
        d = mould["parts"][0]["solids"][1]["direction"]
        assert abs(abs(np.dot(d, [axis.x, axis.y, axis.z])) - 1) < 1e-9
    finally:
        App.closeDocument(doc.Name)


def test_partdesign_body_is_analysed_not_its_features(tmp_path):
    """An FCStd of a PartDesign Body (a box minus a cylinder): the Body is analysed, not
    its features (the worker loads PartDesign as freecadcmd would)."""
    from mfgeom.app import parting_batch
    parting_batch.add_module_paths()
    doc = App.newDocument("cli_parting_body")
    try:
        body = doc.addObject("PartDesign::Body", "Body")
        box = doc.addObject("PartDesign::AdditiveBox", "Box")
        body.addObject(box)
        box.Length, box.Width, box.Height = 30, 20, 10
        hole = doc.addObject("PartDesign::SubtractiveCylinder", "Hole")
        body.addObject(hole)
        hole.Radius, hole.Height = 4, 6
        body.Placement = PLACEMENT
        doc.recompute()
        path = str(tmp_path / "body.FCStd")
        doc.saveAs(path)
        rc, out, err = run([path])
        assert rc == 0 and err is None, err
        solids = out["parts"][0]["solids"]
        assert [s["name"] for s in solids] == ["Body"] and solids[0]["face_count"] == 8
        assert_same(solids[0], feature_result(doc, body, "Mould"))
    finally:
        App.closeDocument(doc.Name)


def test_failing_parts_get_error_entries_and_exit_2(files, tmp_path):
    unknown = tmp_path / "part.obj"
    unknown.write_text("v 0 0 0\n")
    listed = [files["cup"], files["missing"], files["corrupt"], str(unknown),
              files["cup_hole"]]
    rc, out, err = run(listed + ["-j", "2"])
    assert rc == 2
    assert [p["path"] for p in out["parts"]] == listed and out["failed"] == 3
    ok = [p for p in out["parts"] if "error" not in p]
    assert [p["path"] for p in ok] == [files["cup"], files["cup_hole"]]
    bad = {p["path"]: p["error"] for p in out["parts"] if "error" in p}
    assert "no such file" in bad[files["missing"]]
    assert "cannot read" in bad[files["corrupt"]]
    assert "unknown file type" in bad[str(unknown)]
    assert set(err) == {"error"} and err["error"].startswith("3 of 5 parts failed")
    for path in bad:
        assert path in err["error"]


def test_json_and_csv_output_files_and_usage_errors(files, tmp_path):
    import csv
    target, table = tmp_path / "report.json", tmp_path / "faces.csv"
    rc, out, err = run([files["cup"], files["missing"], files["cup_hole"], "--json",
                        str(target), "--csv", str(table)])
    assert rc == 2 and out == {"json": str(target), "parts": 3, "failed": 1}
    doc = json.loads(target.read_text())
    assert doc["parts"][0]["solids"][0]["covered_count"] == 4 and "error" in doc["parts"][1]
    rows = list(csv.DictReader(table.open()))
    # one row per face of the two parts that were analysed, in order, roles as in JSON
    solids = [doc["parts"][0]["solids"][0], doc["parts"][2]["solids"][0]]
    assert [(r["source"], r["face"], r["role"]) for r in rows] == \
        [(s["source"], f["name"], f["role"]) for s in solids for f in s["faces"]]
    undercuts = {r["face"] for r in rows if r["source"].endswith(":cup_hole")
                 and r["role"] == "undercut"}
    assert undercuts == set(solids[1]["undercut_faces"]) and undercuts
    assert "1 of 3 parts failed" in err["error"]
    for bad_args in (["--draft", "95"], ["--draft", "-1"], ["--deflection", "0"],
                     ["-j", "0"], ["--mode", "milling"], ["--weighting", "volume"],
                     ["--timeout", "0"]):
        rc, out, err = run([files["cup"]] + bad_args)
        assert rc == 2 and out is None and set(err) == {"error"}, bad_args
    rc, out, err = run([])
    assert rc == 2 and out is None and "PART" in err["error"]
    # a worker that takes longer than --timeout (here: shorter than its start) is an
    # error entry
    rc, out, err = run([files["cup"], "--timeout", "0.001"])
    assert rc == 2 and out["parts"][0]["error"] == "timed out after 0.001 s"


def test_freecadcmd_workers_give_the_same_results(files, monkeypatch):
    """Where FreeCAD's modules are not found for plain python3, the workers run in
    freecadcmd: same answers."""
    import shutil
    if not shutil.which("freecadcmd"):
        pytest.skip("freecadcmd not on PATH")
    args = [files["cup_hole"], files["bspline_part"], files["corrupt"]]
    rc1, out1, _ = run(args)
    monkeypatch.setenv("MFGEOM_FREECAD_LIB", "/nonexistent")
    rc2, out2, err2 = run(args)
    assert rc1 == rc2 == 2 and out2["failed"] == 1 and "corrupt" in err2["error"]
    assert without_timings(out1) == without_timings(out2)


class _Colliding:
    """A shape, face or edge whose hashCode() is 0: every edge collides, as OCCT's
    pointer-based hash codes sometimes do on large parts (seen on a 4999-face part:
    two different edges with one hash code made adjacency() fail "edge not in face")."""

    def __init__(self, real):
        self.real = real

    def hashCode(self, *args):
        return 0

    def isSame(self, other):
        return self.real.isSame(getattr(other, "real", other))

    @property
    def Faces(self):
        return [_Colliding(f) for f in self.real.Faces]

    @property
    def Edges(self):
        return [_Colliding(e) for e in self.real.Edges]

    def __getattr__(self, name):
        return getattr(self.real, name)


def test_adjacency_when_edge_hash_codes_collide():
    """gauss_map.adjacency groups edges by isSame, not by hash code alone: with every
    hash code equal it still finds each shared edge once, with its kind."""
    from mfgeom.app import gauss_map
    shape = cup_hole.make()
    expected = gauss_map.adjacency(shape)
    shared = sum(1 for e in shape.Edges
                 if not e.Degenerated and len(shape.ancestorsOfType(e, Part.Face)) == 2)
    assert len(expected) == shared
    assert gauss_map.adjacency(_Colliding(shape)) == expected
