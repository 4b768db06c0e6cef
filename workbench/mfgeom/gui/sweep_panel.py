# SPDX-License-Identifier: LGPL-2.1-or-later
"""The task panel of "Rotational sweep": the axis (the selected straight edge or datum
line, a global axis X / Y / Z through an editable point, or a custom point and
direction), reverse, angle (deg), tolerance and deflection (mm), representation (Mesh /
Solid); the result after each recompute.  For a new sweep (from the command) or an
existing one (double click: setEdit).

OK (and Apply) run the change through the Python console (``Gui.doCommand``), so the
Report view and a recorded macro show the exact ``mfgeom.make_rotational_sweep(...)``
call or property assignments, inside one undo transaction; a failure (bad input, a
library error) is shown in the panel and the Report view, the transaction is aborted and
the document stays as it was.
"""

import FreeCAD
import FreeCADGui
from PySide import QtCore, QtGui

from mfgeom.app.sweep_feature import (DEFAULT_ANGLE, DEFAULT_DEFLECTION, DEFAULT_TOLERANCE,
                                      REPRESENTATIONS, TYPE, SweepInputError, axis_of,
                                      check_parameters)
from mfgeom.errors import MfgeomError

TITLE = "Rotational sweep"
GLOBAL_AXES = {"X": (1.0, 0.0, 0.0), "Y": (0.0, 1.0, 0.0), "Z": (0.0, 0.0, 1.0)}


def _is_solid(obj):
    shape = getattr(obj, "Shape", None)
    return shape is not None and not shape.isNull() and bool(shape.Solids)


def _is_line_object(obj):
    """A datum line, an origin axis or a Part object that is one straight edge."""
    if getattr(obj, "TypeId", "") in ("App::Line", "PartDesign::Line"):
        return True
    shape = getattr(obj, "Shape", None)
    return (shape is not None and not shape.isNull() and not shape.Faces
            and len(shape.Edges) == 1
            and type(shape.Edges[0].Curve).__name__ in ("Line", "LineSegment"))


def inputs_from_selection(selection):
    """(source, axis) from ``[(obj, [subnames])]``: one solid (whole, or some of its
    faces or edges) and optionally an axis: a straight edge ``(obj, "EdgeN")`` (of the
    solid itself or of another object) or a datum line / origin axis / line object
    (``(obj, "")``).  ``axis`` is None when none is selected (the panel then offers the
    global axes).  SweepInputError says what is wrong."""
    if not selection:
        raise SweepInputError("Select a solid first (and, for the axis, a straight edge or "
                              "a datum line; or choose a global axis in the panel).")
    solids, axes = [], []
    for obj, subs in selection:
        edges = [s for s in subs if s.startswith("Edge")]
        others = [s for s in subs if not s.startswith(("Edge", "Face", "Vertex"))]
        if others:
            raise SweepInputError(f"Cannot use {', '.join(others)} of '{obj.Label}'.")
        if _is_solid(obj):
            if obj not in solids:
                solids.append(obj)
        elif _is_line_object(obj) and not subs:
            axes.append((obj, ""))
            continue
        elif not edges:
            raise SweepInputError(f"'{obj.Label}' is neither a solid nor a straight line: "
                                  "select a closed solid and an axis.")
        for e in edges:
            axes.append((obj, e))
    if not solids:
        raise SweepInputError("No solid selected: select the closed solid that turns.")
    if len(solids) > 1:
        raise SweepInputError("Select one solid, not "
                              f"{len(solids)} ({', '.join(o.Label for o in solids)}).")
    if len(axes) > 1:
        raise SweepInputError(f"Select one axis, not {len(axes)} edges or lines.")
    axis = axes[0] if axes else None
    if axis is not None:
        axis_of(*axis)   # straight, or SweepInputError saying why not
    return solids[0], axis


def result_text(obj):
    """The panel's summary of a sweep's result."""
    if obj is None:
        return "No result yet."
    if not obj.isValid():
        return f"Failed: {obj.getStatusString()}"
    lines = [f"Volume {obj.Volume:.6g} mm^3, area {obj.Area:.6g} mm^2",
             f"{obj.TriangleCount} triangles ({obj.SourceTriangles} in the source mesh)"]
    if obj.SourceOffset > 0:
        lines.append(f"Curved source faces pushed out by up to {obj.SourceOffset:.3g} mm "
                     "(conservative)")
    return "\n".join(lines)


