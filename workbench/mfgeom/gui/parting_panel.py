# SPDX-License-Identifier: LGPL-2.1-or-later
"""The task panel of "Parting analysis": mode, draft angle (NC: tilt allowance),
weighting, all faces (NC), deflection of sampled faces; the result after each recompute;
JSON / CSV export of the report.  For a new analysis (from the command) or an existing
one (double click: setEdit).

OK (and Apply) run the change through the Python console (``Gui.doCommand``), so the
Report view and a recorded macro show the exact ``mfgeom.make_parting_analysis(...)``
call or property assignments, inside one undo transaction; Cancel leaves the document as
it was since the last Apply.  Apply on a new analysis creates it and the panel then edits
it.  While the analysis runs FreeCAD's progress bar shows and the cursor waits.
"""

import math

import FreeCAD
import FreeCADGui
from PySide import QtGui

from mfgeom.app.parting_feature import MODES, WEIGHTINGS, PartingInputError
from mfgeom.gui.panel_base import TaskPanel, combo, spin

TITLE = "Parting analysis"
MODE_TEXT = {"Mould": "Mould (parting direction)", "NC3Axis": "NC 3-axis (set-ups)",
             "Draft": "Draft analysis (given pull direction)"}


def parse_direction(text):
    """(x, y, z) from "x, y, z" (commas or spaces); PartingInputError if it is not three
    finite numbers, not all zero."""
    parts = text.replace(",", " ").replace(";", " ").split()
    try:
        v = tuple(float(p) for p in parts)
    except ValueError:
        v = ()
    if len(v) != 3 or not all(math.isfinite(c) for c in v) or not any(v):
        raise PartingInputError(f"The pull direction must be three numbers such as "
                                f"'0, 0, 1', got {text!r}.")
    return v


def source_from_selection(selection):
    """(object, face names) from ``[(obj, [subnames])]``: one object with a solid (or a
    shell) shape, whole or some of its faces.  PartingInputError says what is wrong."""
    if not selection:
        raise PartingInputError("Select a solid (or some of its faces) first.")
    objs = {id(o): o for o, _ in selection}
    if len(objs) != 1:
        raise PartingInputError("Select one solid (or faces of one solid), not "
                                f"{len(objs)} objects.")
    obj = selection[0][0]
    subs = [s for _, ss in selection for s in ss]
    shape = getattr(obj, "Shape", None)
    if shape is None or shape.isNull() or not shape.Faces:
        raise PartingInputError(f"'{obj.Label}' has no faces: select a solid.")
    if not (shape.Solids or shape.Shells):
        raise PartingInputError(f"'{obj.Label}' is not a solid or a shell.")
    wrong = [s for s in subs if not s.startswith("Face")]
    if wrong:
        raise PartingInputError(f"Select a solid or its faces, not {', '.join(wrong)}.")
    faces = []
    for s in subs:
        if s not in faces:
            faces.append(s)
    return obj, faces


