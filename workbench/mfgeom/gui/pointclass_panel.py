# SPDX-License-Identifier: LGPL-2.1-or-later
"""The task panel of "Classify points": tolerance, Strict and point size, for a new
classification (from the command) or an existing one (double click: setEdit).

OK runs the change through the Python console (``Gui.doCommand``), so the Report view
and a recorded macro show the exact ``mfgeom.make_point_classification(...)`` call or
property assignments, inside one undo transaction; Cancel leaves the document as it
was.  Nothing is computed while the panel is open.
"""

import FreeCAD
import FreeCADGui
from PySide import QtCore, QtGui

from mfgeom.app import preferences
from mfgeom.errors import InputError
from mfgeom.gui.panel_base import TaskPanel

TITLE = "Classify points"
MAX_POINT_SIZE = 64


def _describe(face_ref, points_ref):
    """'Face: Face3 of Bracket / Points: Cloud' for the panel's header; a link that is gone
    (an edited feature whose input was deleted) reads '(missing)'."""
    face, points = "(missing)", "(missing)"
    if face_ref and face_ref[0] is not None:
        face_obj, sub = face_ref
        sub = sub if isinstance(sub, str) else (sub[0] if sub else "")
        face = f"{sub} of {face_obj.Label}" if sub else face_obj.Label
    if points_ref and points_ref[0] is not None:
        src_obj, src_subs = points_ref
        points = src_obj.Label + (f" ({len(src_subs)} vertices)" if src_subs else "")
    return f"Face: {face}\nPoints: {points}"


