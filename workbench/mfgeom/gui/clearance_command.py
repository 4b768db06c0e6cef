# SPDX-License-Identifier: LGPL-2.1-or-later
"""The "Clearance check" command (issue 8): will the rotating part hit anything?

Select the rotational sweep and the solids to check, in any order (only the sweep: every
other solid of the document); the sweep is found among them by type.  The check runs through the Python console
(``mfgeom.check_clearance(...)``, so a recorded macro repeats it), the table goes to the
Report view, the interfering solids turn the palette's INTERFERENCE colour, and a task
panel shows the table with "Save CSV..." and "Restore colours".

Colours are a temporary highlight, never a change of the document: each coloured
object's ShapeColor and DiffuseColor are kept (per document, in this session) and put
back by "Restore colours", by the next run of the command, by the command with nothing
selected, and around every save (a saved file holds the user's own colours; the highlight
comes back after the save).  A colour the user changed after the highlight is left alone.
"""

import FreeCAD
import FreeCADGui

from mfgeom import palette, paths
from mfgeom.app import clearance
from mfgeom.errors import InputError
from mfgeom.gui.messages import warn

TITLE = "Clearance check"

# doc name -> {object name: (ShapeColor, DiffuseColor or None)} of highlighted objects
_saved = {}


# ------------------------------------------------------------------------- colours
def _colour(c):
    return tuple(round(float(x), 4) for x in c[:3])


def _view(doc, name):
    obj = doc.getObject(name)
    return None if obj is None or obj.ViewObject is None else obj.ViewObject


def highlight(doc, objects):
    """Colours ``objects`` with palette.INTERFERENCE, keeping their colours to restore."""
    saved = _saved.setdefault(doc.Name, {})
    for obj in objects:
        vobj = obj.ViewObject
        if vobj is None or not hasattr(vobj, "ShapeColor"):
            continue
        if obj.Name not in saved:
            diffuse = list(vobj.DiffuseColor) if hasattr(vobj, "DiffuseColor") else None
            saved[obj.Name] = (tuple(vobj.ShapeColor), diffuse)
        vobj.ShapeColor = palette.INTERFERENCE   # also sets DiffuseColor to one colour
    _install_save_guard()


def highlighted(doc):
    """Names of the objects of ``doc`` the last check coloured."""
    return sorted(_saved.get(doc.Name, {}))


def _put_back(doc, saved):
    for name, (shape_colour, diffuse) in saved.items():
        vobj = _view(doc, name)
        if vobj is None or _colour(vobj.ShapeColor) != _colour(palette.INTERFERENCE):
            continue   # deleted, or recoloured by the user since: theirs now
        vobj.ShapeColor = shape_colour
        if diffuse is not None and len(diffuse) > 1:  # per-face colours come back last
            vobj.DiffuseColor = diffuse


def restore_colours(doc):
    """Puts back the colours the last check changed in ``doc``; returns how many objects
    it had coloured."""
    saved = _saved.pop(doc.Name, {})
    _put_back(doc, saved)
    return len(saved)


class _SaveGuard:
    """Document observer: a document is saved with the user's colours, then highlighted
    again."""

    def slotStartSaveDocument(self, doc, _filename):
        _put_back(doc, _saved.get(doc.Name, {}))

    def slotFinishSaveDocument(self, doc, _filename):
        names = list(_saved.get(doc.Name, {}))
        for name in names:
            vobj = _view(doc, name)
            if vobj is not None:
                vobj.ShapeColor = palette.INTERFERENCE

    def slotDeletedDocument(self, doc):
        _saved.pop(doc.Name, None)


_guard = []


def _install_save_guard():
    if not _guard:
        _guard.append(_SaveGuard())
        FreeCAD.addDocumentObserver(_guard[0])


# ------------------------------------------------------------------------- running
def _warn(text):
    warn(TITLE, text)


def check_call(sweep, others, tolerance=None):
    """Python source of the ``mfgeom.check_clearance`` call (``others`` None: the
    document's solids)."""
    from mfgeom.gui import macro
    args = [macro.object_expr(sweep)]
    if others is not None:
        args.append(f"[{', '.join(macro.object_expr(o) for o in others)}]")
    if tolerance is not None:
        args.append(f"tolerance={float(tolerance)!r}")
    return f"mfgeom.check_clearance({', '.join(args)})"


