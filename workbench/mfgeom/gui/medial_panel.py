# SPDX-License-Identifier: LGPL-2.1-or-later
"""Task panels of the medial commands (issue 9): "Medial axis of face" (tolerance),
"Medial surface" (tolerance, major part only, deflection of curved faces) and
"Mid-surface for FEM" (tolerance and deflection when made from a solid, the CSV file, the
histogram's bins).  For a new feature (from the command) or an existing one (double
click: setEdit).

As the rotational sweep's panel: OK (and Apply) run the change through the Python console
(``Gui.doCommand``), so the Report view and a recorded macro show the exact
``mfgeom.make_*(...)`` call or property assignments, inside one undo transaction; a
failure (bad input, a library error) is shown in the panel and the Report view, the
transaction is aborted and the document stays as it was.
"""

import FreeCAD
from PySide import QtCore, QtGui

from mfgeom.app import medial_axis_feature as maf
from mfgeom.app import medial_surface_feature as msf
from mfgeom.app import mid_surface_feature as mid
from mfgeom.errors import InputError
from mfgeom.gui.panel_base import TaskPanel, spin
from mfgeom.palette import legend_labels


def _label(name, text=""):
    label = QtGui.QLabel(text)
    label.setObjectName(name)
    label.setWordWrap(True)
    label.setTextInteractionFlags(QtCore.Qt.TextSelectableByMouse)
    return label


# ---------------------------------------------------------------------------- selection
def face_from_selection(selection):
    """``(obj, "FaceN")`` of the one planar face selected, or InputError saying why not."""
    from mfgeom.app import refs
    faces = [(obj, s.split(".")[-1]) for obj, subs in selection for s in subs
             if s.split(".")[-1].startswith("Face")]
    if len(faces) != 1:
        raise InputError(f"Select one planar face (selected: {len(faces)} faces).")
    obj, sub = refs.normalize_face_ref(faces[0])
    maf.check_planar_face(refs.resolve_face(obj, sub), f"{obj.Label}.{sub}")
    return obj, sub


def solid_from_selection(selection, allow_medial=False):
    """The one solid selected (whole, or any of its faces), or with ``allow_medial`` a
    medial surface feature; InputError saying why not."""
    objs = []
    for obj, _subs in selection:
        if obj not in objs:
            objs.append(obj)
    if len(objs) != 1:
        what = "a solid" + (" or a medial surface" if allow_medial else "")
        raise InputError(f"Select {what} (selected: {len(objs)} objects).")
    obj = objs[0]
    if allow_medial and msf.is_medial_surface(obj):
        return obj
    msf.solid_shape(obj, allow_mesh=True)   # a solid or mesh, or MedialInputError why not
    return obj


# ---------------------------------------------------------------------------- base
class MedialPanel(TaskPanel):
    """What the three panels share beyond TaskPanel: the form (subclasses add their rows
    in ``_rows(layout)``), create through the console or edit in one transaction, the
    result text.  Subclasses set TITLE, TYPE and implement ``_rows``,
    ``_load(obj)``, ``_check()``, ``_call()`` (the make call's Python source) and
    ``_changes(obj)`` (``{property: value}`` an edit sets)."""

    TITLE = ""
    TYPE = ""

    def __init__(self, obj=None):
        self.obj = obj
        layout = self._new_form(self.TITLE)
        self.what.setTextInteractionFlags(QtCore.Qt.TextSelectableByMouse)
        self._rows(layout)
        self._add_result(layout)
        self._add_message(layout)
        self.message.setTextInteractionFlags(QtCore.Qt.TextSelectableByMouse)
        if obj is not None:
            self._load(obj)
        self._show_result()

    # subclasses
    def _rows(self, layout):
        raise NotImplementedError

    def _load(self, obj):
        raise NotImplementedError

    def _call(self):
        raise NotImplementedError

    def _changes(self, obj):
        raise NotImplementedError

    def result_text(self, obj):
        raise NotImplementedError

    def _refresh(self):
        self._show_result()

    def _show_result(self):
        self.result.setText(self.result_text(self.obj) if self.obj is not None
                            else "No result yet.")

    def _document(self):
        raise NotImplementedError

    def _create(self):
        if not self._create_by_call(self._document(), self.TITLE, self._call(), self.TYPE,
                                    "objects"):
            return False
        FreeCAD.Console.PrintMessage(f"mfgeom: {self.obj.Label}: "
                                     + self.result_text(self.obj).replace("\n", "; ") + "\n")
        return True

    def _edit(self):
        from mfgeom.gui import macro
        obj = self.obj
        return self._edit_lines([f"{macro.object_expr(obj)}.{name} = {value!r}"
                                 for name, value in self._changes(obj).items()])


