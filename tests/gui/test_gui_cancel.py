# SPDX-License-Identifier: LGPL-2.1-or-later
"""FreeCAD GUI test of progress and cancel (issue 18), run as a macro under a virtual X
server by tests/gui/run_gui_tests.sh: ``xvfb-run -a freecad tests/gui/test_gui_cancel.py``.

A user sweeps a finely tessellated torus (several seconds of library work) through the
Rotational sweep task panel; the progress dialog appears, shows the library's stages and
a moving bar; a click on its Cancel button (then, again, the Esc key) stops the computation within a
second or two;
the panel then says it was cancelled, the document is as before (no sweep object, the
undo stack unchanged, the torus untouched) and the dialog is gone.  The same sweep is then
run to the end with the dialog left alone (the dialog closes, the sweep is valid), and a
short recompute shows no dialog at all.  Prints ``freecad-gui-cancel: N passed, M failed``.
"""

import os
import sys
import time

import FreeCAD as App
import FreeCADGui as Gui

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
if os.path.join(ROOT, "workbench") not in sys.path:
    sys.path.append(os.path.join(ROOT, "workbench"))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from gui_harness import DialogCloser, check, finish, press, pump, qt, state  # noqa: E402

WORKBENCH = "MfgeomWorkbench"
COMMAND = "Mfgeom_RotationalSweep"
TOL = 0.002  # mm, and ANGLE degrees: the torus sweep then takes several seconds (45 384
ANGLE = 270.0  # triangles, ~4.5 s of library work, 2026-12-07; at 0.005 and 90 degrees it took
               # ~6 s before the arrangement's flips, 0.7 s after: the sweep ended before Esc)


dialogs = DialogCloser()


def progress_dialog():
    _, QtGui = qt()
    found = [w for w in Gui.getMainWindow().findChildren(QtGui.QProgressDialog)
             if w.objectName() == "mfgeomProgress" and w.isVisible()]
    return found[0] if found else None


class Watcher:
    """Polls for the progress dialog while the computation runs (its timer fires inside
    the dialog's own event processing); records what the dialog showed and, with
    ``cancel_after`` seconds, clicks its Cancel button once it has been seen that long."""

    def __init__(self, cancel_after=None, key=False):
        QtCore, _ = qt()
        self.cancel_after = cancel_after
        self.key = key   # cancel with the Esc key instead of the button
        self.seen_at = self.clicked_at = None
        self.labels, self.values = [], []
        self.timer = QtCore.QTimer()
        self.timer.timeout.connect(self._tick)
        self.timer.start(50)

    def _tick(self):
        _, QtGui = qt()
        dialog = progress_dialog()
        if dialog is None:
            return
        now = time.monotonic()
        if self.seen_at is None:
            self.seen_at = now
        self.labels.append(dialog.labelText())
        self.values.append(dialog.value())
        if (self.cancel_after is not None and self.clicked_at is None
                and now - self.seen_at >= self.cancel_after):
            self.clicked_at = now
            if self.key:
                QtCore, _ = qt()
                for kind in (QtCore.QEvent.KeyPress, QtCore.QEvent.KeyRelease):
                    QtGui.QApplication.sendEvent(
                        dialog, QtGui.QKeyEvent(kind, QtCore.Qt.Key_Escape, QtCore.Qt.NoModifier))
                return
            button = [b for b in dialog.findChildren(QtGui.QPushButton)
                      if b.text().replace("&", "") == "Cancel"]
            assert button, "the progress dialog has no Cancel button"
            button[0].click()

    def stop(self):
        self.timer.stop()


def sweeps(doc):
    return [o for o in doc.Objects
            if getattr(getattr(o, "Proxy", None), "Type", "") == "Mfgeom::RotationalSweep"]


def task_panel():
    _, QtGui = qt()
    Gui.updateGui()
    mw = Gui.getMainWindow()
    if not Gui.Control.activeDialog():
        return None
    widgets = {w.objectName(): w for w in mw.findChildren(QtGui.QWidget)
               if w.objectName() and w.isVisible()}
    if "tolerance" not in widgets:
        return None
    boxes = [b for b in mw.findChildren(QtGui.QDialogButtonBox)
             if b.isVisible() and b.button(QtGui.QDialogButtonBox.Ok) is not None]
    widgets["ok"] = boxes[0].button(QtGui.QDialogButtonBox.Ok)
    widgets["cancel"] = boxes[0].button(QtGui.QDialogButtonBox.Cancel)
    return widgets