def _vec_expr(v):
    return f"({float(v[0])!r}, {float(v[1])!r}, {float(v[2])!r})"


def sweep_call(doc, source, point, direction, angle, tolerance, deflection,
               representation="Mesh", axis=None, reverse=False):
    """Python source of the ``mfgeom.make_rotational_sweep`` call for these inputs."""
    from mfgeom.gui import macro
    args = [macro.document_expr(doc), macro.object_expr(source), _vec_expr(point),
            _vec_expr(direction), repr(float(angle)), repr(float(tolerance)),
            f"deflection={float(deflection)!r}"]
    if representation != "Mesh":
        args.append(f"representation={representation!r}")
    if axis is not None:
        obj, sub = axis
        args.append(f"axis=({macro.object_expr(obj)}, {sub!r})" if sub
                    else f"axis={macro.object_expr(obj)}")
    if reverse:
        args.append("reverse=True")
    return f"mfgeom.make_rotational_sweep({', '.join(args)})"


def _spin(name, low, high, decimals, suffix="", value=0.0):
    box = QtGui.QDoubleSpinBox()
    box.setObjectName(name)
    box.setRange(low, high)
    box.setDecimals(decimals)
    if suffix:
        box.setSuffix(suffix)
    box.setValue(value)
    return box


class SweepPanel:
    """Task panel; ``source`` (and ``axis``) to create a sweep, or ``obj`` to edit one."""

    def __init__(self, source=None, axis=None, obj=None):
        if obj is None and source is None:
            raise SweepInputError("the panel needs a source or a sweep to edit")
        self.obj = obj
        self.source = obj.Source if obj is not None else source
        if obj is not None and obj.AxisObject is not None:
            a_obj, subs = obj.AxisObject
            axis = (a_obj, subs[0] if subs else "")
        self.axis = axis
        self.doc = obj.Document if obj is not None else source.Document

        self.form = QtGui.QWidget()
        self.form.setWindowTitle(TITLE if obj is None else f"Edit {obj.Label}")
        layout = QtGui.QFormLayout(self.form)
        self.what = QtGui.QLabel()
        self.what.setObjectName("what")
        self.what.setWordWrap(True)
        layout.addRow(self.what)

        self.axis_choice = QtGui.QComboBox()
        self.axis_choice.setObjectName("axis")
        if axis is not None:
            self.axis_choice.addItem(f"Selected: {self._axis_label(axis)}", "object")
        for name in GLOBAL_AXES:
            self.axis_choice.addItem(f"Global {name} axis", name)
        self.axis_choice.addItem("Custom point and direction", "custom")
        self.axis_choice.setToolTip("The axis the part turns about (counter-clockwise seen "
                                    "from the tip of its direction)")
        layout.addRow("Axis", self.axis_choice)

        self.point = [_spin(f"p{c}", -1e9, 1e9, 4, " mm") for c in "xyz"]
        self.direction = [_spin(f"d{c}", -1e6, 1e6, 6) for c in "xyz"]
        for label, boxes in (("Axis point", self.point), ("Axis direction", self.direction)):
            row = QtGui.QHBoxLayout()
            for b in boxes:
                row.addWidget(b)
            layout.addRow(label, row)
        self.reverse = QtGui.QCheckBox("Reverse (turn the other way)")
        self.reverse.setObjectName("reverse")
        layout.addRow(self.reverse)

        self.angle = _spin("angle", 0.001, 360.0, 3, " deg", DEFAULT_ANGLE)
        self.angle.setToolTip("The part turns by 0 .. this angle (360: solid of revolution)")
        layout.addRow("Angle", self.angle)
        self.tolerance = _spin("tolerance", 1e-6, 1e3, 6, " mm", DEFAULT_TOLERANCE)
        self.tolerance.setToolTip("The result lies within this distance of the true swept "
                                  "volume")
        layout.addRow("Tolerance", self.tolerance)
        self.deflection = _spin("deflection", 1e-6, 1e3, 6, " mm", DEFAULT_DEFLECTION)
        self.deflection.setToolTip("Curved faces are meshed within this distance and the "
                                   "mesh pushed out by it (conservative); planar faces are "
                                   "exact")
        layout.addRow("Deflection", self.deflection)
        self.representation = QtGui.QComboBox()
        self.representation.setObjectName("representation")
        for r in REPRESENTATIONS:
            self.representation.addItem(r, r)
        self.representation.setToolTip("Mesh: fast for any size; Solid: a Part solid "
                                       "(coplanar triangles merged) for Part tools")
        layout.addRow("Representation", self.representation)

        self.result = QtGui.QLabel()
        self.result.setObjectName("result")
        self.result.setWordWrap(True)
        self.result.setTextInteractionFlags(QtCore.Qt.TextSelectableByMouse)
        layout.addRow(self.result)
        self.message = QtGui.QLabel("")
        self.message.setObjectName("message")
        self.message.setWordWrap(True)
        self.message.setStyleSheet("color: #b00000")
        layout.addRow(self.message)

        self.axis_choice.currentIndexChanged.connect(self._axis_changed)
        self._load()

    @staticmethod
    def _axis_label(axis):
        obj, sub = axis
        return f"{obj.Label}.{sub}" if sub else obj.Label

    # ------------------------------------------------------------- values
    def _load(self):
        obj = self.obj
        if obj is not None:
            point = (obj.AxisPoint.x, obj.AxisPoint.y, obj.AxisPoint.z)
            direction = (obj.AxisDirection.x, obj.AxisDirection.y, obj.AxisDirection.z)
            if obj.AxisObject is not None:
                choice = "object"
            else:
                choice = next((k for k, v in GLOBAL_AXES.items() if v == direction), "custom")
            self.reverse.setChecked(bool(obj.AxisReversed))
            self.angle.setValue(obj.Angle.Value)
            self.tolerance.setValue(obj.Tolerance.Value)
            self.deflection.setValue(obj.Deflection.Value)
            self.representation.setCurrentIndex(REPRESENTATIONS.index(obj.Representation))
        else:
            point, direction = (0.0, 0.0, 0.0), GLOBAL_AXES["Z"]
            choice = "object" if self.axis is not None else "Z"
        self._set_vector(self.point, point)
        self._set_vector(self.direction, direction)
        self.axis_choice.setCurrentIndex(self.axis_choice.findData(choice))
        self._axis_changed()
        src = self.source.Label if self.source is not None else "(missing)"
        self.what.setText(f"Part: {src}")
        self.result.setText(result_text(obj))

    @staticmethod
    def _set_vector(boxes, v):
        for b, x in zip(boxes, v):
            b.setValue(float(x))

    def _axis_changed(self, *_):
        choice = self.axis_choice.currentData()
        if choice == "object":
            try:
                p, d = axis_of(*self.axis)
            except SweepInputError as exc:
                self.message.setText(str(exc))
            else:
                self._set_vector(self.point, p)
                self._set_vector(self.direction, d)
        elif choice in GLOBAL_AXES:
            self._set_vector(self.direction, GLOBAL_AXES[choice])
        for b in self.point:
            b.setEnabled(choice != "object")
        for b in self.direction:
            b.setEnabled(choice == "custom")

    def values(self):
        """What the panel asks for: a dict of the make function's inputs."""
        choice = self.axis_choice.currentData()
        return {"axis": self.axis if choice == "object" else None,
                "point": [b.value() for b in self.point],
                "direction": [b.value() for b in self.direction],
                "reverse": bool(self.reverse.isChecked()),
                "angle": float(self.angle.value()),
                "tolerance": float(self.tolerance.value()),
                "deflection": float(self.deflection.value()),
                "representation": self.representation.currentData()}

    # ------------------------------------------------------------- task dialog protocol
    def getStandardButtons(self):
        return int(QtGui.QDialogButtonBox.Ok | QtGui.QDialogButtonBox.Apply
                   | QtGui.QDialogButtonBox.Cancel)

    def clicked(self, button):
        if button == QtGui.QDialogButtonBox.Apply:
            self.apply()

    def apply(self):
        """Create or update the sweep; the panel then shows its result.  Values are
        checked first, so a bad one is shown without touching the document."""
        v = self.values()
        try:
            check_parameters(v["point"], v["direction"] if v["axis"] is None else (0, 0, 1),
                             v["angle"], v["tolerance"], v["deflection"])
        except SweepInputError as exc:
            self._show_error(str(exc))
            return False
        ok = self._create() if self.obj is None else self._edit()
        if ok:
            self._load()
        return ok

    def accept(self):
        ok = self.apply()
        if ok:
            self._close()
        return ok

    def reject(self):
        self._close()
        return True

    def _close(self):
        FreeCADGui.Control.closeDialog()
        if FreeCADGui.ActiveDocument is not None and FreeCADGui.ActiveDocument.getInEdit():
            FreeCADGui.ActiveDocument.resetEdit()

    def _show_error(self, text):
        self.message.setText(text)
        FreeCAD.Console.PrintError(f"mfgeom: {text}\n")

    # ------------------------------------------------------------- create / edit
    def _create(self):
        v = self.values()
        doc = self.doc
        call = sweep_call(doc, self.source, v["point"], v["direction"], v["angle"],
                          v["tolerance"], v["deflection"], v["representation"], v["axis"],
                          v["reverse"])
        before = {o.Name for o in doc.Objects}
        doc.openTransaction(TITLE)
        QtGui.QApplication.setOverrideCursor(QtCore.Qt.WaitCursor)
        try:
            FreeCADGui.doCommand("import mfgeom")
            FreeCADGui.doCommand(call)
            new = [o for o in doc.Objects if o.Name not in before
                   and getattr(getattr(o, "Proxy", None), "Type", "") == TYPE]
            if len(new) != 1:
                raise MfgeomError(f"'{call}' created {len(new)} sweeps, expected 1")
        except (MfgeomError, ValueError, TypeError, RuntimeError, ImportError) as exc:
            doc.abortTransaction()
            self._show_error(str(exc))
            return False
        finally:
            QtGui.QApplication.restoreOverrideCursor()
        doc.commitTransaction()
        self.obj = new[0]
        self.message.setText("")
        FreeCADGui.Selection.clearSelection()
        report(self.obj)
        return True

    def _edit(self):
        from mfgeom.gui import macro
        obj, doc = self.obj, self.doc
        v = self.values()
        target = macro.object_expr(obj)
        lines = []
        if v["axis"] is None and obj.AxisObject is not None:
            lines.append(f"{target}.AxisObject = None")
        if v["axis"] is None:
            lines.append(f"{target}.AxisPoint = App.Vector{_vec_expr(v['point'])}")
            lines.append(f"{target}.AxisDirection = App.Vector{_vec_expr(v['direction'])}")
        current = {"AxisReversed": bool(obj.AxisReversed), "Angle": obj.Angle.Value,
                   "Tolerance": obj.Tolerance.Value, "Deflection": obj.Deflection.Value,
                   "Representation": obj.Representation}
        wanted = {"AxisReversed": v["reverse"], "Angle": v["angle"],
                  "Tolerance": v["tolerance"], "Deflection": v["deflection"],
                  "Representation": v["representation"]}
        for name, value in wanted.items():
            if value != current[name]:
                lines.append(f"{target}.{name} = {value!r}")
        if not lines:
            return True
        doc.openTransaction(f"Edit {obj.Label}")
        QtGui.QApplication.setOverrideCursor(QtCore.Qt.WaitCursor)
        try:
            for line in lines:
                FreeCADGui.doCommand(line)
            macro.recompute(obj)
            if not obj.isValid():
                raise SweepInputError(obj.getStatusString())
        except (MfgeomError, ValueError, TypeError, RuntimeError) as exc:
            doc.abortTransaction()
            doc.recompute()  # the old values are back: so are their results
            self._show_error(str(exc))
            return False
        finally:
            QtGui.QApplication.restoreOverrideCursor()
        doc.commitTransaction()
        self.message.setText("")
        report(obj)
        return True


def report(obj):
    """The sweep's summary in the Report view."""
    FreeCAD.Console.PrintMessage(f"mfgeom: {obj.Label}: " + result_text(obj).replace("\n", "; ")
                                 + "\n")