# ---------------------------------------------------------------------------- panels
class MedialAxisPanel(MedialPanel):
    """Medial axis of a planar face: the tolerance."""

    TITLE = "Medial axis of face"
    TYPE = maf.TYPE

    def __init__(self, face_ref=None, obj=None):
        if face_ref is None and obj is None:
            raise InputError("the panel needs a face or a medial axis to edit")
        self.face_ref = face_ref
        super().__init__(obj)
        if obj is None:
            self.what.setText(f"Face: {face_ref[0].Label}.{face_ref[1]}")

    def _rows(self, layout):
        self.tolerance = spin("tolerance", 1e-6, 1e3, 6, " mm", maf.DEFAULT_TOLERANCE,
                              "The axis' samples and the radii between them are within "
                              "this distance of the true axis and clearance")
        layout.addRow("Tolerance", self.tolerance)

    def _load(self, obj):
        self.tolerance.setValue(obj.Tolerance.Value)
        link = obj.Face
        self.what.setText(f"Face: {link[0].Label}.{link[1][0]}" if link else "Face: (gone)")

    def _document(self):
        return self.face_ref[0].Document

    def _call(self):
        from mfgeom.gui import macro
        obj, sub = self.face_ref
        return (f"mfgeom.make_medial_axis({macro.document_expr(obj.Document)}, "
                f"({macro.object_expr(obj)}, {sub!r}), {self.tolerance.value()!r})")

    def _changes(self, obj):
        v = float(self.tolerance.value())
        return {} if v == obj.Tolerance.Value else {"Tolerance": v}

    def result_text(self, obj):
        if not obj.isValid():
            return f"Failed: {obj.getStatusString()}"
        radii = maf.branch_radii(obj)
        lines = [f"{obj.BranchCount} branches, {obj.JunctionCount} junctions; clearance "
                 f"radius {obj.MinRadius:.4g} .. {obj.MaxRadius:.4g} mm"]
        for b, r in enumerate(radii[:8]):
            lines.append(f"branch {b + 1}: {len(r)} points, radius {min(r):.4g} .. "
                         f"{max(r):.4g} mm")
        if len(radii) > 8:
            lines.append(f"... {len(radii) - 8} more (property Radii / BranchOffsets)")
        return "\n".join(lines)


def legend_text(lo, hi):
    """The colour scale in words, for the panels (the 3-D view draws the bar)."""
    ticks = legend_labels(lo, hi)
    names = ["dark wine", "magenta", "pale", "light blue", "dark blue"]
    if len(ticks) == 1:
        return f"Colour scale: one thickness, {ticks[0][1]}"
    return "Colour scale (thickness): " + ", ".join(
        f"{name} {text}" for name, (_t, text) in zip(names, ticks))


class MedialSurfacePanel(MedialPanel):
    """Medial surface of a solid: tolerance, major part only, deflection."""

    TITLE = "Medial surface"
    TYPE = msf.TYPE

    def __init__(self, source=None, obj=None):
        if source is None and obj is None:
            raise InputError("the panel needs a solid or a medial surface to edit")
        self.source = obj.Source if obj is not None else source
        super().__init__(obj)
        if obj is None:
            self.what.setText(f"Solid: {source.Label}")
            self.tolerance.setValue(msf.default_tolerance(msf.solid_shape(source, allow_mesh=True)))

    def _rows(self, layout):
        self.tolerance = spin("tolerance", 1e-6, 1e4, 6, " mm", 0.1,
                              "Sheets and seams lie within this distance of the true "
                              "medial surface (default: 0.5 % of the bounding-box diagonal)")
        layout.addRow("Tolerance", self.tolerance)
        self.major = QtGui.QCheckBox("Major part only (the mid-surface)")
        self.major.setObjectName("major")
        self.major.setChecked(True)
        self.major.setToolTip("Off: the full medial surface, with the sheets that run out "
                              "to convex edges and corners")
        layout.addRow(self.major)
        self.deflection = spin("deflection", 1e-6, 1e3, 6, " mm", msf.DEFAULT_DEFLECTION,
                               "Curved faces are tessellated within this distance; the "
                               "result is the medial surface of that polyhedron")
        layout.addRow("Deflection", self.deflection)
        self.legend = _label("legend")
        layout.addRow(self.legend)

    def _load(self, obj):
        self.tolerance.setValue(obj.Tolerance.Value)
        self.major.setChecked(bool(obj.MajorOnly))
        self.deflection.setValue(obj.Deflection.Value)
        src = obj.Source.Label if obj.Source is not None else "(gone)"
        self.what.setText(f"Solid: {src}")

    def _document(self):
        return self.source.Document

    def _call(self):
        from mfgeom.gui import macro
        args = [macro.document_expr(self.source.Document), macro.object_expr(self.source),
                repr(float(self.tolerance.value()))]
        if not self.major.isChecked():
            args.append("major_only=False")
        args.append(f"deflection={float(self.deflection.value())!r}")
        return f"mfgeom.make_medial_surface({', '.join(args)})"

    def _changes(self, obj):
        out = {}
        for name, value, old in (("Tolerance", float(self.tolerance.value()), obj.Tolerance.Value),
                                 ("MajorOnly", bool(self.major.isChecked()), bool(obj.MajorOnly)),
                                 ("Deflection", float(self.deflection.value()),
                                  obj.Deflection.Value)):
            if value != old:
                out[name] = value
        return out

    def result_text(self, obj):
        text = msf.result_text(obj)
        if obj.isValid():
            self.legend.setText(legend_text(2 * obj.MinRadius, 2 * obj.MaxRadius))
        return text