def open_panel(doc, torus):
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(torus)
    Gui.runCommand(COMMAND)
    panel = task_panel()
    assert panel is not None, "no task panel"
    panel["angle"].setValue(ANGLE)
    panel["tolerance"].setValue(TOL)
    panel["deflection"].setValue(TOL)
    return panel


@check("a long sweep shows the progress dialog; Cancel stops it and leaves the document as before")
def _():
    Gui.activateWorkbench(WORKBENCH)
    doc = App.newDocument("CancelGui")
    Gui.ActiveDocument = Gui.getDocument(doc.Name)
    torus = doc.addObject("Part::Torus", "Torus")
    torus.Radius1, torus.Radius2 = 10.0, 3.0
    torus.Placement.Base = App.Vector(20, 0, 0)
    doc.recompute()
    state.update(doc=doc, torus=torus)
    undo, names = doc.UndoCount, [o.Name for o in doc.Objects]
    panel = open_panel(doc, torus)
    watcher = Watcher(cancel_after=0.3)
    t0 = time.monotonic()
    press(panel["ok"])
    returned = time.monotonic()
    watcher.stop()
    assert watcher.seen_at is not None, "no progress dialog during a long sweep"
    assert watcher.clicked_at is not None, \
        f"the sweep ended before Cancel was clicked ({returned - t0:.1f} s)"
    assert any("Recomputing" in t and "sweep:" in t for t in watcher.labels), watcher.labels[:5]
    assert returned - watcher.clicked_at < 3.0, \
        f"Cancel took {returned - watcher.clicked_at:.1f} s to stop the sweep"
    left = task_panel()
    assert left is not None, "the panel closed although the sweep was cancelled"
    assert "cancelled" in left["message"].text(), left["message"].text()
    assert progress_dialog() is None, "the progress dialog stayed open"
    assert sweeps(doc) == [] and [o.Name for o in doc.Objects] == names, doc.Objects
    assert doc.UndoCount == undo, (undo, doc.UndoCount)
    assert torus.isValid() and "Touched" not in torus.State, torus.State
    state["panel"] = left
    state["cancel_stop_s"] = returned - watcher.clicked_at


@check("Esc in the progress dialog cancels too")
def _():
    doc, panel = state["doc"], state["panel"]
    undo = doc.UndoCount
    watcher = Watcher(cancel_after=0.3, key=True)
    press(panel["ok"])
    returned = time.monotonic()
    watcher.stop()
    assert watcher.clicked_at is not None, "the sweep ended before Esc was pressed"
    assert returned - watcher.clicked_at < 3.0, f"{returned - watcher.clicked_at:.1f} s"
    left = task_panel()
    assert left is not None and "cancelled" in left["message"].text()
    assert progress_dialog() is None and sweeps(doc) == [] and doc.UndoCount == undo
    state["panel"] = left


@check("the same sweep left alone runs to the end; the dialog closes, the sweep is valid")
def _():
    doc = state["doc"]
    panel = state["panel"]
    undo = doc.UndoCount
    watcher = Watcher()
    press(panel["ok"])
    watcher.stop()
    assert watcher.seen_at is not None, "no progress dialog during a long sweep"
    values = watcher.values
    assert values == sorted(values) and values[-1] > values[0], values
    assert task_panel() is None, "OK left the panel open"
    assert progress_dialog() is None, "the progress dialog stayed open"
    new = sweeps(doc)
    assert len(new) == 1 and new[0].isValid() and new[0].TriangleCount > 0, new
    assert doc.UndoCount == undo + 1
    state["sweep"] = new[0]


@check("a short recompute shows no progress dialog")
def _():
    import mfgeom
    doc = state["doc"]
    box = doc.addObject("Part::Box", "Box")
    box.Placement.Base = App.Vector(0, 40, 0)
    doc.recompute()
    watcher = Watcher()
    t0 = time.monotonic()
    small = mfgeom.make_rotational_sweep(doc, box, (0, 0, 0), (0, 0, 1), 30.0, 0.1)
    took = time.monotonic() - t0
    watcher.stop()
    assert small.isValid(), small.getStatusString()
    from mfgeom.gui import progress_dialog
    assert took < progress_dialog.SHOW_AFTER, f"the small sweep took {took:.2f} s"
    assert watcher.seen_at is None, "a dialog flashed for a short recompute"


print(f"cancel: Cancel stopped the sweep after {state.get('cancel_stop_s', float('nan')):.2f} s")
finish("freecad-gui-cancel")