def result_text(obj):
    """The panel's summary of an analysis' result properties."""
    if obj is None or not obj.isValid():
        return "No result yet." if obj is None else f"Failed: {obj.getStatusString()}"
    d = obj.Direction
    lines = [f"Direction ({d.x:+.4f}, {d.y:+.4f}, {d.z:+.4f}), margin {obj.MarginDeg:.3g} deg",
             f"Covers {obj.CoveredCount} of {obj.TotalCount} surfaces"]
    def listing(names, most=8):
        more = f" ... (+{len(names) - most} more)" if len(names) > most else ""
        return " ".join(list(names)[:most]) + more
    if obj.Mode == "Draft":
        lines = [f"Pull direction ({d.x:+.4f}, {d.y:+.4f}, {d.z:+.4f}), draft "
                 f"{obj.DraftAngle.Value:g} deg",
                 f"Faces: {len(obj.PositiveDraftFaces)} positive, "
                 f"{len(obj.NegativeDraftFaces)} negative, "
                 f"{len(obj.InsufficientDraftFaces)} insufficient, "
                 f"{len(obj.StraddleFaces)} straddle"]
        if obj.InsufficientDraftFaces:
            lines.append(f"Insufficient draft: {listing(obj.InsufficientDraftFaces)}")
        if obj.StraddleFaces:
            lines.append(f"Straddle: {listing(obj.StraddleFaces)}")
        return "\n".join(lines)
    if obj.Mode == "Mould":
        if obj.UncoveredFaces:
            lines.append(f"Undercuts: {listing(obj.UncoveredFaces)}")
        zero = set(obj.ZeroDraftFaces)
        if zero:
            lines.append(f"Zero draft: {listing(obj.ZeroDraftFaces)}")
        if getattr(obj, "ShadowedFaces", None):
            lines.append(f"Blocked by rays (shadowed): {listing(obj.ShadowedFaces)}")
        below = [f for f in obj.InsufficientDraftFaces if f not in zero]
        if below:
            lines.append(f"Insufficient draft: {listing(below)}")
        for k, v in enumerate(obj.SideCoreDirections, 1):
            lines.append(f"Side core {k}: ({v.x:+.4f}, {v.y:+.4f}, {v.z:+.4f})")
    else:
        import json
        for k, entry in enumerate(obj.Setups, 1):
            e = json.loads(entry)
            x, y, z = e["direction"]
            lines.append(f"Set-up {k}: ({x:+.4f}, {y:+.4f}, {z:+.4f}), "
                         f"{len(e['faces'])} faces")
    if obj.UnresolvedFaces:
        lines.append(f"No single direction: {listing(obj.UnresolvedFaces)}")
    if getattr(obj, "Warnings", None):
        lines.append(f"Warnings: {len(obj.Warnings)} (see the Report view)")
    return "\n".join(lines)