class MidSurfacePanel(MedialPanel):
    """FEM mid-surface: tolerance and deflection (from a solid), CSV file, bins."""

    TITLE = "Mid-surface for FEM"
    TYPE = mid.TYPE

    def __init__(self, source=None, obj=None, csv_path=""):
        if source is None and obj is None:
            raise InputError("the panel needs a solid, a medial surface or a mid-surface")
        self.source = obj.Source if obj is not None else source
        self.from_solid = obj is None and not msf.is_medial_surface(source)
        self._csv_default = csv_path
        super().__init__(obj)
        if obj is None:
            self.what.setText(("Solid: " if self.from_solid else "Medial surface: ")
                              + source.Label)
            if self.from_solid:
                self.tolerance.setValue(msf.default_tolerance(msf.solid_shape(source, allow_mesh=True)))
        for box in (self.tolerance, self.deflection):
            box.setEnabled(self.from_solid)

    def _rows(self, layout):
        self.tolerance = spin("tolerance", 1e-6, 1e4, 6, " mm", 0.1,
                              "Of the medial surface made from the solid (default: 0.5 % "
                              "of the bounding-box diagonal)")
        layout.addRow("Tolerance", self.tolerance)
        self.deflection = spin("deflection", 1e-6, 1e3, 6, " mm", msf.DEFAULT_DEFLECTION,
                               "Curved faces are tessellated within this distance")
        layout.addRow("Deflection", self.deflection)
        row = QtGui.QHBoxLayout()
        self.csv = QtGui.QLineEdit(getattr(self, "_csv_default", "") or "")
        self.csv.setObjectName("csv")
        self.csv.setPlaceholderText("(no CSV file)")
        self.csv.setToolTip("Points and thickness (sheet, x, y, z, radius, thickness) are "
                            "written here on every recompute")
        browse = QtGui.QPushButton("...")
        browse.setObjectName("browse")
        browse.clicked.connect(self._browse)
        row.addWidget(self.csv)
        row.addWidget(browse)
        layout.addRow("CSV file", row)
        self.bins = QtGui.QSpinBox()
        self.bins.setObjectName("bins")
        self.bins.setRange(1, 100)
        self.bins.setValue(mid.DEFAULT_BINS)
        layout.addRow("Histogram bins", self.bins)
        self.legend = _label("legend")
        layout.addRow(self.legend)

    def _browse(self):
        path, _filter = QtGui.QFileDialog.getSaveFileName(
            self.form, "Thickness CSV file", self.csv.text() or "thickness.csv",
            "CSV files (*.csv)")
        if path:
            self.csv.setText(path)

    def _load(self, obj):
        self.csv.setText(obj.CsvFile)
        self.bins.setValue(obj.Bins)
        if obj.Source is not None and msf.is_medial_surface(obj.Source):
            # shown read-only: its medial surface's, not the spin boxes' defaults
            self.tolerance.setValue(obj.Source.Tolerance.Value)
            self.deflection.setValue(obj.Source.Deflection.Value)
        self.what.setText(f"Medial surface: {obj.Source.Label if obj.Source else '(gone)'}")

    def _check(self):
        path = self.csv.text().strip()
        if path:
            import os
            folder = os.path.dirname(os.path.abspath(os.path.expanduser(path)))
            if not os.path.isdir(folder):
                raise InputError(f"the CSV file's folder does not exist: {folder}")

    def _document(self):
        return self.source.Document

    def _call(self):
        from mfgeom.gui import macro
        path = self.csv.text().strip()
        args = [macro.document_expr(self.source.Document), macro.object_expr(self.source),
                repr(path) if path else "None"]
        if self.from_solid:
            args.append(repr(float(self.tolerance.value())))
            args.append(f"deflection={float(self.deflection.value())!r}")
        if self.bins.value() != mid.DEFAULT_BINS:
            args.append(f"bins={int(self.bins.value())}")
        return f"mfgeom.make_mid_surface({', '.join(args)})"

    def _changes(self, obj):
        out = {}
        path = self.csv.text().strip()
        if path != obj.CsvFile:
            out["CsvFile"] = path
        if int(self.bins.value()) != obj.Bins:
            out["Bins"] = int(self.bins.value())
        return out

    def result_text(self, obj):
        if not obj.isValid():
            return f"Failed: {obj.getStatusString()}"
        self.legend.setText(legend_text(obj.MinThickness, obj.MaxThickness))
        return (f"{len(obj.Shape.Faces)} faces\n" + "\n".join(obj.Histogram)
                + (f"\nCSV: {obj.CsvFile}" if obj.CsvFile else ""))
