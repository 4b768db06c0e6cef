# SPDX-License-Identifier: LGPL-2.1-or-later
"""mfgeom.parting_legend: the class of each face from a parting result's properties and
the legend the task panel lists (FreeCAD-free since it left gui/parting_view.py).  The
result object is a plain stand-in with the properties the feature writes."""

import json
from types import SimpleNamespace

from mfgeom import palette
from mfgeom import parting_legend as pl


def mould(**props):
    base = dict(Mode="Mould", CoreFaces=[], CavityFaces=[], UncoveredFaces=[],
                InsufficientDraftFaces=[], UnresolvedFaces=[])
    base.update(props)
    return SimpleNamespace(**base)


def test_mould_classes_later_assignments_win_and_bad_names_are_ignored():
    obj = mould(CoreFaces=["Face1", "Face4"], CavityFaces=["Face2", "Face9", "Edge1", "Face0"],
                UncoveredFaces=["Face3"], InsufficientDraftFaces=["Face1"],
                ShadowedFaces=["Face3"])
    assert pl.face_classes(obj, 5) == ["insufficient_draft", "cavity", "shadowed", "core",
                                       "other"]
    assert pl.face_colors(obj, 5)[1] == palette.CAVITY_SIDE


def test_legend_lists_present_classes_in_table_order_other_last():
    obj = mould(CoreFaces=["Face4"], CavityFaces=["Face2"], InsufficientDraftFaces=["Face1"],
                ShadowedFaces=["Face3"])
    entries = pl.legend_entries(obj, 5)
    assert [k for k, _label, _rgb in entries] == ["core", "cavity", "insufficient_draft",
                                                   "shadowed", "other"]
    assert entries[0] == ("core", "Core side (+d)", palette.CORE_SIDE)
    assert entries[-1][2] == palette.SHAPE_GREY


def test_setups_by_number_after_the_table_classes():
    obj = SimpleNamespace(Mode="NC3Axis", UnresolvedFaces=["Face3"],
                          Setups=[json.dumps({"faces": ["Face2", "Face10"]}),
                                  json.dumps({"faces": ["Face1"]})] +
                          [json.dumps({"faces": []})] * 8 +
                          [json.dumps({"faces": ["Face4"]})])
    assert pl.face_classes(obj, 4) == ["setup2", "setup1", "unresolved", "setup11"]
    keys = [k for k, _l, _c in pl.legend_entries(obj, 4)]
    assert keys == ["unresolved", "setup1", "setup2", "setup11"]      # numeric order
    assert pl.class_label("setup11") == "Set-up 11"
    assert pl.class_color("setup2") == palette.setup_color(2)


def test_draft_classes_and_face_count_from_the_source():
    shape = SimpleNamespace(Faces=[object()] * 3)
    obj = SimpleNamespace(Mode="Draft", PositiveDraftFaces=["Face1"], NegativeDraftFaces=["Face2"],
                          InsufficientDraftFaces=["Face2"], StraddleFaces=[],
                          Source=SimpleNamespace(Shape=shape))
    assert [k for k, _l, _c in pl.legend_entries(obj)] == ["positive", "insufficient", "other"]
    assert pl.legend_entries(SimpleNamespace(Mode="Draft", PositiveDraftFaces=[],
                                             InsufficientDraftFaces=[], Source=None)) == []