class PartingPanel(TaskPanel):
    """Task panel; ``source``/``faces`` to create an analysis, or ``obj`` to edit one."""

    def __init__(self, source=None, faces=None, obj=None):
        if obj is None and source is None:
            raise PartingInputError("the panel needs a source or an analysis to edit")
        self.obj = obj
        self.source = obj.Source if obj is not None else source
        self.faces = list(obj.Faces) if obj is not None else list(faces or [])
        self.doc = obj.Document if obj is not None else source.Document

        layout = self._new_form(TITLE)

        self.mode = combo("mode", [(MODE_TEXT[m], m) for m in MODES],
                          "Mould: parting direction (core +d, cavity -d), undercuts and "
                          "side cores.\nNC 3-axis: set-up plan for the pockets.\n"
                          "Draft analysis: positive / negative / insufficient / straddle "
                          "draft of every face along a pull direction you give.")
        layout.addRow("Mode", self.mode)

        pull_row = QtGui.QHBoxLayout()
        self.pull = QtGui.QLineEdit("0, 0, 1")
        self.pull.setObjectName("pullDirection")
        self.pull.setToolTip("Draft analysis: the pull direction x, y, z (global)")
        self.pull_pick = QtGui.QPushButton("From selection")
        self.pull_pick.setObjectName("pullFromSelection")
        self.pull_pick.setToolTip("Take the normal of the selected face or the direction "
                                  "of the selected straight edge")
        self.pull_pick.clicked.connect(self.pull_from_selection)
        pull_row.addWidget(self.pull)
        pull_row.addWidget(self.pull_pick)
        layout.addRow("Pull direction", pull_row)

        self.draft = spin("draft", 0.0, 89.9, 3, " deg",
                          tip="Mould: least angle each covered face must make with the "
                          "parting plane.\nNC 3-axis: tool-axis tilt allowance.")
        layout.addRow("Draft angle", self.draft)

        self.weighting = combo("weighting", [(w, w) for w in WEIGHTINGS],
                               "Count: each concave-connected surface counts 1; "
                               "Area: by its area")
        layout.addRow("Weighting", self.weighting)

        self.all_faces = QtGui.QCheckBox("Include all faces (not only pockets)")
        self.all_faces.setObjectName("allFaces")
        layout.addRow(self.all_faces)

        self.deflection = spin("deflection", 0.001, 10.0, 3, " deg",
                               tip="An angle, not a length (property NormalDeflection): "
                               "sampled (non-analytic) faces' Gaussian maps are shrunk by "
                               "at most this angle so every direction holds on the true "
                               "faces.\nThe ray check's tessellation deflection (mm) is "
                               "the property RayDeflection.")
        layout.addRow("Normal deflection", self.deflection)

        self._add_result(layout)
        self._add_legend(layout)

        buttons = QtGui.QHBoxLayout()
        self.export_json_button = QtGui.QPushButton("Export JSON...")
        self.export_json_button.setObjectName("exportJson")
        self.export_csv_button = QtGui.QPushButton("Export CSV...")
        self.export_csv_button.setObjectName("exportCsv")
        self.export_json_button.clicked.connect(lambda: self.export("json"))
        self.export_csv_button.clicked.connect(lambda: self.export("csv"))
        buttons.addWidget(self.export_json_button)
        buttons.addWidget(self.export_csv_button)
        layout.addRow(buttons)

        self._add_message(layout)

        self.mode.currentIndexChanged.connect(self._mode_changed)
        self._load()

    def _add_legend(self, layout):
        """The colour legend of the view: one swatch and label per face class present
        in the result (mfgeom.parting_legend.legend_entries, the view's own table)."""
        self.legend = QtGui.QGroupBox("Colours")
        self.legend.setObjectName("legend")
        self._legend_grid = QtGui.QGridLayout(self.legend)
        self._legend_grid.setContentsMargins(6, 6, 6, 6)
        self._legend_grid.setColumnStretch(1, 1)
        layout.addRow(self.legend)

    def _fill_legend(self):
        from mfgeom.parting_legend import legend_entries
        grid = self._legend_grid
        while grid.count():
            w = grid.takeAt(0).widget()
            if w is not None:
                w.setParent(None)
                w.deleteLater()
        obj = self.obj
        entries = legend_entries(obj) if obj is not None and obj.isValid() else []
        for row, (key, label, rgb) in enumerate(entries):
            swatch = QtGui.QLabel()
            swatch.setObjectName(f"legendSwatch_{key}")
            swatch.setFixedSize(18, 14)
            r, g, b = (int(round(255 * c)) for c in rgb)
            swatch.setStyleSheet(f"background-color: rgb({r}, {g}, {b}); "
                                 "border: 1px solid #404040")
            text = QtGui.QLabel(label)
            text.setObjectName(f"legendText_{key}")
            grid.addWidget(swatch, row, 0)
            grid.addWidget(text, row, 1)
        self.legend.setVisible(bool(entries))

    # ------------------------------------------------------------- values
    def _load(self):
        obj = self.obj
        if obj is not None:
            self.mode.setCurrentIndex(MODES.index(obj.Mode))
            self.draft.setValue(obj.DraftAngle.Value)
            self.weighting.setCurrentIndex(WEIGHTINGS.index(obj.Weighting))
            self.all_faces.setChecked(bool(obj.AllFaces))
            p = obj.PullDirection
            self.pull.setText(f"{p.x:.12g}, {p.y:.12g}, {p.z:.12g}")
            self._deflection = obj.NormalDeflection.Value
        else:
            self._deflection = math.degrees(1e-3)
        # the box rounds to its decimals: an untouched box keeps the exact value
        self.deflection.setValue(self._deflection)
        self._deflection_shown = self.deflection.value()
        src = self.source.Label if self.source is not None else "(missing)"
        which = ", ".join(self.faces) if self.faces else "all faces"
        self.what.setText(f"Part: {src} ({which})")
        self.result.setText(result_text(obj))
        self._fill_legend()
        self.export_json_button.setEnabled(obj is not None)
        self.export_csv_button.setEnabled(obj is not None)
        self._mode_changed()

    def _mode_changed(self, *_):
        nc = self.mode.currentData() == "NC3Axis"
        self.all_faces.setEnabled(nc)
        draft = self.mode.currentData() == "Draft"
        self.pull.setEnabled(draft)
        self.pull_pick.setEnabled(draft)

    def pull_from_selection(self):
        """Fill the pull direction from the selected face (normal) or edge."""
        from mfgeom.app.parting_feature import pull_vector
        sel = [(s.Object, n) for s in FreeCADGui.Selection.getSelectionEx() for n in
               s.SubElementNames]
        try:
            if len(sel) != 1:
                raise PartingInputError("Select one face or one straight edge for the pull "
                                        "direction.")
            v = pull_vector(sel[0])
        except PartingInputError as exc:
            self._show_error(str(exc))
            return None
        self.pull.setText(f"{v.x:.12g}, {v.y:.12g}, {v.z:.12g}")
        return v

    def values(self):
        return {"Mode": self.mode.currentData(), "DraftAngle": float(self.draft.value()),
                "PullDirection": parse_direction(self.pull.text()),
                "Weighting": self.weighting.currentData(),
                "AllFaces": bool(self.all_faces.isChecked()),
                "NormalDeflection": (self._deflection if self.deflection.value() == self._deflection_shown
                               else float(self.deflection.value()))}

    # ------------------------------------------------------------- create / edit
    def _check(self):
        self.values()   # a bad pull direction raises PartingInputError

    def _refresh(self):
        self._load()

    def _create(self):
        from mfgeom.gui import macro
        v = self.values()
        made = []

        def make():
            obj = macro.echo_make_parting_analysis(
                self.doc, self.source, v["Mode"], v["DraftAngle"], v["Weighting"],
                v["AllFaces"], self.faces,
                pull_direction=v["PullDirection"] if v["Mode"] == "Draft" else None)
            made.append(obj)
            if abs(v["NormalDeflection"] - obj.NormalDeflection.Value) > 1e-12:
                self._set_and_recompute(
                    obj, [f"{macro.object_expr(obj)}.NormalDeflection = {v['NormalDeflection']!r}"])
            # the analysis shows a coloured copy of the part: hide the source meanwhile
            macro.app_set(self.source, "Visibility", False)
        if not self._run(self.doc, TITLE, make):
            return False
        self.obj = made[0]
        FreeCADGui.Selection.clearSelection()
        report(self.obj)
        return True

    def _edit(self):
        from mfgeom.gui import macro
        obj = self.obj
        p = obj.PullDirection
        current = {"Mode": obj.Mode, "DraftAngle": obj.DraftAngle.Value,
                   "Weighting": obj.Weighting, "AllFaces": bool(obj.AllFaces),
                   "NormalDeflection": obj.NormalDeflection.Value, "PullDirection": (p.x, p.y, p.z)}
        values = self.values()
        lines = [f"{macro.object_expr(obj)}.{k} = {v!r}" for k, v in values.items()
                 if v != current[k] and k != "PullDirection"]
        if values["PullDirection"] != current["PullDirection"]:
            x, y, z = values["PullDirection"]
            lines.append(f"{macro.object_expr(obj)}.PullDirection = "
                         f"FreeCAD.Vector({x!r}, {y!r}, {z!r})")
        if not lines:
            return True
        if not self._edit_lines(lines):
            return False
        report(obj)
        return True

    # ------------------------------------------------------------- export
    def export(self, kind, path=None):
        """Write the report as JSON or CSV to ``path`` (None: ask with a file dialog)."""
        if self.obj is None:
            return None
        if path is None:
            flt = "JSON (*.json)" if kind == "json" else "CSV (*.csv)"
            path, _ = QtGui.QFileDialog.getSaveFileName(
                FreeCADGui.getMainWindow(), f"Export the {kind.upper()} report",
                f"{self.obj.Name}.{kind}", flt)
            if not path:
                return None
        return export_report(self.obj, path, kind)


def export_report(obj, path, kind=None):
    """Write ``obj``'s report (:func:`mfgeom.parting.report`) to ``path`` as JSON or CSV
    (by ``kind`` or the file's extension)."""
    from mfgeom import parting
    from mfgeom.app.parting_feature import feature_report
    kind = kind or ("csv" if str(path).lower().endswith(".csv") else "json")
    rep = feature_report(obj)
    (parting.write_report_csv if kind == "csv" else parting.write_report_json)(path, rep)
    FreeCAD.Console.PrintMessage(f"mfgeom: {obj.Label}: report written to {path}\n")
    return path


def report(obj):
    """The analysis' summary in the Report view (mfgeom.parting.report_text)."""
    from mfgeom import parting
    from mfgeom.app.parting_feature import feature_report
    FreeCAD.Console.PrintMessage("mfgeom: " + parting.report_text(feature_report(obj)))
