# SPDX-License-Identifier: LGPL-2.1-or-later
"""What the GUI test scripts (run inside FreeCAD under Xvfb) share: the check decorator
and its results, GUI event pumping, the modal-dialog closer, and the summary line and
exit code that tests/gui/run_gui_tests.sh reads (printed by tests/freecad/fc_testsupport.py,
the runner of the App tests too: a run where nothing passed fails, skips are listed)."""

import os
import sys
import time
import traceback
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
                                "freecad"))
import fc_testsupport  # noqa: E402

results = []  # (name, ok, detail)
skips = []    # (name, reason): a check that raised unittest.SkipTest (environment only)
state = {}    # "image": the screenshot's path, printed by finish()


def check(name):
    """Decorator: run a test function now, record pass/fail with the reason (a
    unittest.SkipTest is recorded as a skip with its reason)."""
    def run(fn):
        try:
            fn()
        except unittest.SkipTest as exc:
            skips.append((name, str(exc)))
        except Exception:  # any failure of a test is reported, then the next one runs
            results.append((name, False, traceback.format_exc()))
        else:
            results.append((name, True, ""))
        return fn
    return run


def qt():
    from PySide import QtCore, QtGui
    return QtCore, QtGui


def screenshot(out_dir, name, doc=None, clear_selection=False, size=(1000, 700)):
    """Saves the 3-D view of ``doc`` (a document name; None: the active one), isometric and
    fitted, as ``out_dir/name`` on white; ``clear_selection`` first drops the selection
    (its green would hide the result's colours).  Returns the path."""
    import FreeCADGui as Gui
    os.makedirs(out_dir, exist_ok=True)
    if clear_selection:
        Gui.Selection.clearSelection()
    view = (Gui.getDocument(doc) if doc else Gui.ActiveDocument).ActiveView
    view.viewIsometric()
    view.fitAll()
    Gui.updateGui()
    path = os.path.join(out_dir, name)
    view.saveImage(path, size[0], size[1], "White")
    return path


def pump(until, seconds):
    """Processes GUI events until ``until()`` is true or ``seconds`` have passed."""
    _QtCore, QtGui = qt()
    end = time.monotonic() + seconds
    while not until() and time.monotonic() < end:
        QtGui.QApplication.processEvents()
        time.sleep(0.02)
    return until()


def press(button):
    import FreeCADGui as Gui
    button.click()
    Gui.updateGui()


class DialogCloser:
    """Closes every modal dialog (the commands' message boxes) shortly after it opens and
    keeps its text: a bad selection can be tested without a human, and an unexpected
    dialog fails a test instead of hanging the run."""

    def __init__(self):
        QtCore, _QtGui = qt()
        self.texts = []
        self.timer = QtCore.QTimer()
        self.timer.timeout.connect(self._tick)
        self.timer.start(100)

    def _tick(self):
        _QtCore, QtGui = qt()
        box = QtGui.QApplication.activeModalWidget()
        # the progress dialog of a long recompute is the workbench's own, not a message
        # to answer: closing it would cancel the computation under test
        if box is not None and box.objectName() != "mfgeomProgress":
            self.texts.append(box.text() if hasattr(box, "text") else box.windowTitle())
            box.done(0)

    def take(self):
        texts, self.texts = self.texts, []
        return texts


def finish(label):
    """Prints every result and ``<label>: N passed, M failed``, then leaves FreeCAD with
    the exit code (os._exit: a normal exit of the GUI can hang or crash under Xvfb)."""
    failed = [r for r in results if not r[1]]
    for name, ok, detail in results:
        sys.stdout.write(f"{'PASS' if ok else 'FAIL'}: {name}\n")
        if not ok:
            sys.stdout.write(detail + "\n")
    if "image" in state:
        sys.stdout.write(f"screenshot: {state['image']}\n")
    rc = fc_testsupport.summarize(label, len(results) - len(failed), len(failed), skips)
    from mfgeom import compat  # flushes C stdio too: FreeCAD 1.0 buffers it in a pipe
    compat.exit_now(rc)
