# SPDX-License-Identifier: LGPL-2.1-or-later
"""mfgeom.parting.report / write_report_json / write_report_csv on the cup with a radial
hole (the faces as gauss_map gives them): roles, groups and directions per face."""

import csv
import json
import math

import numpy as np

from mfgeom import parting as P

F = P.FaceGauss
X, Y, Z = np.eye(3)


def circle(axis, k=4):
    axis = np.asarray(axis, float)
    e1 = np.cross(axis, X if abs(axis @ X) < 0.9 else Y)
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(axis, e1)
    t = np.linspace(0, 2 * math.pi, k + 1)
    return np.outer(np.cos(t), e1) + np.outer(np.sin(t), e2)


def cup_hole():
    faces = [F(circle(Z), name="Face1"), F([-Z], name="Face2"), F([Z], name="Face3"),
             F(-circle(Z), name="Face4"), F([Z], name="Face5"),
             F(-circle(X), name="Face6"), F([X], name="Face7", shrink=math.radians(0.01))]
    adj = [(0, 1, "convex"), (0, 2, "convex"), (2, 3, "convex"), (3, 4, "concave"),
           (0, 5, "convex"), (5, 6, "concave")]
    return faces, adj


def test_mould_report_roles_side_core_and_files(tmp_path):
    faces, adj = cup_hole()
    rep = P.report(P.mould_parting(faces, adj), faces, source="cup_hole")
    assert rep["mode"] == "Mould" and np.allclose(rep["direction"], Z)
    assert (rep["covered_count"], rep["total_count"]) == (4, 5)
    assert rep["undercut_faces"] == ["Face6", "Face7"]
    # the walls (outer, pocket) are parallel to d: zero draft, listed as insufficient
    assert rep["core_faces"] == ["Face3", "Face5"] and rep["cavity_faces"] == ["Face2"]
    assert rep["zero_draft_faces"] == ["Face1", "Face4"]
    assert rep["insufficient_draft_faces"] == ["Face1", "Face4"]
    worst = {w["name"]: w for w in rep["worst_faces"]}
    assert sorted(worst) == ["Face1", "Face4", "Face6", "Face7"]
    assert worst["Face6"]["worst_angle_deg"] == -90.0   # the hole wall faces -z too
    assert worst["Face1"]["worst_angle_deg"] == 0.0 and worst["Face1"]["role"] == "zero_draft"
    assert len(rep["side_cores"]) == 1 and np.allclose(rep["side_cores"][0]["direction"], X)
    roles = {f["name"]: (f["role"], f["group"]) for f in rep["faces"]}
    assert roles["Face6"] == ("undercut", "side_core_1") and roles["Face2"] == ("cavity", "main")
    assert rep["sampled_faces"] == ["Face7"] and abs(rep["max_shrink_deg"] - 0.01) < 1e-12
    assert "sampled" in rep["notes"][0]
    P.write_report_json(tmp_path / "r.json", rep)
    assert json.loads((tmp_path / "r.json").read_text()) == json.loads(json.dumps(rep))
    P.write_report_csv(tmp_path / "r.csv", rep)
    rows = list(csv.DictReader(open(tmp_path / "r.csv")))
    assert [r["face"] for r in rows] == [f"Face{i}" for i in range(1, 8)]
    hole = rows[5]
    assert hole["group"] == "side_core_1" and float(hole["dx"]) == 1.0
    assert float(rows[2]["dz"]) == 1.0 and rows[2]["role"] == "core"
    text = P.report_text(rep)
    assert "Face6 Face7" in text and "2 zero draft" in text and "1 undercut" not in text
    assert float(hole["worst_angle_deg"]) == -90.0


def test_nc_report_setups_and_not_considered(tmp_path):
    faces, adj = cup_hole()
    rep = P.report(P.nc_setups(faces, adj), faces, draft_angle=0.0)
    assert [s["faces"] for s in rep["setups"]] == [["Face4", "Face5"], ["Face6", "Face7"]]
    assert np.allclose(rep["setups"][1]["direction"], X)
    roles = {f["name"]: (f["role"], f["group"]) for f in rep["faces"]}
    assert roles["Face1"] == ("not_considered", "") and roles["Face7"] == ("setup", "setup_2")
    P.write_report_csv(tmp_path / "r.csv", [rep, rep])
    rows = list(csv.DictReader(open(tmp_path / "r.csv")))
    assert len(rows) == 14 and rows[6]["group"] == "setup_2" and float(rows[6]["dx"]) == 1.0
    assert rows[0]["dx"] == ""  # a surface not considered has no direction


class _Rays:
    """A FaceRays stand-in: blocked fractions along +d and -d."""

    def __init__(self, pos, neg, samples=10):
        self.blocked_pos, self.blocked_neg, self.samples = pos, neg, samples


def test_ray_check_flags_faces_the_normals_call_demouldable():
    """apply_ray_check: a core face blocked along +d and a cavity face blocked along -d
    are shadowed; a core face blocked only along -d (its other side) is not; an undercut
    blocked either way is not 'shadowed' (the normals already say so); under 2 % is noise."""
    faces, adj = cup_hole()
    r = P.mould_parting(faces, adj)
    rays = {"Face3": _Rays(0.5, 1.0),      # top, core: blocked along +d -> shadowed
            "Face2": _Rays(0.0, 0.3),      # bottom, cavity: blocked along -d -> shadowed
            "Face5": _Rays(0.0, 1.0),      # pocket floor, core: free along +d
            "Face1": _Rays(0.01, 0.5),     # outer wall, zero draft: 1 % -> not flagged
            "Face6": _Rays(1.0, 1.0)}      # hole wall: an undercut already
    assert P.apply_ray_check(r, faces, rays) == [1, 2]
    assert r.ray_blocked[2] == 0.5 and r.ray_blocked[1] == 0.3 and r.ray_blocked[0] == 0.01
    assert r.ray_blocked[4] == 0.0 and r.ray_blocked[6] is None   # Face7: no rays given
    rep = P.report(r, faces)
    assert rep["ray_checked"] and rep["shadowed_faces"] == ["Face2", "Face3"]
    row = {x["name"]: x for x in rep["faces"]}
    assert row["Face3"]["shadowed"] and not row["Face1"]["shadowed"]
    assert "2 faces demouldable by their normals are blocked" in P.report_text(rep)
