# SPDX-License-Identifier: LGPL-2.1-or-later
"""Task panel of the "Thickness analysis" command (issue 21, section 4): the thin / thick
thresholds, the medial tolerance, the deflection of curved faces, the sample spacing and
the wall angle; the result, a histogram of the wall thickness over the part's area and an
Export CSV button.  For a new analysis (from the command) or an existing one (double
click).  As the other panels, OK and Apply run the change through the Python console in
one undo transaction (the Report view and a recorded macro show the
``mfgeom.make_thickness_analysis(...)`` call); a failure is shown here and in the Report
view and the document stays as it was."""

import FreeCAD
from PySide import QtCore, QtGui

from mfgeom.app import thickness_feature as tf
from mfgeom.errors import InputError
from mfgeom.gui.medial_panel import MedialPanel
from mfgeom.gui.panel_base import spin

BAR_WIDTH = 30   # characters of the longest histogram bar


def histogram_text(edges, areas, lo, hi):
    """The histogram as text rows "from .. to mm  bar  percent  (thin / thick)"."""
    total = float(sum(areas)) or 1.0
    peak = max(areas) if len(areas) else 0.0
    rows = []
    for a, b, w in zip(list(edges[:-1]), list(edges[1:]), list(areas)):
        bar = "#" * (int(round(BAR_WIDTH * w / peak)) if peak > 0 else 0)
        note = " thin" if b <= lo else " thick" if a >= hi else ""
        rows.append(f"{a:8.3f} .. {b:8.3f} mm {bar:<{BAR_WIDTH}} {100 * w / total:5.1f} %{note}")
    return "\n".join(rows)


