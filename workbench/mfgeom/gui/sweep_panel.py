# SPDX-License-Identifier: LGPL-2.1-or-later
"""The task panel of "Rotational sweep": the axis (the selected straight edge or datum
line, a global axis X / Y / Z through an editable point, or a custom point and
direction), reverse, angle (deg), tolerance and deflection (mm: for a new sweep a
thousandth of the part's size, rounded down to 1, 2 or 5 x 10^k, which the user may
change), representation (Mesh / Solid); the result after each recompute.  For a new sweep (from the command) or an
existing one (double click: setEdit).

OK (and Apply) run the change through the Python console (``Gui.doCommand``), so the
Report view and a recorded macro show the exact ``mfgeom.make_rotational_sweep(...)``
call or property assignments, inside one undo transaction; a failure (bad input, a
library error) is shown in the panel and the Report view, the transaction is aborted and
the document stays as it was.
"""

import FreeCAD
from PySide import QtGui

from mfgeom.app.sweep_feature import (DEFAULT_ANGLE, DEFAULT_DEFLECTION, DEFAULT_TOLERANCE,
                                      REPRESENTATIONS, TYPE, SweepInputError, axis_of,
                                      check_parameters, part_defaults)
from mfgeom.gui.panel_base import TaskPanel, combo, spin

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


class SweepPanel(TaskPanel):
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

        layout = self._new_form(TITLE)

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

        self.point = [spin(f"p{c}", -1e9, 1e9, 4, " mm") for c in "xyz"]
        self.direction = [spin(f"d{c}", -1e6, 1e6, 6) for c in "xyz"]
        for label, boxes in (("Axis point", self.point), ("Axis direction", self.direction)):
            row = QtGui.QHBoxLayout()
            for b in boxes:
                row.addWidget(b)
            layout.addRow(label, row)
        self.reverse = QtGui.QCheckBox("Reverse (turn the other way)")
        self.reverse.setObjectName("reverse")
        layout.addRow(self.reverse)

        self.angle = spin("angle", 0.001, 360.0, 3, " deg", DEFAULT_ANGLE)
        self.angle.setToolTip("The part turns by 0 .. this angle (360: solid of revolution)")
        layout.addRow("Angle", self.angle)
        self.tolerance = spin("tolerance", 1e-6, 1e3, 6, " mm", DEFAULT_TOLERANCE)
        self.tolerance.setToolTip("The result lies within this distance of the true swept "
                                  "volume")
        layout.addRow("Tolerance", self.tolerance)
        self.deflection = spin("deflection", 1e-6, 1e3, 6, " mm", DEFAULT_DEFLECTION)
        self.deflection.setToolTip("Curved faces are meshed within this distance and the "
                                   "mesh pushed out by it (conservative); planar faces are "
                                   "exact")
        layout.addRow("Deflection", self.deflection)
        # a new sweep starts from a thousandth of its part's size (the user may change it)
        self.scaled = None
        if obj is None:
            try:
                self.scaled = part_defaults(self.source)
            except SweepInputError:   # no extent: the absolute values stay
                self.scaled = None
        self.defaults_note = QtGui.QLabel("")
        self.defaults_note.setObjectName("defaultsNote")
        self.defaults_note.setWordWrap(True)
        if self.scaled is not None:
            tol, defl, diagonal = self.scaled
            self.defaults_note.setText(
                f"Tolerance and deflection start at 1/1000 of the part's size "
                f"({diagonal:.4g} mm diagonal), rounded down: {tol:g} mm.")
        layout.addRow(self.defaults_note)
        self.representation = combo("representation", [(r, r) for r in REPRESENTATIONS],
                                    "Mesh: fast for any size; Solid: a Part solid "
                                    "(coplanar triangles merged) for Part tools")
        layout.addRow("Representation", self.representation)

        self._add_result(layout)
        self._add_message(layout)

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
            if self.scaled is not None:
                self.tolerance.setValue(self.scaled[0])
                self.deflection.setValue(self.scaled[1])
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

    # ------------------------------------------------------------- create / edit
    def _check(self):
        v = self.values()
        check_parameters(v["point"], v["direction"] if v["axis"] is None else (0, 0, 1),
                         v["angle"], v["tolerance"], v["deflection"])

    def _refresh(self):
        self._load()

    def _create(self):
        v = self.values()
        call = sweep_call(self.doc, self.source, v["point"], v["direction"], v["angle"],
                          v["tolerance"], v["deflection"], v["representation"], v["axis"],
                          v["reverse"])
        if not self._create_by_call(self.doc, TITLE, call, TYPE, "sweeps"):
            return False
        report(self.obj)
        return True

    def _edit(self):
        from mfgeom.gui import macro
        obj = self.obj
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
        if not self._edit_lines(lines):
            return False
        report(obj)
        return True


def report(obj):
    """The sweep's summary in the Report view."""
    FreeCAD.Console.PrintMessage(f"mfgeom: {obj.Label}: " + result_text(obj).replace("\n", "; ")
                                 + "\n")
