# SPDX-License-Identifier: LGPL-2.1-or-later
"""The task panel of the mould commands (issue 21): "Parting line" (from a Mould
analysis: which side zero-draft walls go to), "Parting surface" (from a parting line: the
margin) and "Core and cavity" (from a Mould analysis: margin and zero-draft side; makes
the line and surface it needs).  One panel class, three kinds.

OK (and Apply) run the change through the Python console, so the Report view and a
recorded macro show the ``mfgeom.make_*`` call or the property assignments, in one undo
transaction; a failure is shown in the panel and the document is left as it was.
"""

import FreeCAD

from mfgeom.app.mould import MouldInputError, ZERO_DRAFT_SIDES
from mfgeom.app.mould_feature import DEFAULT_MARGIN
from mfgeom.gui.panel_base import TaskPanel, combo, spin

TITLES = {"line": "Parting line", "surface": "Parting surface", "blocks": "Core and cavity"}
TYPES = {"line": "Mfgeom::PartingLine", "surface": "Mfgeom::PartingSurface",
         "blocks": "Mfgeom::MouldBlocks"}
SIDE_TEXT = {"Cavity": "Cavity (line along their +d edge)",
             "Core": "Core (line along their -d edge)"}


def _type(obj):
    return getattr(getattr(obj, "Proxy", None), "Type", "")


def input_from_selection(kind, selection):
    """The input object of ``kind`` from ``[(obj, [subnames])]``: a Mould analysis (line,
    blocks) or a parting line (surface).  MouldInputError says what to select."""
    want = "Mfgeom::PartingLine" if kind == "surface" else "Mfgeom::PartingAnalysis"
    noun = "a parting line" if kind == "surface" else "a parting analysis in Mould mode"
    objs = [o for o, _subs in selection]
    found = [o for o in objs if _type(o) == want]
    if len(found) != 1:
        raise MouldInputError(f"Select {noun} first (in the tree), "
                              f"not {len(objs)} other object(s)." if not found else
                              f"Select one object: {noun}.")
    obj = found[0]
    if kind != "surface" and obj.Mode != "Mould":
        raise MouldInputError(f"'{obj.Label}' is a {obj.Mode} analysis: select one in "
                              "Mould mode.")
    return obj


def result_text(kind, obj):
    if obj is None:
        return "No result yet."
    if not obj.isValid():
        return f"Failed: {obj.getStatusString()}"
    if kind == "line":
        lines = [f"{obj.LoopCount} parting loop(s)"] + list(obj.Loops) + list(obj.ShutOffLoops)
        if obj.SplitFaces:
            lines.append(f"Split along silhouettes: {' '.join(obj.SplitFaces)}")
        return "\n".join(lines)
    if kind == "surface":
        return (f"{obj.PartingSurfaceCount} parting surface(s), {obj.ShutOffCount} "
                "shut-off surface(s)")
    v = list(obj.Volumes)
    lines = [f"Core {v[2]:.6g} mm^3, cavity {v[3]:.6g} mm^3, {len(v) - 4} insert(s)",
             f"Block {v[0]:.6g} mm^3, part {v[1]:.6g} mm^3"]
    lines += list(obj.Checks)
    return "\n".join(lines)