class PointClassificationPanel(TaskPanel):
    """Task panel; ``face_ref``/``points_ref`` to create a classification, or ``obj`` (an
    existing PointClassification) to edit it."""

    APPLY = False         # nothing is computed while the panel is open
    WAIT_CURSOR = False

    def __init__(self, face_ref=None, points_ref=None, obj=None):
        if obj is None and (face_ref is None or points_ref is None):
            raise InputError("the panel needs a face and points, or an object to edit")
        self.obj = obj
        self.face_ref, self.points_ref = face_ref, points_ref
        if obj is not None:  # editing needs the object only; its links are shown
            self.face_ref, self.points_ref = obj.Face, obj.PointSource
        self.doc = obj.Document if obj is not None else face_ref[0].Document

        layout = self._new_form(TITLE)
        self.what.setText(_describe(self.face_ref, self.points_ref))

        self.tolerance = FreeCADGui.UiLoader().createWidget("Gui::QuantitySpinBox")
        self.tolerance.setObjectName("tolerance")
        self.tolerance.setProperty("unit", "mm")
        self.tolerance.setProperty("minimum", 0.0)
        self.tolerance.setProperty("maximum", 1e6)
        self.tolerance.setProperty("singleStep", 0.01)
        self.tolerance.setToolTip(
            "Points whose distance to the face's boundary is at most this are ON.\n"
            "Any length unit may be typed (e.g. 10 um); it is kept in mm.")
        self._mm = obj.Tolerance.Value if obj is not None else preferences.default_tolerance()
        # Gui::QuantitySpinBox shows lengths in the user's unit schema (0.01 mm as
        # "10.00 µm", rounded to its decimals): the panel keeps the text in mm, at full
        # precision, each time the box is shown and after each edit.
        self._keeper = _MillimetreKeeper(self)
        self.tolerance.installEventFilter(self._keeper)
        self._line_edit().textChanged.connect(self._typed)
        self._line_edit().editingFinished.connect(self.show_mm)
        self.show_mm()
        layout.addRow("Tolerance", self.tolerance)

        self.strict = QtGui.QCheckBox("Strict: points off the face's surface are OUT")
        self.strict.setObjectName("strict")
        self.strict.setToolTip(
            "Checked: a point farther than the tolerance from the face's surface is OUT.\n"
            "Unchecked: every point is classified by its projection onto the surface\n"
            "(the Report view then says how far the farthest point was).")
        self.strict.setChecked(bool(obj.Strict) if obj is not None else True)
        layout.addRow(self.strict)

        self.point_size = QtGui.QSpinBox()
        self.point_size.setObjectName("pointSize")
        self.point_size.setRange(1, MAX_POINT_SIZE)
        self.point_size.setSuffix(" px")
        vobj = getattr(obj, "ViewObject", None) if obj is not None else None
        self.point_size.setValue(int(vobj.PointSize) if vobj is not None
                                 else preferences.point_size())
        layout.addRow("Point size", self.point_size)

        self._add_message(layout)

    # ------------------------------------------------------------- values
    def _line_edit(self):
        return self.tolerance.findChild(QtGui.QLineEdit)

    def _typed(self, text):
        try:
            self._mm = self.tolerance_mm()
        except InputError:
            pass  # not a length (yet): OK will say why

    def show_mm(self):
        """Show the last valid tolerance in mm (unless the box holds a wrong entry)."""
        try:
            self.tolerance_mm()
            edit = self._line_edit()
        except (InputError, RuntimeError):  # a wrong entry, or the panel is gone already
            return
        text = f"{self._mm:.12g} mm"
        if edit.text() != text:
            edit.setText(text)

    def tolerance_mm(self):
        """The tolerance typed in, in mm; InputError (with the reason) if it is not a length."""
        from mfgeom.app.pointclass import _check_tolerance
        return _check_tolerance(self._line_edit().text().strip())

    # ------------------------------------------------------------- create / edit
    def _check(self):
        self.tolerance_mm()   # InputError (with the reason) unless a length

    def _create(self):
        from mfgeom.gui import macro
        tol, strict, size = self.tolerance_mm(), self.strict.isChecked(), self.point_size.value()
        made = []

        def make():
            # on a failure make_point_classification removed its half-made object
            # already; the abort drops whatever else the transaction holds.
            obj = macro.make_point_classification(self.face_ref, self.points_ref, tol, strict)
            made.append(obj)
            if size != preferences.point_size():
                macro.gui_set(obj, "PointSize", size)
            src = self.points_ref[0]
            if src.isDerivedFrom("Points::Feature") and src.ViewObject is not None:
                macro.gui_set(src, "Visibility", False)  # our coloured copy sits on top of it
        if not self._run(self.doc, TITLE, make):
            return False
        FreeCADGui.Selection.clearSelection()
        report(made[0])
        return True

    def _edit(self):
        from mfgeom.gui import macro
        obj = self.obj
        tol, strict, size = self.tolerance_mm(), self.strict.isChecked(), self.point_size.value()
        changes = []
        if tol != obj.Tolerance.Value:
            changes.append(("Tolerance", tol))
        if strict != bool(obj.Strict):
            changes.append(("Strict", strict))
        vobj = obj.ViewObject
        if not changes and (vobj is None or size == vobj.PointSize):
            return True

        def change():
            if changes:
                self._set_and_recompute(obj, [f"{macro.object_expr(obj)}.{name} = {value!r}"
                                              for name, value in changes])
            if vobj is not None and size != vobj.PointSize:
                macro.gui_set(obj, "PointSize", size)
        if not self._run(obj.Document, f"Edit {obj.Label}", change, restore=True):
            return False
        if changes:
            report(obj)
        return True


class _MillimetreKeeper(QtCore.QObject):
    """Event filter: puts the tolerance back in mm after the box is shown (the spin box
    re-formats it in the unit schema then)."""

    def __init__(self, panel):
        super().__init__()
        self.panel = panel

    def eventFilter(self, watched, event):
        if event.type() == QtCore.QEvent.Show:
            QtCore.QTimer.singleShot(0, self.panel.show_mm)
        return False


def report(obj):
    """One line in the Report view: the counts, the tolerance and the largest distance of
    a point to the surface (the recompute itself warns about points farther than the
    tolerance)."""
    FreeCAD.Console.PrintMessage(
        f"mfgeom: {obj.Label}: IN {obj.CountIn}, ON {obj.CountOn}, OUT {obj.CountOut} "
        f"(tolerance {obj.Tolerance.Value:g} mm{', strict' if obj.Strict else ''}; largest "
        f"distance to the surface {obj.MaxDistanceToSurface.Value:g} mm)\n")