def run(objects, tolerance=None, show_panel=True):
    """The command on ``objects``, selected in any order: the rotational sweep among
    them (by type, :func:`mfgeom.app.clearance.find_sweep`) against the others.  Restores
    an earlier highlight, runs the check through the console, prints the table, colours
    the interfering solids and shows the panel.  Returns the results, or None after a
    message; a refused selection (no sweep, two sweeps, a sweep that is no solid)
    changes nothing: no colour, no panel, no console line."""
    doc = objects[0].Document if objects else FreeCAD.ActiveDocument
    if not objects:
        restored = restore_colours(doc) if doc is not None else 0
        if restored:
            FreeCAD.Console.PrintMessage(
                f"{TITLE}: colours of {restored} object(s) restored.\n")
        else:
            _warn("Select the rotational sweep and the solids to check against it "
                  "(Ctrl+click, in any order), or only the sweep to check every other "
                  "solid.")
        return None
    try:   # the user's mistakes as a message here, not a traceback in the console
        sweep, others = clearance.find_sweep(objects, stand_in=False)
        clearance.check_volume_source(sweep)
    except InputError as exc:
        text = str(exc)
        _warn(f"{text[:1].upper()}{text[1:]}.")
        return None
    others = others or None
    restore_colours(doc)
    call = check_call(sweep, others, tolerance)
    import __main__
    try:
        FreeCADGui.doCommand("import mfgeom")
        FreeCADGui.doCommand(f"_clearance = {call}")
    except InputError as exc:
        _warn(str(exc))
        return None
    results = __main__._clearance
    FreeCADGui.doCommand("del _clearance")
    tol = clearance.default_tolerance(sweep) if tolerance is None else float(tolerance)
    FreeCAD.Console.PrintMessage(clearance.report_text(results, sweep.Label, tol))
    for r in results:
        if r.status == clearance.INVALID:
            FreeCAD.Console.PrintWarning(f"{TITLE}: {r.message}\n")
    highlight(doc, [doc.getObject(r.name) for r in results if r.interferes])
    if show_panel and not FreeCADGui.Control.activeDialog():
        FreeCADGui.Control.showDialog(ClearancePanel(doc, sweep.Label, results, tol))
    return results


# ------------------------------------------------------------------------- panel
class ClearancePanel:
    """The results table, "Save CSV..." and "Restore colours"; Close keeps the colours."""

    last = None   # the panel shown last (macros and tests reach its save_csv)

    def __init__(self, doc, sweep_label, results, tolerance):
        from PySide import QtGui
        ClearancePanel.last = self
        self.doc, self.results = doc, results
        self.form = QtGui.QWidget()
        self.form.setObjectName("clearancePanel")
        self.form.setWindowTitle(TITLE)
        layout = QtGui.QVBoxLayout(self.form)
        n = sum(1 for r in results if r.interferes)
        summary = QtGui.QLabel(f"Against '{sweep_label}' (tolerance {tolerance:g} mm): "
                               f"{n} of {len(results)} object(s) interfere.")
        summary.setObjectName("summary")
        summary.setWordWrap(True)
        layout.addWidget(summary)
        rows = clearance.report_rows(results)
        table = QtGui.QTableWidget(len(rows) - 1, 4)
        table.setObjectName("results")
        table.setHorizontalHeaderLabels(["Object", "Status", "Interference (mm^3)",
                                         "Distance (mm)"])
        for i, (row, r) in enumerate(zip(rows[1:], results)):
            for j, text in enumerate(row[:4]):
                item = QtGui.QTableWidgetItem(text)
                if r.message:
                    item.setToolTip(r.message)
                table.setItem(i, j, item)
        table.resizeColumnsToContents()
        table.setEditTriggers(QtGui.QAbstractItemView.NoEditTriggers)
        layout.addWidget(table)
        self.table = table
        buttons = QtGui.QHBoxLayout()
        self.csv_button = QtGui.QPushButton("Save CSV...")
        self.csv_button.setObjectName("saveCsv")
        self.csv_button.clicked.connect(self.save_csv)
        self.restore_button = QtGui.QPushButton("Restore colours")
        self.restore_button.setObjectName("restoreColours")
        self.restore_button.setEnabled(bool(highlighted(doc)))
        self.restore_button.clicked.connect(self.restore)
        buttons.addWidget(self.csv_button)
        buttons.addWidget(self.restore_button)
        layout.addLayout(buttons)

    def getStandardButtons(self):
        from PySide import QtGui
        return int(QtGui.QDialogButtonBox.Close)

    def reject(self):
        FreeCADGui.Control.closeDialog()
        return True

    def save_csv(self, path=None):
        if not path:
            from PySide import QtGui
            path, _ = QtGui.QFileDialog.getSaveFileName(
                FreeCADGui.getMainWindow(), "Save the clearance table", "clearance.csv",
                "CSV (*.csv)")
        if path:
            clearance.write_csv(self.results, path)
            FreeCAD.Console.PrintMessage(f"{TITLE}: table saved to {path}\n")
        return path

    def restore(self):
        restore_colours(self.doc)
        self.restore_button.setEnabled(False)


# ------------------------------------------------------------------------- command
class ClearanceCheckCommand:
    """Interference volume and minimum distance of solids from the swept volume."""

    def GetResources(self):
        return {"Pixmap": paths.icon("ClearanceCheck.svg"), "MenuText": TITLE,
                "ToolTip": ("Will the rotating part hit anything?  Select the rotational "
                            "sweep and the solids to check, in any order (or only the "
                            "sweep: every other solid).\nReports each solid's interference volume and "
                            "minimum distance (Report view, optional CSV) and colours the "
                            "interfering solids magenta;\nrun it again (or with nothing "
                            "selected) to restore their colours.")}

    def IsActive(self):
        return FreeCAD.ActiveDocument is not None

    def Activated(self):
        if FreeCADGui.Control.activeDialog():
            _warn("A task panel is open: close it first.")
            return
        # in any order: run() finds the sweep among them
        objects = [s.Object for s in FreeCADGui.Selection.getSelectionEx()]
        run(objects)