class MouldPanel(TaskPanel):
    """Task panel of ``kind`` ("line", "surface", "blocks"): ``source`` (the analysis or
    parting line) to create, or ``obj`` to edit."""

    def __init__(self, kind, source=None, obj=None):
        if kind not in TITLES:
            raise ValueError(f"unknown kind {kind!r}")
        if obj is None and source is None:
            raise MouldInputError("the panel needs an input or an object to edit")
        self.kind = kind
        self.obj = obj
        if obj is not None:
            source = {"line": lambda o: o.Analysis, "surface": lambda o: o.PartingLine,
                      "blocks": lambda o: o.PartingSurface.PartingLine.Analysis}[kind](obj)
        self.source = source
        self.doc = source.Document
        layout = self._new_form(TITLES[kind])
        self.side = self.margin = None
        if kind in ("line", "blocks"):
            self.side = combo("zeroDraftSide", [(SIDE_TEXT[s], s) for s in ZERO_DRAFT_SIDES],
                              "Zero-draft walls touching both sides (a cup's outer wall, a "
                              "through-hole) go to this side")
            layout.addRow("Zero-draft walls", self.side)
        if kind in ("surface", "blocks"):
            self.margin = spin("margin", 0.01, 1e6, 3, " mm", DEFAULT_MARGIN,
                               "How far the mould block (and the parting surface) reaches "
                               "beyond the part")
            layout.addRow("Margin", self.margin)
        self._add_result(layout)
        self.export_button = None
        if kind == "blocks":
            from PySide import QtGui
            self.export_button = QtGui.QPushButton("Export STEP...")
            self.export_button.setObjectName("exportStep")
            self.export_button.setToolTip("Write core, cavity and inserts as STEP files "
                                          "(<label>_core.step, _cavity.step, _insert1.step) "
                                          "into a folder")
            self.export_button.clicked.connect(lambda: self.export_step())
            layout.addRow(self.export_button)
        self._add_message(layout)
        self._load()

    def _load(self):
        obj = self.obj
        if obj is not None:
            if self.side is not None:
                line = obj if self.kind == "line" else obj.PartingSurface.PartingLine
                self.side.setCurrentIndex(ZERO_DRAFT_SIDES.index(line.ZeroDraftSide))
            if self.margin is not None:
                self.margin.setValue(obj.Margin.Value)
        what = "Parting line" if self.kind == "surface" else "Analysis"
        self.what.setText(f"{what}: {self.source.Label}")
        self.result.setText(result_text(self.kind, obj))
        if self.export_button is not None:
            self.export_button.setEnabled(obj is not None and obj.isValid())

    def export_step(self, directory=None):
        """Core, cavity and inserts of the blocks as STEP files in ``directory`` (None:
        ask with a folder dialog); returns {"core": path, ...} or None."""
        from mfgeom.app.mould import export_step_files
        obj = self.obj
        if obj is None or not obj.isValid():
            return None
        if directory is None:
            import FreeCADGui
            from PySide import QtGui
            directory = QtGui.QFileDialog.getExistingDirectory(
                FreeCADGui.getMainWindow(), "Export core, cavity and inserts as STEP")
            if not directory:
                return None
        try:
            files = export_step_files(obj.Core, obj.Cavity, obj.Inserts.Solids, directory,
                                      obj.Label.replace("/", "_").replace(" ", "_"))
        except (OSError, RuntimeError) as exc:
            self._show_error(f"Export failed: {exc}")
            return None
        FreeCAD.Console.PrintMessage(f"mfgeom: {obj.Label}: wrote "
                                     f"{', '.join(files.values())}\n")
        return files

    def _refresh(self):
        self._load()

    def _call(self):
        from mfgeom.gui import macro
        args = [macro.document_expr(self.doc), macro.object_expr(self.source)]
        if self.margin is not None:
            args.append(f"margin={float(self.margin.value())!r}")
        if self.side is not None:
            args.append(f"zero_draft_side={self.side.currentData()!r}")
        name = {"line": "make_parting_line", "surface": "make_parting_surface",
                "blocks": "make_mould_blocks"}[self.kind]
        return f"mfgeom.{name}({', '.join(args)})"

    def _create(self):
        if not self._create_by_call(self.doc, TITLES[self.kind], self._call(),
                                    TYPES[self.kind], TITLES[self.kind].lower()):
            return False
        FreeCAD.Console.PrintMessage(f"mfgeom: {self.obj.Label}: "
                                     f"{result_text(self.kind, self.obj)}\n")
        return True

    def _edit(self):
        from mfgeom.gui import macro
        obj = self.obj
        lines = []
        if self.margin is not None and abs(self.margin.value() - obj.Margin.Value) > 1e-9:
            lines.append(f"{macro.object_expr(obj)}.Margin = {float(self.margin.value())!r}")
        if self.side is not None:
            line = obj if self.kind == "line" else obj.PartingSurface.PartingLine
            if self.side.currentData() != line.ZeroDraftSide:
                lines.append(f"{macro.object_expr(line)}.ZeroDraftSide = "
                             f"{self.side.currentData()!r}")
        return self._edit_lines(lines)


def command_panel(kind, selection):
    """The panel a command opens on ``selection`` (MouldInputError: what to select)."""
    return MouldPanel(kind, input_from_selection(kind, selection))