class ThicknessPanel(MedialPanel):
    """Wall thickness of a solid: thresholds, tolerance, deflection, spacing, angle."""

    TITLE = "Thickness analysis"
    TYPE = tf.TYPE

    def __init__(self, source=None, obj=None):
        if source is None and obj is None:
            raise InputError("the panel needs a solid or a thickness analysis to edit")
        self.source = obj.Source if obj is not None else source
        super().__init__(obj)
        if obj is None:
            from mfgeom.app.medial_surface_feature import solid_shape
            diag = solid_shape(source).BoundBox.DiagonalLength
            self.what.setText(f"Solid: {source.Label}")
            self.tolerance.setValue(tf.TOLERANCE_FRACTION * diag)
            self.deflection.setValue(tf.TOLERANCE_FRACTION * diag)
            self.spacing.setValue(tf.default_spacing(solid_shape(source),
                                                     tf.TOLERANCE_FRACTION * diag))

    def _rows(self, layout):
        self.min_thickness = spin("minThickness", 1e-4, 1e5, 4, " mm", 1.0,
                                  "Walls thinner than this are shown pink (fill problems)")
        layout.addRow("Minimum thickness", self.min_thickness)
        self.max_thickness = spin("maxThickness", 1e-4, 1e5, 4, " mm", 4.0,
                                  "Walls thicker than this are shown brown (sink marks, "
                                  "long cooling)")
        layout.addRow("Maximum thickness", self.max_thickness)
        self.tolerance = spin("tolerance", 1e-6, 1e4, 6, " mm", 0.1,
                              "Medial surface tolerance (default: 0.5 % of the "
                              "bounding-box diagonal)")
        layout.addRow("Tolerance", self.tolerance)
        self.deflection = spin("deflection", 1e-6, 1e3, 6, " mm", 0.1,
                               "Curved faces are tessellated within this distance (the "
                               "thickness is that polyhedron's)")
        layout.addRow("Deflection", self.deflection)
        self.spacing = spin("spacing", 1e-4, 1e4, 4, " mm", 1.0,
                            "Largest distance between the samples coloured on the part")
        layout.addRow("Sample spacing", self.spacing)
        self.angle = spin("minAngle", 1.0, 180.0, 1, " deg", tf.DEFAULT_MIN_ANGLE,
                          "A ball is a wall's when two points it touches are at least this "
                          "far apart seen from its centre (convex corners are not walls)")
        layout.addRow("Wall angle", self.angle)
        self.histogram = QtGui.QLabel("")
        self.histogram.setObjectName("histogram")
        self.histogram.setFont(QtGui.QFont("Monospace", 8))
        self.histogram.setTextInteractionFlags(QtCore.Qt.TextSelectableByMouse)
        layout.addRow(self.histogram)
        self.export_button = QtGui.QPushButton("Export CSV...")
        self.export_button.setObjectName("exportCsv")
        self.export_button.setToolTip("Write every sample (x, y, z, face, thickness, "
                                      "thin / ok / thick) and the histogram to a CSV file")
        self.export_button.clicked.connect(lambda: self.export_csv())
        layout.addRow(self.export_button)

    def _load(self, obj):
        self.min_thickness.setValue(obj.MinThickness.Value)
        self.max_thickness.setValue(obj.MaxThickness.Value)
        self.tolerance.setValue(obj.Tolerance.Value)
        self.deflection.setValue(obj.Deflection.Value)
        self.spacing.setValue(obj.SampleSpacing.Value)
        self.angle.setValue(obj.MinAngle.Value)
        self.what.setText(f"Solid: {obj.Source.Label if obj.Source else '(gone)'}")

    def _check(self):
        tf.check_parameters(float(self.min_thickness.value()), float(self.max_thickness.value()),
                            float(self.tolerance.value()), float(self.deflection.value()),
                            float(self.spacing.value()), float(self.angle.value()))

    def _document(self):
        return self.source.Document

    def _call(self):
        from mfgeom.gui import macro
        args = [macro.document_expr(self.source.Document), macro.object_expr(self.source),
                repr(float(self.min_thickness.value())), repr(float(self.max_thickness.value())),
                f"tolerance={float(self.tolerance.value())!r}",
                f"deflection={float(self.deflection.value())!r}",
                f"sample_spacing={float(self.spacing.value())!r}"]
        if float(self.angle.value()) != tf.DEFAULT_MIN_ANGLE:
            args.append(f"min_angle={float(self.angle.value())!r}")
        return f"mfgeom.make_thickness_analysis({', '.join(args)})"

    def _changes(self, obj):
        out = {}
        for name, value, old in (
                ("MinThickness", float(self.min_thickness.value()), obj.MinThickness.Value),
                ("MaxThickness", float(self.max_thickness.value()), obj.MaxThickness.Value),
                ("Tolerance", float(self.tolerance.value()), obj.Tolerance.Value),
                ("Deflection", float(self.deflection.value()), obj.Deflection.Value),
                ("SampleSpacing", float(self.spacing.value()), obj.SampleSpacing.Value),
                ("MinAngle", float(self.angle.value()), obj.MinAngle.Value)):
            if value != old:
                out[name] = value
        return out

    def result_text(self, obj):
        text = tf.result_text(obj)
        ok = obj is not None and obj.isValid() and len(obj.VertexThickness) > 0
        if ok:
            edges, areas = tf.histogram_of(obj)
            self.histogram.setText("Area by wall thickness:\n" + histogram_text(
                edges, areas, obj.MinThickness.Value, obj.MaxThickness.Value))
        else:
            self.histogram.setText("")
        self.export_button.setEnabled(ok)
        return text

    def export_csv(self, path=None):
        """The samples and histogram as CSV at ``path`` (None: asks for it); returns the
        path written or None."""
        obj = self.obj
        if obj is None or not obj.isValid():
            return None
        if path is None:
            import FreeCADGui
            path, _filter = QtGui.QFileDialog.getSaveFileName(
                FreeCADGui.getMainWindow(), "Export wall thickness as CSV",
                f"{obj.Label.replace(' ', '_')}.csv", "CSV files (*.csv)")
            if not path:
                return None
        try:
            rows = tf.write_csv(obj, path)
        except (OSError, InputError) as exc:
            self._show_error(f"Export failed: {exc}")
            return None
        FreeCAD.Console.PrintMessage(f"mfgeom: {obj.Label}: wrote {rows} samples to {path}\n")
        return path
